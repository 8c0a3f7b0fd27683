//! Faces with holes: their validation, the bridges that join their loops (seed 001 §3.1
//! method \[a\], spec §5), and splitting them into simple polygons along those bridges, which
//! the subdivision's method \[a\], the stroke cut and every front end that stores no holes use.
//!
//! A face with holes has an outer loop P (counter-clockwise seen from the front) and hole loops
//! C (clockwise), all in one plane (seed 001 §2, spec §1.1). [`validate_faces_with_holes`]
//! checks that this is so. [`bridge_face`] builds the *virtual faces* of method \[a\]: the loop
//! with fewer vertices, S, is joined to the other, L, by one bridge per vertex of S
//! (`s_a → l(a)`, the nearest vertex of L), and the bridges cut the face into one virtual face
//! per edge of S (spec §5.2 step 3), whose face point averages only the bridges' end vertices
//! (spec §5.2 step 4). When the nearest-vertex bridges would cross, a shortest non-crossing set
//! is found by dynamic programming (spec A2); several holes are bridged independently when
//! they use disjoint arcs of P (spec A6).
//!
//! # How the bridges are chosen
//!
//! - **Monotone nearest map (seed).** `G_a` walks L forwards from `l(a+1)` to `l(a)`, so along
//!   S the targets must step *backwards* along L, by `d_a = l(a) − l(a+1) (mod m)` vertices,
//!   and the steps must add up to exactly one turn, `Σ d_a = m` (the sum is always a multiple
//!   of `m`; `0` means a single target, `2m` or more means the bridges wind round twice, i.e.
//!   cross). The nearest map is kept when it is monotone in this sense, every bridge leaves
//!   both of its ends into the face and meets no loop edge, and no two consecutive bridges meet
//!   (or, sharing their L end, make a triangle that turns left, A3).
//! - **Dynamic programme (A2).** Otherwise every vertex of S gets the list of its valid
//!   targets, nearest first (cut to the nearest `K` if the loops are very large, see
//!   `DP_BUDGET`). Fixing the target of one vertex of S (the one with the fewest candidates,
//!   each candidate in turn), a shortest path over S in order chooses the others, each at the
//!   same or a later position going backwards along L, one step never a whole turn, the last
//!   step closing the turn, and consecutive bridges compatible as above. Cost: total bridge
//!   length, then the number of targets that are not the nearest one (A2's tie-breaker). No
//!   feasible path: [`BridgeFailure::NoBridgeSet`]. Consecutive bridges that do not cross,
//!   each inside the face, and one turn in all imply that no two bridges cross at all.
//! - **Several holes (A6).** Each hole is bridged as if it were alone (its bridges still may
//!   not cross any other loop). All bridges are then cut into the face together; the pieces
//!   are traced (exact angular order of the bridges at each vertex), and must be simple
//!   polygons, `B − H + 1` of them. Each hole must keep all its own virtual faces but the one
//!   in which the other holes lie; that one, shared by all holes, is the single virtual face
//!   between them, and its face point averages the ends of all the bridges on its boundary.
//!   Bridges of two holes that cross give [`BridgeFailure::BridgesCross`]; other holes in two
//!   virtual faces of one hole give [`BridgeFailure::SharedArc`].
//!
//! All geometric decisions are exact: the face is projected onto the coordinate plane most
//! perpendicular to its normal (dropping a coordinate, so no rounding), and every side-of-line
//! test is Shewchuk's adaptive exact `orient2d` from the `robust` crate. Written by hand
//! because no crate bridges the loops of a B-rep face the way the seed describes.

mod bridges;
mod exact;
mod face;
mod pieces;

use std::fmt;

use crate::error::{Error, Result};
use crate::mesh::{FaceId, PolyMesh, VertexId};

use bridges::bridge_hole;
use face::FaceGeom;

/// Relative distance from the face's plane up to which a loop vertex counts as coplanar:
/// a vertex may be at most `PLANARITY_TOLERANCE × face size` from the plane, the face size
/// being the diagonal of the bounding box of its loops. Default value: `1e-6`.
pub const PLANARITY_TOLERANCE: f64 = 1e-6;

/// Work budget of the bridge optimisation (spec A2): the dynamic programme looks at about
/// `q × K³` bridge pairs for `q` vertices of S and `K` candidate targets per vertex; `K` is
/// cut to the nearest valid targets so that this stays below the budget.
const DP_BUDGET: f64 = 2.0e7;

/// Method \[a\] (seed 001 §3.1 \[a\], spec §5.2): the bridged virtual faces of one face with holes.
#[derive(Debug, Clone, PartialEq)]
pub struct Bridged {
    /// The virtual faces `G_a` as vertex loops, counter-clockwise like the outer loop. They tile
    /// the face: every loop edge of the face appears in exactly one virtual face (in its own
    /// direction), every bridge in exactly two (once in each direction). Order: hole by hole,
    /// `G_0, G_1, …` along S from its first stored vertex; `G_a` starts at `s_a` and reads
    /// `s_a, s_{a+1}, l(a+1), …, l(a)`. With several holes (spec A6) the one virtual face that
    /// lies between them comes where it is first met.
    pub faces: Vec<Vec<VertexId>>,
    /// For each virtual face, the vertices whose average is its face point (spec §5.2 step 4):
    /// the end vertices of the bridges on its boundary, in the face's order — `s_a, s_{a+1},
    /// l(a+1), l(a)`, three distinct ones when `l(a) = l(a+1)` (spec A3). The vertices of L
    /// strictly between `l(a+1)` and `l(a)` are *not* in it. The one virtual face between
    /// several holes (spec A6) averages the ends of all the bridges around it.
    pub face_point_vertices: Vec<Vec<VertexId>>,
    /// The bridges `(s_a, l(a))`, hole after hole, each in the order of S.
    pub bridges: Vec<(VertexId, VertexId)>,
    /// How each hole was bridged, in the order of the face's holes (loops 1, 2, …).
    pub holes: Vec<HoleBridges>,
}

/// How one hole of a face was bridged (part of [`Bridged`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HoleBridges {
    /// Whether S (the loop with fewer vertices, whose every vertex gets one bridge) is the
    /// hole; otherwise it is the outer loop. Equal counts give the hole (spec A8).
    pub short_is_hole: bool,
    /// Whether the bridges are the nearest-vertex ones (seed) or the optimised ones (spec A2).
    pub choice: BridgeChoice,
    /// The index of this hole's first bridge in [`Bridged::bridges`].
    pub first_bridge: u32,
    /// The number of this hole's bridges (the number of vertices of S).
    pub bridge_count: u32,
}

/// How a hole's bridges were chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BridgeChoice {
    /// Each vertex of S is bridged to its nearest vertex of L (seed 001 §3.1 \[a\]); ties go to
    /// the first vertex of L counted from its lowest vertex id (spec A5).
    Nearest,
    /// The nearest-vertex bridges would cross, leave the face or not go round the hole once;
    /// these are the shortest non-crossing bridges, nearest ones preferred on ties (spec A2).
    Optimised,
}

/// Why method \[a\] cannot bridge a face; the caller falls back to method \[b\] for it and
/// reports the reason (its `Display` is a sentence).
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum BridgeFailure {
    /// The face does not pass [`validate_faces_with_holes`]; the message says why.
    InvalidFace(String),
    /// No set of bridges joins this hole (loop index within the face) to the outer loop
    /// without crossing a loop or each other (spec A2).
    NoBridgeSet { hole: u32 },
    /// Bridges of two holes cross each other or meet along a line: both holes need the same
    /// part of the outer loop (spec A6).
    BridgesCross { first: u32, second: u32 },
    /// A hole lies between two bridges of another hole, so the two share an arc of the outer
    /// loop and cannot be bridged independently (spec A6).
    SharedArc { first: u32, second: u32 },
    /// The bridges do not cut the face into simple polygons (a bug or an input at the edge
    /// of floating point; the message says which check failed).
    Degenerate(String),
}

impl fmt::Display for BridgeFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BridgeFailure::InvalidFace(m) => {
                write!(f, "the face is not a valid face with holes: {m}")
            }
            BridgeFailure::NoBridgeSet { hole } => write!(
                f,
                "no set of bridges joins hole (loop {hole}) to the outer loop \
                 without crossing a loop or each other"
            ),
            BridgeFailure::BridgesCross { first, second } => write!(
                f,
                "bridges of holes (loops {first} and {second}) cross: \
                 the two holes need the same arc of the outer loop"
            ),
            BridgeFailure::SharedArc { first, second } => write!(
                f,
                "hole (loop {second}) lies between two bridges of hole (loop {first}): \
                 the holes share an arc of the outer loop"
            ),
            BridgeFailure::Degenerate(m) => {
                write!(
                    f,
                    "the bridges do not cut the face into simple polygons: {m}"
                )
            }
        }
    }
}

impl std::error::Error for BridgeFailure {}

/// Checks every face with holes (seed 001 §2, spec §1.1): all its loops lie in the plane of
/// its outer loop (within [`PLANARITY_TOLERANCE`] × face size); no loop crosses or touches
/// itself or another (sharing a vertex counts as touching); every hole lies inside the outer
/// loop; no hole lies inside another (spec A9: a hole inside a hole is not a valid face); and
/// the holes run opposite to the outer loop (clockwise seen from the front).
///
/// Faces without holes are not looked at. Errors name the face and the loops at fault.
pub fn validate_faces_with_holes(mesh: &PolyMesh) -> Result<()> {
    for f in mesh.faces() {
        if mesh.face_loop_count(f) > 1 {
            validate_face_with_holes(mesh, f, PLANARITY_TOLERANCE)?;
        }
    }
    Ok(())
}

/// [`validate_faces_with_holes`] for one face, with a chosen relative planarity tolerance.
/// A face without holes passes when it is planar.
pub fn validate_face_with_holes(mesh: &PolyMesh, face: FaceId, tolerance: f64) -> Result<()> {
    if face.idx() >= mesh.face_count() as usize {
        return Err(Error::InvalidArgument(format!(
            "face {face} does not exist (the mesh has {} faces)",
            mesh.face_count()
        )));
    }
    let g = FaceGeom::new(mesh, face)?;
    g.check(tolerance)
}

/// Method \[a\] (seed 001 §3.1 \[a\], spec §5.2 and A1–A9): the virtual faces of one face with
/// holes, or why it cannot be bridged.
///
/// For each hole, S is the loop with fewer vertices (the hole on ties, A8) and L the other;
/// each `s_a` is bridged to its nearest vertex `l(a)` of L (3D distance; ties to the first
/// vertex of L counted from its lowest vertex id, A5). These bridges are kept when they go
/// round the hole once in order (the map `a → l(a)` is cyclically monotone), lie inside the
/// face, and no two consecutive ones cross; otherwise the shortest set of bridges with these
/// properties is found by dynamic programming over the two loops (A2). `l(a) = l(a+1)` gives
/// a triangle (A3). Several holes are bridged independently, which works when they use
/// disjoint arcs of the outer loop (A6). A face without holes comes back as itself.
///
/// The face is first checked as [`validate_face_with_holes`] does; an invalid face gives
/// [`BridgeFailure::InvalidFace`]. Never panics.
pub fn bridge_face(mesh: &PolyMesh, face: FaceId) -> std::result::Result<Bridged, BridgeFailure> {
    if face.idx() >= mesh.face_count() as usize {
        return Err(BridgeFailure::InvalidFace(format!(
            "face {face} does not exist (the mesh has {} faces)",
            mesh.face_count()
        )));
    }
    if mesh.face_loop_count(face) == 1 {
        let outer = mesh.face_outer(face).to_vec();
        return Ok(Bridged {
            faces: vec![outer.clone()],
            face_point_vertices: vec![outer],
            bridges: Vec::new(),
            holes: Vec::new(),
        });
    }
    let g = FaceGeom::new(mesh, face).map_err(|e| BridgeFailure::InvalidFace(e.to_string()))?;
    g.check(PLANARITY_TOLERANCE)
        .map_err(|e| BridgeFailure::InvalidFace(e.to_string()))?;
    let plans = (1..g.loops.len())
        .map(|h| bridge_hole(&g, h))
        .collect::<std::result::Result<Vec<_>, _>>()?;
    g.assemble(&plans)
}

/// Replaces every face with holes by the simple polygons its method \[a\] bridges cut it
/// into (spec §6.4 B4), for formats and hosts that store no faces with holes (OBJ, PLY,
/// OFF, Blender, MeshLab). The geometry is unchanged; only bridge edges are added. Returns
/// the new mesh and, per new face, the face it came from. A face that cannot be bridged is
/// an error naming it.
pub fn split_faces_with_holes(mesh: &PolyMesh) -> Result<(PolyMesh, Vec<FaceId>)> {
    if mesh.faces().all(|f| mesh.face_loop_count(f) == 1) {
        return Ok((mesh.clone(), mesh.faces().collect()));
    }
    let mut faces: Vec<Vec<u32>> = Vec::with_capacity(mesh.face_count() as usize);
    let mut origin = Vec::with_capacity(mesh.face_count() as usize);
    for f in mesh.faces() {
        if mesh.face_loop_count(f) == 1 {
            faces.push(mesh.face_outer(f).iter().map(|v| v.0).collect());
            origin.push(f);
            continue;
        }
        let b = bridge_face(mesh, f).map_err(|why| Error::InvalidFaceWithHoles {
            face: f.0,
            reason: format!("cannot be split into simple polygons: {why}"),
        })?;
        for vf in b.faces {
            faces.push(vf.iter().map(|v| v.0).collect());
            origin.push(f);
        }
    }
    let mut out = PolyMesh::from_polygons(mesh.positions().to_vec(), faces)?;
    out.set_edge_sharpnesses(mesh.sharp_edges().collect::<Vec<_>>())?;
    out.set_all_vertex_sharpness(mesh.vertex_sharpness().to_vec())?;
    Ok((out, origin))
}
