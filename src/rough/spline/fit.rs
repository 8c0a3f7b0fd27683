//! Fitting a B-spline surface to points (seed 003 §4; spec `rough_model.md` §2, after Weiss,
//! Andor, Renner and Várady 2002): least squares with thin-plate smoothing, parameter
//! correction by Newton steps, and knots inserted where the fit is not close enough.

use glam::DVec3;

use super::banded::BandedSpd;
use super::knots::Knots;
use super::surface::BSplineSurface;
use crate::error::{Error, Result, RoughError};

/// Options of [`fit_points`] and [`super::fit_surface`], defaulting to the spec's values.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct FitOptions {
    /// The degree in u and v (spec §2: bicubic). Default value: `3`.
    pub degree: usize,
    /// The control net's initial size (count in u, count in v); spec §2: 8 × 8.
    /// Default value: `(8, 8)`.
    pub net: (usize, usize),
    /// β₀ of the thin-plate term, scale-free: β = β₀ · trace(NᵀN) / trace(E) (spec §2).
    /// `0` fits without smoothing. Default value: `1e-3`.
    pub smoothing: f64,
    /// Rounds of solve → parameter correction (spec §2: until the squared error falls by
    /// less than 1e-4 relatively, at most 10). Default value: `10`.
    pub correction_rounds: usize,
    /// Knots are inserted in spans where a point is farther than this from the surface, until
    /// none is or the net has a third as many points as the data (spec §2's adaptive knot
    /// insertion). `None`: no insertion for [`fit_points`], half the region's mean edge
    /// length for [`super::fit_surface`]. Default value: `None`.
    pub tolerance: Option<f64>,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            degree: 3,
            net: (8, 8),
            smoothing: 1e-3,
            correction_rounds: 10,
            tolerance: None,
        }
    }
}

impl FitOptions {
    /// Checks the values.
    pub fn validate(&self) -> Result<()> {
        let bad =
            |option: &'static str, message: String| Err(Error::InvalidOption { option, message });
        if !(1..=super::knots::MAX_DEGREE).contains(&self.degree) {
            return bad("degree", format!("{} is not in 1..=5", self.degree));
        }
        let (nu, nv) = self.net;
        if nu <= self.degree || nv <= self.degree || nu > 4096 || nv > 4096 {
            return bad(
                "net",
                format!(
                    "{nu} × {nv}: each side needs more points than the degree ({}) and at most 4096",
                    self.degree
                ),
            );
        }
        if !(self.smoothing.is_finite() && self.smoothing >= 0.0) {
            return bad(
                "smoothing",
                format!("{} is not finite and ≥ 0", self.smoothing),
            );
        }
        if self.correction_rounds > 1000 {
            return bad(
                "correction_rounds",
                format!("{} is above 1000", self.correction_rounds),
            );
        }
        if let Some(t) = self.tolerance {
            if !(t.is_finite() && t > 0.0) {
                return bad("tolerance", format!("{t} is not finite and > 0"));
            }
        }
        Ok(())
    }
}

/// A fitted surface, the parameters it gave the points, and how close it is.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceFit {
    pub surface: BSplineSurface,
    /// Per point: its (u, v) after parameter correction.
    pub params: Vec<[f64; 2]>,
    /// Root mean square of |Q_t − S(u_t, v_t)|.
    pub rms: f64,
    /// The largest |Q_t − S(u_t, v_t)|.
    pub max: f64,
    /// The RMS after each solve, in order (the first before any parameter correction).
    pub rms_history: Vec<f64>,
}

/// Fits a B-spline surface to `points` starting from the parameters `params` (in [0, 1]²):
/// minimises Σ|Q_t − S(u_t, v_t)|² + β ∬ |S_uu|² + 2|S_uv|² + |S_vv|² (spec §2), corrects the
/// parameters and solves again, and inserts knots where the tolerance does not hold.
pub fn fit_points(
    points: &[DVec3],
    params: &[[f64; 2]],
    options: &FitOptions,
) -> Result<SurfaceFit> {
    options.validate()?;
    if params.len() != points.len() {
        return Err(Error::InvalidArgument(format!(
            "surface fit: {} points but {} parameter pairs",
            points.len(),
            params.len()
        )));
    }
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(Error::InvalidArgument(format!(
            "surface fit: point {i} is not finite"
        )));
    }
    if let Some(i) = params
        .iter()
        .position(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Err(Error::InvalidArgument(format!(
            "surface fit: parameters of point {i} are not finite"
        )));
    }
    let (nu, nv) = options.net;
    let limit = points.len() / 3;
    if nu * nv > limit {
        return Err(RoughError::RegionTooSmall {
            points: points.len() as u32,
            net_u: nu as u32,
            net_v: nv as u32,
        }
        .into());
    }
    let mut params: Vec<[f64; 2]> = params
        .iter()
        .map(|p| [p[0].clamp(0.0, 1.0), p[1].clamp(0.0, 1.0)])
        .collect();
    let mut ku = Knots::uniform(options.degree, nu)?;
    let mut kv = Knots::uniform(options.degree, nv)?;
    let mut history = Vec::new();
    let mut surface = solve(&ku, &kv, points, &params, options.smoothing)?;
    loop {
        let mut err = squared_error(&surface, points, &params);
        history.push((err / points.len() as f64).sqrt());
        for _ in 0..options.correction_rounds {
            correct_parameters(&surface, points, &mut params);
            surface = solve(&ku, &kv, points, &params, options.smoothing)?;
            let next = squared_error(&surface, points, &params);
            history.push((next / points.len() as f64).sqrt());
            let done = err - next < 1e-4 * err;
            err = next;
            if done {
                break;
            }
        }
        let Some(tol) = options.tolerance else { break };
        // Adaptive knot insertion (spec §2): halve each span holding a point beyond tol.
        let (new_u, new_v) = spans_to_split(&surface, points, &params, tol);
        if new_u.is_empty() && new_v.is_empty() {
            break;
        }
        let (cu, cv) = (ku.count() + new_u.len(), kv.count() + new_v.len());
        if cu * cv > limit {
            break;
        }
        for u in new_u {
            ku = ku.with_knot(u)?;
        }
        for v in new_v {
            kv = kv.with_knot(v)?;
        }
        surface = solve(&ku, &kv, points, &params, options.smoothing)?;
    }
    let (rms, max) = residuals(&surface, points, &params);
    Ok(SurfaceFit {
        surface,
        params,
        rms,
        max,
        rms_history: history,
    })
}

fn residuals(s: &BSplineSurface, points: &[DVec3], params: &[[f64; 2]]) -> (f64, f64) {
    let mut sum = 0.0;
    let mut max = 0.0f64;
    for (q, p) in points.iter().zip(params) {
        let d = s.point(p[0], p[1]).distance(*q);
        sum += d * d;
        max = max.max(d);
    }
    ((sum / points.len().max(1) as f64).sqrt(), max)
}

fn squared_error(s: &BSplineSurface, points: &[DVec3], params: &[[f64; 2]]) -> f64 {
    points
        .iter()
        .zip(params)
        .map(|(q, p)| s.point(p[0], p[1]).distance_squared(*q))
        .sum()
}

/// The midpoints of the spans (in u, in v) that hold a point farther than `tol`.
fn spans_to_split(
    s: &BSplineSurface,
    points: &[DVec3],
    params: &[[f64; 2]],
    tol: f64,
) -> (Vec<f64>, Vec<f64>) {
    let (ku, kv) = (s.knots_u(), s.knots_v());
    let mut bad_u = vec![false; ku.count()];
    let mut bad_v = vec![false; kv.count()];
    for (q, p) in points.iter().zip(params) {
        if s.point(p[0], p[1]).distance(*q) > tol {
            bad_u[ku.span(p[0])] = true;
            bad_v[kv.span(p[1])] = true;
        }
    }
    let mids = |k: &Knots, bad: &[bool]| -> Vec<f64> {
        let t = k.as_slice();
        (0..bad.len())
            .filter(|&i| bad[i] && t[i + 1] - t[i] > 1e-9)
            .map(|i| 0.5 * (t[i] + t[i + 1]))
            .collect()
    };
    (mids(ku, &bad_u), mids(kv, &bad_v))
}

/// Parameter correction (spec §2; Weiss et al. 2002, Hoschek's intrinsic parameterization):
/// Newton steps on ½|S(u, v) − Q|², which solve S_u·(S − Q) = 0, S_v·(S − Q) = 0 (seed 003
/// §4); Gauss–Newton where the Hessian is not positive definite; a step that does not bring
/// the point closer is halved. At most 5 steps, or until the step is below 1e-10.
fn correct_parameters(s: &BSplineSurface, points: &[DVec3], params: &mut [[f64; 2]]) {
    for (q, p) in points.iter().zip(params.iter_mut()) {
        let [mut u, mut v] = *p;
        for _ in 0..5 {
            let e = s.evaluate(u, v);
            let r = e.point - *q;
            let g = [e.du.dot(r), e.dv.dot(r)];
            let gn = [e.du.dot(e.du), e.du.dot(e.dv), e.dv.dot(e.dv)];
            let full = [
                gn[0] + e.duu.dot(r),
                gn[1] + e.duv.dot(r),
                gn[2] + e.dvv.dot(r),
            ];
            let det = |h: [f64; 3]| h[0] * h[2] - h[1] * h[1];
            let h = if full[0] > 0.0 && det(full) > 0.0 {
                full
            } else if gn[0] > 0.0 && det(gn) > 0.0 {
                gn
            } else {
                break;
            };
            let d = det(h);
            let mut du = -(h[2] * g[0] - h[1] * g[1]) / d;
            let mut dv = -(h[0] * g[1] - h[1] * g[0]) / d;
            let before = r.length_squared();
            let mut moved = false;
            for _ in 0..8 {
                let (nu, nv) = ((u + du).clamp(0.0, 1.0), (v + dv).clamp(0.0, 1.0));
                if s.point(nu, nv).distance_squared(*q) <= before {
                    du = nu - u;
                    dv = nv - v;
                    u = nu;
                    v = nv;
                    moved = true;
                    break;
                }
                du *= 0.5;
                dv *= 0.5;
            }
            if !moved || du.hypot(dv) < 1e-10 {
                break;
            }
        }
        *p = [u, v];
    }
}

/// Solves (NᵀN + β E) P = NᵀQ for the control net (spec §2), x, y and z at once.
fn solve(
    ku: &Knots,
    kv: &Knots,
    points: &[DVec3],
    params: &[[f64; 2]],
    smoothing: f64,
) -> Result<BSplineSurface> {
    let (p, q) = (ku.degree(), kv.degree());
    let (nu, nv) = (ku.count(), kv.count());
    let n = nu * nv;
    // Unknown (k, l) is k·nv + l: two basis functions overlap only when |k − k'| ≤ p and
    // |l − l'| ≤ q, so the matrix is banded with half-bandwidth p·nv + q.
    let band = p * nv + q;
    let mut a = BandedSpd::new(n, band);
    let mut rhs = vec![DVec3::ZERO; n];
    let mut idx = Vec::with_capacity((p + 1) * (q + 1));
    let mut w = Vec::with_capacity((p + 1) * (q + 1));
    for (pt, uv) in points.iter().zip(params) {
        let bu = ku.basis(uv[0]);
        let bv = kv.basis(uv[1]);
        idx.clear();
        w.clear();
        for r in 0..=p {
            for c in 0..=q {
                idx.push((bu.first + r) * nv + bv.first + c);
                w.push(bu.values[0][r] * bv.values[0][c]);
            }
        }
        for i in 0..idx.len() {
            rhs[idx[i]] += w[i] * *pt;
            for j in 0..idx.len() {
                if idx[j] <= idx[i] {
                    a.add(idx[i], idx[j], w[i] * w[j]);
                }
            }
        }
    }
    if smoothing > 0.0 {
        // E = G_u^(2,2) ⊗ G_v^(0,0) + 2 G_u^(1,1) ⊗ G_v^(1,1) + G_u^(0,0) ⊗ G_v^(2,2).
        let gu = Gram::new(ku);
        let gv = Gram::new(kv);
        let e = |k: usize, l: usize, k2: usize, l2: usize| {
            gu.get(2, k, k2) * gv.get(0, l, l2)
                + 2.0 * gu.get(1, k, k2) * gv.get(1, l, l2)
                + gu.get(0, k, k2) * gv.get(2, l, l2)
        };
        let trace_n = (0..n).map(|i| a.get(i, i)).sum::<f64>();
        let trace_e = (0..nu)
            .flat_map(|k| (0..nv).map(move |l| (k, l)))
            .map(|(k, l)| e(k, l, k, l))
            .sum::<f64>();
        let beta = if trace_e > 0.0 {
            smoothing * trace_n / trace_e
        } else {
            0.0
        };
        for k in 0..nu {
            for l in 0..nv {
                let i = k * nv + l;
                for k2 in k.saturating_sub(p)..=k {
                    for l2 in l.saturating_sub(q)..(l + q + 1).min(nv) {
                        let j = k2 * nv + l2;
                        if j <= i {
                            a.add(i, j, beta * e(k, l, k2, l2));
                        }
                    }
                }
            }
        }
    }
    a.factor().map_err(|i| {
        Error::from(RoughError::FitSingular {
            control_u: (i / nv) as u32,
            control_v: (i % nv) as u32,
        })
    })?;
    let control = a.solve(rhs);
    BSplineSurface::new(ku.clone(), kv.clone(), control)
}

/// The Gram matrices ∫₀¹ N_k^(a) N_k'^(a) du for a = 0, 1, 2, exact by Gauss–Legendre with
/// degree + 1 points per knot span (spec §2); banded, entry (k, k') at `k · (2p + 1) + k' − k + p`.
struct Gram {
    p: usize,
    g: [Vec<f64>; 3],
}

impl Gram {
    fn new(k: &Knots) -> Gram {
        let (p, n) = (k.degree(), k.count());
        let width = 2 * p + 1;
        let mut g = [
            vec![0.0; n * width],
            vec![0.0; n * width],
            vec![0.0; n * width],
        ];
        let (nodes, weights) = gauss_legendre(p + 1);
        for (a, b) in k.spans() {
            if b <= a {
                continue;
            }
            let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
            for (x, wx) in nodes.iter().zip(&weights) {
                let basis = k.basis(mid + half * x);
                for (d, gd) in g.iter_mut().enumerate() {
                    for r in 0..=p {
                        for s in 0..=p {
                            // k = first + r, k' = first + s: offset k' − k + p = s − r + p.
                            gd[(basis.first + r) * width + s + p - r] +=
                                half * wx * basis.values[d][r] * basis.values[d][s];
                        }
                    }
                }
            }
        }
        Gram { p, g }
    }

    /// Entry (k, k') of the matrix of derivative order `d` (zero outside the band).
    fn get(&self, d: usize, k: usize, k2: usize) -> f64 {
        if k.abs_diff(k2) > self.p {
            return 0.0;
        }
        self.g[d][k * (2 * self.p + 1) + k2 + self.p - k]
    }
}

/// Gauss–Legendre nodes and weights on [−1, 1], by Newton's method on P_n.
fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = Vec::with_capacity(n);
    let mut weights = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_n(x) and P_n'(x) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let pk = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = pk;
            }
            let pn = if n == 0 { 1.0 } else { p1 };
            let pn1 = if n == 1 { 1.0 } else { p0 };
            dp = n as f64 * (x * pn - pn1) / (x * x - 1.0);
            let step = pn / dp;
            x -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        nodes.push(x);
        weights.push(2.0 / ((1.0 - x * x) * dp * dp));
    }
    (nodes, weights)
}
