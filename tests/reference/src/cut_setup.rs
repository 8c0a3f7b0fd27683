//! Views and strokes for comparing stroke cuts on a model: the exact cut ([`crate::cgal_stroke_cut`])
//! now, katachi's `cut_by_stroke` later, on the very same input.
//!
//! A view looks at a model's bounding box ([`look_at_bounds`]), perspective or orthographic, with
//! OpenGL clip conventions (`w > 0` in front of the eye, ndc in `[-1, 1]`); the stroke is a wavy
//! line across the middle of the box's screen image ([`wavy_stroke`]). [`model_setup`] does both
//! with the defaults the baseline figures were taken with.
//!
//! ```
//! use katachi_reference::cut_setup::{look_at_bounds, project, wavy_stroke, Projection};
//! use katachi::DVec3;
//! let (lo, hi) = (DVec3::splat(-1.0), DVec3::splat(1.0));
//! let view = look_at_bounds(lo, hi, DVec3::Z, Projection::Orthographic, 800, 600);
//! let centre = project(&view, DVec3::ZERO).unwrap();
//! assert!((centre[0] - 400.0).abs() < 1e-9 && (centre[1] - 300.0).abs() < 1e-9);
//! let stroke = wavy_stroke(&view, lo, hi, 50);
//! assert_eq!(stroke.len(), 50);
//! ```

use glam::{DMat4, DVec3, DVec4};
use katachi::PolyMesh;

use crate::{CutView, RefMesh};

/// The projection of a view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// `DMat4::perspective_rh_gl` with this vertical field of view, in degrees.
    Perspective {
        /// Vertical field of view in degrees.
        fov_y_deg: f64,
    },
    /// `DMat4::orthographic_rh_gl` framing the bounding sphere.
    Orthographic,
}

/// The direction (from the box's centre towards the eye) [`model_setup`] uses: in front (+z),
/// a little from the right and from above, so that no face is seen exactly edge-on by accident.
pub const DEFAULT_VIEW_DIRECTION: DVec3 = DVec3::new(0.3, 0.2, 1.0);

/// The viewport [`model_setup`] uses, in pixels.
pub const DEFAULT_VIEWPORT: (u32, u32) = (1280, 720);

/// A view of the box `[lo, hi]` from `direction` (from the centre towards the eye; need not be
/// unit), up = +y (+z if `direction` is along y), framing the box's bounding sphere with a 10%
/// margin in a `width` x `height` pixel viewport at the origin. The whole box is in front of
/// the eye and between the near and far planes.
pub fn look_at_bounds(
    lo: DVec3,
    hi: DVec3,
    direction: DVec3,
    projection: Projection,
    width: u32,
    height: u32,
) -> CutView {
    let centre = (lo + hi) * 0.5;
    let radius = ((hi - lo).length() * 0.5).max(1e-12);
    let dir = direction.try_normalize().unwrap_or(DVec3::Z);
    let up = if dir.cross(DVec3::Y).length() < 1e-6 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    let aspect = f64::from(width.max(1)) / f64::from(height.max(1));
    let (eye_distance, proj) = match projection {
        Projection::Perspective { fov_y_deg } => {
            let half = (fov_y_deg.to_radians() * 0.5).clamp(1e-3, 1.5);
            // Fit the sphere in the narrower of the two fields of view.
            let half_narrow = if aspect < 1.0 {
                (half.tan() * aspect).atan()
            } else {
                half
            };
            let d = 1.1 * radius / half_narrow.sin();
            (
                d,
                DMat4::perspective_rh_gl(2.0 * half, aspect, d - 1.5 * radius, d + 1.5 * radius),
            )
        }
        Projection::Orthographic => {
            let d = 3.0 * radius;
            let half_h = 1.1 * radius * if aspect < 1.0 { 1.0 / aspect } else { 1.0 };
            let half_w = half_h * aspect;
            (
                d,
                DMat4::orthographic_rh_gl(
                    -half_w,
                    half_w,
                    -half_h,
                    half_h,
                    d - 1.5 * radius,
                    d + 1.5 * radius,
                ),
            )
        }
    };
    let eye = centre + dir * eye_distance;
    let view = DMat4::look_at_rh(eye, centre, up);
    CutView {
        view_proj: (proj * view).to_cols_array(),
        viewport: [0.0, 0.0, f64::from(width), f64::from(height)],
    }
}

/// The pixel position of `p` in `view`, or `None` if `p` is not in front of the eye (`w <= 0`).
pub fn project(view: &CutView, p: DVec3) -> Option<[f64; 2]> {
    let (sx, sy, w) = project_w(view, p);
    (w > 0.0).then_some([sx, sy])
}

/// The pixel position of `p` and its clip `w` (the position is meaningless for `w <= 0`).
pub fn project_w(view: &CutView, p: DVec3) -> (f64, f64, f64) {
    let m = DMat4::from_cols_array(&view.view_proj);
    let c: DVec4 = m * p.extend(1.0);
    let [x0, y0, w, h] = view.viewport;
    (
        x0 + (c.x / c.w + 1.0) * 0.5 * w,
        y0 + (1.0 - c.y / c.w) * 0.5 * h,
        c.w,
    )
}

/// A wavy stroke of `n` points (at least 2) across the middle of the screen image of the box
/// `[lo, hi]`: from 5% left of the image to 5% right of it, two full sine waves of amplitude
/// 10% of the image's height around its middle row.
pub fn wavy_stroke(view: &CutView, lo: DVec3, hi: DVec3, n: usize) -> Vec<[f64; 2]> {
    let n = n.max(2);
    let (mut xmin, mut xmax, mut ymin, mut ymax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for i in 0..8 {
        let corner = DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        if let Some([x, y]) = project(view, corner) {
            xmin = xmin.min(x);
            xmax = xmax.max(x);
            ymin = ymin.min(y);
            ymax = ymax.max(y);
        }
    }
    if xmin > xmax {
        // No corner in front of the eye: a stroke across the viewport.
        let [x0, y0, w, h] = view.viewport;
        (xmin, xmax, ymin, ymax) = (x0, x0 + w, y0, y0 + h);
    }
    let (width, height) = (xmax - xmin, ymax - ymin);
    let ymid = 0.5 * (ymin + ymax);
    (0..n)
        .map(|i| {
            let u = i as f64 / (n - 1) as f64;
            let x = xmin - 0.05 * width + u * 1.1 * width;
            let y = ymid + 0.1 * height * (2.0 * std::f64::consts::TAU * u).sin();
            [x, y]
        })
        .collect()
}

/// The view and stroke the baseline figures use for a model: [`look_at_bounds`] of the model's
/// bounding box from [`DEFAULT_VIEW_DIRECTION`] in a [`DEFAULT_VIEWPORT`], and a 50-point
/// [`wavy_stroke`]. `None` for a mesh without vertices.
pub fn model_setup(mesh: &PolyMesh, projection: Projection) -> Option<(CutView, Vec<[f64; 2]>)> {
    let (lo, hi) = mesh.bounding_box()?;
    let (w, h) = DEFAULT_VIEWPORT;
    let view = look_at_bounds(lo, hi, DEFAULT_VIEW_DIRECTION, projection, w, h);
    let stroke = wavy_stroke(&view, lo, hi, 50);
    Some((view, stroke))
}

/// A katachi mesh as a [`RefMesh`] (each face's outer loop); an error for faces with holes.
pub fn ref_mesh(mesh: &PolyMesh) -> Result<RefMesh, String> {
    let mut out = RefMesh {
        positions: mesh.positions().iter().map(|p| p.to_array()).collect(),
        ..RefMesh::default()
    };
    for f in mesh.faces() {
        if mesh.face_loop_count(f) != 1 {
            return Err(format!("face {} has holes", f.0));
        }
        let outer = mesh.face_outer(f);
        out.face_sizes.push(outer.len() as u32);
        out.face_vertices.extend(outer.iter().map(|v| v.0));
    }
    Ok(out)
}

/// The smallest interior angle of the triangle `(a, b, c)`, in degrees (0 if an edge has zero
/// length), measured as the exact cut measures it (`atan2(|u x v|, u . v)` at each corner).
pub fn triangle_min_angle_deg(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    if a == b || b == c || c == a {
        return 0.0;
    }
    let angle = |u: DVec3, v: DVec3| u.cross(v).length().atan2(u.dot(v));
    angle(b - a, c - a)
        .min(angle(c - b, a - b))
        .min(angle(a - c, b - c))
        .to_degrees()
}
