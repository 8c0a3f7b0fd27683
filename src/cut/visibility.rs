//! Visible-only mode: is a point on a face seen from the eye? (seed 002 Fig. 2; spec §3,
//! gap-fill: decided per crossing by a ray through it.)
//!
//! Every face that can hide a point under the stroke projects onto that point, so it is in
//! the cut region: the ray is tested against the region's faces only ([`FaceIndex`]
//! narrows them down). A point is hidden when a face holds it on screen at a depth nearer
//! by more than `depth_eps_rel` × the region's diagonal.
//!
//! Snapping moves vertices after the user saw the mesh: a point it did not move is seen only
//! if it was seen both before and after (katachi's gap-fill), so a snapped occluder that
//! slides aside does not expose what was hidden ([`Before`]).
//!
//! Faces with a vertex behind the eye are not tested as occluders (they have no screen
//! triangle); a face that close to the camera rarely sits in front of a stroke.

use glam::{DVec2, DVec3};

use super::fast::{FaceIndex, SegmentIndex};
use super::geom::{barycentric, in_triangle, map3};
use super::ids::{Lf, Lv};
use super::region::{lift_with, Region};
use super::view::SeenList;

/// What the visibility tests need: the faces indexed, the depth tolerance, and the region as
/// it was before snapping.
pub(crate) struct Visibility {
    pub faces: FaceIndex,
    /// A face nearer than a point by no more than this (world units) does not hide it.
    eps_world: f64,
    pub before: Before,
}

impl Visibility {
    /// Set up on the region before snapping; vertices may then move up to `slack` pixels.
    pub fn new(region: &Region, segments: &SegmentIndex, depth_eps_rel: f64, slack: f64) -> Self {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for &p in region.positions() {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let diag = if region.vertex_count() == 0 {
            0.0
        } else {
            (hi - lo).length()
        };
        Visibility {
            faces: FaceIndex::new(segments, region, slack),
            eps_world: depth_eps_rel * diag,
            before: Before::new(region),
        }
    }

    /// Whether some face lies in front of world point `x` (screen `s`, NDC depth `z`) by
    /// more than the depth tolerance; with `unmoved`, for a point that snapping did not move,
    /// also whether the faces hid it as they were before snapping. `own`: the faces the point
    /// lies on (its edge's, its vertex's), which hold it at its own depth and never hide it.
    pub fn hidden(
        &self,
        r: &Region,
        s: DVec2,
        z: f64,
        x: DVec3,
        unmoved: bool,
        own: &[Lf],
    ) -> bool {
        let b = &self.before;
        self.faces.any_in_front(s, z, |f| {
            if own.contains(&f) {
                return false;
            }
            let (t, sign) = (r.corners(f), r.sign(f));
            self.hides(t, sign, r.seen_list(), r.positions(), s, z, x)
                || (unmoved
                    && t.iter().any(|&v| b.moved(v))
                    && self.hides(t, sign, &b.seen, &b.pos, s, z, x))
        })
    }

    /// Whether triangle `t` (orientation `sign`), its vertices seen as `seen` at `pos`, holds
    /// screen point `s` at a depth nearer than `z`, and away from world point `x`.
    #[allow(clippy::too_many_arguments)]
    fn hides(
        &self,
        t: [Lv; 3],
        sign: f64,
        seen: &SeenList,
        pos: &[DVec3],
        s: DVec2,
        z: f64,
        x: DVec3,
    ) -> bool {
        debug_assert!(seen.front3(t), "an indexed face is projectable");
        let [a, b, c] = map3(t, |v| seen.screen[v.idx()]);
        if in_triangle(a, b, c, sign, s).is_none() {
            return false;
        }
        let (zf, y) = lift_with(seen, pos, t, barycentric(a, b, c, s));
        zf < z && (y - x).length() > self.eps_world
    }
}

/// The region's vertices as they were before snapping, and which ones moved.
pub(crate) struct Before {
    seen: SeenList,
    pos: Vec<DVec3>,
    moved: Vec<bool>,
}

impl Before {
    /// The region as it is now (call before snapping).
    pub fn new(r: &Region) -> Self {
        Before {
            seen: r.seen_list().clone(),
            pos: r.positions().to_vec(),
            moved: vec![false; r.vertex_count()],
        }
    }

    /// Records the vertices snapping moved.
    pub fn mark_moved(&mut self, moved: impl IntoIterator<Item = Lv>) {
        for v in moved {
            self.moved[v.idx()] = true;
        }
    }

    /// Whether vertex `v` moved.
    #[inline]
    pub fn moved(&self, v: Lv) -> bool {
        self.moved[v.idx()]
    }
}
