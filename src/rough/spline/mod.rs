//! B-spline base surfaces (seed 003 §4): knots and basis functions, tensor-product surfaces,
//! and their fitting to a region of a mesh.

mod banded;
mod fit;
mod knots;
mod surface;

pub use fit::{fit_points, FitOptions, SurfaceFit};
pub use knots::Knots;
pub use surface::{BSplineSurface, SurfacePoint};

use glam::DVec3;

use crate::error::{Result, RoughError};
use crate::mesh::{FaceId, PolyMesh, VertexId};

/// Fits the base surface to the vertices of `region` (seed 003 §4: the points Q_t around a
/// feature): parameters from the region's least-squares plane (spec §2: PCA, the bounding
/// rectangle with a 5 % margin mapped to [0, 1]²), then [`fit_points`]; the tolerance for
/// knot insertion defaults to half the region's mean edge length.
///
/// Errors: a face index out of range, a region whose projection onto its plane folds
/// ([`RoughError::RegionFolds`]: the mean-value parameterization the spec falls back to is not
/// written yet), a region too small for the net, a singular fit.
pub fn fit_surface(mesh: &PolyMesh, region: &[FaceId], options: &FitOptions) -> Result<SurfaceFit> {
    options.validate()?;
    let nf = mesh.face_count();
    let mut used = vec![false; mesh.vertex_count() as usize];
    let mut edge_sum = 0.0;
    let mut edge_count = 0usize;
    for &f in region {
        if f.0 >= nf {
            return Err(RoughError::FaceOutOfRange {
                what: "region",
                face: f.0,
                face_count: nf,
            }
            .into());
        }
        for l in mesh.face_loops(f) {
            let lp = mesh.loop_vertices(l);
            for (i, &v) in lp.iter().enumerate() {
                used[v.idx()] = true;
                edge_sum += mesh
                    .position(v)
                    .distance(mesh.position(lp[(i + 1) % lp.len()]));
                edge_count += 1;
            }
        }
    }
    let vertices: Vec<VertexId> = (0..used.len() as u32)
        .filter(|&v| used[v as usize])
        .map(VertexId)
        .collect();
    if vertices.is_empty() {
        return Err(RoughError::RegionTooSmall {
            points: 0,
            net_u: options.net.0 as u32,
            net_v: options.net.1 as u32,
        }
        .into());
    }
    let points: Vec<DVec3> = vertices.iter().map(|&v| mesh.position(v)).collect();
    let frame = PlaneFrame::fit(&points);
    // The region must be a height field over the plane: no face flips in projection.
    let mut orientation = 0.0f64;
    let extent = points
        .iter()
        .map(|p| p.distance(frame.origin))
        .fold(0.0, f64::max);
    let flat = 1e-12 * extent * extent;
    for &f in region {
        let lp = mesh.face_outer(f);
        let mut area = 0.0;
        for (i, &a) in lp.iter().enumerate() {
            let (pa, pb) = (
                frame.project(mesh.position(a)),
                frame.project(mesh.position(lp[(i + 1) % lp.len()])),
            );
            area += pa[0] * pb[1] - pa[1] * pb[0];
        }
        // Faces seen edge-on (|area| at rounding level) decide nothing.
        if area.abs() <= flat {
            continue;
        }
        if orientation == 0.0 {
            orientation = area.signum();
        } else if area * orientation < 0.0 {
            return Err(RoughError::RegionFolds { face: f.0 }.into());
        }
    }
    let params = frame.parameters(&points);
    let mut options = options.clone();
    if options.tolerance.is_none() && edge_count > 0 {
        options.tolerance = Some(0.5 * edge_sum / edge_count as f64);
    }
    fit_points(&points, &params, &options)
}

/// The least-squares plane of points: centroid and principal axes (largest two in the plane).
struct PlaneFrame {
    origin: DVec3,
    axes: [DVec3; 2],
}

impl PlaneFrame {
    fn fit(points: &[DVec3]) -> PlaneFrame {
        let c = points.iter().copied().sum::<DVec3>() / points.len() as f64;
        let mut m = [[0.0f64; 3]; 3];
        for p in points {
            let d = *p - c;
            let d = [d.x, d.y, d.z];
            for i in 0..3 {
                for j in 0..3 {
                    m[i][j] += d[i] * d[j];
                }
            }
        }
        let (values, vectors) = symmetric_eigen(m);
        // Descending eigenvalues: the first two span the plane.
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| values[b].total_cmp(&values[a]));
        let axis = |k: usize| DVec3::new(vectors[0][k], vectors[1][k], vectors[2][k]);
        PlaneFrame {
            origin: c,
            axes: [axis(order[0]), axis(order[1])],
        }
    }

    fn project(&self, p: DVec3) -> [f64; 2] {
        let d = p - self.origin;
        [d.dot(self.axes[0]), d.dot(self.axes[1])]
    }

    /// The points' projections, their bounding rectangle grown by 5 % on each side mapped to
    /// [0, 1]² (spec §2).
    fn parameters(&self, points: &[DVec3]) -> Vec<[f64; 2]> {
        let proj: Vec<[f64; 2]> = points.iter().map(|&p| self.project(p)).collect();
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in &proj {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let mut scale = [0.0; 2];
        for k in 0..2 {
            let w = (hi[k] - lo[k]).max(f64::MIN_POSITIVE);
            lo[k] -= 0.05 * w;
            scale[k] = 1.0 / (1.1 * w);
        }
        proj.iter()
            .map(|p| [(p[0] - lo[0]) * scale[0], (p[1] - lo[1]) * scale[1]])
            .collect()
    }
}

/// Eigenvalues and eigenvectors (columns) of a symmetric 3 × 3 matrix by cyclic Jacobi
/// rotations.
#[allow(clippy::needless_range_loop)] // index form: the rotation as written
fn symmetric_eigen(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..64 {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        let diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if off <= 1e-30 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A ← Jᵀ A J with J the rotation in the (p, q) plane.
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}
