//! Options of [`super::cut_by_stroke`].

use crate::error::{Error, Result};

/// Which faces a stroke cuts (seed 002 §2.1, Fig. 2; spec §3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CutMode {
    /// Only faces seen from the eye: front-facing (counter-clockwise in OpenGL NDC) and not
    /// hidden, decided per crossing by a ray through it (spec §3, gap-fill). The paper's Fig. 2.
    VisibleOnly,
    /// Every face under the stroke, front and back sheets alike, each sheet with its own
    /// element array (spec §6.14).
    ThroughAll,
}

/// Options of [`super::cut_by_stroke`]. Defaults are the spec's (`spec/stroke_cut.md` §1);
/// the paper gives thresholds only as "a ratio of the mean edge length" (seed 002 §3.2).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct CutOptions {
    /// Which faces are cut. Default value: [`CutMode::VisibleOnly`] (the paper's Fig. 2).
    pub mode: CutMode,
    /// Open the cut: duplicate the path's vertices so the mesh gets a slit, two boundaries or
    /// two components (spec §4 step 8, as libigl's `cut_mesh`); otherwise only the edge path
    /// is inserted. A slit of one edge whose ends are both inside the mesh has no vertex to
    /// split and stays closed. Default value: `false`.
    pub open: bool,
    /// Snap a model vertex to a stroke vertex closer than this × L (seed 002 §3.2; L is the
    /// mean screen edge length, see [`super::CutReport::mean_edge_length_px`]). Default value:
    /// `0.3` (spec §1).
    pub snap_vertex_ratio: f64,
    /// Snap a model vertex onto a stroke segment closer than this × L (seed 002 §3.2, Fig. 4).
    /// Default value: `0.3` (spec §1).
    pub snap_segment_ratio: f64,
    /// Split the stroke where it turns by more than this many degrees (seed 002 §3.4,
    /// Fig. 11). Default value: `60` (spec §1).
    pub corner_angle_deg: f64,
    /// Drop a stroke point closer than this many pixels to the previous kept point, and close
    /// a stroke whose last point is this close to its first (gap-fill, spec §4 preprocessing).
    /// Default value: `2.0` (spec §1).
    pub min_stroke_px: f64,
    /// Visible-only: a face hides a crossing only if it is nearer than the crossing by more
    /// than this × the diagonal of the cut region's bounding box (gap-fill, spec §3).
    /// Default value: `1e-4` (spec §1).
    pub depth_eps_rel: f64,
    /// Refuse a cut that would split more than this many triangles, with
    /// [`crate::Error::CutTooLarge`] and nothing changed (spec §1; a guard for interactive tools).
    /// Default value: `u32::MAX` (no limit).
    pub max_faces_split: u32,
}

impl Default for CutOptions {
    fn default() -> Self {
        CutOptions {
            mode: CutMode::VisibleOnly,
            open: false,
            snap_vertex_ratio: 0.3,
            snap_segment_ratio: 0.3,
            corner_angle_deg: 60.0,
            min_stroke_px: 2.0,
            depth_eps_rel: 1e-4,
            max_faces_split: u32::MAX,
        }
    }
}

impl CutOptions {
    /// Default options with the given mode.
    pub fn with_mode(mode: CutMode) -> Self {
        CutOptions {
            mode,
            ..Default::default()
        }
    }

    /// Checks every value's domain, naming the first bad option (what [`super::cut_by_stroke`]
    /// does first; front ends call it to report a bad option before any work).
    pub fn validate(&self) -> Result<()> {
        let bad =
            |option: &'static str, message: String| Err(Error::InvalidOption { option, message });
        for (name, v, max) in [
            ("snap_vertex_ratio", self.snap_vertex_ratio, 0.5),
            ("snap_segment_ratio", self.snap_segment_ratio, 0.5),
        ] {
            // Above 0.5·L two vertices of one edge could snap to the same stroke point.
            if !(v.is_finite() && (0.0..=max).contains(&v)) {
                return bad(name, format!("{v} is not in [0, {max}]"));
            }
        }
        if !(self.corner_angle_deg.is_finite() && (0.0..=180.0).contains(&self.corner_angle_deg)) {
            return bad(
                "corner_angle_deg",
                format!("{} is not in [0, 180]", self.corner_angle_deg),
            );
        }
        if !(self.min_stroke_px.is_finite() && self.min_stroke_px >= 0.0) {
            return bad(
                "min_stroke_px",
                format!("{} is not a finite value ≥ 0", self.min_stroke_px),
            );
        }
        if !(self.depth_eps_rel.is_finite() && self.depth_eps_rel >= 0.0) {
            return bad(
                "depth_eps_rel",
                format!("{} is not a finite value ≥ 0", self.depth_eps_rel),
            );
        }
        Ok(())
    }
}
