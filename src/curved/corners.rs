//! Small input angles (spec §4.3 "small input angles" [DESIGN], Ruppert's practice): a
//! corner of a trim loop whose interior angle, measured in the metric at the corner, is
//! below `small_angle_deg` cannot get well-shaped triangles, so the triangles at it are
//! exempt from the angle bound and reported apart.

use glam::DVec2;

use super::domain::Domain;

/// The interior angle at a loop corner, in degrees, in the metric `m` given by its Cholesky
/// frame: the counter-clockwise angle from the leaving tangent to the reversed arriving one
/// (the region lies on the left of its loops).
pub(crate) fn interior_angle_deg(leaving: DVec2, arriving: DVec2, f: &super::tensor::Frame2) -> f64 {
    let a = f.apply(leaving);
    let b = f.apply(-arriving);
    let ang = a.perp_dot(b).atan2(a.dot(b)).to_degrees();
    if ang < 0.0 {
        ang + 360.0
    } else {
        ang
    }
}

/// Per vertex of `d`: whether it is a loop corner with a small interior angle.
pub(crate) fn small_corners(d: &Domain, regions: &[u32], small_angle_deg: f64) -> Vec<bool> {
    let mut out = vec![false; d.tr.vertex_count()];
    for &r in regions {
        for lp in &d.input.regions[r as usize].loops {
            let n = lp.uses.len();
            for k in 0..n {
                let (prev, next) = (lp.uses[(k + n - 1) % n], lp.uses[k]);
                let at = d.input.use_start(next);
                let Some(v) = d.vertex_at(at) else { continue };
                let cn = d.input.curve_of(next);
                let cp = d.input.curve_of(prev);
                let leaving = cn.derivative(0.0);
                let arriving = cp.derivative(1.0);
                let Some(f) = d.tr.metric[v as usize].cholesky() else {
                    continue;
                };
                if interior_angle_deg(leaving, arriving, &f) < small_angle_deg {
                    out[v as usize] = true;
                }
            }
        }
    }
    out
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
        assert!((a - (180.0 - 10f64.atan2(-1.0).to_degrees())).abs() < 1e-9, "{a}");
    }
}
