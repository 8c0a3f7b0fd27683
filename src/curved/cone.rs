//! The cone of a curve's control vectors: guardability (seed 000 Def. 2.1) and, applied to
//! the hodograph, regularity (spec §1.4 (a)).

use glam::DVec2;

use super::predicates::cross_sign;

/// The smallest cone `[minus, plus]` (counter-clockwise from `minus` to `plus`) holding a
/// set of vectors that all lie in one open half-plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Cone {
    /// The most counter-clockwise vector, s⁺ (seed 000 §2.2).
    pub plus: DVec2,
    /// The most clockwise vector, s⁻.
    pub minus: DVec2,
}

impl Cone {
    /// The cone of `vectors`, or `None` when no direction `a` has `a·s > 0` for every `s`
    /// (a zero vector, or vectors spreading over 180° or more). Exact: every side test is
    /// `orient2d` (spec §3.1's procedure).
    pub fn of(vectors: &[DVec2]) -> Option<Cone> {
        let first = *vectors.first()?;
        if first == DVec2::ZERO {
            return None;
        }
        let mut cone = Cone {
            plus: first,
            minus: first,
        };
        for &s in &vectors[1..] {
            if s == DVec2::ZERO {
                return None;
            }
            if cross_sign(cone.plus, s) > 0.0 {
                // s is counter-clockwise of s⁺: the spread from s⁻ to s must stay below 180°.
                if cross_sign(cone.minus, s) <= 0.0 {
                    return None;
                }
                cone.plus = s;
            } else if cross_sign(cone.minus, s) < 0.0 {
                // s is clockwise of s⁻: the spread from s to s⁺ must stay below 180°.
                if cross_sign(s, cone.plus) <= 0.0 {
                    return None;
                }
                cone.minus = s;
            } else if cross_sign(cone.plus, s) == 0.0 && cone.plus.dot(s) < 0.0 {
                return None;
            }
        }
        let a = cone.axis();
        (a.dot(cone.plus) > 0.0 && a.dot(cone.minus) > 0.0).then_some(cone)
    }

    /// The axis `d = s⁺/|s⁺| + s⁻/|s⁻|`, bisecting the cone (seed 000 §2.2, Def. 2.4).
    pub fn axis(&self) -> DVec2 {
        self.plus.normalize() + self.minus.normalize()
    }

    /// The angle from `s⁻` to `s⁺`, in degrees.
    pub fn spread_deg(&self) -> f64 {
        let c = self.minus.perp_dot(self.plus);
        let d = self.minus.dot(self.plus);
        c.atan2(d).to_degrees()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    #[test]
    fn guardable_and_not() {
        let c = Cone::of(&[v(1.0, 1.0), v(1.0, 0.0), v(1.0, -1.0)]).unwrap();
        assert_eq!(c.plus, v(1.0, 1.0));
        assert_eq!(c.minus, v(1.0, -1.0));
        assert!((c.spread_deg() - 90.0).abs() < 1e-12);
        // An S whose control polygon turns through more than 180°.
        assert!(Cone::of(&[v(1.0, 0.0), v(0.0, 1.0), v(-1.0, -0.1)]).is_none());
        assert!(Cone::of(&[v(1.0, 0.0), v(0.0, 1.0), v(-1.0, 0.1)]).is_some());
        // Opposite vectors.
        assert!(Cone::of(&[v(1.0, 0.0), v(-1.0, 0.0)]).is_none());
        // A zero vector.
        assert!(Cone::of(&[v(1.0, 0.0), v(0.0, 0.0)]).is_none());
        // Exactly 180° apart through a third vector.
        assert!(Cone::of(&[v(0.0, 1.0), v(1.0, 0.0), v(0.0, -1.0)]).is_none());
    }
}
