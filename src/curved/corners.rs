//! Small input angles (spec §4.3 "small input angles" \[DESIGN\], Ruppert's practice): a
//! corner of a trim loop whose interior angle, measured in the metric at the corner, is
//! below `small_angle_deg` cannot get well-shaped triangles, so the triangles at it are
//! exempt from the angle bound and reported apart.

use glam::DVec2;

use super::domain::Domain;

/// The interior angle at a loop corner, in degrees, in the metric `m` given by its Cholesky
/// frame: the counter-clockwise angle from the leaving tangent to the reversed arriving one
/// (the region lies on the left of its loops).
pub(crate) fn interior_angle_deg(
    leaving: DVec2,
    arriving: DVec2,
    f: &super::tensor::Frame2,
) -> f64 {
    let a = f.apply(leaving);
    let b = f.apply(-arriving);
    let ang = a.perp_dot(b).atan2(a.dot(b)).to_degrees();
    if ang < 0.0 {
        ang + 360.0
    } else {
        ang
    }
}

/// The small corners of a patch's regions.
#[derive(Debug, Clone, Default)]
pub(crate) struct Corners {
    /// Per vertex: a loop corner with a small interior angle.
    pub at_vertex: Vec<bool>,
    /// `(v, a, b)`: the corner vertex and the input curves meeting there.
    pub pairs: Vec<(u32, u32, u32)>,
}

impl Corners {
    /// Finds the loop corners of `regions` whose interior angle in the metric at the corner
    /// is below `small_angle_deg`.
    pub fn find(d: &Domain, regions: &[u32], small_angle_deg: f64) -> Corners {
        let mut c = Corners {
            at_vertex: vec![false; d.tr.vertex_count()],
            pairs: Vec::new(),
        };
        for &r in regions {
            for lp in &d.input.regions[r as usize].loops {
                let n = lp.uses.len();
                for k in 0..n {
                    let (prev, next) = (lp.uses[(k + n - 1) % n], lp.uses[k]);
                    let at = d.input.use_start(next);
                    let Some(v) = d.vertex_at(at) else { continue };
                    let leaving = d.input.curve_of(next).derivative(0.0);
                    let arriving = d.input.curve_of(prev).derivative(1.0);
                    let Some(f) = d.tr.metric[v as usize].cholesky() else {
                        continue;
                    };
                    if interior_angle_deg(leaving, arriving, &f) < small_angle_deg {
                        c.at_vertex[v as usize] = true;
                        c.pairs.push((v, prev.curve.0, next.curve.0));
                    }
                }
            }
        }
        c
    }

    pub fn is_corner(&self, v: u32) -> bool {
        self.at_vertex.get(v as usize).copied().unwrap_or(false)
    }

    /// Whether curves `a` and `b` meet at a small corner.
    pub fn is_pair(&self, a: u32, b: u32) -> bool {
        self.pairs
            .iter()
            .any(|&(_, x, y)| (x == a && y == b) || (x == b && y == a))
    }

    /// Whether triangle `t` is exempt from the angle bound: it has a small corner as a
    /// vertex, or its shortest edge (in the mean metric) spans the two curves of a small
    /// corner — the wedge's own angle, which no refinement removes (Shewchuk's rule for
    /// Delaunay refinement with small input angles, \[DESIGN\]).
    pub fn exempts(&self, d: &Domain, t: u32) -> bool {
        if self.pairs.is_empty() {
            return false;
        }
        let v = d.tr.tri(t);
        if v.iter().any(|&x| self.is_corner(x)) {
            return true;
        }
        let m = v
            .iter()
            .fold(super::tensor::Metric2::new(0.0, 0.0, 0.0), |acc, &i| {
                acc.add(&d.tr.metric[i as usize])
            });
        let p = v.map(|i| d.tr.pos[i as usize]);
        let k = (0..3)
            .min_by(|&i, &j| {
                m.norm_sq(p[(i + 1) % 3] - p[i])
                    .total_cmp(&m.norm_sq(p[(j + 1) % 3] - p[j]))
            })
            .unwrap_or(0);
        match (d.curve_of_vertex(v[k]), d.curve_of_vertex(v[(k + 1) % 3])) {
            (Some(a), Some(b)) => a != b && self.is_pair(a, b),
            _ => false,
        }
    }

    /// Whether an encroachment of a guard edge of `curve` by vertex `w` is the two sides of
    /// a small corner encroaching each other, which splitting would only repeat forever
    /// (Ruppert's small-angle problem): ignored.
    pub fn protects(&self, d: &Domain, curve: u32, w: u32) -> bool {
        match d.curve_of_vertex(w) {
            Some(b) => b != curve && self.is_pair(curve, b),
            None => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curved::tensor::Metric2;

    #[test]
    fn square_corner_and_its_metric() {
        let f = Metric2::IDENTITY.cholesky().unwrap();
        // Arriving along +x, leaving along +y: 90°.
        assert!((interior_angle_deg(DVec2::Y, DVec2::X, &f) - 90.0).abs() < 1e-12);
        // A reflex corner: arriving along +x, leaving along −y: 270°.
        assert!((interior_angle_deg(-DVec2::Y, DVec2::X, &f) - 270.0).abs() < 1e-12);
        // In a metric 10 × finer across x, a 45° corner between +x and the diagonal shrinks.
        let g = Metric2::new(1.0, 0.0, 100.0).cholesky().unwrap();
        let a = interior_angle_deg(DVec2::new(-1.0, 1.0), DVec2::X, &g);
        assert!(
            (a - (180.0 - 10f64.atan2(-1.0).to_degrees())).abs() < 1e-9,
            "{a}"
        );
    }
}
