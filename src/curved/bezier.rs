//! Planar Bézier curves of any degree: the trim curves in a patch's parameter square
//! (seed 000 §2.1: "polynomial curves of any degree"; spec §1.3).
//!
//! Evaluation and splitting use de Casteljau's algorithm, which only forms convex
//! combinations, so pieces stay within the parent's control polygon hull and the same call
//! on the same curve gives the same bits.

use glam::DVec2;

/// A planar Bézier curve `c(t) = Σ Bᵢᵈ(t) pᵢ`, `t ∈ [0, 1]`, of degree `d = points.len() − 1 ≥ 1`.
#[derive(Debug, Clone, PartialEq)]
pub struct BezierCurve {
    points: Vec<DVec2>,
}

impl BezierCurve {
    /// A curve through these control points (at least two; [`super::validate`] checks).
    pub fn new(points: Vec<DVec2>) -> BezierCurve {
        BezierCurve { points }
    }

    /// The straight segment from `a` to `b` (degree 1).
    pub fn line(a: DVec2, b: DVec2) -> BezierCurve {
        BezierCurve::new(vec![a, b])
    }

    /// The control points `p₀ … p_d`.
    pub fn points(&self) -> &[DVec2] {
        &self.points
    }

    /// The degree `d`.
    pub fn degree(&self) -> usize {
        self.points.len().saturating_sub(1)
    }

    /// `c(0) = p₀`.
    pub fn start(&self) -> DVec2 {
        self.points[0]
    }

    /// `c(1) = p_d`.
    pub fn end(&self) -> DVec2 {
        self.points[self.points.len() - 1]
    }

    /// The same curve traversed backwards.
    pub fn reversed(&self) -> BezierCurve {
        let mut p = self.points.clone();
        p.reverse();
        BezierCurve::new(p)
    }

    /// `c(t)` by de Casteljau.
    pub fn eval(&self, t: f64) -> DVec2 {
        de_casteljau(&self.points, t)
    }

    /// The control points of the hodograph `c'(t)`, a curve of degree `d − 1`:
    /// `d (pᵢ₊₁ − pᵢ)` (spec §1.4 (a)).
    pub fn hodograph(&self) -> Vec<DVec2> {
        let d = self.degree() as f64;
        self.points.windows(2).map(|w| d * (w[1] - w[0])).collect()
    }

    /// `c'(t)`.
    pub fn derivative(&self, t: f64) -> DVec2 {
        de_casteljau(&self.hodograph(), t)
    }

    /// The two halves at `t = 1/2` (seed 000 §2.2: "split at t = 1/2").
    pub fn split_half(&self) -> (BezierCurve, BezierCurve) {
        self.split(0.5)
    }

    /// The pieces over `[0, t]` and `[t, 1]`, by de Casteljau.
    pub fn split(&self, t: f64) -> (BezierCurve, BezierCurve) {
        let n = self.points.len();
        let mut work = self.points.clone();
        let mut left = Vec::with_capacity(n);
        let mut right = vec![DVec2::ZERO; n];
        left.push(work[0]);
        right[n - 1] = work[n - 1];
        for level in 1..n {
            for i in 0..n - level {
                work[i] = lerp(work[i], work[i + 1], t);
            }
            left.push(work[0]);
            right[n - 1 - level] = work[n - 1 - level];
        }
        (BezierCurve::new(left), BezierCurve::new(right))
    }

    /// The same curve as a curve of degree `d + 1`.
    pub fn elevated(&self) -> BezierCurve {
        let d = self.degree();
        let n = d + 1;
        let mut q = Vec::with_capacity(n + 1);
        q.push(self.points[0]);
        for i in 1..n {
            let a = i as f64 / n as f64;
            q.push(a * self.points[i - 1] + (1.0 - a) * self.points[i]);
        }
        q.push(self.points[d]);
        BezierCurve::new(q)
    }

    /// `∫ u dv − ∫ v du` over the curve, halved: its contribution to the signed area enclosed
    /// by a loop (Green's theorem), in closed form from the control points (spec §3.4):
    /// `∫₀¹ Bᵢᵈ B_jᵈ⁻¹ dt = C(d,i) C(d−1,j) / (2d · C(2d−1, i+j))`.
    pub fn area_term(&self) -> f64 {
        let d = self.degree();
        let p = &self.points;
        let mut s = 0.0;
        for i in 0..=d {
            for j in 0..d {
                let w = binomial(d, i) * binomial(d - 1, j) / (2.0 * binomial(2 * d - 1, i + j));
                let dp = p[j + 1] - p[j];
                // x dy − y dx, with x, y from the degree-d curve and dx, dy = d Δp (the d cancels
                // against the 2d of the integral: weight w already holds 1/(2d)·d = 1/2).
                s += w * (p[i].x * dp.y - p[i].y * dp.x);
            }
        }
        0.5 * s
    }

    /// The axis-aligned box of the control points (it holds the curve).
    pub fn control_box(&self) -> (DVec2, DVec2) {
        let mut lo = self.points[0];
        let mut hi = self.points[0];
        for p in &self.points[1..] {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        (lo, hi)
    }

    /// The length of the control polygon (an upper bound on the arc length).
    pub fn control_polygon_length(&self) -> f64 {
        self.points.windows(2).map(|w| (w[1] - w[0]).length()).sum()
    }
}

/// `(1 − t) a + t b`, written so that `t = 1/2` gives the rounded midpoint.
#[inline]
pub(crate) fn lerp(a: DVec2, b: DVec2, t: f64) -> DVec2 {
    if t == 0.5 {
        0.5 * (a + b)
    } else {
        a + t * (b - a)
    }
}

/// de Casteljau evaluation of the control points `p` at `t` (any length ≥ 1).
pub(crate) fn de_casteljau(p: &[DVec2], t: f64) -> DVec2 {
    match p.len() {
        0 => DVec2::ZERO,
        1 => p[0],
        2 => lerp(p[0], p[1], t),
        n => {
            let mut buf = [DVec2::ZERO; 16];
            let mut heap;
            let work: &mut [DVec2] = if n <= 16 {
                buf[..n].copy_from_slice(p);
                &mut buf[..n]
            } else {
                heap = p.to_vec();
                &mut heap
            };
            for level in 1..n {
                for i in 0..n - level {
                    work[i] = lerp(work[i], work[i + 1], t);
                }
            }
            work[0]
        }
    }
}

/// The binomial coefficient `C(n, k)` as f64 (exact for the degrees used here).
pub(crate) fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let k = k.min(n - k);
    let mut r = 1.0;
    for i in 0..k {
        r = r * (n - i) as f64 / (i + 1) as f64;
    }
    r.round()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cubic() -> BezierCurve {
        BezierCurve::new(vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(0.3, -0.25),
            DVec2::new(0.7, -0.25),
            DVec2::new(1.0, 0.0),
        ])
    }

    #[test]
    fn halves_reproduce_the_parent() {
        let c = cubic();
        let (l, r) = c.split_half();
        for k in 0..=1000 {
            let t = k as f64 / 1000.0;
            let p = c.eval(t);
            let q = if t <= 0.5 {
                l.eval(2.0 * t)
            } else {
                r.eval(2.0 * t - 1.0)
            };
            assert!((p - q).length() <= 1e-15, "t = {t}");
        }
        assert_eq!(l.end(), r.start());
    }

    #[test]
    fn elevation_keeps_the_curve() {
        let c = cubic();
        let e = c.elevated().elevated();
        for k in 0..=100 {
            let t = k as f64 / 100.0;
            assert!((c.eval(t) - e.eval(t)).length() < 1e-15);
        }
    }

    #[test]
    fn hodograph_matches_differences() {
        let c = cubic();
        for k in 1..100 {
            let t = k as f64 / 100.0;
            let h = 1e-6;
            let fd = (c.eval(t + h) - c.eval(t - h)) / (2.0 * h);
            assert!((fd - c.derivative(t)).length() < 1e-8);
        }
    }

    #[test]
    fn unit_circle_quadrants_area() {
        // Four cubic quarter arcs (k = 0.5523) enclose about π.
        let k = 0.552_284_749_830_793_4;
        let e = [DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y];
        let mut area = 0.0;
        for i in 0..4 {
            let (a, b) = (e[i], e[(i + 1) % 4]);
            let c = BezierCurve::new(vec![a, a + k * a.perp(), b - k * b.perp(), b]);
            area += c.area_term();
        }
        assert!((area - std::f64::consts::PI).abs() < 1e-3, "{area}");
        // A triangle of lines: exact.
        let t = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(0.0, 1.0),
        ];
        let a: f64 = (0..3)
            .map(|i| BezierCurve::line(t[i], t[(i + 1) % 3]).area_term())
            .sum();
        assert_eq!(a, 1.0);
    }
}
