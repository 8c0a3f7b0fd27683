//! The cut region: the faces the cut may touch, with their own vertex, face and edge
//! numbers ([`super::ids`]), their adjacency, and L (spec §4: the mean screen edge length of
//! the faces the stroke meets, which scales every threshold of seed 002 §3.2).
//!
//! The region holds every face within the snap distance max_ratio · L of the stroke on
//! screen (no snap and no crossing reaches beyond), so every vertex within that distance has
//! all its faces in it ("complete"), and so has every edge the stroke crosses: the adjacency
//! is exact wherever the cut acts. Faces straddling the eye plane are kept too, so an edge
//! they share with a cut face is split on both sides. L is measured on the region, and the
//! region's extent depends on L: the candidates are looked for within a margin first guessed,
//! and grown once when the snap distance turns out larger.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::fast::edges::EdgeTable;
use super::fast::grid::Kept;
use super::fast::{Machinery, SegmentIndex};
use super::geom::{map3, orient, segment_triangle_gap2};
use super::ids::{Le, Lf, Lv};
use super::options::{CutMode, CutOptions};
use super::view::{split_seen, Projector, Seen, SeenList};
use crate::error::{Error, Result};
use crate::mesh::PolyMesh;

/// The faces near the stroke with local ids ([`super::ids`]).
#[derive(Debug, Clone)]
pub(crate) struct Region {
    /// Triangle ids (in the triangulated input) of the faces, ascending.
    faces: Vec<u32>,
    /// Corners of each face.
    tri: Vec<[Lv; 3]>,
    /// Global ids of the vertices, ascending.
    verts: Vec<u32>,
    pos: Vec<DVec3>,
    /// Each vertex as seen (NaN behind the eye).
    seen: SeenList,
    /// Whether the snap may move the vertex, as far as the region tells: every face around
    /// it is in the region (it is within the snap distance) and in front of the eye, and the
    /// cut may split one of them (in visible-only mode, all of them).
    movable: Vec<bool>,
    /// Whether the vertex can lie on the stroke: within the snap distance of it, plus a slack
    /// far above rounding (the snapped polyline's points and segments are within a few ulps
    /// of the stroke's segments, so a vertex beyond is on none of them).
    on_band: Vec<bool>,
    /// The edge of corner i → i + 1 of each face.
    face_edges: Vec<[Le; 3]>,
    /// Ends of each edge, ascending.
    edges: Vec<[Lv; 2]>,
    /// The one or two faces of each edge, ascending ([`Lf::NONE`] for a missing second).
    edge_faces: Vec<[Lf; 2]>,
    /// Vertex → faces, CSR, each vertex's faces ascending.
    vf_start: Vec<u32>,
    vf_list: Vec<Lf>,
    /// Screen orientation sign of each face (−1, 0, +1); 0 for degenerate or clipped.
    sign: Vec<f64>,
    /// Faces the cut may split: projectable, non-degenerate, front-facing in visible-only.
    cuttable: Vec<bool>,
}

impl Region {
    pub fn face_count(&self) -> usize {
        self.tri.len()
    }

    pub fn vertex_count(&self) -> usize {
        self.verts.len()
    }

    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// The faces, in order.
    pub fn faces(&self) -> impl Iterator<Item = Lf> {
        (0..self.tri.len() as u32).map(Lf)
    }

    /// The vertices, in order.
    pub fn vertices(&self) -> impl Iterator<Item = Lv> {
        (0..self.verts.len() as u32).map(Lv)
    }

    /// The triangle (of the triangulated input) that face `f` is.
    #[inline]
    pub fn triangle(&self, f: Lf) -> u32 {
        self.faces[f.idx()]
    }

    /// The global id of vertex `v`.
    #[inline]
    pub fn global(&self, v: Lv) -> u32 {
        self.verts[v.idx()]
    }

    /// The corners of face `f`.
    #[inline]
    pub fn corners(&self, f: Lf) -> [Lv; 3] {
        self.tri[f.idx()]
    }

    /// Every face's corners, in face order.
    pub fn all_corners(&self) -> &[[Lv; 3]] {
        &self.tri
    }

    /// The edges of face `f`: corner i → i + 1.
    #[inline]
    pub fn face_edges(&self, f: Lf) -> [Le; 3] {
        self.face_edges[f.idx()]
    }

    /// The ends of edge `e`, ascending.
    #[inline]
    pub fn ends(&self, e: Le) -> [Lv; 2] {
        self.edges[e.idx()]
    }

    /// The one or two faces of edge `e`, ascending ([`Lf::NONE`] for a missing second).
    #[inline]
    pub fn edge_faces(&self, e: Le) -> [Lf; 2] {
        self.edge_faces[e.idx()]
    }

    /// Faces around vertex `v`, ascending.
    #[inline]
    pub fn vertex_faces(&self, v: Lv) -> &[Lf] {
        &self.vf_list[self.vf_start[v.idx()] as usize..self.vf_start[v.idx() + 1] as usize]
    }

    /// The screen orientation sign of face `f` (0: degenerate or clipped).
    #[inline]
    pub fn sign(&self, f: Lf) -> f64 {
        self.sign[f.idx()]
    }

    /// Whether the cut may split face `f`.
    #[inline]
    pub fn cuttable(&self, f: Lf) -> bool {
        self.cuttable[f.idx()]
    }

    /// Whether the snap may move vertex `v`, as far as the region tells ([`Region::movable`]).
    #[inline]
    pub fn movable(&self, v: Lv) -> bool {
        self.movable[v.idx()]
    }

    /// Whether vertex `v` can lie on the stroke.
    #[inline]
    pub fn on_band(&self, v: Lv) -> bool {
        self.on_band[v.idx()]
    }

    /// World position of vertex `v`.
    #[inline]
    pub fn pos(&self, v: Lv) -> DVec3 {
        self.pos[v.idx()]
    }

    /// Every vertex's world position.
    pub fn positions(&self) -> &[DVec3] {
        &self.pos
    }

    /// Every vertex as seen.
    pub fn seen_list(&self) -> &SeenList {
        &self.seen
    }

    /// Vertex `v` as seen, `None` behind the eye.
    #[inline]
    pub fn seen(&self, v: Lv) -> Option<Seen> {
        self.seen.get(v)
    }

    /// Screen position of a projectable vertex.
    #[inline]
    pub fn screen(&self, v: Lv) -> DVec2 {
        debug_assert!(self.seen.front(v), "a projectable vertex");
        self.seen.screen[v.idx()]
    }

    /// Screen corners of a projectable face.
    #[inline]
    pub fn face_screen(&self, f: Lf) -> [DVec2; 3] {
        map3(self.tri[f.idx()], |v| self.screen(v))
    }

    /// Whether a face's corners are all in front of the eye.
    #[inline]
    pub fn projectable(&self, f: Lf) -> bool {
        self.seen.front3(self.tri[f.idx()])
    }

    /// Moves vertex `v` to world point `pos`, seen at `screen` (at the same depth).
    pub fn move_vertex(&mut self, v: Lv, screen: DVec2, pos: DVec3) {
        self.seen.screen[v.idx()] = screen;
        self.pos[v.idx()] = pos;
    }

    /// NDC depth and world point at screen barycentrics `l` of face `f`: depth is affine on
    /// screen, the world point perspective-correct (weights over clip w).
    pub fn lift(&self, f: Lf, l: [f64; 3]) -> (f64, DVec3) {
        lift_with(&self.seen, &self.pos, self.tri[f.idx()], l)
    }
}

/// The region around a stroke, and what finding it measured.
pub(crate) struct Around {
    pub region: Region,
    pub length: EdgeLength,
    /// The snap distance, max_ratio · L: the region holds every face within it.
    pub reach: f64,
    /// The stroke's segments, indexed for distances up to the snap distance.
    pub segments: SegmentIndex,
    /// Faces of the triangulated input with a vertex behind the eye and one in front,
    /// ascending: never cut (spec §2), kept in the region so shared edges split on both sides.
    pub clipped: Vec<u32>,
}

/// The region of `mesh` (triangles) around the stroke's `segments` (screen space), L, and
/// the segments indexed ([`Around`]). Errors: a non-manifold or inconsistently oriented edge
/// among the region's faces.
pub(crate) fn around_stroke(
    mesh: &PolyMesh,
    segments: &[(DVec2, DVec2)],
    proj: &Projector,
    options: &CutOptions,
    machinery: Machinery,
) -> Result<Around> {
    let max_ratio = options.snap_vertex_ratio.max(options.snap_segment_ratio);
    // The margin must cover the snap distance max_ratio · L, and L is measured on the
    // region: start from a guess, grow if it was too small. The faces L is measured on
    // (those the stroke meets) are among the candidates whatever the margin, so L does not
    // change and a second round always suffices.
    let (mut margin, l_guess) = machinery.first_margin(max_ratio, mesh, proj);
    loop {
        let index = SegmentIndex::new(machinery, segments, margin, margin.max(l_guess));
        let (candidates, clipped) = index.candidate_faces(mesh, proj);
        match build(
            mesh, candidates, &index, segments, margin, max_ratio, proj, options, machinery,
        )? {
            Built::Region {
                region,
                length,
                reach,
            } => {
                return Ok(Around {
                    region: *region,
                    length,
                    reach,
                    segments: index,
                    clipped,
                })
            }
            Built::Grow(l_px) => margin = 2.0 * max_ratio * l_px,
        }
    }
}

/// What one attempt at the region gives.
enum Built {
    Region {
        region: Box<Region>,
        length: EdgeLength,
        reach: f64,
    },
    /// The snap distance, from this L, exceeds the margin: grow it and build again.
    Grow(f64),
}

/// The region from `candidates` (triangles, ascending, a superset of those within `margin`
/// of the stroke on screen, with their corners): L is measured on the faces the stroke
/// meets; when the snap distance exceeds the margin, [`Built::Grow`]; otherwise the faces
/// within the snap distance and those straddling the eye plane are kept.
#[allow(clippy::too_many_arguments)]
fn build(
    mesh: &PolyMesh,
    candidates: Kept,
    index: &SegmentIndex,
    segments: &[(DVec2, DVec2)],
    margin: f64,
    max_ratio: f64,
    proj: &Projector,
    options: &CutOptions,
    machinery: Machinery,
) -> Result<Built> {
    let Kept {
        faces: candidates,
        corners,
    } = candidates;
    let (verts, tri) = machinery.local_ids(corners, mesh.vertex_count() as usize);
    // Each vertex read from the mesh and projected once.
    let ps = mesh.positions();
    let (pos, seen): (Vec<DVec3>, (Vec<DVec2>, Vec<DVec2>)) = verts
        .par_iter()
        .with_min_len(1024)
        .map(|&v| {
            let p = ps[v as usize];
            (p, split_seen(proj.see(p)))
        })
        .unzip();
    let seen = SeenList::from(seen);
    let near: Vec<Near> = tri
        .par_iter()
        .with_min_len(1024)
        .map_init(Vec::new, |scratch, &t| {
            let corners = seen.front3(t).then(|| map3(t, |v| seen.screen[v.idx()]));
            face_near(corners, index, segments, margin, scratch)
        })
        .collect();
    let length = mean_edge_length(&tri, &near, &seen, &pos, &candidates);
    let reach = max_ratio * length.px;
    if reach > margin {
        return Ok(Built::Grow(length.px));
    }
    // Down to the snap distance: the faces the stroke meets stay, the others only if they
    // come within reach.
    let NearFaces {
        faces,
        tri,
        verts,
        seen,
        pos,
    } = keep_near(&candidates, tri, verts, seen, pos, &near, reach);
    let (sign, (cuttable, projectable)) = face_signs(&tri, &seen, &pos, options.mode);
    let (vf_start, vf_list, vf_corner, around) =
        vertex_faces_csr(&tri, verts.len(), &cuttable, &projectable);
    // Within reach of the stroke: every face around is kept.
    let (complete, on_band): (Vec<bool>, Vec<bool>) = (0..seen.len() as u32)
        .into_par_iter()
        .with_min_len(1024)
        .map(|v| match seen.get(Lv(v)) {
            Some(s) => {
                let d = index.distance_to(s.screen, segments);
                let slack = 1e-9 * (1.0 + s.screen.abs().max_element());
                (d <= reach, d <= reach + slack)
            }
            None => (false, false),
        })
        .unzip();
    let all_cuttable = options.mode == CutMode::VisibleOnly;
    let movable = complete
        .iter()
        .zip(&around)
        .map(|(&c, &a)| {
            c && a & SOME_UNPROJECTABLE == 0
                && a & SOME_CUTTABLE != 0
                && (!all_cuttable || a & SOME_UNCUTTABLE == 0)
        })
        .collect();
    let (face_edges, edges, edge_faces): EdgeTable =
        machinery.edge_table(&tri, &verts, &vf_start, &vf_corner)?;
    one_fan_each(
        &complete,
        &vf_start,
        &vf_list,
        &tri,
        &face_edges,
        &edge_faces,
        &verts,
    )?;
    let region = Region {
        faces,
        tri,
        verts,
        pos,
        seen,
        movable,
        on_band,
        face_edges,
        edges,
        edge_faces,
        vf_start,
        vf_list,
        sign,
        cuttable,
    };
    Ok(Built::Region {
        region: Box::new(region),
        length,
        reach,
    })
}

/// L on screen and in space, and the degenerate faces the stroke meets (for the report;
/// triangle ids of the triangulated input).
pub(crate) struct EdgeLength {
    pub px: f64,
    pub world: f64,
    pub degenerate_met: Vec<u32>,
}

/// L: the mean screen (and world) length of the edges of the projectable, non-degenerate
/// faces that the stroke meets, each face's three (gap-fill for seed 002 §3.2's "mean edge
/// length", spec §4: a third of their mean perimeter; an edge two of them share counts for
/// both). The perimeters are summed one after the other in face order, so L's bits depend
/// on those faces alone, not on the other candidates. `tri` are the `candidates`' corners.
fn mean_edge_length(
    tri: &[[Lv; 3]],
    near: &[Near],
    seen: &SeenList,
    pos: &[DVec3],
    candidates: &[u32],
) -> EdgeLength {
    let (mut px, mut world, mut faces) = (0.0, 0.0, 0u64);
    let mut degenerate_met = Vec::new();
    for (i, (&t, n)) in tri.iter().zip(near).enumerate() {
        if !n.met() {
            continue;
        }
        debug_assert!(seen.front3(t), "a face the stroke meets is projectable");
        let s = map3(t, |v| seen.screen[v.idx()]);
        let p = map3(t, |v| pos[v.idx()]);
        if is_degenerate(s[0], s[1], s[2], p) {
            degenerate_met.push(candidates[i]);
            continue;
        }
        px += (s[0] - s[1]).length() + (s[1] - s[2]).length() + (s[2] - s[0]).length();
        world += (p[0] - p[1]).length() + (p[1] - p[2]).length() + (p[2] - p[0]).length();
        faces += 1;
    }
    let n = 3 * faces;
    let (px, world) = if n == 0 {
        (0.0, 0.0)
    } else {
        (px / n as f64, world / n as f64)
    };
    EdgeLength {
        px,
        world,
        degenerate_met,
    }
}

/// A face degenerate on screen (corners `a`, `b`, `c`) or in space (corners `p`).
#[inline]
fn is_degenerate(a: DVec2, b: DVec2, c: DVec2, p: [DVec3; 3]) -> bool {
    orient(a, b, c) == 0.0 || (p[1] - p[0]).cross(p[2] - p[0]).length_squared() == 0.0
}

/// How near a face is to the stroke on screen ([`face_near`]), as one number: the squared gap
/// between them, −1 where the stroke meets the face ([`Near::MET`]), 0 for a face with a
/// corner behind the eye (kept at every radius, never cut), infinite beyond the margin
/// ([`Near::AWAY`]).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Near(f64);

/// The slack on a radius: membership only needs to be conservative.
#[inline]
fn keep_radius(r: f64) -> f64 {
    r * (1.0 + 1e-9) + 1e-12
}

impl Near {
    /// The stroke meets the face (L is measured on those).
    const MET: Near = Near(-1.0);
    /// Beyond the margin.
    const AWAY: Near = Near(f64::INFINITY);

    /// Whether the stroke meets the face.
    #[inline]
    fn met(self) -> bool {
        self.0 == Self::MET.0
    }

    /// Whether the face is within a radius whose [`keep_radius`] squared is `lim2`.
    #[inline]
    fn within(self, lim2: f64) -> bool {
        self.0 <= lim2
    }
}

/// How near a face with screen corners `s` (`None`: a corner behind the eye) is to the
/// stroke, [`Near::AWAY`] beyond `margin` ([`segment_triangle_gap2`]). Plain f64 with a
/// relative slack on the margin: membership only needs to be conservative (a face around a
/// vertex within the margin is at most as far as that vertex, up to rounding far below the
/// slack), and L is a mean; every topological decision is taken later by exact predicates.
/// Segments whose box is farther than the margin from the face's are skipped: they can
/// neither meet it nor be the nearest within the margin.
fn face_near(
    s: Option<[DVec2; 3]>,
    index: &SegmentIndex,
    segments: &[(DVec2, DVec2)],
    margin: f64,
    scratch: &mut Vec<u32>,
) -> Near {
    let Some(s) = s else {
        return Near(0.0);
    };
    let keep = keep_radius(margin);
    let pad = DVec2::splat(keep);
    let (lo, hi) = (s[0].min(s[1]).min(s[2]), s[0].max(s[1]).max(s[2]));
    let near = index.near_box(lo, hi, scratch);
    let (lo, hi) = (lo - pad, hi + pad);
    let mut gap2 = f64::INFINITY;
    for &k in near {
        let (p, q) = segments[k as usize];
        if (p.max(q).cmplt(lo) | p.min(q).cmpgt(hi)).any() {
            continue;
        }
        match segment_triangle_gap2(p, q, s) {
            None => return Near::MET,
            Some(g) => gap2 = gap2.min(g),
        }
    }
    if gap2 <= keep * keep {
        Near(gap2)
    } else {
        Near::AWAY
    }
}

/// The candidates [`face_near`] kept, vertices renumbered in the same (ascending global)
/// order.
struct NearFaces {
    faces: Vec<u32>,
    tri: Vec<[Lv; 3]>,
    verts: Vec<u32>,
    seen: SeenList,
    pos: Vec<DVec3>,
}

/// [`NearFaces`] of the `candidates` within `reach` ([`Near::within`]).
fn keep_near(
    candidates: &[u32],
    tri: Vec<[Lv; 3]>,
    verts: Vec<u32>,
    seen: SeenList,
    pos: Vec<DVec3>,
    near: &[Near],
    reach: f64,
) -> NearFaces {
    let lim2 = keep_radius(reach) * keep_radius(reach);
    let kept: Vec<usize> = (0..candidates.len())
        .filter(|&i| near[i].within(lim2))
        .collect();
    let mut used = vec![false; verts.len()];
    for &i in &kept {
        for v in tri[i] {
            used[v.idx()] = true;
        }
    }
    let mut new_id = vec![Lv::NONE; verts.len()];
    let mut out = NearFaces {
        faces: kept.iter().map(|&i| candidates[i]).collect(),
        tri: Vec::with_capacity(kept.len()),
        verts: Vec::new(),
        seen: SeenList::default(),
        pos: Vec::new(),
    };
    for v in (0..verts.len()).filter(|&v| used[v]) {
        new_id[v] = Lv(out.verts.len() as u32);
        out.verts.push(verts[v]);
        out.seen.screen.push(seen.screen[v]);
        out.seen.depth.push(seen.depth[v]);
        out.pos.push(pos[v]);
    }
    out.tri = kept
        .iter()
        .map(|&i| tri[i].map(|v| new_id[v.idx()]))
        .collect();
    out
}

/// [`Region::lift`] on triangle `t` of vertices seen as `seen` at `pos`.
pub(crate) fn lift_with(seen: &SeenList, pos: &[DVec3], t: [Lv; 3], l: [f64; 3]) -> (f64, DVec3) {
    debug_assert!(seen.front3(t), "a candidate face is projectable");
    // (z, w) of each corner.
    let d = map3(t, |v| seen.depth[v.idx()]);
    let z = l[0] * d[0].x + l[1] * d[1].x + l[2] * d[2].x;
    let m = [l[0] / d[0].y, l[1] / d[1].y, l[2] / d[2].y];
    let x = (pos[t[0].idx()] * m[0] + pos[t[1].idx()] * m[1] + pos[t[2].idx()] * m[2])
        / (m[0] + m[1] + m[2]);
    (z, x)
}

/// [`vertex_faces_csr`]'s flags of a vertex's faces.
const SOME_UNPROJECTABLE: u8 = 1;
const SOME_CUTTABLE: u8 = 2;
const SOME_UNCUTTABLE: u8 = 4;

/// Vertex → faces (CSR, faces ascending within each vertex), beside each face its corner at
/// the vertex (3 · face + corner), and what the faces around each vertex are (`SOME_*` flags
/// from `cuttable` and `projectable`).
#[allow(clippy::type_complexity)]
fn vertex_faces_csr(
    tri: &[[Lv; 3]],
    nv: usize,
    cuttable: &[bool],
    projectable: &[bool],
) -> (Vec<u32>, Vec<Lf>, Vec<u32>, Vec<u8>) {
    let mut vf_start = vec![0u32; nv + 1];
    for t in tri {
        for &v in t {
            vf_start[v.idx() + 1] += 1;
        }
    }
    for k in 0..nv {
        vf_start[k + 1] += vf_start[k];
    }
    let mut fill = vf_start.clone();
    let mut vf_list = vec![Lf::NONE; vf_start[nv] as usize];
    let mut vf_corner = vec![0u32; vf_start[nv] as usize];
    let mut around = vec![0u8; nv];
    for (lf, t) in tri.iter().enumerate() {
        let flags = if projectable[lf] {
            0
        } else {
            SOME_UNPROJECTABLE
        } | if cuttable[lf] {
            SOME_CUTTABLE
        } else {
            SOME_UNCUTTABLE
        };
        for (c, &v) in t.iter().enumerate() {
            let at = fill[v.idx()] as usize;
            vf_list[at] = Lf(lf as u32);
            vf_corner[at] = 3 * lf as u32 + c as u32;
            fill[v.idx()] += 1;
            around[v.idx()] |= flags;
        }
    }
    (vf_start, vf_list, vf_corner, around)
}

/// Each face's screen orientation sign (0 for a degenerate or clipped face), whether the
/// cut may split it and whether it is in front of the eye.
#[allow(clippy::type_complexity)]
fn face_signs(
    tri: &[[Lv; 3]],
    seen: &SeenList,
    pos: &[DVec3],
    mode: CutMode,
) -> (Vec<f64>, (Vec<bool>, Vec<bool>)) {
    tri.par_iter()
        .with_min_len(2048)
        .map(|&t| {
            if !seen.front3(t) {
                return (0.0, (false, false));
            }
            let [a, b, c] = map3(t, |v| seen.screen[v.idx()]);
            let p = map3(t, |v| pos[v.idx()]);
            if is_degenerate(a, b, c, p) {
                return (0.0, (false, true));
            }
            let o = orient(a, b, c);
            // Front-facing = counter-clockwise in y-up NDC = negative orient on the y-down
            // screen.
            let cuttable = match mode {
                CutMode::ThroughAll => true,
                CutMode::VisibleOnly => o < 0.0,
            };
            (o.signum(), (cuttable, true))
        })
        .unzip()
}

/// Spec §1: the vertices within reach of the stroke (`complete`: all their faces are in the
/// region) each have one fan of faces, closed or open. A bow-tie vertex, whose faces form
/// several fans that touch only at it, is [`Error::NonManifoldVertex`] (the first in vertex
/// order): the cut would move or open it as if its fans were one surface. Faces around a
/// vertex are joined through the edges at it that they share.
fn one_fan_each(
    complete: &[bool],
    vf_start: &[u32],
    vf_list: &[Lf],
    tri: &[[Lv; 3]],
    face_edges: &[[Le; 3]],
    edge_faces: &[[Lf; 2]],
    verts: &[u32],
) -> Result<()> {
    let fans = |v: usize| -> u32 {
        let around = &vf_list[vf_start[v] as usize..vf_start[v + 1] as usize];
        let mut seen = vec![false; around.len()];
        let mut stack = Vec::new();
        let mut fans = 0;
        for start in 0..around.len() {
            if seen[start] {
                continue;
            }
            fans += 1;
            seen[start] = true;
            stack.push(start);
            while let Some(k) = stack.pop() {
                let f = around[k];
                let t = tri[f.idx()];
                for c in (0..3).filter(|&c| t[c].idx() == v) {
                    // The two sides of the face at its corner c: c → c + 1 and c − 1 → c.
                    for e in [face_edges[f.idx()][c], face_edges[f.idx()][(c + 2) % 3]] {
                        if !e.is_some() {
                            continue;
                        }
                        for g in edge_faces[e.idx()] {
                            if let Ok(j) = around.binary_search(&g) {
                                if !seen[j] {
                                    seen[j] = true;
                                    stack.push(j);
                                }
                            }
                        }
                    }
                }
            }
        }
        fans
    };
    let bad = (0..complete.len())
        .into_par_iter()
        .with_min_len(1024)
        .filter(|&v| complete[v])
        .map(|v| (v, fans(v)))
        .find_first(|&(_, n)| n > 1);
    match bad {
        Some((v, fans)) => Err(Error::NonManifoldVertex {
            vertex: verts[v],
            fans,
        }),
        None => Ok(()),
    }
}
