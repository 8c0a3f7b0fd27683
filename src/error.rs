//! The one error type of the kernel.
//!
//! Every message says what was wrong and where, naming the element at fault
//! ("face 17, loop 0: vertex index 1203 is out of range (the mesh has 1200 vertices)").
//! [`Error::kind`] sorts the variants into the families a caller acts on differently:
//! bad input, bad topology, I/O, and internal bugs.

use std::borrow::Cow;
use std::path::PathBuf;

/// `text` as one line of plain text: each control character (a line break, a terminal escape
/// code, NUL) written as its Rust escape (`\n`, `\u{1b}`, `\0`), everything else unchanged.
/// Whatever echoes input goes through it (names from a file in the readers' messages, the C
/// ABI's messages, the command-line tool's lines), so an input cannot carry escape codes to a
/// terminal or break a message's line.
///
/// ```
/// use katachi::error::escape_control_characters;
/// assert_eq!(escape_control_characters("red\x1b[31m\nname\0"), r"red\u{1b}[31m\nname\0");
/// assert_eq!(escape_control_characters("plain é"), "plain é");
/// ```
pub fn escape_control_characters(text: &str) -> Cow<'_, str> {
    if !text.chars().any(char::is_control) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_debug());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// The family an [`Error`] belongs to; the C ABI maps each family to a status code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ErrorKind {
    /// The caller's data or arguments are invalid (indices, coordinates, option values).
    BadInput,
    /// The mesh is valid element by element but its connectivity is not what the operation needs.
    BadTopology,
    /// A file could not be read, written or parsed.
    Io,
    /// The caller cancelled the operation.
    Cancelled,
    /// A bug in katachi: an invariant did not hold.
    Internal,
}

/// Which of the three coordinates of a position.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Axis {
    X,
    Y,
    Z,
}

impl std::fmt::Display for Axis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Axis::X => "x",
            Axis::Y => "y",
            Axis::Z => "z",
        })
    }
}

/// Everything that can go wrong in katachi.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A loop refers to a vertex that does not exist.
    #[error("face {face}, loop {loop_index}: vertex index {index} is out of range (the mesh has {vertex_count} vertices)")]
    VertexOutOfRange {
        face: u32,
        loop_index: u32,
        index: u64,
        vertex_count: u32,
    },
    /// A position has a NaN or infinite coordinate.
    #[error("vertex {vertex}: coordinate {axis} is {value}, not a finite number")]
    NonFiniteCoordinate { vertex: u32, axis: Axis, value: f64 },
    /// An operation's result has a coordinate f64 cannot hold: the input's coordinates are too
    /// large for the operation's arithmetic (a sum of them overflows). `vertex` is the input
    /// vertex with the largest coordinate magnitude, `axis` and `value` that coordinate.
    #[error("{operation} overflows: the result has a coordinate that is not a finite number; the input's vertex {vertex} has {axis} = {value:e}, too large for it (scale the model down)")]
    CoordinateOverflow {
        operation: &'static str,
        vertex: u32,
        axis: Axis,
        value: f64,
    },
    /// A loop has fewer than three distinct vertices.
    #[error("face {face}, loop {loop_index}: a loop needs at least 3 distinct vertices, this one has {distinct}")]
    DegenerateLoop {
        face: u32,
        loop_index: u32,
        distinct: u32,
    },
    /// A loop visits the same vertex twice.
    #[error("face {face}, loop {loop_index}: vertex {vertex} appears more than once in the loop")]
    RepeatedVertex {
        face: u32,
        loop_index: u32,
        vertex: u32,
    },
    /// A face has no loops at all.
    #[error("face {face} has no loops (a face needs an outer loop)")]
    FaceWithoutLoops { face: u32 },
    /// The operation needs a mesh with elements and got none.
    #[error("the mesh is empty: {what} needs at least one {needs}")]
    EmptyMesh {
        what: &'static str,
        needs: &'static str,
    },
    /// Flat construction arrays disagree with each other.
    #[error("the mesh arrays disagree: {message}")]
    InconsistentArrays { message: String },
    /// An attribute array has the wrong length.
    #[error("attribute {attribute}: expected {expected} values (one per {per}), got {got}")]
    AttributeLength {
        attribute: &'static str,
        per: &'static str,
        expected: usize,
        got: usize,
    },
    /// A sharpness value is negative or not finite.
    #[error("{element}: sharpness {} is invalid (it must be finite and at least 0)", Num(*.value))]
    InvalidSharpness { element: String, value: f64 },
    /// A face with holes is not a valid planar face with holes: a loop off its plane, loops
    /// crossing or touching, a hole outside the outer loop or inside another hole, a hole
    /// wound like the outer loop, or an outer loop without area.
    #[error("face {face}: {reason}")]
    InvalidFaceWithHoles { face: u32, reason: String },
    /// The two vertices are not joined by an edge of any face.
    #[error("there is no edge between vertices {a} and {b}")]
    NoSuchEdge { a: u32, b: u32 },
    /// More than two faces share an edge.
    #[error(
        "edge {a}-{b} is non-manifold: it is used by {uses} face sides (at most 2 are allowed)"
    )]
    NonManifoldEdge { a: u32, b: u32, uses: u32 },
    /// The faces around a vertex form more than one fan (a bow-tie: they touch at the vertex
    /// but are not joined through edges around it).
    #[error("vertex {vertex} is non-manifold: its faces form {fans} fans that touch only at it")]
    NonManifoldVertex { vertex: u32, fans: u32 },
    /// Two faces traverse an edge in the same direction.
    #[error("edge {a}-{b} has inconsistent orientation: two faces traverse it from {a} to {b}")]
    InconsistentOrientation { a: u32, b: u32 },
    /// An option value is outside its domain.
    #[error("option {option}: {message}")]
    InvalidOption {
        option: &'static str,
        message: String,
    },
    /// A stroke has fewer than two points left once points closer than `min_px` to the
    /// previous kept point are dropped (stroke cut, seed 002).
    #[error("the stroke has {points} point(s) at least {} px apart; a cut needs at least 2", Num(*.min_px))]
    StrokeTooShort { points: u32, min_px: f64 },
    /// A stroke point has a NaN or infinite coordinate.
    #[error("stroke point {index}: coordinate {axis} is {value}, not a finite number")]
    NonFiniteStrokePoint { index: u32, axis: Axis, value: f64 },
    /// A stroke point lies beyond the screen range the cut works in
    /// (`katachi::cut::SCREEN_RANGE_PX`, ±2^40 pixels).
    #[error("stroke point {index}: coordinate {axis} is {}, beyond the ±{} pixels a cut works in", Num(*.value), Num(*.limit))]
    StrokePointOutOfRange {
        index: u32,
        axis: Axis,
        value: f64,
        limit: f64,
    },
    /// Two segments of a stroke cross or touch (seed 002 §2.2 assumes a stroke that does not
    /// cross itself). Segment `i` joins input points `i` and the next kept point.
    #[error("the stroke crosses itself: segment {first} (from point {first}) meets segment {second} (from point {second})")]
    StrokeSelfIntersects { first: u32, second: u32 },
    /// A view-projection matrix entry is NaN or infinite (column-major: `column`, `row`).
    #[error(
        "view-projection matrix entry (column {column}, row {row}) is {value}, not a finite number"
    )]
    NonFiniteMatrixEntry { column: u32, row: u32, value: f64 },
    /// A view-projection matrix entry is so large that the matrix's determinant overflows
    /// (`column`, `row`: the largest entry).
    #[error("view-projection matrix entry (column {column}, row {row}) is {}: too large (the matrix's determinant overflows)", Num(*.value))]
    ViewProjectionOutOfRange { column: u32, row: u32, value: f64 },
    /// The view-projection matrix cannot be inverted, so moved vertices cannot be unprojected.
    #[error("the view-projection matrix is singular (determinant {})", Num(*.determinant))]
    SingularViewProjection { determinant: f64 },
    /// The viewport is not finite or has no area.
    #[error("viewport [x0, y0, width, height] = [{}, {}, {}, {}]: {reason}", Num(.viewport[0]), Num(.viewport[1]), Num(.viewport[2]), Num(.viewport[3]))]
    InvalidViewport {
        viewport: [f64; 4],
        reason: &'static str,
    },
    /// A cut would split more triangles than `CutOptions::max_faces_split` allows (stroke cut;
    /// a guard for interactive tools against a stroke drawn over far more than meant).
    #[error(
        "the cut would split {split_faces} faces, more than the limit of {limit} (max_faces_split)"
    )]
    CutTooLarge { split_faces: u32, limit: u32 },
    /// An argument is invalid (used by the C ABI and the CLI for things that are not mesh data).
    #[error("{0}")]
    InvalidArgument(String),
    /// The operating system refused a file operation.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A file is malformed. `line` is 1-based; for binary files `line` is 0 and `byte` is set.
    #[error("{}", parse_message(path, *line, *byte, message))]
    Parse {
        path: PathBuf,
        line: usize,
        byte: Option<u64>,
        message: String,
    },
    /// The file extension names no format katachi reads or writes.
    #[error("{path}: unknown file format (use .obj, .ply or .off)")]
    UnknownFormat { path: PathBuf },
    /// Curved meshing (seed 000) rejected its input or ran out of budget.
    #[error(transparent)]
    Curved(#[from] CurvedError),
    /// The caller cancelled the operation (through its progress function).
    #[error("{operation} was cancelled")]
    Cancelled { operation: &'static str },
    /// Rough-model editing (seed 003) rejected its input.
    #[error(transparent)]
    Rough(#[from] RoughError),
    /// A bug in katachi.
    #[error("internal error: {0} (this is a bug in katachi; please report it)")]
    Internal(String),
}

/// A number in a message: plain for ordinary magnitudes (`2.5`, `-3`), with an exponent for
/// very large or small ones (`1e300`, not three hundred digits).
struct Num(f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || !a.is_finite() || (1e-4..1e15).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

fn parse_message(path: &std::path::Path, line: usize, byte: Option<u64>, message: &str) -> String {
    match (line, byte) {
        (0, Some(b)) => format!("{}: byte {b}: {message}", path.display()),
        (0, None) => format!("{}: {message}", path.display()),
        (l, _) => format!("{}:{l}: {message}", path.display()),
    }
}

impl Error {
    /// The family of this error.
    pub fn kind(&self) -> ErrorKind {
        match self {
            Error::NonManifoldEdge { .. }
            | Error::NonManifoldVertex { .. }
            | Error::InconsistentOrientation { .. } => ErrorKind::BadTopology,
            Error::Cancelled { .. } => ErrorKind::Cancelled,
            Error::Io { .. } | Error::Parse { .. } | Error::UnknownFormat { .. } => ErrorKind::Io,
            Error::Internal(_) => ErrorKind::Internal,
            _ => ErrorKind::BadInput,
        }
    }
}

/// `Result` with katachi's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// An error of curved meshing ([`crate::curved::mesh`], seed 000) or its input validation;
/// every message names the curve, loop, region, patch or sample at fault.
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

/// An error of rough-model editing ([`crate::rough`], seed 003): a band, seed or feature that
/// cannot be used; every message names the face at fault.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RoughError {
    /// The band has no faces.
    #[error("the band has no faces")]
    EmptyBand,
    /// A face index a caller gave is not a face of the mesh.
    #[error("{what}: face {face} is out of range (the mesh has {face_count} faces)")]
    FaceOutOfRange {
        what: &'static str,
        face: u32,
        face_count: u32,
    },
    /// The seed face marking the feature side lies in the band itself.
    #[error("the seed face {face} is in the band; give a face on the feature's side of the band")]
    SeedInBand { face: u32 },
    /// The seed face is on no side of the band (its part of the mesh does not touch it).
    #[error("the seed face {face} is not next to the band (its part of the mesh does not touch the band)")]
    SeedNotNextToBand { face: u32 },
    /// The band does not separate the mesh into an inside and an outside: it leaves a gap.
    #[error("the band does not separate the mesh: it is open, one of its ends is face {face}; close the band around the feature")]
    BandNotClosed { face: u32 },
    /// The band does not separate the mesh and reaches the mesh's boundary, where nothing
    /// can close it.
    #[error("the band does not separate the mesh and it reaches the mesh boundary at face {face}; close the band around the feature")]
    BandOpenAtBoundary { face: u32 },
    /// The region has too few points for the control net (spec §2: n_u · n_v ≤ s / 3).
    #[error("the region has {points} points, too few for a {net_u} × {net_v} control net (a fit needs 3 points per control point); give a larger region or a smaller net")]
    RegionTooSmall { points: u32, net_u: u32, net_v: u32 },
    /// The region folds over its least-squares plane: it is no height field over it.
    #[error("the region folds over its plane at face {face}: the fit's parameterization needs a region that is a height field over a plane")]
    RegionFolds { face: u32 },
    /// The fit's normal equations are singular: no data, and no smoothing, fixes a control point.
    #[error("the surface fit is singular at control point ({control_u}, {control_v}): no point determines it; turn smoothing on or use a smaller net")]
    FitSingular { control_u: u32, control_v: u32 },
}
