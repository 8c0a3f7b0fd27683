//! The camera: a view-projection matrix and a viewport, and the projection of spec §2.
//!
//! Conventions (the C header states the same):
//! - `clip = view_proj · [x, y, z, 1]` with `view_proj` a column-major [`DMat4`]; a point is in
//!   front of the eye iff `clip.w > 0`, and `ndc = clip.xyz / clip.w`.
//! - OpenGL-style NDC: x right, y up, depth growing away from the eye (z in [-1, 1]). A
//!   D3D-style matrix (z in [0, 1], y up) works unchanged: only the depth order is used. A
//!   Vulkan-style matrix (y down in NDC) shows the mesh upside down against the stroke and
//!   turns front faces into back faces: negate its second row first. A reversed-Z matrix
//!   (near at z = 1) inverts visibility: pass a forward-Z one.
//! - Pixels: origin at the viewport's top-left corner, y down, as Blender's region and Qt's
//!   widget coordinates are once flipped: `s = (x0 + (ndc.x + 1)/2 · W, y0 + (1 − ndc.y)/2 · H)`.
//! - Perspective and orthographic matrices go through the same formula (spec §2).

use glam::{DMat4, DVec2, DVec3, DVec4};

use super::ids::Lv;
use crate::error::{Error, Result};

/// The screen range a cut works in, ±2^40 pixels (about 1.1e12): stroke points and viewport
/// values beyond it are errors, and a vertex that projects beyond it is treated like one
/// behind the eye (its faces are never cut). Far beyond any screen, and small enough that
/// products of screen coordinates (the exact predicates) and the sizes of the cut's grids
/// stay far from overflow.
pub const SCREEN_RANGE_PX: f64 = 1_099_511_627_776.0;

/// A camera: the matrix taking world points to clip space and the viewport in pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// `clip = view_proj · [x, y, z, 1]`, column-major, OpenGL NDC conventions (module docs).
    pub view_proj: DMat4,
    /// `[x0, y0, width, height]` in pixels, origin top-left, y down.
    pub viewport: [f64; 4],
}

impl View {
    /// A view from its matrix and viewport.
    pub fn new(view_proj: DMat4, viewport: [f64; 4]) -> Self {
        View {
            view_proj,
            viewport,
        }
    }
}

/// A hand-drawn stroke: pixel positions in the viewport's convention (top-left origin, y down),
/// in drawing order. A stroke whose last point lies within `min_stroke_px` of its first is
/// closed (a loop).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Stroke {
    /// The points, in pixels.
    pub points: Vec<DVec2>,
}

impl Stroke {
    /// A stroke through these pixel positions.
    pub fn new(points: Vec<DVec2>) -> Self {
        Stroke { points }
    }
}

/// Whether a screen point lies within [`SCREEN_RANGE_PX`] (not NaN).
#[inline]
pub(crate) fn in_range(s: DVec2) -> bool {
    s.x.abs() <= SCREEN_RANGE_PX && s.y.abs() <= SCREEN_RANGE_PX
}

/// The rows of the view-projection matrix and the viewport's terms that
/// [`Projector::screen_of`] computes a screen point from: `w = w·[p, 1]`, and
/// `(x0 + (x·[p, 1] / w + 1) · half_w, y0 + (1 − y·[p, 1] / w) · half_h)`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ScreenRows {
    pub x: DVec4,
    pub y: DVec4,
    pub w: DVec4,
    pub x0: f64,
    pub y0: f64,
    pub half_w: f64,
    pub half_h: f64,
}

/// A vertex seen through the view: its pixel position, its clip-space w (> 0 in front) and its
/// NDC depth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Seen {
    pub screen: DVec2,
    pub w: f64,
    pub z: f64,
}

/// The [`Seen`] of many vertices, as two arrays: screen points are read far more often than
/// depths (snapping's guards, faces' corners on screen), and as `Option<Seen>`s of 40 bytes
/// half of them lay across two cache lines. Behind the eye, w and the screen point are NaN.
#[derive(Debug, Clone, Default)]
pub(crate) struct SeenList {
    pub screen: Vec<DVec2>,
    /// (NDC z, clip w) of each vertex.
    pub depth: Vec<DVec2>,
}

impl SeenList {
    pub fn len(&self) -> usize {
        self.screen.len()
    }

    /// Vertex `v` as seen, `None` behind the eye.
    #[inline]
    pub fn get(&self, v: Lv) -> Option<Seen> {
        let d = self.depth[v.idx()];
        Self::in_front(d).then(|| Seen {
            screen: self.screen[v.idx()],
            w: d.y,
            z: d.x,
        })
    }

    /// Whether vertex `v` is in front of the eye.
    #[inline]
    pub fn front(&self, v: Lv) -> bool {
        Self::in_front(self.depth[v.idx()])
    }

    /// Whether a `depth` entry, (z, w), is of a vertex in front of the eye (for passes that
    /// walk the arrays side by side).
    #[inline]
    pub fn in_front(depth: DVec2) -> bool {
        depth.y > 0.0
    }

    /// Whether a face's corners `t` are all in front of the eye (one branch, at the caller).
    #[inline]
    pub fn front3(&self, t: [Lv; 3]) -> bool {
        self.front(t[0]) & self.front(t[1]) & self.front(t[2])
    }
}

impl From<(Vec<DVec2>, Vec<DVec2>)> for SeenList {
    fn from((screen, depth): (Vec<DVec2>, Vec<DVec2>)) -> Self {
        SeenList { screen, depth }
    }
}

/// A [`SeenList`] entry: screen point and (z, w), NaN behind the eye.
#[inline]
pub(crate) fn split_seen(s: Option<Seen>) -> (DVec2, DVec2) {
    match s {
        Some(s) => (s.screen, DVec2::new(s.z, s.w)),
        None => (DVec2::NAN, DVec2::NAN),
    }
}

/// The checked view with its inverse, shared by every stage.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Projector {
    vp: DMat4,
    inv: DMat4,
    x0: f64,
    y0: f64,
    half_w: f64,
    half_h: f64,
}

impl Projector {
    /// Checks the view (finite entries, invertible matrix, viewport with area).
    pub fn new(view: &View) -> Result<Self> {
        for (c, col) in view.view_proj.to_cols_array_2d().iter().enumerate() {
            for (r, &value) in col.iter().enumerate() {
                if !value.is_finite() {
                    return Err(Error::NonFiniteMatrixEntry {
                        column: c as u32,
                        row: r as u32,
                        value,
                    });
                }
            }
        }
        let vp = view.viewport;
        if vp.iter().any(|v| !v.is_finite()) {
            return Err(Error::InvalidViewport {
                viewport: vp,
                reason: "a value is not finite",
            });
        }
        if vp.iter().any(|v| v.abs() > SCREEN_RANGE_PX) {
            return Err(Error::InvalidViewport {
                viewport: vp,
                reason: "a value is beyond the ±2^40 (1.1e12) pixels a cut works in",
            });
        }
        if vp[2] <= 0.0 || vp[3] <= 0.0 {
            return Err(Error::InvalidViewport {
                viewport: vp,
                reason: "width and height must be positive",
            });
        }
        let m = view.view_proj;
        let determinant = m.determinant();
        let entries = m.to_cols_array();
        if !determinant.is_finite() {
            // Finite entries whose products overflow: name the largest.
            let (k, &value) = entries
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
                .expect("16 entries");
            return Err(Error::ViewProjectionOutOfRange {
                column: (k / 4) as u32,
                row: (k % 4) as u32,
                value,
            });
        }
        // Relative to the entries' scale, so a matrix in millimetres is not "singular".
        let scale = entries.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let inv = m.inverse();
        if !(determinant.abs() > 1e-300
            && determinant.abs() > 1e-14 * scale.powi(4)
            && inv.is_finite())
        {
            return Err(Error::SingularViewProjection { determinant });
        }
        Ok(Projector {
            vp: m,
            inv,
            x0: vp[0],
            y0: vp[1],
            half_w: vp[2] * 0.5,
            half_h: vp[3] * 0.5,
        })
    }

    /// Clip coordinates of a world point.
    #[inline]
    pub fn clip(&self, p: DVec3) -> DVec4 {
        self.vp * p.extend(1.0)
    }

    /// Pixel position of NDC x, y.
    #[inline]
    pub fn ndc_to_screen(&self, x: f64, y: f64) -> DVec2 {
        DVec2::new(
            self.x0 + (x + 1.0) * self.half_w,
            self.y0 + (1.0 - y) * self.half_h,
        )
    }

    /// NDC x, y of a pixel position.
    #[inline]
    pub fn screen_to_ndc(&self, s: DVec2) -> DVec2 {
        DVec2::new(
            (s.x - self.x0) / self.half_w - 1.0,
            1.0 - (s.y - self.y0) / self.half_h,
        )
    }

    /// The vertex as seen, or `None` when it is unprojectable (spec §2): behind the eye
    /// (`w ≤ 0`), with a clip w that is not finite, or seen beyond [`SCREEN_RANGE_PX`].
    #[inline]
    pub fn see(&self, p: DVec3) -> Option<Seen> {
        let c = self.clip(p);
        if !(c.w > 0.0 && c.w < f64::INFINITY) {
            return None;
        }
        let inv_w = 1.0 / c.w;
        let screen = self.ndc_to_screen(c.x * inv_w, c.y * inv_w);
        in_range(screen).then_some(Seen {
            screen,
            w: c.w,
            z: c.z * inv_w,
        })
    }

    /// [`Projector::see`]'s screen position alone, without the depth row (the same products
    /// summed in the same order, so the same bits).
    #[inline]
    pub fn screen_of(&self, p: DVec3) -> Option<DVec2> {
        let h = p.extend(1.0);
        let w = self.vp.row(3).dot(h);
        if !(w > 0.0 && w < f64::INFINITY) {
            return None;
        }
        let inv_w = 1.0 / w;
        let screen =
            self.ndc_to_screen(self.vp.row(0).dot(h) * inv_w, self.vp.row(1).dot(h) * inv_w);
        in_range(screen).then_some(screen)
    }

    /// What [`Projector::screen_of`] computes, for passes that repeat it lane by lane.
    pub fn screen_rows(&self) -> ScreenRows {
        ScreenRows {
            x: self.vp.row(0),
            y: self.vp.row(1),
            w: self.vp.row(3),
            x0: self.x0,
            y0: self.y0,
            half_w: self.half_w,
            half_h: self.half_h,
        }
    }

    /// The world point seen at pixel `s` with clip w `w` and NDC depth `z`: "move in the
    /// plane parallel to the screen" (seed 002 §3.2; spec §2: keep clip w and z_ndc).
    pub fn unproject(&self, s: DVec2, w: f64, z: f64) -> DVec3 {
        let n = self.screen_to_ndc(s);
        let h = self.inv * DVec4::new(n.x * w, n.y * w, z * w, w);
        h.truncate() / h.w
    }
}

#[cfg(test)]
mod tests {
    use super::{Projector, View};
    use glam::{DMat4, DVec3};

    #[test]
    fn screen_of_is_see_without_depth() {
        let views = [
            DMat4::perspective_rh_gl(0.9, 1.6, 0.01, 100.0)
                * DMat4::look_at_rh(DVec3::new(3.0, -7.0, 5.0), DVec3::ZERO, DVec3::Z),
            DMat4::orthographic_rh_gl(-2.0, 3.0, -1.0, 2.5, 0.1, 50.0)
                * DMat4::look_at_rh(DVec3::new(0.3, 0.2, 9.0), DVec3::ZERO, DVec3::Y),
        ];
        for vp in views {
            let p = Projector::new(&View::new(vp, [10.0, 20.0, 1280.0, 720.0])).unwrap();
            let mut x = 0x2545_f491_4f6c_dd1du64;
            for _ in 0..10_000 {
                let mut r = || {
                    x ^= x << 13;
                    x ^= x >> 7;
                    x ^= x << 17;
                    (x >> 11) as f64 / (1u64 << 53) as f64 * 20.0 - 10.0
                };
                let q = DVec3::new(r(), r(), r());
                let s = p.see(q).map(|s| s.screen);
                assert_eq!(
                    p.screen_of(q).map(|v| v.to_array().map(f64::to_bits)),
                    s.map(|v| v.to_array().map(f64::to_bits)),
                    "{q}"
                );
            }
        }
    }
}
