//! Metric fields (seed 000 §3.1: "a tensor field given in real space"), and their pull-back
//! to a patch's parameter square (seed 000 §3.3 and §4 Step 1; spec §2).

use std::fmt;
use std::sync::Arc;

use glam::{DVec2, DVec3};

use super::error::CurvedError;
use super::patch::BezierPatch;
use super::tensor::{Metric2, Metric3};

/// A size in real space at every point (the isotropic metric `I / h²`).
#[derive(Clone)]
pub enum SizeField {
    /// The same size everywhere.
    Constant(f64),
    /// Sizes sampled on a regular grid, interpolated trilinearly.
    Grid(Grid3<f64>),
    /// Any function of the real-space point (Rust callers only).
    Function(Arc<dyn Fn(DVec3) -> f64 + Send + Sync>),
}

/// The metric the mesh should follow. Real-space fields are pulled back to each patch's
/// parameter square; parameter-space fields are used as they are.
#[derive(Clone)]
pub enum MetricField {
    /// One tensor everywhere in real space.
    Constant(Metric3),
    /// An isotropic size field in real space, `M = I / h(X)²`.
    Isotropic(SizeField),
    /// Real-space tensors sampled on a regular grid, interpolated trilinearly entry by entry
    /// (a convex combination of positive-definite matrices is positive definite).
    Grid(Grid3<Metric3>),
    /// Any function of the real-space point (Rust callers only).
    Function(Arc<dyn Fn(DVec3) -> Metric3 + Send + Sync>),
    /// Parameter-space tensors sampled on a regular grid over the parameter square,
    /// interpolated bilinearly; no pull-back.
    ParameterGrid(Grid2<Metric2>),
    /// Any function of the parameter point, in parameter space (Rust callers only).
    ParameterFunction(Arc<dyn Fn(DVec2) -> Metric2 + Send + Sync>),
}

impl MetricField {
    /// Size `h` everywhere, in real space.
    pub fn isotropic(h: f64) -> MetricField {
        MetricField::Isotropic(SizeField::Constant(h))
    }

    /// The real-space tensor at `x`, or `None` for parameter-space fields (or a value that is
    /// not a metric).
    pub fn real_space(&self, x: DVec3) -> Option<Metric3> {
        let m = match self {
            MetricField::Constant(m) => *m,
            MetricField::Isotropic(SizeField::Constant(h)) => Metric3::isotropic(*h),
            MetricField::Isotropic(SizeField::Grid(g)) => Metric3::isotropic(g.sample(x)),
            MetricField::Isotropic(SizeField::Function(f)) => Metric3::isotropic(f(x)),
            MetricField::Grid(g) => g.sample(x),
            MetricField::Function(f) => f(x),
            MetricField::ParameterGrid(_) | MetricField::ParameterFunction(_) => return None,
        };
        m.is_positive_definite().then_some(m)
    }

    /// Whether the field is given in parameter space (no pull-back).
    pub fn is_parameter_space(&self) -> bool {
        matches!(
            self,
            MetricField::ParameterGrid(_) | MetricField::ParameterFunction(_)
        )
    }
}

impl fmt::Debug for SizeField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SizeField::Constant(h) => write!(f, "SizeField::Constant({h})"),
            SizeField::Grid(g) => write!(f, "SizeField::Grid({:?} samples)", g.counts),
            SizeField::Function(_) => f.write_str("SizeField::Function(..)"),
        }
    }
}

impl fmt::Debug for MetricField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MetricField::Constant(m) => write!(f, "MetricField::Constant({m:?})"),
            MetricField::Isotropic(s) => write!(f, "MetricField::Isotropic({s:?})"),
            MetricField::Grid(g) => write!(f, "MetricField::Grid({:?} samples)", g.counts),
            MetricField::Function(_) => f.write_str("MetricField::Function(..)"),
            MetricField::ParameterGrid(g) => {
                write!(f, "MetricField::ParameterGrid({:?} samples)", g.counts)
            }
            MetricField::ParameterFunction(_) => f.write_str("MetricField::ParameterFunction(..)"),
        }
    }
}

/// Values on a regular `nx × ny × nz` grid over the box `[min, max]`, `x` fastest:
/// sample `(i, j, k)` is `values[i + nx (j + ny k)]`. Points outside the box take the value
/// at the nearest point of the box.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid3<T> {
    pub min: DVec3,
    pub max: DVec3,
    pub counts: [u32; 3],
    pub values: Vec<T>,
}

/// Values on a regular `nu × nv` grid over the box `[min, max]` of the parameter plane,
/// `u` fastest; points outside take the nearest point's value.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid2<T> {
    pub min: DVec2,
    pub max: DVec2,
    pub counts: [u32; 2],
    pub values: Vec<T>,
}

/// Linear interpolation weights along one axis: the lower sample index and the weight of
/// the upper one.
fn axis(x: f64, lo: f64, hi: f64, n: u32) -> (usize, f64) {
    if n <= 1 || hi <= lo {
        return (0, 0.0);
    }
    let s = ((x - lo) / (hi - lo)).clamp(0.0, 1.0) * (n - 1) as f64;
    let i = (s.floor() as usize).min(n as usize - 2);
    (i, s - i as f64)
}

/// Entry-wise linear combination for the sample types.
pub trait Blend: Copy {
    fn blend(items: &[(f64, Self)]) -> Self;
}

impl Blend for f64 {
    fn blend(items: &[(f64, f64)]) -> f64 {
        items.iter().map(|(w, x)| w * x).sum()
    }
}

impl Blend for Metric3 {
    fn blend(items: &[(f64, Metric3)]) -> Metric3 {
        Metric3::weighted_sum(items)
    }
}

impl Blend for Metric2 {
    fn blend(items: &[(f64, Metric2)]) -> Metric2 {
        let mut m = Metric2::new(0.0, 0.0, 0.0);
        for (w, x) in items {
            m = m.add(&x.scale(*w));
        }
        m
    }
}

impl<T: Blend> Grid3<T> {
    /// The trilinear interpolant at `p`.
    pub fn sample(&self, p: DVec3) -> T {
        let [nx, ny, nz] = self.counts;
        let (i, fx) = axis(p.x, self.min.x, self.max.x, nx);
        let (j, fy) = axis(p.y, self.min.y, self.max.y, ny);
        let (k, fz) = axis(p.z, self.min.z, self.max.z, nz);
        let (nx, ny) = (nx as usize, ny as usize);
        let at = |a: usize, b: usize, c: usize| self.values[a + nx * (b + ny * c)];
        let (i1, j1, k1) = (
            (i + 1).min(nx - 1),
            (j + 1).min(ny - 1),
            (k + 1).min(self.counts[2] as usize - 1),
        );
        let items = [
            ((1.0 - fx) * (1.0 - fy) * (1.0 - fz), at(i, j, k)),
            (fx * (1.0 - fy) * (1.0 - fz), at(i1, j, k)),
            ((1.0 - fx) * fy * (1.0 - fz), at(i, j1, k)),
            (fx * fy * (1.0 - fz), at(i1, j1, k)),
            ((1.0 - fx) * (1.0 - fy) * fz, at(i, j, k1)),
            (fx * (1.0 - fy) * fz, at(i1, j, k1)),
            ((1.0 - fx) * fy * fz, at(i, j1, k1)),
            (fx * fy * fz, at(i1, j1, k1)),
        ];
        T::blend(&items)
    }
}

impl<T: Blend> Grid2<T> {
    /// The bilinear interpolant at `p`.
    pub fn sample(&self, p: DVec2) -> T {
        let [nu, nv] = self.counts;
        let (i, fu) = axis(p.x, self.min.x, self.max.x, nu);
        let (j, fv) = axis(p.y, self.min.y, self.max.y, nv);
        let nu = nu as usize;
        let at = |a: usize, b: usize| self.values[a + nu * b];
        let (i1, j1) = (
            (i + 1).min(nu - 1),
            (j + 1).min(self.counts[1] as usize - 1),
        );
        T::blend(&[
            ((1.0 - fu) * (1.0 - fv), at(i, j)),
            (fu * (1.0 - fv), at(i1, j)),
            ((1.0 - fu) * fv, at(i, j1)),
            (fu * fv, at(i1, j1)),
        ])
    }
}

/// The clamp applied to every pulled-back metric (spec §2, \[DESIGN\]): eigenvalues within
/// `[1/max_size², 1/min_size²]` (sizes in parameter units) and anisotropy at most
/// `max_anisotropy`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MetricClamp {
    pub min_size: f64,
    pub max_size: f64,
    pub max_anisotropy: f64,
}

/// A metric field bound to one patch: the parameter-space metric at any `(u, v)`.
pub(crate) struct PatchMetric<'a> {
    pub field: &'a MetricField,
    pub patch: &'a BezierPatch,
    pub patch_id: u32,
    pub clamp: MetricClamp,
    /// `|P_u × P_v|` at or below this is a degenerate surface point (spec §1.4 (d)).
    regular_eps: f64,
}

impl<'a> PatchMetric<'a> {
    pub fn new(
        field: &'a MetricField,
        patch: &'a BezierPatch,
        patch_id: u32,
        clamp: MetricClamp,
    ) -> Self {
        let s = patch.scale();
        PatchMetric {
            field,
            patch,
            patch_id,
            clamp,
            regular_eps: 1e-10 * s * s,
        }
    }

    /// `M_uv(u, v) = Jᵀ M₃(P(u, v)) J`, `J = [P_u | P_v]` (spec §2), clamped; or the
    /// parameter-space field's value. Fails on a degenerate surface point (spec §1.4 (d)) or
    /// a field value that is not a metric.
    pub fn at(&self, uv: DVec2) -> Result<Metric2, CurvedError> {
        let s = self.patch.eval_with_derivatives(uv.x, uv.y);
        let n = s.du.cross(s.dv).length();
        if n.is_nan() || n <= self.regular_eps {
            return Err(CurvedError::DegenerateSurface {
                patch: self.patch_id,
                u: uv.x,
                v: uv.y,
            });
        }
        let m = match self.field {
            MetricField::Constant(m) => m.pull_back(s.du, s.dv),
            MetricField::Isotropic(size) => {
                let h = match size {
                    SizeField::Constant(h) => *h,
                    SizeField::Grid(g) => g.sample(s.position),
                    SizeField::Function(f) => f(s.position),
                };
                if !(h.is_finite() && h > 0.0) {
                    return Err(CurvedError::InvalidMetric {
                        at: format!("(u, v) = ({}, {})", uv.x, uv.y),
                        reason: format!("the size is {h}, not a positive number"),
                    });
                }
                Metric3::isotropic(h).pull_back(s.du, s.dv)
            }
            MetricField::Grid(g) => check3(g.sample(s.position), uv)?.pull_back(s.du, s.dv),
            MetricField::Function(f) => check3(f(s.position), uv)?.pull_back(s.du, s.dv),
            MetricField::ParameterGrid(g) => g.sample(uv),
            MetricField::ParameterFunction(f) => f(uv),
        };
        if !m.is_positive_definite() {
            return Err(CurvedError::InvalidMetric {
                at: format!("(u, v) = ({}, {})", uv.x, uv.y),
                reason: format!(
                    "the parameter-space metric [[{}, {}], [{}, {}]] is not positive definite",
                    m.xx, m.xy, m.xy, m.yy
                ),
            });
        }
        let c = self.clamp;
        Ok(m.clamped(
            1.0 / (c.max_size * c.max_size),
            1.0 / (c.min_size * c.min_size),
            c.max_anisotropy,
        ))
    }
}

fn check3(m: Metric3, uv: DVec2) -> Result<Metric3, CurvedError> {
    if m.is_positive_definite() {
        Ok(m)
    } else {
        Err(CurvedError::InvalidMetric {
            at: format!("(u, v) = ({}, {})", uv.x, uv.y),
            reason: format!(
                "the tensor {:?} is not symmetric positive definite",
                m.to_array()
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trilinear_reproduces_linear_functions() {
        let mut values = Vec::new();
        for k in 0..3 {
            for j in 0..4 {
                for i in 0..5 {
                    values.push(1.0 + 0.5 * i as f64 + 0.25 * j as f64 - 0.125 * k as f64);
                }
            }
        }
        let g = Grid3 {
            min: DVec3::ZERO,
            max: DVec3::new(4.0, 3.0, 2.0),
            counts: [5, 4, 3],
            values,
        };
        let p = DVec3::new(1.3, 2.2, 0.7);
        assert!((g.sample(p) - (1.0 + 0.5 * 1.3 + 0.25 * 2.2 - 0.125 * 0.7)).abs() < 1e-14);
        // Outside: the nearest point of the box.
        assert!((g.sample(DVec3::new(-1.0, 0.0, 0.0)) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn cylinder_first_fundamental_form() {
        // A quarter cylinder of radius 2 as a rational-free approximation is not exact, so
        // use a plane tilted in 3D: P = (u, v, u), E = 2, F = 0, G = 1.
        let patch = BezierPatch::bilinear(
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 1.0),
        );
        let field = MetricField::isotropic(0.5);
        let pm = PatchMetric::new(
            &field,
            &patch,
            0,
            MetricClamp {
                min_size: 1e-9,
                max_size: 10.0,
                max_anisotropy: 1e3,
            },
        );
        let m = pm.at(DVec2::new(0.3, 0.6)).unwrap();
        assert!((m.xx - 8.0).abs() < 1e-12 && m.xy.abs() < 1e-12 && (m.yy - 4.0).abs() < 1e-12);
    }
}
