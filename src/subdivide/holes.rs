//! Faces with holes: their validation, and the bridges of method \[a\] (seed 001 §3.1 \[a\],
//! spec §5).
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

use std::fmt;

use glam::DVec3;
use robust::{orient2d, Coord};

use crate::error::{Error, Result};
use crate::mesh::{FaceId, PolyMesh, VertexId};

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

// ---------------------------------------------------------------------------------------------
// Exact 2D predicates.

type P2 = [f64; 2];

/// Twice the signed area of triangle `abc`, exact in sign: > 0 when `abc` turns left.
fn orient(a: P2, b: P2, c: P2) -> f64 {
    orient2d(
        Coord { x: a[0], y: a[1] },
        Coord { x: b[0], y: b[1] },
        Coord { x: c[0], y: c[1] },
    )
}

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Whether `(b - a)` and `(c - a)` point the same way (only meaningful when collinear).
/// Exact for collinear vectors: all products in the sum have the same sign.
fn same_direction(a: P2, b: P2, c: P2) -> bool {
    (b[0] - a[0]) * (c[0] - a[0]) + (b[1] - a[1]) * (c[1] - a[1]) > 0.0
}

/// `p`, collinear with `a` and `b`, lies on the closed segment `ab`.
fn on_segment(a: P2, b: P2, p: P2) -> bool {
    a[0].min(b[0]) <= p[0]
        && p[0] <= a[0].max(b[0])
        && a[1].min(b[1]) <= p[1]
        && p[1] <= a[1].max(b[1])
}

/// Whether the closed segments `ab` and `cd` have a point in common.
fn segments_meet(a: P2, b: P2, c: P2, d: P2) -> bool {
    let o1 = sign(orient(a, b, c));
    let o2 = sign(orient(a, b, d));
    let o3 = sign(orient(c, d, a));
    let o4 = sign(orient(c, d, b));
    if o1 * o2 < 0 && o3 * o4 < 0 {
        return true;
    }
    (o1 == 0 && on_segment(a, b, c))
        || (o2 == 0 && on_segment(a, b, d))
        || (o3 == 0 && on_segment(c, d, a))
        || (o4 == 0 && on_segment(c, d, b))
}

/// Two segments `xy` and `xz` sharing the end `x` overlap beyond it.
fn overlap_at_shared(x: P2, y: P2, z: P2) -> bool {
    orient(x, y, z) == 0.0 && same_direction(x, y, z)
}

/// Whether the axis-aligned boxes of segments `ab` and `cd` overlap.
fn boxes_meet(a: P2, b: P2, c: P2, d: P2) -> bool {
    a[0].max(b[0]) >= c[0].min(d[0])
        && c[0].max(d[0]) >= a[0].min(b[0])
        && a[1].max(b[1]) >= c[1].min(d[1])
        && c[1].max(d[1]) >= a[1].min(b[1])
}

/// Winding number of the closed polygon `poly` around `p` (Sunday's crossing rule, exact);
/// `p` must not lie on the polygon.
fn winding(poly: &[P2], p: P2) -> i32 {
    let mut w = 0;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        if a[1] <= p[1] {
            if b[1] > p[1] && orient(a, b, p) > 0.0 {
                w += 1;
            }
        } else if b[1] <= p[1] && orient(a, b, p) < 0.0 {
            w -= 1;
        }
    }
    w
}

/// Orientation of a simple polygon, exact: the turn at its lowest-leftmost vertex.
fn simple_polygon_turn(poly: &[P2]) -> i8 {
    let n = poly.len();
    let mut k = 0;
    for i in 1..n {
        if (poly[i][0], poly[i][1]) < (poly[k][0], poly[k][1]) {
            k = i;
        }
    }
    sign(orient(poly[(k + n - 1) % n], poly[k], poly[(k + 1) % n]))
}

/// A number with about four significant digits, for messages.
fn num(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || !a.is_finite() {
        return format!("{x}");
    }
    if (1e-3..1e6).contains(&a) {
        let digits = (3 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.3e}")
    }
}

// ---------------------------------------------------------------------------------------------
// One face, in local indices: its loops' vertices one after the other.

struct FaceGeom {
    face: FaceId,
    /// Local vertex → mesh vertex.
    vid: Vec<VertexId>,
    /// Local vertex → 3D position (for distances).
    p3: Vec<DVec3>,
    /// Local vertex → position projected on the face's plane (an exact coordinate drop).
    p2: Vec<P2>,
    /// Local vertex → its loop (0 = outer).
    loop_of: Vec<u32>,
    /// Loop `k` is local vertices `loops[k].0 .. loops[k].1`.
    loops: Vec<(usize, usize)>,
    /// Unit normal (Newell, outer loop), a point on the plane and the face size.
    normal: DVec3,
    origin: DVec3,
    size: f64,
}

impl FaceGeom {
    fn new(mesh: &PolyMesh, face: FaceId) -> Result<FaceGeom> {
        let mut vid = Vec::new();
        let mut loops = Vec::new();
        let mut loop_of = Vec::new();
        for (k, l) in mesh.face_loops(face).enumerate() {
            let start = vid.len();
            vid.extend_from_slice(mesh.loop_vertices(l));
            loop_of.resize(vid.len(), k as u32);
            loops.push((start, vid.len()));
        }
        let p3: Vec<DVec3> = vid.iter().map(|&v| mesh.position(v)).collect();
        let (lo, hi) = p3.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let size = (hi - lo).length();
        let outer = &p3[loops[0].0..loops[0].1];
        let origin = outer.iter().sum::<DVec3>() / outer.len() as f64;
        let mut n = DVec3::ZERO;
        for i in 0..outer.len() {
            let (a, b) = (outer[i] - origin, outer[(i + 1) % outer.len()] - origin);
            n += a.cross(b);
        }
        let area = 0.5 * n.length();
        let has_area = size > 0.0 && area > 1e-12 * size * size && area.is_finite();
        if !has_area {
            return Err(Error::InvalidFaceWithHoles {
                face: face.0,
                reason: "the outer loop (loop 0) has zero area, so the face has no plane".into(),
            });
        }
        let normal = n / n.length();
        // Drop the coordinate along which the normal is largest; keep the orientation.
        let na = normal.abs();
        let k = if na.x >= na.y && na.x >= na.z {
            0
        } else if na.y >= na.z {
            1
        } else {
            2
        };
        let (mut i, mut j) = ((k + 1) % 3, (k + 2) % 3);
        if normal[k] < 0.0 {
            std::mem::swap(&mut i, &mut j);
        }
        let p2 = p3.iter().map(|p| [p[i], p[j]]).collect();
        Ok(FaceGeom {
            face,
            vid,
            p3,
            p2,
            loop_of,
            loops,
            normal,
            origin,
            size,
        })
    }

    fn n(&self) -> usize {
        self.vid.len()
    }

    /// The next local vertex along its loop (the loop edge `u → next(u)`).
    fn next(&self, u: usize) -> usize {
        let (s, e) = self.loops[self.loop_of[u] as usize];
        if u + 1 == e {
            s
        } else {
            u + 1
        }
    }

    fn prev(&self, u: usize) -> usize {
        let (s, e) = self.loops[self.loop_of[u] as usize];
        if u == s {
            e - 1
        } else {
            u - 1
        }
    }

    fn loop_name(k: u32) -> String {
        if k == 0 {
            "the outer loop (loop 0)".to_string()
        } else {
            format!("hole (loop {k})")
        }
    }

    fn edge_name(&self, u: usize) -> String {
        format!("{}-{}", self.vid[u], self.vid[self.next(u)])
    }

    fn err(&self, message: String) -> Error {
        Error::InvalidFaceWithHoles {
            face: self.face.0,
            reason: message,
        }
    }

    // -----------------------------------------------------------------------------------------
    // Validation.

    fn check(&self, tolerance: f64) -> Result<()> {
        // Coplanarity.
        let limit = tolerance * self.size;
        for u in 0..self.n() {
            let d = (self.p3[u] - self.origin).dot(self.normal).abs();
            if d > limit || !d.is_finite() {
                let k = self.loop_of[u];
                let what = if k == 0 {
                    "the outer loop (loop 0) is not planar".to_string()
                } else {
                    format!("hole (loop {k}) is not coplanar with the face")
                };
                return Err(self.err(format!(
                    "{what}: vertex {} is {} from its plane (face size {}, tolerance {})",
                    self.vid[u],
                    num(d),
                    num(self.size),
                    num(limit)
                )));
            }
        }
        // Loops sharing a vertex touch.
        let mut ids: Vec<(VertexId, u32)> = self
            .vid
            .iter()
            .copied()
            .zip(self.loop_of.iter().copied())
            .collect();
        ids.sort_unstable();
        for w in ids.windows(2) {
            if w[0].0 == w[1].0 {
                return Err(self.err(format!(
                    "{} and {} share vertex {}; \
                     a hole must not touch the outer loop or another hole",
                    Self::loop_name(w[0].1),
                    Self::loop_name(w[1].1),
                    w[0].0
                )));
            }
        }
        // No loop edge meets another except adjacent ones at their shared vertex.
        if let Some((u, v)) = self.first_crossing() {
            let (ku, kv) = (self.loop_of[u], self.loop_of[v]);
            let (u, v, ku, kv) = if (ku, u) <= (kv, v) {
                (u, v, ku, kv)
            } else {
                (v, u, kv, ku)
            };
            let what = if ku == kv {
                format!("{} crosses or touches itself", Self::loop_name(ku))
            } else if ku == 0 {
                format!("hole (loop {kv}) crosses or touches the outer loop")
            } else {
                format!("holes (loops {ku} and {kv}) cross or touch")
            };
            return Err(self.err(format!(
                "{what}: edge {} meets edge {}",
                self.edge_name(u),
                self.edge_name(v)
            )));
        }
        // Holes run clockwise (the loops are simple now, so the turn at an extreme vertex
        // gives the orientation); the outer loop is counter-clockwise by the choice of normal.
        let polys: Vec<Vec<P2>> = self
            .loops
            .iter()
            .map(|&(s, e)| self.p2[s..e].to_vec())
            .collect();
        for (k, poly) in polys.iter().enumerate().skip(1) {
            if simple_polygon_turn(poly) > 0 {
                return Err(self.err(format!(
                    "hole (loop {k}) runs the same way as the outer loop \
                     (counter-clockwise seen from the face's front); holes must run the other way"
                )));
            }
        }
        // Holes inside the outer loop, and not inside each other (spec A9).
        for k in 1..polys.len() {
            if winding(&polys[0], polys[k][0]) == 0 {
                return Err(self.err(format!("hole (loop {k}) lies outside the outer loop")));
            }
            for (j, other) in polys.iter().enumerate().skip(1) {
                if j != k && winding(other, polys[k][0]) != 0 {
                    return Err(self.err(format!(
                        "hole (loop {k}) lies inside hole (loop {j}); nested loops are not \
                         a valid face (an island inside a hole is a face of its own)"
                    )));
                }
            }
        }
        Ok(())
    }

    /// The first pair of loop edges (by their first local vertex) that meet other than at the
    /// shared vertex of two consecutive edges. Sweep and prune along x.
    fn first_crossing(&self) -> Option<(usize, usize)> {
        let n = self.n();
        let xmin = |u: usize| self.p2[u][0].min(self.p2[self.next(u)][0]);
        let xmax = |u: usize| self.p2[u][0].max(self.p2[self.next(u)][0]);
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| xmin(a).total_cmp(&xmin(b)).then(a.cmp(&b)));
        for (i, &u) in order.iter().enumerate() {
            let hi = xmax(u);
            for &v in &order[i + 1..] {
                if xmin(v) > hi {
                    break;
                }
                if self.edges_meet(u, v) {
                    return Some((u.min(v), u.max(v)));
                }
            }
        }
        None
    }

    /// Whether loop edges `u → next(u)` and `v → next(v)` (u ≠ v) meet improperly.
    fn edges_meet(&self, u: usize, v: usize) -> bool {
        let (nu, nv) = (self.next(u), self.next(v));
        let p = &self.p2;
        if !boxes_meet(p[u], p[nu], p[v], p[nv]) {
            return false;
        }
        if nu == v {
            overlap_at_shared(p[v], p[u], p[nv])
        } else if nv == u {
            overlap_at_shared(p[u], p[nu], p[v])
        } else {
            segments_meet(p[u], p[nu], p[v], p[nv])
        }
    }

    // -----------------------------------------------------------------------------------------
    // Bridges.

    /// Direction `x → toward` lies strictly inside the face's angle at loop vertex `x`
    /// (counter-clockwise from the outgoing to the reversed incoming loop edge).
    fn in_sector(&self, x: usize, toward: usize) -> bool {
        let p = &self.p2;
        let (px, a, b, d) = (p[x], p[self.next(x)], p[self.prev(x)], p[toward]);
        let turn = orient(px, a, b);
        let o1 = orient(px, a, d);
        let o2 = orient(px, d, b);
        if turn > 0.0 {
            o1 > 0.0 && o2 > 0.0
        } else if turn < 0.0 {
            !(o1 <= 0.0 && o2 <= 0.0)
        } else if !same_direction(px, a, b) {
            o1 > 0.0
        } else {
            !(o1 == 0.0 && same_direction(px, a, d))
        }
    }

    /// A bridge from `s` to `l` (vertices of different loops) lies inside the face: it leaves
    /// both ends into the face and meets no loop edge elsewhere.
    fn bridge_ok(&self, s: usize, l: usize) -> bool {
        if !self.in_sector(s, l) || !self.in_sector(l, s) {
            return false;
        }
        let (a, b) = (self.p2[s], self.p2[l]);
        for u in 0..self.n() {
            let nu = self.next(u);
            if u == s || u == l || nu == s || nu == l {
                continue;
            }
            if boxes_meet(a, b, self.p2[u], self.p2[nu])
                && segments_meet(a, b, self.p2[u], self.p2[nu])
            {
                return false;
            }
        }
        true
    }

    /// Two consecutive bridges `s_a → x`, `s_{a+1} → y` bound a proper virtual face between
    /// them: they do not meet, or (A3) they share `x = y` and the triangle turns left.
    fn consecutive_ok(&self, sa: usize, x: usize, sb: usize, y: usize) -> bool {
        let p = &self.p2;
        if x == y {
            orient(p[sa], p[sb], p[x]) > 0.0
        } else {
            !(boxes_meet(p[sa], p[x], p[sb], p[y]) && segments_meet(p[sa], p[x], p[sb], p[y]))
        }
    }

    // -----------------------------------------------------------------------------------------
    // Virtual faces.

    /// Cuts the face along all holes' bridges, checks the pieces and assembles the result.
    fn assemble(&self, plans: &[HolePlan]) -> std::result::Result<Bridged, BridgeFailure> {
        let n = self.n();
        let p = &self.p2;
        // Bridges (s, l) in local indices, hole by hole.
        let mut bridges: Vec<(usize, usize)> = Vec::new();
        let mut bridge_hole: Vec<u32> = Vec::new();
        let mut holes = Vec::with_capacity(plans.len());
        for plan in plans {
            let first = bridges.len();
            let (ss, se) = self.loops[plan.s_loop];
            for (a, s) in (ss..se).enumerate() {
                bridges.push((s, plan.map[a]));
                bridge_hole.push(plan.hole as u32);
            }
            holes.push(HoleBridges {
                short_is_hole: plan.s_loop != 0,
                choice: plan.choice,
                first_bridge: first as u32,
                bridge_count: (se - ss) as u32,
            });
        }
        let nb = bridges.len();
        // No two bridges meet but at a shared end. (For one hole's bridges this follows from
        // the checks made when they were chosen; it is checked again, cheaply, all the same.)
        for i in 0..nb {
            for j in i + 1..nb {
                let ((a, b), (c, d)) = (bridges[i], bridges[j]);
                let meet = if a == c || a == d || b == c || b == d {
                    let (x, y, z) = if a == c {
                        (a, b, d)
                    } else if a == d {
                        (a, b, c)
                    } else if b == c {
                        (b, a, d)
                    } else {
                        (b, a, c)
                    };
                    overlap_at_shared(p[x], p[y], p[z])
                } else {
                    boxes_meet(p[a], p[b], p[c], p[d]) && segments_meet(p[a], p[b], p[c], p[d])
                };
                if meet && bridge_hole[i] != bridge_hole[j] {
                    return Err(BridgeFailure::BridgesCross {
                        first: bridge_hole[i],
                        second: bridge_hole[j],
                    });
                }
                if meet {
                    return Err(BridgeFailure::Degenerate(format!(
                        "bridges {}-{} and {}-{} of hole (loop {}) meet",
                        self.vid[a], self.vid[b], self.vid[c], self.vid[d], bridge_hole[i]
                    )));
                }
            }
        }
        // Bridges at each vertex, counter-clockwise from the outgoing loop edge.
        let mut at: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (k, &(s, l)) in bridges.iter().enumerate() {
            at[s].push(k);
            at[l].push(k);
        }
        let other = |k: usize, x: usize| {
            if bridges[k].0 == x {
                bridges[k].1
            } else {
                bridges[k].0
            }
        };
        for x in 0..n {
            if at[x].len() < 2 {
                continue;
            }
            let (px, r) = (p[x], p[self.next(x)]);
            let half = |d: P2| {
                let o = orient(px, r, d);
                if o > 0.0 || (o == 0.0 && same_direction(px, r, d)) {
                    0
                } else {
                    1
                }
            };
            let mut list = std::mem::take(&mut at[x]);
            let mut tie = None;
            list.sort_by(|&i, &j| {
                let (di, dj) = (p[other(i, x)], p[other(j, x)]);
                half(di).cmp(&half(dj)).then_with(|| {
                    let o = orient(px, di, dj);
                    if o > 0.0 {
                        std::cmp::Ordering::Less
                    } else if o < 0.0 {
                        std::cmp::Ordering::Greater
                    } else {
                        if i != j {
                            tie = Some((i, j));
                        }
                        i.cmp(&j)
                    }
                })
            });
            if let Some((i, j)) = tie {
                return Err(if bridge_hole[i] != bridge_hole[j] {
                    BridgeFailure::BridgesCross {
                        first: bridge_hole[i].min(bridge_hole[j]),
                        second: bridge_hole[i].max(bridge_hole[j]),
                    }
                } else {
                    BridgeFailure::Degenerate(format!(
                        "two bridges leave vertex {} in the same direction",
                        self.vid[x]
                    ))
                });
            }
            at[x] = list;
        }
        // Half-edges: loop edge u → next(u) is u; bridge k is n + 2k (s → l) and n + 2k + 1.
        let from = |h: usize| {
            if h < n {
                h
            } else {
                let (s, l) = bridges[(h - n) / 2];
                if (h - n).is_multiple_of(2) {
                    s
                } else {
                    l
                }
            }
        };
        let leave = |k: usize, x: usize| {
            if bridges[k].0 == x {
                n + 2 * k
            } else {
                n + 2 * k + 1
            }
        };
        let to = |h: usize| {
            if h < n {
                self.next(h)
            } else {
                let (s, l) = bridges[(h - n) / 2];
                if (h - n).is_multiple_of(2) {
                    l
                } else {
                    s
                }
            }
        };
        let next_he = |h: usize| {
            let x = to(h);
            let list = &at[x];
            if h < n {
                match list.last() {
                    Some(&k) => leave(k, x),
                    None => x,
                }
            } else {
                let k = (h - n) / 2;
                let pos = list.iter().position(|&b| b == k).unwrap_or(0);
                if pos > 0 {
                    leave(list[pos - 1], x)
                } else {
                    x
                }
            }
        };
        let total = n + 2 * nb;
        let mut piece_of = vec![usize::MAX; total];
        let mut pieces: Vec<Vec<usize>> = Vec::new();
        let mut corners: Vec<Vec<usize>> = Vec::new();
        for k in 0..nb {
            let h0 = next_he(n + 2 * k + 1);
            if piece_of[h0] != usize::MAX {
                continue;
            }
            let id = pieces.len();
            let (mut verts, mut corner) = (Vec::new(), Vec::new());
            let (mut h, mut prev_bridge) = (h0, true);
            loop {
                if piece_of[h] != usize::MAX || verts.len() > total {
                    return Err(BridgeFailure::Degenerate(
                        "walking a virtual face does not close".into(),
                    ));
                }
                piece_of[h] = id;
                let v = from(h);
                verts.push(v);
                if prev_bridge || h >= n {
                    corner.push(v);
                }
                prev_bridge = h >= n;
                h = next_he(h);
                if h == h0 {
                    break;
                }
            }
            pieces.push(verts);
            corners.push(corner);
        }
        if let Some(u) = (0..n).find(|&u| piece_of[u] == usize::MAX) {
            return Err(BridgeFailure::Degenerate(format!(
                "loop edge {} is in no virtual face",
                self.edge_name(u)
            )));
        }
        // Every piece a simple polygon turning left; their number B - H + 1 (Euler).
        let mut stamp = vec![usize::MAX; n];
        for (i, piece) in pieces.iter().enumerate() {
            for &v in piece {
                if stamp[v] == i {
                    return Err(BridgeFailure::Degenerate(format!(
                        "a virtual face passes vertex {} twice",
                        self.vid[v]
                    )));
                }
                stamp[v] = i;
            }
            let poly: Vec<P2> = piece.iter().map(|&v| p[v]).collect();
            if piece.len() < 3 || simple_polygon_turn(&poly) <= 0 {
                return Err(BridgeFailure::Degenerate(format!(
                    "the virtual face at vertex {} does not turn left",
                    self.vid[piece[0]]
                )));
            }
        }
        let hole_count = self.loops.len() - 1;
        if pieces.len() + hole_count != nb + 1 {
            return Err(BridgeFailure::Degenerate(format!(
                "{} virtual faces for {nb} bridges and {hole_count} holes",
                pieces.len()
            )));
        }
        // Spec A6: each hole keeps all its own virtual faces but the one that holds the other
        // holes (one of them if there is a single hole: none is lost).
        for plan in plans {
            let (ss, se) = self.loops[plan.s_loop];
            let q = se - ss;
            let (ls, le) = self.loops[plan.l_loop];
            let m = le - ls;
            let mut kept = 0;
            let mut foreign = None;
            for a in 0..q {
                let b = (a + 1) % q;
                let mut own = vec![ss + a, ss + b];
                let (x, y) = (plan.map[b], plan.map[a]);
                let mut v = x;
                own.push(v);
                while v != y && own.len() <= m + 2 {
                    v = self.next(v);
                    own.push(v);
                }
                let k = holes[plan.hole - 1].first_bridge as usize + a;
                let piece = &pieces[piece_of[n + 2 * k + 1]];
                let same = piece.len() == own.len() && {
                    let start = piece.iter().position(|&w| w == own[0]).unwrap_or(0);
                    (0..own.len()).all(|i| piece[(start + i) % piece.len()] == own[i])
                };
                if same {
                    kept += 1;
                } else if foreign.is_none() {
                    foreign = Some(piece_of[n + 2 * k + 1]);
                }
            }
            let expected = if hole_count == 1 { q } else { q - 1 };
            if kept != expected {
                if hole_count == 1 {
                    return Err(BridgeFailure::Degenerate(
                        "the virtual faces are not the ones the bridges define".into(),
                    ));
                }
                let me = plan.hole as u32;
                let second = foreign
                    .and_then(|f| {
                        pieces[f]
                            .iter()
                            .map(|&v| self.loop_of[v])
                            .find(|&k| k != 0 && k != me)
                    })
                    .unwrap_or(me);
                return Err(BridgeFailure::SharedArc { first: me, second });
            }
        }
        let ids = |list: &Vec<usize>| list.iter().map(|&v| self.vid[v]).collect::<Vec<_>>();
        Ok(Bridged {
            faces: pieces.iter().map(ids).collect(),
            face_point_vertices: corners.iter().map(ids).collect(),
            bridges: bridges
                .iter()
                .map(|&(s, l)| (self.vid[s], self.vid[l]))
                .collect(),
            holes,
        })
    }
}

// ---------------------------------------------------------------------------------------------
// One hole's bridges (spec §5.2 steps 1–3, A2, A3, A5, A8).

struct HolePlan {
    /// The hole's loop index in the face.
    hole: usize,
    /// S and L as loop indices (one of them is the hole, the other 0).
    s_loop: usize,
    l_loop: usize,
    /// For each vertex `a` of S (in order), the local vertex `l(a)` of L.
    map: Vec<usize>,
    choice: BridgeChoice,
}

/// A candidate target of one vertex of S in the dynamic programme.
#[derive(Clone, Copy)]
struct Cand {
    /// Local vertex of L.
    v: usize,
    len: f64,
    nearest: bool,
}

fn bridge_hole(g: &FaceGeom, hole: usize) -> std::result::Result<HolePlan, BridgeFailure> {
    let (cs, ce) = g.loops[hole];
    let (ps, pe) = g.loops[0];
    // Spec §5.2 step 1 and A8: S has fewer vertices, the hole on ties.
    let (s_loop, l_loop) = if ce - cs <= pe - ps {
        (hole, 0)
    } else {
        (0, hole)
    };
    let (ss, se) = g.loops[s_loop];
    let (ls, le) = g.loops[l_loop];
    let (q, m) = (se - ss, le - ls);
    // Spec A5: count L from its lowest vertex id.
    let first = (ls..le).min_by_key(|&v| g.vid[v]).unwrap_or(ls);
    let rank = |v: usize| (v + m - first) % m;
    let dist2 = |s: usize, v: usize| (g.p3[s] - g.p3[v]).length_squared();
    // Step 2: the nearest vertex of L to each s_a.
    let nearest: Vec<usize> = (ss..se)
        .map(|s| {
            (ls..le)
                .min_by(|&a, &b| {
                    dist2(s, a)
                        .total_cmp(&dist2(s, b))
                        .then(rank(a).cmp(&rank(b)))
                })
                .unwrap_or(ls)
        })
        .collect();
    // Going along S, l(a) must step backwards along L (G_a walks L forwards from l(a+1) to
    // l(a)), by 0..m-1 vertices each time and by exactly m in all (once round the hole).
    let back = |from: usize, to: usize| (from + m - to) % m;
    let turns: usize = (0..q).map(|a| back(nearest[a], nearest[(a + 1) % q])).sum();
    let ok = turns == m
        && (0..q).all(|a| g.bridge_ok(ss + a, nearest[a]))
        && (0..q).all(|a| {
            let b = (a + 1) % q;
            g.consecutive_ok(ss + a, nearest[a], ss + b, nearest[b])
        });
    if ok {
        return Ok(HolePlan {
            hole,
            s_loop,
            l_loop,
            map: nearest,
            choice: BridgeChoice::Nearest,
        });
    }
    // Spec A2: the shortest monotone set of valid, pairwise non-crossing bridges.
    let k_max = ((DP_BUDGET / q as f64).cbrt() as usize).max(8).min(m);
    let mut by_distance: Vec<usize> = (ls..le).collect();
    let mut cands: Vec<Vec<Cand>> = Vec::with_capacity(q);
    for (a, &near) in nearest.iter().enumerate() {
        let s = ss + a;
        by_distance.sort_by(|&x, &y| {
            dist2(s, x)
                .total_cmp(&dist2(s, y))
                .then(rank(x).cmp(&rank(y)))
        });
        let list: Vec<Cand> = by_distance
            .iter()
            .filter(|&&v| g.bridge_ok(s, v))
            .take(k_max)
            .map(|&v| Cand {
                v,
                len: dist2(s, v).sqrt(),
                nearest: v == near,
            })
            .collect();
        if list.is_empty() {
            return Err(BridgeFailure::NoBridgeSet { hole: hole as u32 });
        }
        cands.push(list);
    }
    // Start the cycle at the vertex of S with the fewest candidates.
    let r = (0..q).min_by_key(|&a| cands[a].len()).unwrap_or(0);
    let row = |i: usize| (r + i) % q;
    // compat[i][x * |C(i)| + y]: candidate x of row i-1 and y of row i may be consecutive
    // (for i = 0: row q-1 then row 0, closing the cycle).
    let compat: Vec<Vec<bool>> = (0..q)
        .map(|i| {
            let (a0, a1) = (row((i + q - 1) % q), row(i));
            let (c0, c1) = (&cands[a0], &cands[a1]);
            let mut t = Vec::with_capacity(c0.len() * c1.len());
            for x in c0 {
                for y in c1 {
                    t.push(g.consecutive_ok(ss + a0, x.v, ss + a1, y.v));
                }
            }
            t
        })
        .collect();
    #[derive(Clone, Copy)]
    struct State {
        cand: usize,
        /// Steps backwards along L from the start target, 0..=m.
        t: usize,
        len: f64,
        dev: u32,
        pred: usize,
    }
    let better = |len: f64, dev: u32, than: Option<(f64, u32)>| match than {
        None => true,
        Some((l, d)) => len < l || (len == l && dev < d),
    };
    let mut best: Option<(f64, u32, Vec<usize>)> = None;
    for (c0, start) in cands[row(0)].iter().enumerate() {
        let mut table: Vec<Vec<State>> = Vec::with_capacity(q);
        table.push(vec![State {
            cand: c0,
            t: 0,
            len: start.len,
            dev: u32::from(!start.nearest),
            pred: usize::MAX,
        }]);
        for i in 1..q {
            let a = row(i);
            let width = cands[a].len();
            let mut states: Vec<State> = Vec::with_capacity(width + 1);
            for (ci, c) in cands[a].iter().enumerate() {
                let t = back(start.v, c.v);
                states.push(State {
                    cand: ci,
                    t,
                    len: f64::INFINITY,
                    dev: 0,
                    pred: usize::MAX,
                });
                if c.v == start.v {
                    states.push(State {
                        cand: ci,
                        t: m,
                        len: f64::INFINITY,
                        dev: 0,
                        pred: usize::MAX,
                    });
                }
            }
            let prev = &table[i - 1];
            for st in states.iter_mut() {
                let c = cands[a][st.cand];
                let mut found: Option<(f64, u32)> = None;
                for (pi, ps) in prev.iter().enumerate() {
                    if ps.pred == usize::MAX && i > 1 {
                        continue; // unreachable
                    }
                    if ps.t > st.t || st.t - ps.t >= m || !compat[i][ps.cand * width + st.cand] {
                        continue;
                    }
                    let (len, dev) = (ps.len + c.len, ps.dev + u32::from(!c.nearest));
                    if better(len, dev, found) {
                        found = Some((len, dev));
                        st.len = len;
                        st.dev = dev;
                        st.pred = pi;
                    }
                }
            }
            table.push(states);
        }
        // Close the cycle: the last step backwards, m - t, must be 0..m-1.
        let width0 = cands[row(0)].len();
        let last = &table[q - 1];
        for (li, st) in last.iter().enumerate() {
            let reachable = q == 1 || st.pred != usize::MAX;
            if !reachable || st.t == 0 || !compat[0][st.cand * width0 + c0] {
                continue;
            }
            if better(st.len, st.dev, best.as_ref().map(|b| (b.0, b.1))) {
                let mut chosen = vec![0usize; q];
                let mut idx = li;
                for i in (0..q).rev() {
                    let s = table[i][idx];
                    chosen[row(i)] = cands[row(i)][s.cand].v;
                    idx = s.pred;
                }
                best = Some((st.len, st.dev, chosen));
            }
        }
    }
    match best {
        Some((_, _, map)) => Ok(HolePlan {
            hole,
            s_loop,
            l_loop,
            map,
            choice: BridgeChoice::Optimised,
        }),
        None => Err(BridgeFailure::NoBridgeSet { hole: hole as u32 }),
    }
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
