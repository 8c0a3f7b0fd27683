//! Angles of a triangle measured in a metric (seed 000 §3.1's angle formula).

use glam::DVec2;

use super::tensor::Metric2;

/// The three corner angles of triangle `p` measured in `m`, in radians (they sum to π).
#[cfg(test)]
pub(crate) fn corner_angles(p: &[DVec2; 3], m: &Metric2) -> [f64; 3] {
    [
        m.angle(p[1] - p[0], p[2] - p[0]),
        m.angle(p[2] - p[1], p[0] - p[1]),
        m.angle(p[0] - p[2], p[1] - p[2]),
    ]
}

/// Whether every corner angle of `p` in `m` is at least the angle whose cosine is `cos_min`
/// (`cos_min > 0`), without inverse trigonometry: the angle at a corner between edge vectors
/// `u`, `w` is below θ exactly when `uᵀMw > cos θ · |u|_M |w|_M`.
#[inline]
pub(crate) fn angles_at_least(p: &[DVec2; 3], m: &Metric2, cos_min: f64) -> bool {
    let e0 = p[1] - p[0];
    let e1 = p[2] - p[1];
    let e2 = p[0] - p[2];
    let (g00, g11, g22) = (m.norm_sq(e0), m.norm_sq(e1), m.norm_sq(e2));
    let c2 = cos_min * cos_min;
    // Corner 0 between e0 and −e2, corner 1 between e1 and −e0, corner 2 between e2 and −e1.
    for (dot, na, nb) in [
        (-m.dot(e0, e2), g00, g22),
        (-m.dot(e1, e0), g11, g00),
        (-m.dot(e2, e1), g22, g11),
    ] {
        if dot > 0.0 && dot * dot > c2 * na * nb {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equilateral_in_its_metric() {
        // An equilateral triangle squashed by 10 along y is equilateral in diag(1, 100).
        let h = 3f64.sqrt() / 2.0 / 10.0;
        let p = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.5, h),
        ];
        let m = Metric2::new(1.0, 0.0, 100.0);
        for a in corner_angles(&p, &m) {
            assert!((a.to_degrees() - 60.0).abs() < 1e-9);
        }
        assert!(angles_at_least(&p, &m, 59.9f64.to_radians().cos()));
        assert!(!angles_at_least(
            &p,
            &Metric2::IDENTITY,
            20f64.to_radians().cos()
        ));
    }
}
