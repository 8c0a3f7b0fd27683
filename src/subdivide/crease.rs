//! Sharpness rules of semi-sharp creases (DeRose, Kass, Truong 1998 §5 and appendix), with
//! OpenSubdiv's semantics: 0 is smooth, ≥ 10 is infinitely sharp, and the arithmetic is done
//! in `f32` as OpenSubdiv does, so that fractional weights, and hence positions, agree with
//! it for every sharpness a user can type, not only for binary fractions.

use super::options::CreaseMethod;

/// Sharpness at or above which an edge or vertex is infinitely sharp.
pub(crate) const INFINITE: f32 = 10.0;

#[inline]
pub(crate) fn is_sharp(s: f32) -> bool {
    s > 0.0
}
#[inline]
pub(crate) fn is_semi_sharp(s: f32) -> bool {
    s > 0.0 && s < INFINITE
}

/// One level's relaxation under the uniform rule: s − 1, infinite stays infinite.
#[inline]
pub(crate) fn decrement(s: f32) -> f32 {
    if s >= INFINITE {
        INFINITE
    } else if s > 1.0 {
        s - 1.0
    } else {
        0.0
    }
}

/// The rule a vertex follows, from its sharp edge count and its own sharpness
/// (seed 001 §2.2 table: 0 or 1 sharp edges smooth eq. (2), 2 crease eq. (3), ≥ 3 corner eq. (4)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Rule {
    Smooth,
    Crease,
    Corner,
}

#[inline]
pub(crate) fn vertex_rule(vertex_sharpness: f32, sharp_edges: u32) -> Rule {
    if is_sharp(vertex_sharpness) || sharp_edges > 2 {
        Rule::Corner
    } else if sharp_edges == 2 {
        Rule::Crease
    } else {
        Rule::Smooth
    }
}

/// Per-vertex sums over the incident semi-sharp edges, for Chaikin's rule.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SemiSharpAtVertex {
    pub sum: f32,
    pub count: u32,
}

/// Sharpness of the child of an edge (sharpness `s`) at one of its end vertices.
#[inline]
pub(crate) fn child_sharpness(method: CreaseMethod, s: f32, at: SemiSharpAtVertex) -> f32 {
    match method {
        CreaseMethod::Uniform => decrement(s),
        CreaseMethod::Chaikin => {
            if !is_sharp(s) {
                0.0
            } else if s >= INFINITE {
                INFINITE
            } else if at.count <= 1 {
                decrement(s)
            } else {
                let others = (at.sum - s) / (at.count - 1) as f32;
                let c = (0.75 * s + 0.25 * others) - 1.0;
                if is_sharp(c) {
                    c
                } else {
                    0.0
                }
            }
        }
    }
}

/// Weight of the parent rule when a vertex changes rule between levels: the average of the
/// sharpness values that went from sharp to smooth, clamped to 1 (OpenSubdiv's
/// `ComputeFractionalWeightAtVertex`). Under the uniform rule an edge transitions when its
/// sharpness is in (0, 1].
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Transitions {
    pub sum: f32,
    pub count: u32,
}

impl Transitions {
    #[inline]
    pub(crate) fn add_edge(&mut self, method: CreaseMethod, parent: f32, child: f32) {
        let transitions = match method {
            CreaseMethod::Uniform => is_sharp(parent) && parent <= 1.0,
            CreaseMethod::Chaikin => is_sharp(parent) && !is_sharp(child),
        };
        if transitions {
            self.sum += parent;
            self.count += 1;
        }
    }

    #[inline]
    pub(crate) fn weight(self, parent_vertex: f32, child_vertex: f32) -> f32 {
        let (mut sum, mut count) = (self.sum, self.count);
        if is_sharp(parent_vertex) && !is_sharp(child_vertex) {
            sum += parent_vertex;
            count += 1;
        }
        if count == 0 {
            0.0
        } else {
            (sum / count as f32).min(1.0)
        }
    }
}
