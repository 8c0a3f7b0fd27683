//! What can go wrong in curved meshing; every message names the curve, loop, region, patch
//! or sample at fault. Wrapped in [`crate::Error::Curved`].

/// An error of [`super::mesh`] or its input validation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CurvedError {
    /// Nothing to mesh.
    #[error("the input has no {what}")]
    Empty { what: &'static str },
    /// A curve has fewer than two control points.
    #[error("curve {curve}: a Bézier curve needs at least 2 control points, it has {points}")]
    CurveTooShort { curve: u32, points: usize },
    /// A control point is NaN or infinite.
    #[error("{element}: control point {index} has a coordinate {value}, not a finite number")]
    NonFinite {
        element: String,
        index: usize,
        value: f64,
    },
    /// A patch's point count does not match its degrees.
    #[error("patch {patch}: bidegree ({degree_u}, {degree_v}) needs {expected} control points, it has {got}")]
    PatchPointCount {
        patch: u32,
        degree_u: usize,
        degree_v: usize,
        expected: usize,
        got: usize,
    },
    /// A patch degree is 0.
    #[error("patch {patch}: degrees must be at least 1, got ({degree_u}, {degree_v})")]
    PatchDegree {
        patch: u32,
        degree_u: usize,
        degree_v: usize,
    },
    /// A curve leaves the parameter square `[0, 1]²`.
    #[error("curve {curve} leaves the parameter square [0, 1]² near (u, v) = ({u}, {v})")]
    OutsideParameterSquare { curve: u32, u: f64, v: f64 },
    /// A curve has a zero derivative: a cusp or a repeated end control point (spec §1.4 (a)).
    #[error("curve {curve} is not regular: its derivative vanishes near t = {t} (a cusp, or a repeated control point at an end)")]
    SingularCurve { curve: u32, t: f64 },
    /// A region names a patch that does not exist.
    #[error("region {region}: patch {patch} does not exist (the input has {patch_count} patches)")]
    UnknownPatch {
        region: u32,
        patch: u32,
        patch_count: usize,
    },
    /// A loop names a curve that does not exist.
    #[error("region {region}, loop {loop_index}, use {position}: curve {curve} does not exist (the input has {curve_count} curves)")]
    UnknownCurve {
        region: u32,
        loop_index: u32,
        position: u32,
        curve: u32,
        curve_count: usize,
    },
    /// A region has no loops, or a loop has no curves.
    #[error("region {region}{}: {what} is empty", loop_index.map(|l| format!(", loop {l}")).unwrap_or_default())]
    EmptyLoop {
        region: u32,
        loop_index: Option<u32>,
        what: &'static str,
    },
    /// Consecutive curves of a loop do not share their end point bit for bit.
    #[error("region {region}, loop {loop_index} is not closed: use {position} (curve {curve}) ends at ({}, {}) but the next use (curve {next_curve}) starts at ({}, {}); consecutive curves must share their end point exactly", end[0], end[1], next_start[0], next_start[1])]
    LoopNotClosed {
        region: u32,
        loop_index: u32,
        position: u32,
        curve: u32,
        next_curve: u32,
        end: [f64; 2],
        next_start: [f64; 2],
    },
    /// An outer loop is clockwise or a hole counter-clockwise (the region must be on the left).
    #[error("region {region}, loop {loop_index} runs {found}; {role} must run {expected} (signed area {area})")]
    LoopOrientation {
        region: u32,
        loop_index: u32,
        role: &'static str,
        expected: &'static str,
        found: &'static str,
        area: f64,
    },
    /// Two curves leave a common end point in the same direction (spec §1.4 (b)).
    #[error("curves {a} and {b} meet at ({}, {}) at a zero angle (their tangents there coincide)", at[0], at[1])]
    ZeroAngle { a: u32, b: u32, at: [f64; 2] },
    /// A curve is used more than twice, twice the same way, or by two patches.
    #[error("curve {curve}: {reason}")]
    CurveUse { curve: u32, reason: String },
    /// Two distinct curves have the same control points (a private copy of a shared curve).
    #[error("curves {a} and {b} are the same curve; a curve between two regions must be one curve used by both (spec §1.3)")]
    DuplicateCurve { a: u32, b: u32 },
    /// Curves cross or touch away from shared end points, or a curve crosses itself
    /// (spec §1.4 (c)); found when their guarding envelopes cannot be separated.
    #[error("{} near (u, v) = ({}, {})", if a == b { format!("curve {a} crosses or touches itself") } else { format!("curves {a} and {b} cross or touch") }, near[0], near[1])]
    CurvesIntersect { a: u32, b: u32, near: [f64; 2] },
    /// The envelopes of two curve pieces still overlap after the split depth cap.
    #[error("curves {a} and {b} come too close near (u, v) = ({}, {}) to be separated within {depth} bisections (options.max_split_depth)", near[0], near[1])]
    EnvelopeResolution {
        a: u32,
        b: u32,
        near: [f64; 2],
        depth: u32,
    },
    /// A region's loops do not bound one area: a hole outside the outer loop or inside
    /// another hole.
    #[error("region {region}: its loops do not bound an area (a hole outside its outer loop, or inside another hole)")]
    LoopsDoNotBound { region: u32 },
    /// Two regions of one patch overlap.
    #[error("regions {a} and {b} overlap on patch {patch}")]
    RegionsOverlap { a: u32, b: u32, patch: u32 },
    /// `P_u × P_v = 0` at a point of a trimmed region: a collapsed edge or a pole (spec §1.4 (d)).
    #[error("patch {patch} is degenerate at (u, v) = ({u}, {v}): P_u × P_v vanishes there (a collapsed edge or a pole inside the trimmed region)")]
    DegenerateSurface { patch: u32, u: f64, v: f64 },
    /// A metric sample or value is not symmetric positive definite.
    #[error("metric at {at}: {reason}")]
    InvalidMetric { at: String, reason: String },
    /// A curved element stays folded however its curve piece is split (an order below the
    /// curve's degree that cannot follow it).
    #[error("the curved element on curve {curve}, t in [{t0}, {t1}], folds at order {order}; try a higher order")]
    InvalidElement {
        curve: u32,
        t0: f64,
        t1: f64,
        order: u32,
    },
    /// A budget ran out: the mesh would need more than a limit allows.
    #[error("{what}: the limit of {limit} was reached ({detail}); raise options.{option} or coarsen the metric")]
    Budget {
        what: &'static str,
        option: &'static str,
        limit: u64,
        detail: String,
    },
}
