//! What [`super::cut_by_stroke`] returns: the mesh, the face map and the report a user reads.

use glam::DVec3;

use super::first_normalization::{key_cmp, Elem, Elements};
use super::geom::in_triangle;
use super::ids::Lv;
use super::path_and_opening::{Path, Steps};
use super::region::{EdgeLength, Region};
use super::snap::Snapped;
use super::stroke_checks::{Pieces, Prepared};
use super::triangulate::Triangles;
use crate::mesh::{FaceId, PolyMesh, VertexId};

/// The result of a cut.
#[derive(Debug, Clone)]
pub struct CutOutput {
    /// The cut mesh, all triangles. Vertex `v` of the input is vertex `v` here (possibly moved
    /// by snapping, [`CutReport::moved`]); new vertices follow, split vertices first, then
    /// copies made by opening. Face `f` of the (triangulated) input keeps slot `f`; a split
    /// face's other pieces are appended.
    pub mesh: PolyMesh,
    /// For each output face, the face of the INPUT mesh it lies in (before triangulation),
    /// so UVs, materials and labels follow.
    pub face_origin: Vec<FaceId>,
    /// What was done.
    pub report: CutReport,
    /// Where each output face and vertex comes from, for [`CutOutput::interpolate_corner_data`].
    pub(crate) provenance: super::interpolate::Provenance,
}

/// A model vertex moved onto the stroke (seed 002 §3.2, Fig. 4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexMove {
    /// The vertex (same id in input and output).
    pub vertex: VertexId,
    /// Position before.
    pub from: DVec3,
    /// Position after: same clip-space w and NDC depth, moved parallel to the screen.
    pub to: DVec3,
    /// Distance moved on screen, pixels.
    pub pixels: f64,
}

/// Which stage of the paper set a stroke point aside (indices into the input stroke).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct DroppedPoints {
    /// Closer than `min_stroke_px` to the previous kept point, or a closing point merged into
    /// the first (spec §4 preprocessing).
    pub preprocessing: Vec<u32>,
    /// Inside a face, so the cut passes by it on straight chords (seed 002 §3.3, Fig. 5:
    /// first normalization).
    pub first_normalization: Vec<u32>,
    /// On a vertex or an edge, but removed so no triangle is crossed twice (seed 002 §3.3,
    /// Figs. 8-10: second normalization).
    pub second_normalization: Vec<u32>,
    /// Over no face the cut may touch (background, hidden or back faces in visible-only mode,
    /// faces behind the eye): nothing to cut there.
    pub off_mesh: Vec<u32>,
}

/// The cut's edge path for one chain of a stroke piece (one sheet, one visible stretch).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CutPath {
    /// The stroke piece (split at sharp corners, seed 002 §3.4) this path belongs to; a
    /// closed stroke that is cut whole reports its two halves joined, under piece 0.
    pub piece: u32,
    /// Output vertices along the path, in stroke order; consecutive ones share an output
    /// edge. When the cut is opened these are the ids before opening: around each of them the
    /// faces of one wedge kept the id, the others' corners moved to copies (ids at the end).
    pub vertices: Vec<VertexId>,
    /// Whether the path returns to its first vertex (the last edge joins last and first).
    pub closed: bool,
}

/// What a cut did, so nothing is simplified silently.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CutReport {
    /// Vertices moved onto the stroke, ascending id.
    pub moved: Vec<VertexMove>,
    /// The largest move in world units (0 when none).
    pub max_move_world: f64,
    /// The largest move in pixels (0 when none).
    pub max_move_px: f64,
    /// Vertices that were within the snap distance but kept in place because moving them
    /// would flip or flatten a face (fold-over guard, spec §4 step 2, gap-fill), ascending.
    pub snaps_refused: Vec<VertexId>,
    /// Stroke points dropped, by stage.
    pub dropped: DroppedPoints,
    /// Piece ends (stroke ends, sharp corners) that lay inside a face within
    /// `snap_segment_ratio`·L / 3 of one of its edges and were moved onto that edge, so the
    /// face is not split into a sliver by seed 002's 1 → 3 split (gap-fill); input stroke
    /// indices, ascending.
    pub ends_moved_to_edges: Vec<u32>,
    /// Number of stroke pieces after splitting at sharp corners (seed 002 §3.4).
    pub pieces: u32,
    /// Vertices added: split vertices and opening copies.
    pub new_vertices: u32,
    /// Faces added (output faces minus triangulated input faces).
    pub new_faces: u32,
    /// Triangulated input faces that were split (their ids in the triangulated input, which
    /// for a triangle mesh are the input's).
    pub split_faces: u32,
    /// The edge paths, per piece and chain.
    pub paths: Vec<CutPath>,
    /// Faces under the stroke's region with a vertex behind the eye and one in front: never
    /// cut (spec §2 `CLIPPED_FACES_SKIPPED`). Input face ids, ascending.
    pub clipped_faces: Vec<FaceId>,
    /// Faces near the stroke with zero area on screen or in space: never split by a path
    /// (spec §6.10); they may still get a vertex on an edge to avoid T-junctions.
    pub degenerate_faces: Vec<FaceId>,
    /// L, the mean screen length of the edges of the faces the stroke passes over (each
    /// face's three), pixels (gap-fill for the paper's "mean edge length", spec §4). 0 when
    /// the stroke meets no face.
    pub mean_edge_length_px: f64,
    /// The same edges' mean length in world units.
    pub mean_edge_length_world: f64,
    /// Pairs of path elements whose straight chord crossed another piece's path inside one
    /// face (pieces are normalized separately, seed 002 §3.4); the path follows that face's
    /// edges between them instead, as (piece, output vertex, vertex).
    pub rerouted: Vec<(u32, VertexId, VertexId)>,
    /// Pairs of path elements whose chord could not be made an edge (should stay empty; a
    /// non-empty list means the path is broken there), as (piece, output vertex, vertex).
    pub unjoined: Vec<(u32, VertexId, VertexId)>,
}

impl CutReport {
    /// Whether the cut changed nothing (spec §6.1 `OK_NOTHING_CUT`): no path, no move.
    pub fn nothing_cut(&self) -> bool {
        self.paths.is_empty() && self.moved.is_empty() && self.new_faces == 0
    }
}

/// What the report is built from ([`build`]).
pub(crate) struct Parts<'a> {
    pub prep: &'a Prepared,
    pub snapped: &'a Snapped,
    pub pieces: &'a Pieces,
    pub elements: &'a Elements<'a>,
    /// Whether each occurrence is in a normalized array.
    pub placed: &'a [bool],
    pub paths: &'a [Path],
    pub rerouted: &'a Steps,
    pub unjoined: &'a Steps,
    pub clipped: &'a [u32],
    pub length: &'a EdgeLength,
    pub tris: &'a Triangles<'a>,
    pub region: &'a Region,
    /// Output vertex ids of the region's vertices and the cut's new ones.
    pub gid: &'a dyn Fn(Lv) -> VertexId,
}

/// The report's lists (the counts are the caller's).
pub(crate) fn build(p: &Parts) -> CutReport {
    let Parts {
        prep,
        snapped,
        pieces,
        elements,
        placed,
        paths,
        rerouted,
        unjoined,
        clipped,
        length,
        tris,
        region,
        gid,
    } = *p;
    let line = &snapped.line;
    let mut moved: Vec<VertexMove> = snapped
        .moves
        .iter()
        .map(|&(lv, from, to, pixels)| VertexMove {
            vertex: gid(lv),
            from,
            to,
            pixels,
        })
        .collect();
    moved.sort_by_key(|m| m.vertex);
    let max_move_world = moved
        .iter()
        .map(|m| (m.to - m.from).length())
        .fold(0.0, f64::max);
    let max_move_px = moved.iter().map(|m| m.pixels).fold(0.0, f64::max);
    let mut snaps_refused: Vec<VertexId> = snapped.refused.iter().map(|&v| gid(v)).collect();
    snaps_refused.sort_unstable();
    let mut paths: Vec<CutPath> = paths
        .iter()
        .map(|p| {
            let mut vertices: Vec<VertexId> = p.verts.iter().map(|&v| gid(v)).collect();
            let closed = vertices.len() > 2 && vertices.first() == vertices.last();
            if closed {
                vertices.pop();
            }
            CutPath {
                piece: p.piece,
                vertices,
                closed,
            }
        })
        .collect();
    if pieces.artificial && paths.len() == 2 && paths[0].piece == 0 && paths[1].piece == 1 {
        let (a, b) = (&paths[0].vertices, &paths[1].vertices);
        // Joined, the halves must enclose something: at least three distinct vertices.
        let distinct = {
            let mut v: Vec<VertexId> = a.iter().chain(b.iter()).copied().collect();
            v.sort_unstable();
            v.dedup();
            v.len()
        };
        if a.last() == b.first() && b.last() == a.first() && distinct >= 3 {
            let mut joined = a.clone();
            joined.extend_from_slice(&b[1..b.len() - 1]);
            paths = vec![CutPath {
                piece: 0,
                vertices: joined,
                closed: true,
            }];
        }
    }
    let mut ends_moved_to_edges: Vec<u32> = elements
        .ends_moved
        .iter()
        .filter_map(|&j| line.src[j as usize].map(|k| prep.input_index[k as usize]))
        .collect();
    ends_moved_to_edges.sort_unstable();
    ends_moved_to_edges.dedup();
    let tri_face = |t: u32| match &tris.origin {
        Some(o) => o[t as usize],
        None => FaceId(t),
    };
    let mut clipped_faces: Vec<FaceId> = clipped.iter().map(|&t| tri_face(t)).collect();
    clipped_faces.dedup();
    let mut degenerate_faces: Vec<FaceId> =
        length.degenerate_met.iter().map(|&t| tri_face(t)).collect();
    degenerate_faces.sort_unstable();
    degenerate_faces.dedup();
    let global_steps = |steps: &Steps| -> Vec<(u32, VertexId, VertexId)> {
        steps.iter().map(|&(p, u, w)| (p, gid(u), gid(w))).collect()
    };
    CutReport {
        moved,
        max_move_world,
        max_move_px,
        snaps_refused,
        paths,
        unjoined: global_steps(unjoined),
        ends_moved_to_edges,
        rerouted: global_steps(rerouted),
        clipped_faces,
        degenerate_faces,
        dropped: dropped_points(prep, snapped, elements, placed, region),
        ..Default::default()
    }
}

/// Sorts every input stroke point by what became of it.
fn dropped_points(
    prep: &Prepared,
    snapped: &Snapped,
    elements: &Elements,
    placed: &[bool],
    region: &Region,
) -> DroppedPoints {
    let (line, occ, in_chain) = (&snapped.line, &elements.occ, &elements.in_chain);
    let mut d = DroppedPoints {
        preprocessing: prep.dropped.clone(),
        ..Default::default()
    };
    let last = line.pts.len() - 1;
    for (j, src) in line.src.iter().enumerate() {
        let Some(k) = *src else { continue };
        if prep.closed && j == last {
            continue;
        }
        let input = prep.input_index[k as usize];
        let lo = occ.partition_point(|o| key_cmp(o.key, (j as u32, 0.0)).is_lt());
        let hi = occ.partition_point(|o| key_cmp(o.key, (j as u32, 0.0)).is_le());
        let here = lo..hi;
        if here.clone().any(|i| placed[i]) {
            continue;
        }
        if here.clone().any(|i| in_chain[i]) {
            d.second_normalization.push(input);
            continue;
        }
        let s = line.pts[j];
        let inside = elements.locate.faces_at(region, s).into_iter().any(|f| {
            if !region.cuttable(f) {
                return false;
            }
            let [a, b, c] = region.face_screen(f);
            in_triangle(a, b, c, region.sign(f), s) == Some(true)
        });
        if inside && !here.clone().any(|i| matches!(occ[i].elem, Elem::P { .. })) {
            d.first_normalization.push(input);
        } else {
            d.off_mesh.push(input);
        }
    }
    for v in [
        &mut d.first_normalization,
        &mut d.second_normalization,
        &mut d.off_mesh,
    ] {
        v.sort_unstable();
    }
    d
}
