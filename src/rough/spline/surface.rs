//! Tensor-product B-spline surfaces S(u, v) = Σ_k Σ_l N_k(u) M_l(v) P_kl (seed 003 §4's base
//! surface).

use glam::DVec3;

use super::knots::Knots;
use crate::error::{Error, Result};

/// A tensor-product B-spline surface over [0, 1]²: knots in u and in v, and a control net of
/// `count_u × count_v` points, `P_kl` at index `k · count_v + l`.
///
/// ```
/// use katachi::rough::{BSplineSurface, Knots};
/// use katachi::DVec3;
/// // A bilinear patch: the plane z = 0 over [0, 2] × [0, 3].
/// let (ku, kv) = (Knots::uniform(1, 2).unwrap(), Knots::uniform(1, 2).unwrap());
/// let net = vec![DVec3::ZERO, DVec3::new(0.0, 3.0, 0.0), DVec3::new(2.0, 0.0, 0.0), DVec3::new(2.0, 3.0, 0.0)];
/// let s = BSplineSurface::new(ku, kv, net).unwrap();
/// assert_eq!(s.point(0.5, 0.5), DVec3::new(1.0, 1.5, 0.0));
/// assert_eq!(s.normal(0.5, 0.5), DVec3::Z);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct BSplineSurface {
    knots_u: Knots,
    knots_v: Knots,
    control: Vec<DVec3>,
}

/// A point of a surface with its first and second partial derivatives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    pub point: DVec3,
    pub du: DVec3,
    pub dv: DVec3,
    pub duu: DVec3,
    pub duv: DVec3,
    pub dvv: DVec3,
}

impl BSplineSurface {
    /// A surface from its knots and control net (`knots_u.count() × knots_v.count()` points,
    /// row by row in u).
    pub fn new(knots_u: Knots, knots_v: Knots, control: Vec<DVec3>) -> Result<Self> {
        let want = knots_u.count() * knots_v.count();
        if control.len() != want {
            return Err(Error::InvalidArgument(format!(
                "B-spline surface: {} control points given, the knots need {} × {} = {want}",
                control.len(),
                knots_u.count(),
                knots_v.count()
            )));
        }
        if let Some(i) = control.iter().position(|p| !p.is_finite()) {
            return Err(Error::InvalidArgument(format!(
                "B-spline surface: control point {i} is not finite"
            )));
        }
        Ok(BSplineSurface {
            knots_u,
            knots_v,
            control,
        })
    }

    /// The knots in u.
    pub fn knots_u(&self) -> &Knots {
        &self.knots_u
    }

    /// The knots in v.
    pub fn knots_v(&self) -> &Knots {
        &self.knots_v
    }

    /// The control points, `P_kl` at `k · count_v + l`.
    pub fn control_points(&self) -> &[DVec3] {
        &self.control
    }

    /// The control net's size: (count in u, count in v).
    pub fn net_size(&self) -> (usize, usize) {
        (self.knots_u.count(), self.knots_v.count())
    }

    /// S(u, v); parameters outside [0, 1] are clamped.
    pub fn point(&self, u: f64, v: f64) -> DVec3 {
        self.evaluate(u, v).point
    }

    /// The unit normal S_u × S_v / |S_u × S_v| (zero where the surface is degenerate).
    pub fn normal(&self, u: f64, v: f64) -> DVec3 {
        let e = self.evaluate(u, v);
        e.du.cross(e.dv).normalize_or_zero()
    }

    /// S and its partial derivatives up to the second at (u, v).
    pub fn evaluate(&self, u: f64, v: f64) -> SurfacePoint {
        let bu = self.knots_u.basis(u);
        let bv = self.knots_v.basis(v);
        let (p, q) = (self.knots_u.degree(), self.knots_v.degree());
        let nv = self.knots_v.count();
        let mut out = [DVec3::ZERO; 6];
        for r in 0..=p {
            // Σ_l M_l^(b)(v) P_kl for the row k = first + r, then weighted by N_k^(a)(u).
            let row = (bu.first + r) * nv + bv.first;
            let mut s = [DVec3::ZERO; 3];
            for c in 0..=q {
                let pt = self.control[row + c];
                for (b, sb) in s.iter_mut().enumerate() {
                    *sb += bv.values[b][c] * pt;
                }
            }
            let n = [bu.values[0][r], bu.values[1][r], bu.values[2][r]];
            out[0] += n[0] * s[0];
            out[1] += n[1] * s[0];
            out[2] += n[0] * s[1];
            out[3] += n[2] * s[0];
            out[4] += n[1] * s[1];
            out[5] += n[0] * s[2];
        }
        SurfacePoint {
            point: out[0],
            du: out[1],
            dv: out[2],
            duu: out[3],
            duv: out[4],
            dvv: out[5],
        }
    }
}
