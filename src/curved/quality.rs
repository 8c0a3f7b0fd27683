//! Measuring angles "in the metric" (seed 000 §5.1, Tables 1–2; spec §6): per element, in the
//! metric of each vertex (the refinement's bound), over a sampling lattice in parameter
//! space (variant (A)) and on the flat triangle in R³ (variant (B)); and the statistics the
//! seed reports (min, max, mean, median) plus the 1% quantile and the shares below 14.48°,
//! 20° and 20.7°.

use glam::{DVec2, DVec3};

use super::element::{eval_scalar, BezierTriangle};
use super::field::{MetricField, PatchMetric};
use super::output::{ElementKind, ElementQuality};
use super::patch::BezierPatch;
use super::tensor::Metric2;

/// Statistics of a list of angles, in degrees.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AngleStats {
    pub count: u64,
    pub min: f64,
    pub max: f64,
    pub mean: f64,
    pub median: f64,
    /// The 1% quantile.
    pub q01: f64,
    /// Shares (0 to 1) below arcsin(1/4) ≈ 14.4775°, below 20° and below arcsin(1/(2√2)) ≈ 20.705°.
    pub below_14_48: f64,
    pub below_20: f64,
    pub below_20_7: f64,
}

impl AngleStats {
    /// The statistics of `values` (NaNs ignored).
    pub fn of(values: impl IntoIterator<Item = f64>) -> AngleStats {
        let mut v: Vec<f64> = values.into_iter().filter(|x| !x.is_nan()).collect();
        if v.is_empty() {
            return AngleStats::default();
        }
        v.sort_by(f64::total_cmp);
        let n = v.len();
        let quantile = |q: f64| v[((q * (n - 1) as f64).round() as usize).min(n - 1)];
        let median = if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        };
        let share = |x: f64| v.partition_point(|&a| a < x) as f64 / n as f64;
        AngleStats {
            count: n as u64,
            min: v[0],
            max: v[n - 1],
            mean: v.iter().sum::<f64>() / n as f64,
            median,
            q01: quantile(0.01),
            below_14_48: share(0.25f64.asin().to_degrees()),
            below_20: share(20.0),
            below_20_7: share((1.0 / (2.0 * 2f64.sqrt())).asin().to_degrees()),
        }
    }
}

/// The quality of a whole mesh (spec §6 "statistics": straight and curved apart and together).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct QualityReport {
    /// The bound the refinement guarantees on straight, non-exempt elements, arcsin(1/(2B)).
    pub guaranteed_angle_deg: f64,
    /// Per straight, non-exempt element: its smallest angle in its vertices' metrics.
    pub straight_min_vertex: AngleStats,
    /// Every corner angle (centroid metric), as the seed's Tables 1 and 2 pool them:
    /// straight elements, curved elements, all.
    pub straight_angles: AngleStats,
    pub curved_angles: AngleStats,
    pub all_angles: AngleStats,
    /// Per element, smallest angle over the sampling lattice (variant (A)): straight
    /// non-exempt, curved.
    pub straight_min_sampled: AngleStats,
    pub curved_min_sampled: AngleStats,
    /// Per straight element, smallest angle on the flat triangle in R³ (variant (B)), and
    /// every corner angle of all elements in R³.
    pub straight_min_xyz: AngleStats,
    pub all_angles_xyz: AngleStats,
    /// Elements at small input angles (no bound) and their smallest vertex-metric angle.
    pub exempt: AngleStats,
    /// The smallest scaled Jacobian over all elements (> 0: all valid), in parameter space and
    /// on the surface.
    pub min_scaled_jacobian: f64,
    pub min_scaled_jacobian_surface: f64,
}

impl QualityReport {
    pub(crate) fn of(q: &[(ElementKind, bool, ElementQuality)], guaranteed: f64) -> QualityReport {
        let straight = || q.iter().filter(|e| e.0 == ElementKind::Straight && !e.1);
        let curved = || q.iter().filter(|e| e.0 == ElementKind::Curved);
        QualityReport {
            guaranteed_angle_deg: guaranteed,
            straight_min_vertex: AngleStats::of(straight().map(|e| e.2.min_angle_vertex)),
            straight_angles: AngleStats::of(straight().flat_map(|e| e.2.angles)),
            curved_angles: AngleStats::of(curved().flat_map(|e| e.2.angles)),
            all_angles: AngleStats::of(q.iter().flat_map(|e| e.2.angles)),
            straight_min_sampled: AngleStats::of(straight().map(|e| e.2.min_angle_sampled)),
            curved_min_sampled: AngleStats::of(curved().map(|e| e.2.min_angle_sampled)),
            straight_min_xyz: AngleStats::of(straight().map(|e| e.2.min_angle_xyz)),
            all_angles_xyz: AngleStats::of(q.iter().flat_map(|e| e.2.xyz_angles)),
            exempt: AngleStats::of(
                q.iter()
                    .filter(|e| e.0 == ElementKind::Straight && e.1)
                    .map(|e| e.2.min_angle_vertex),
            ),
            min_scaled_jacobian: q
                .iter()
                .map(|e| e.2.scaled_jacobian)
                .fold(f64::INFINITY, f64::min),
            min_scaled_jacobian_surface: q
                .iter()
                .map(|e| e.2.scaled_jacobian_surface)
                .fold(f64::INFINITY, f64::min),
        }
    }
}

/// Everything needed to measure one element.
pub(crate) struct Measure<'a> {
    pub metric: &'a PatchMetric<'a>,
    pub field: &'a MetricField,
    pub patch: &'a BezierPatch,
    pub samples: u32,
    pub sampled: bool,
}

/// The directions along the two edges leaving each corner of an element, in parameter
/// space: `(along edge to the next corner, along edge to the previous corner)`; a curved
/// edge contributes its tangent.
type Corners = [(DVec2, DVec2); 3];

fn straight_corners(p: &[DVec2; 3]) -> Corners {
    [
        (p[1] - p[0], p[2] - p[0]),
        (p[2] - p[1], p[0] - p[1]),
        (p[0] - p[2], p[1] - p[2]),
    ]
}

fn corner_angles_in(c: &Corners, m: &Metric2) -> [f64; 3] {
    c.map(|(a, b)| m.angle(a, b).to_degrees())
}

impl Measure<'_> {
    fn metric_at(&self, x: DVec2, fallback: &Metric2) -> Metric2 {
        self.metric.at(x).unwrap_or(*fallback)
    }

    /// Quality of a straight element with corners `p` and vertex metrics `m`.
    pub fn straight(&self, p: &[DVec2; 3], m: &[Metric2; 3]) -> ElementQuality {
        let corners = straight_corners(p);
        self.measure(
            &corners,
            p,
            m,
            |l| l[0] * p[0] + l[1] * p[1] + l[2] * p[2],
            None,
        )
    }

    /// Quality of a curved element: Bézier triangle `tri` with corners `p` (edge 0→1 curved).
    pub fn curved(&self, tri: &BezierTriangle, p: &[DVec2; 3], m: &[Metric2; 3]) -> ElementQuality {
        let d = tri.degree as usize;
        let edge: Vec<DVec2> = super::element::multi_indices(tri.degree)
            .iter()
            .zip(&tri.points)
            .filter(|(a, _)| a[2] == 0)
            .map(|(_, q)| *q)
            .collect();
        // Edge row in multi_indices order runs from v₀ (i = d) to v₁ (j = d).
        let t0 = d as f64 * (edge[1] - edge[0]);
        let t1 = d as f64 * (edge[d] - edge[d - 1]);
        let corners: Corners = [
            (t0, p[2] - p[0]),
            (p[2] - p[1], -t1),
            (p[0] - p[2], p[1] - p[2]),
        ];
        let jac = scaled_jacobian(tri);
        self.measure(&corners, p, m, |l| tri.eval(l[1], l[2]), Some(jac))
    }

    fn measure(
        &self,
        corners: &Corners,
        p: &[DVec2; 3],
        m: &[Metric2; 3],
        at: impl Fn([f64; 3]) -> DVec2,
        jac: Option<f64>,
    ) -> ElementQuality {
        // The smallest angle has the largest cosine: one arccos for the nine corner angles.
        let max_cos = m
            .iter()
            .flat_map(|mk| {
                corners.map(|(a, b)| mk.dot(a, b) / (mk.norm_sq(a) * mk.norm_sq(b)).sqrt())
            })
            .fold(f64::NEG_INFINITY, f64::max);
        let min_vertex = max_cos.clamp(-1.0, 1.0).acos().to_degrees();
        // Pooled angles: in the mean of the vertex metrics (no field evaluation).
        let mean = m[0].add(&m[1]).add(&m[2]).scale(1.0 / 3.0);
        let angles = corner_angles_in(corners, &mean);
        let (mut smin, mut smax) = (f64::NAN, f64::NAN);
        let (mut xmin, mut xmax) = (f64::NAN, f64::NAN);
        let mut xyz_angles = [f64::NAN; 3];
        if self.sampled {
            let xyz: [DVec3; 3] = p.map(|q| self.patch.eval(q.x, q.y));
            let jacs: [(DVec3, DVec3); 3] = p.map(|q| {
                let s = self.patch.eval_with_derivatives(q.x, q.y);
                (s.du, s.dv)
            });
            // Directions in R³: the edges of the flat triangle, curved edges pushed forward by J.
            let push = |k: usize, w: DVec2| jacs[k].0 * w.x + jacs[k].1 * w.y;
            let flat = [
                (xyz[1] - xyz[0], xyz[2] - xyz[0]),
                (xyz[2] - xyz[1], xyz[0] - xyz[1]),
                (xyz[0] - xyz[2], xyz[1] - xyz[2]),
            ];
            let dirs3: [(DVec3, DVec3); 3] = if jac.is_some() {
                [
                    (push(0, corners[0].0), flat[0].1),
                    (flat[1].0, push(1, corners[1].1)),
                    flat[2],
                ]
            } else {
                flat
            };
            let centroid = at([1.0 / 3.0; 3]);
            let centroid3 = self.patch.eval(centroid.x, centroid.y);
            if let Some(m3) = self.field.real_space(centroid3) {
                xyz_angles = dirs3.map(|(a, b)| m3.angle(a, b).to_degrees());
            }
            let n = self.samples.max(1);
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            let (mut lo3, mut hi3) = (f64::INFINITY, f64::NEG_INFINITY);
            for i in 0..=n {
                for j in 0..=n - i {
                    let l = [
                        (n - i - j) as f64 / n as f64,
                        i as f64 / n as f64,
                        j as f64 / n as f64,
                    ];
                    let x = at(l);
                    let ms = self.metric_at(x, &m[0]);
                    for a in corner_angles_in(corners, &ms) {
                        lo = lo.min(a);
                        hi = hi.max(a);
                    }
                    let x3 = self.patch.eval(x.x, x.y);
                    if let Some(m3) = self.field.real_space(x3) {
                        for (a, b) in dirs3 {
                            let ang = m3.angle(a, b).to_degrees();
                            lo3 = lo3.min(ang);
                            hi3 = hi3.max(ang);
                        }
                    }
                }
            }
            smin = lo;
            smax = hi;
            if lo3.is_finite() {
                xmin = lo3;
                xmax = hi3;
            }
        }
        ElementQuality {
            min_angle_vertex: min_vertex,
            angles,
            min_angle_sampled: smin,
            max_angle_sampled: smax,
            min_angle_xyz: xmin,
            max_angle_xyz: xmax,
            xyz_angles,
            scaled_jacobian: jac.unwrap_or(1.0),
            scaled_jacobian_surface: f64::NAN,
        }
    }
}

/// Smallest over largest `det DF` over a lattice of order `max(2(d − 1) + 2, 8)` (spec §6),
/// evaluated exactly from the Bézier form of `det DF`; > 0 means no sample is folded (the
/// coefficient test in [`BezierTriangle::jacobian_coefficients`] is the proof of validity).
pub(crate) fn scaled_jacobian(tri: &BezierTriangle) -> f64 {
    let coef = tri.jacobian_coefficients();
    let deg = 2 * tri.degree.saturating_sub(1);
    // A denser lattice where the coefficients do not prove the sign (thin elements).
    let n = if coef.iter().all(|&c| c > 0.0) {
        (deg + 2).max(8)
    } else {
        (4 * deg).max(32)
    };
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..=n {
        for j in 0..=n - i {
            let det = eval_scalar(deg, &coef, i as f64 / n as f64, j as f64 / n as f64);
            lo = lo.min(det);
            hi = hi.max(det);
        }
    }
    if hi <= 0.0 {
        return -1.0;
    }
    lo / hi
}
