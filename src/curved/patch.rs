//! Tensor-product Bézier patches of any bidegree (seed 000 §3.2, Step 1: "Bézier surfaces
//! as the parametric surface"; spec §1.1).

use glam::DVec3;

/// `P(u, v) = Σᵢ Σⱼ Bᵢᵐ(u) Bⱼⁿ(v) Qᵢⱼ` over the parameter square `[0, 1]²`.
///
/// Control points are stored `u`-major: `Qᵢⱼ` is `points[i * (n + 1) + j]`, `i ≤ m` along
/// `u`, `j ≤ n` along `v` ((m + 1)(n + 1) points).
#[derive(Debug, Clone, PartialEq)]
pub struct BezierPatch {
    degree_u: usize,
    degree_v: usize,
    points: Vec<DVec3>,
}

/// A point of a patch with its first partial derivatives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// `P(u, v)`.
    pub position: DVec3,
    /// `∂P/∂u`.
    pub du: DVec3,
    /// `∂P/∂v`.
    pub dv: DVec3,
}

impl BezierPatch {
    /// A patch of bidegree `(degree_u, degree_v)`; [`super::validate`] checks that
    /// `points.len() == (degree_u + 1)(degree_v + 1)`, the degrees are ≥ 1 and every point is finite.
    pub fn new(degree_u: usize, degree_v: usize, points: Vec<DVec3>) -> BezierPatch {
        BezierPatch {
            degree_u,
            degree_v,
            points,
        }
    }

    /// The bilinear patch through four corners `P(0,0), P(1,0), P(0,1), P(1,1)`.
    pub fn bilinear(p00: DVec3, p10: DVec3, p01: DVec3, p11: DVec3) -> BezierPatch {
        BezierPatch::new(1, 1, vec![p00, p01, p10, p11])
    }

    /// `(m, n)`.
    pub fn degrees(&self) -> (usize, usize) {
        (self.degree_u, self.degree_v)
    }

    /// The control points, `u`-major.
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// `P(u, v)`.
    pub fn eval(&self, u: f64, v: f64) -> DVec3 {
        self.eval_with_derivatives(u, v).position
    }

    /// `P`, `P_u` and `P_v` at `(u, v)` (spec §1.1: the partials are Bézier patches of one
    /// degree less in their direction, evaluated here through the Bernstein derivatives).
    pub fn eval_with_derivatives(&self, u: f64, v: f64) -> SurfacePoint {
        let (m, n) = (self.degree_u, self.degree_v);
        let mut bu = [0.0; 32];
        let mut du = [0.0; 32];
        let mut bv = [0.0; 32];
        let mut dv = [0.0; 32];
        let (mut hu, mut hdu, mut hv, mut hdv);
        let (bu, du): (&mut [f64], &mut [f64]) = if m < 32 {
            (&mut bu[..=m], &mut du[..=m])
        } else {
            hu = vec![0.0; m + 1];
            hdu = vec![0.0; m + 1];
            (&mut hu, &mut hdu)
        };
        let (bv, dv): (&mut [f64], &mut [f64]) = if n < 32 {
            (&mut bv[..=n], &mut dv[..=n])
        } else {
            hv = vec![0.0; n + 1];
            hdv = vec![0.0; n + 1];
            (&mut hv, &mut hdv)
        };
        bernstein_with_derivative(m, u, bu, du);
        bernstein_with_derivative(n, v, bv, dv);
        let mut p = DVec3::ZERO;
        let mut pu = DVec3::ZERO;
        let mut pv = DVec3::ZERO;
        for i in 0..=m {
            let row = &self.points[i * (n + 1)..(i + 1) * (n + 1)];
            let mut r = DVec3::ZERO;
            let mut rv = DVec3::ZERO;
            for j in 0..=n {
                r += bv[j] * row[j];
                rv += dv[j] * row[j];
            }
            p += bu[i] * r;
            pu += du[i] * r;
            pv += bu[i] * rv;
        }
        SurfacePoint {
            position: p,
            du: pu,
            dv: pv,
        }
    }

    /// The diagonal of the control points' bounding box (a length scale for tolerances).
    pub fn scale(&self) -> f64 {
        let mut lo = self.points[0];
        let mut hi = self.points[0];
        for p in &self.points {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        (hi - lo).length()
    }
}

/// The Bernstein polynomials `Bᵢᵈ(t)` and their derivatives, `i = 0..=d`, into `b` and `db`
/// (each of length `d + 1`), by the triangular recurrence `Bᵢᵏ = (1−t) Bᵢᵏ⁻¹ + t Bᵢ₋₁ᵏ⁻¹`.
pub(crate) fn bernstein_with_derivative(d: usize, t: f64, b: &mut [f64], db: &mut [f64]) {
    let s = 1.0 - t;
    b.iter_mut().for_each(|x| *x = 0.0);
    b[0] = 1.0;
    for k in 1..=d {
        if k == d {
            // Bᵢ'(t) = d (Bᵢ₋₁ᵈ⁻¹ − Bᵢᵈ⁻¹), from the degree d − 1 values held in b now.
            for i in 0..=d {
                let lo = if i > 0 { b[i - 1] } else { 0.0 };
                let hi = if i < d { b[i] } else { 0.0 };
                db[i] = d as f64 * (lo - hi);
            }
        }
        let mut prev = 0.0;
        for bi in b.iter_mut().take(k + 1) {
            let cur = *bi;
            *bi = s * cur + t * prev;
            prev = cur;
        }
    }
    if d == 0 {
        db[0] = 0.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn saddle() -> BezierPatch {
        let mut pts = Vec::new();
        for i in 0..=3 {
            for j in 0..=2 {
                let (u, v) = (i as f64 / 3.0, j as f64 / 2.0);
                pts.push(DVec3::new(u, v, ((i * 7 + j * 3) % 5) as f64 * 0.1));
            }
        }
        BezierPatch::new(3, 2, pts)
    }

    #[test]
    fn bernstein_sums_to_one() {
        for d in 1..8 {
            let mut b = vec![0.0; d + 1];
            let mut db = vec![0.0; d + 1];
            bernstein_with_derivative(d, 0.37, &mut b, &mut db);
            assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            assert!(db.iter().sum::<f64>().abs() < 1e-13);
        }
    }

    #[test]
    fn corners_interpolate() {
        let p = saddle();
        assert_eq!(p.eval(0.0, 0.0), p.points()[0]);
        assert_eq!(p.eval(1.0, 1.0), *p.points().last().unwrap());
        assert_eq!(p.eval(1.0, 0.0), p.points()[3 * 3]);
    }

    #[test]
    fn partials_match_central_differences() {
        let p = saddle();
        for &(u, v) in &[(0.2, 0.7), (0.5, 0.5), (0.9, 0.1)] {
            let s = p.eval_with_derivatives(u, v);
            let h = 1e-6;
            let fu = (p.eval(u + h, v) - p.eval(u - h, v)) / (2.0 * h);
            let fv = (p.eval(u, v + h) - p.eval(u, v - h)) / (2.0 * h);
            assert!((fu - s.du).length() < 1e-8 && (fv - s.dv).length() < 1e-8);
        }
    }
}
