//! The cut region: candidate faces with local vertex ids, local edge adjacency (sorted
//! vectors, no hashing), the local manifold check, and L.
//!
//! Only the faces within the snap distance of the stroke (max_ratio · L) are ever looked at
//! after the two streaming passes ([`super::fast::grid`]) and L's measurement on their
//! candidates. Every vertex within that distance has all its faces
//! among them ("complete"), and so has every edge the stroke crosses, so the local adjacency
//! is exact wherever the cut acts; faces straddling the eye plane are kept too, so an edge
//! they share with a cut face is split on both sides.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::fast::grid::{segment_triangle_gap2, CellGrid, Kept};
use super::geom::{map3, orient};
use super::options::{CutMode, CutOptions};
use super::view::{split_seen, Projector, SeenList};
use super::visibility::FaceBuckets;
use crate::error::{Error, Result};
use crate::mesh::PolyMesh;

pub(crate) const NONE: u32 = u32::MAX;
/// The grid cell x of a vertex behind the eye, in the region's build.
const BEHIND_CELL: i32 = i32::MIN;

/// Local data of the candidate faces. `lf` indexes faces, `lv` vertices, `le` edges.
#[derive(Debug, Clone)]
pub(crate) struct Region {
    /// Triangle ids (in the triangulated input), ascending.
    pub faces: Vec<u32>,
    /// Corners of each face, local vertex ids.
    pub tri: Vec<[u32; 3]>,
    /// Global vertex ids, ascending.
    pub verts: Vec<u32>,
    pub pos: Vec<DVec3>,
    /// Each vertex as seen (NaN behind the eye).
    pub seen: SeenList,
    /// Whether the snap may move the vertex, as far as the region tells: every face around
    /// it is in the region (it is within the snap distance) and in front of the eye, and the
    /// cut may split one of them (in visible-only mode, all of them).
    pub movable: Vec<bool>,
    /// Whether the vertex can lie on the stroke: within the snap distance of it, plus a slack
    /// far above rounding (the snapped polyline's points and segments are within a few ulps
    /// of the stroke's segments, so a vertex beyond is on none of them).
    pub on_band: Vec<bool>,
    /// Local edge of corner i → i+1 of each face. The edge table (this and the next two) is
    /// empty until [`Region::set_edges`].
    pub face_edges: Vec<[u32; 3]>,
    /// Endpoints of each local edge (ascending local ids).
    pub edges: Vec<[u32; 2]>,
    /// The one or two candidate faces of each edge (`NONE` for a missing second).
    pub edge_faces: Vec<[u32; 2]>,
    /// CSR vertex → faces.
    vf_start: Vec<u32>,
    vf_list: Vec<u32>,
    /// Screen orientation sign of each face (−1, 0, +1); 0 for degenerate or clipped.
    pub sign: Vec<f64>,
    /// Faces the cut may split: projectable, non-degenerate, front-facing in visible-only.
    pub cuttable: Vec<bool>,
}

impl Region {
    /// NDC depth and world point at screen barycentrics `l` of local face `f`: depth is
    /// affine on screen, the world point perspective-correct (weights over clip w).
    pub fn lift(&self, f: u32, l: [f64; 3]) -> (f64, DVec3) {
        lift_with(&self.seen, &self.pos, self.tri[f as usize], l)
    }

    /// `candidates`: triangles, ascending, a superset of those within `margin` of the stroke
    /// on screen ([`super::fast::grid::candidate_faces`]). L is measured on the faces the
    /// stroke meets; when the snap distance `max_ratio` · L exceeds the margin the region is
    /// not built ([`Built::Grow`]). Otherwise the region keeps the faces within the snap
    /// distance (none beyond can be reached by a snap or a crossing) and the faces straddling
    /// the eye plane, with its faces bucketed for visibility tests in visible-only mode
    /// (built beside the vertex → face lists). The edge table is left for
    /// [`Region::edges_job`]: nothing before the snap reads it, so the cut builds it beside
    /// the snap.
    #[allow(clippy::too_many_arguments)]
    pub fn build(
        mesh: &PolyMesh,
        candidates: Kept,
        grid: &CellGrid,
        segments: &[(DVec2, DVec2)],
        margin: f64,
        max_ratio: f64,
        proj: &Projector,
        options: &CutOptions,
    ) -> Result<Built> {
        let (mode, depth_eps_rel) = (options.mode, options.depth_eps_rel);
        let Kept {
            faces: candidates,
            corners,
        } = candidates;
        let (verts, tri) = local_ids(corners, mesh.vertex_count() as usize);
        // Each position read once from the mesh (its vertices are scattered through it:
        // reading them again per edge or face missed the caches), on rayon with the
        // projection so the misses overlap, and prefetched a few vertices ahead (on a mesh
        // whose vertex order is not spatial, a subdivided one, nearly every read misses).
        let ps = mesh.positions();
        // With each vertex's grid cell: membership is measured on screen, each vertex
        // projected once and placed in its grid cell once (a face's cell range is its
        // corners' least and greatest); behind the eye, `BEHIND_CELL`, so the near test tells
        // a clipped face from the cells it reads anyway. In the same pass as the reads (a
        // pass of its own was one more wait for the other thread).
        #[allow(clippy::type_complexity)]
        let (pos, (seen, cells)): (
            Vec<DVec3>,
            ((Vec<DVec2>, Vec<DVec2>), Vec<(i32, i32)>),
        ) = (0..verts.len())
            .into_par_iter()
            .with_min_len(1024)
            .map(|i| {
                if let Some(&ahead) = verts.get(i + 24) {
                    crate::mem::prefetch(ps.as_ptr().wrapping_add(ahead as usize));
                }
                let p = ps[verts[i] as usize];
                let (s, d) = split_seen(proj.see(p));
                let cell = if SeenList::in_front(d) {
                    // Far left of the grid either way, but never taken for behind the eye.
                    let (cx, cy) = grid.cell(s);
                    (cx.max(BEHIND_CELL + 1), cy)
                } else {
                    (BEHIND_CELL, 0)
                };
                (p, ((s, d), cell))
            })
            .unzip();
        let seen = SeenList::from(seen);
        // L's parts beside the near test, one a job (a serial pass after it was a sixth of
        // the region's build).
        let mut near: Vec<Near> = vec![Near::AWAY; tri.len()];
        let parts: Vec<LengthSum> = near
            .par_chunks_mut(NEAR_JOB)
            .zip(tri.par_chunks(NEAR_JOB))
            .enumerate()
            .map(|(job, (near, tri))| {
                let mut part = LengthSum::default();
                for (i, (n, &t)) in near.iter_mut().zip(tri).enumerate() {
                    *n = face_near(t, &seen.screen, &cells, grid, segments, margin);
                    if n.met() {
                        part.add((job * NEAR_JOB + i) as u32, t, &seen, &pos);
                    }
                }
                part
            })
            .collect();
        let mut length = mean_edge_length(parts);
        for f in &mut length.degenerate_met {
            *f = candidates[*f as usize];
        }
        let reach = max_ratio * length.px;
        if reach > margin {
            return Ok(Built::Grow(length.px));
        }
        // Down to the snap distance: the faces the stroke meets stay, the others only if
        // they come within reach.
        let NearFaces {
            faces,
            tri,
            verts,
            seen,
            pos,
        } = keep_near(&candidates, tri, verts, seen, pos, &near, reach);
        let (sign, (cuttable, projectable)) = face_signs(&tri, &seen, &pos, mode);
        // The visibility buckets (the longest) beside the adjacency and the per-vertex data.
        // The buckets' boxes are grown by the snap distance.
        let complete = || -> (Vec<bool>, Vec<bool>) {
            // Within reach of the stroke: every face around is kept.
            (0..seen.len() as u32)
                .into_par_iter()
                .with_min_len(1024)
                .map(|v| match seen.get(v) {
                    Some(s) => {
                        let d = grid.distance_to(s.screen, segments);
                        let slack = 1e-9 * (1.0 + s.screen.abs().max_element());
                        (d <= reach, d <= reach + slack)
                    }
                    None => (false, false),
                })
                .unzip()
        };
        let lists = || {
            rayon::join(
                || vertex_faces_csr(&tri, verts.len(), &cuttable, &projectable),
                complete,
            )
        };
        // Only visible-only mode asks what hides a point (through all, the few points a cut
        // locates get their own table: `locate`). Without the buckets, no join around the
        // lists: this thread would wait in it for the other one's half, and a rayon thread
        // that waits without work falls asleep.
        let (buckets, ((vf_start, vf_list, vf_corner, around), complete)) = match mode {
            CutMode::VisibleOnly => rayon::join(
                || {
                    Some(FaceBuckets::new(
                        &tri,
                        &sign,
                        &seen,
                        &pos,
                        grid,
                        depth_eps_rel,
                        reach,
                    ))
                },
                lists,
            ),
            CutMode::ThroughAll => (None, lists()),
        };
        let (complete, on_band) = complete;
        // Which the snap may move: in the lists' pass over the faces, not in a pass of the
        // snap's own over every vertex's faces (the snap then held up its step).
        let all_cuttable = mode == CutMode::VisibleOnly;
        let movable = complete
            .iter()
            .zip(&around)
            .map(|(&c, &a)| {
                c && a & SOME_UNPROJECTABLE == 0
                    && a & SOME_CUTTABLE != 0
                    && (!all_cuttable || a & SOME_UNCUTTABLE == 0)
            })
            .collect();
        let region = Region {
            faces,
            tri,
            verts,
            pos,
            seen,
            movable,
            on_band,
            face_edges: Vec::new(),
            edges: Vec::new(),
            edge_faces: Vec::new(),
            vf_start,
            vf_list,
            sign,
            cuttable,
        };
        Ok(Built::Region {
            region: Box::new(region),
            vf_corner,
            buckets,
            length,
            reach,
        })
    }

    /// The edge table's build ([`edge_table`]), to run beside steps that change the region's
    /// geometry but not its faces (the snap): it owns copies of the faces, vertices and the
    /// vertex → face lists (some 130 KiB on spot, through all), and `vf_corner` from
    /// [`Built::Region`].
    /// Its result goes to [`Region::set_edges`].
    pub fn edges_job(&self, vf_corner: Vec<u32>) -> impl FnOnce() -> Result<EdgeTable> + Send {
        let (tri, verts, vf_start) = (self.tri.clone(), self.verts.clone(), self.vf_start.clone());
        move || edge_table(&tri, &verts, &vf_start, &vf_corner)
    }

    /// Sets the edge table ([`Region::edges_job`]), or passes on its error.
    pub fn set_edges(&mut self, table: Result<EdgeTable>) -> Result<()> {
        (self.face_edges, self.edges, self.edge_faces) = table?;
        Ok(())
    }

    /// Faces around local vertex `v`, ascending.
    #[inline]
    pub fn vertex_faces(&self, v: u32) -> &[u32] {
        &self.vf_list[self.vf_start[v as usize] as usize..self.vf_start[v as usize + 1] as usize]
    }

    /// Screen position of a projectable local vertex.
    #[inline]
    pub fn screen(&self, v: u32) -> DVec2 {
        debug_assert!(self.seen.front(v), "a projectable vertex");
        self.seen.screen[v as usize]
    }

    /// Screen corners of a projectable face.
    #[inline]
    pub fn face_screen(&self, lf: u32) -> [DVec2; 3] {
        map3(self.tri[lf as usize], |v| self.screen(v))
    }

    /// Whether a face's corners are all in front of the eye.
    #[inline]
    pub fn projectable(&self, lf: u32) -> bool {
        self.tri[lf as usize].iter().all(|&v| self.seen.front(v))
    }
}

/// What [`Region::build`] gives.
pub(crate) enum Built {
    Region {
        /// Without its edge table ([`Region::edges_job`]).
        region: Box<Region>,
        /// Beside each face around each vertex, its corner there (3 · face + corner), for the
        /// edge table.
        vf_corner: Vec<u32>,
        /// Visible-only mode's visibility buckets.
        buckets: Option<FaceBuckets>,
        length: EdgeLength,
        /// The snap distance, max_ratio · L: the region holds every face within it.
        reach: f64,
    },
    /// The snap distance, from this L, exceeds the margin: grow it and build again.
    Grow(f64),
}

/// L on screen and in space, and the degenerate faces the stroke meets (for the report;
/// triangle ids of the triangulated input).
pub(crate) struct EdgeLength {
    pub px: f64,
    pub world: f64,
    pub degenerate_met: Vec<u32>,
}

/// Faces per job of the near test.
const NEAR_JOB: usize = 1024;

/// One job's faces that the stroke meets, in face order, for L ([`mean_edge_length`]).
#[derive(Default)]
struct LengthSum {
    /// Each non-degenerate face's perimeter on screen and in space.
    perimeters: Vec<(f64, f64)>,
    /// Degenerate faces the stroke meets (local ids).
    degenerate: Vec<u32>,
}

impl LengthSum {
    /// Adds local face `lf` with corners `t`, which the stroke meets (so its corners are in
    /// front of the eye).
    #[inline]
    fn add(&mut self, lf: u32, t: [u32; 3], seen: &SeenList, pos: &[DVec3]) {
        debug_assert!(seen.front3(t), "a face the stroke meets is projectable");
        let s = map3(t, |v| seen.screen[v as usize]);
        let p = map3(t, |v| pos[v as usize]);
        if is_degenerate(s[0], s[1], s[2], p) {
            self.degenerate.push(lf);
            return;
        }
        self.perimeters.push((
            (s[0] - s[1]).length() + (s[1] - s[2]).length() + (s[2] - s[0]).length(),
            (p[0] - p[1]).length() + (p[1] - p[2]).length() + (p[2] - p[0]).length(),
        ));
    }
}

/// L: the mean screen (and world) length of the edges of the projectable, non-degenerate
/// faces that the stroke meets, each face's three (gap-fill for seed 002 §3.2's "mean edge
/// length", spec §4: a third of their mean perimeter; an edge two of them share counts for
/// both). The perimeters are summed one after the other in face order, so L's bits depend on
/// those faces alone, not on which other faces were looked at. `parts` in job order.
fn mean_edge_length(parts: Vec<LengthSum>) -> EdgeLength {
    let (mut px, mut world, mut faces) = (0.0, 0.0, 0u64);
    let mut degenerate_met = Vec::new();
    for part in parts {
        for (p, w) in part.perimeters {
            px += p;
            world += w;
            faces += 1;
        }
        degenerate_met.extend(part.degenerate);
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
/// ([`Near::AWAY`]). A number, so that keeping the faces within a radius is one comparison a
/// face: a match on an enum there was a branch, and keeping took more than twice as long
/// (spot, through all, one thread: 170 → 75 µs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Near(f64);

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

/// How near face `t` is to the stroke on screen, [`Near::AWAY`] beyond `margin`
/// ([`segment_triangle_gap2`]). Plain f64 with a relative slack on the margin: membership
/// only needs to be conservative (a face around a vertex within the margin is at most as
/// far as that vertex, up to rounding far below the slack), and L is a mean; every
/// topological decision is taken later by exact predicates. `screen` and `cells`: the
/// vertices' screen points and grid cells ([`BEHIND_CELL`] behind the eye).
fn face_near(
    t: [u32; 3],
    screen: &[DVec2],
    cells: &[(i32, i32)],
    grid: &CellGrid,
    segments: &[(DVec2, DVec2)],
    margin: f64,
) -> Near {
    let c = map3(t, |v| cells[v as usize]);
    if (c[0].0 == BEHIND_CELL) | (c[1].0 == BEHIND_CELL) | (c[2].0 == BEHIND_CELL) {
        return Near(0.0);
    }
    let s = map3(t, |v| screen[v as usize]);
    let keep = keep_radius(margin);
    let pad = DVec2::splat(keep);
    let (lo, hi) = (s[0].min(s[1]).min(s[2]), s[0].max(s[1]).max(s[2]));
    // A segment within `keep` of the face is within `keep` of a point of the face's box, and
    // the cell of that point lists every segment within the margin of it (cells list those
    // within the margin and half a diagonal of their centre, with a relative slack of 1e-4
    // of the half diagonal, far above 1e-9 of the margin). Each segment tested once: the last
    // few tested are remembered (a segment spans many cells of a small box). Segments whose
    // box is farther than `keep` are skipped: they cannot be the nearest within it. A box at
    // most three cells across takes its middle cell's wide list instead: the segments it adds
    // are farther than `keep`, so they neither meet the face nor lower a gap within `keep`.
    let Some((x0, y0, x1, y1)) = grid.clamp(
        (
            c[0].0.min(c[1].0).min(c[2].0),
            c[0].1.min(c[1].1).min(c[2].1),
        ),
        (
            c[0].0.max(c[1].0).max(c[2].0),
            c[0].1.max(c[1].1).max(c[2].1),
        ),
    ) else {
        return Near::AWAY;
    };
    let (lo, hi) = (lo - pad, hi + pad);
    let mut gap2 = f64::INFINITY;
    // Whether segment k meets the face (else its gap is taken).
    let mut meets = |k: u32| {
        let (p, q) = segments[k as usize];
        // One branch for the two boxes apart (as in `segment_triangle_gap2`).
        if (p.max(q).cmplt(lo) | p.min(q).cmpgt(hi)).any() {
            return false;
        }
        match segment_triangle_gap2(p, q, s) {
            None => true,
            Some(g) => {
                gap2 = gap2.min(g);
                false
            }
        }
    };
    // A face at most three cells across (nearly all): the wide list of its middle cell.
    if let Some(list) = grid.segments_around((x0, y0, x1, y1)) {
        if list.iter().any(|&k| meets(k)) {
            return Near::MET;
        }
    } else {
        // A ring of the last four (a slice rotation per segment was a library call).
        let (mut recent, mut slot) = ([u32::MAX; 4], 0usize);
        for cy in y0..y1 + 1 {
            for &k in grid.segments_along(cy, x0, x1) {
                if recent.contains(&k) {
                    continue;
                }
                recent[slot & 3] = k;
                slot += 1;
                if meets(k) {
                    return Near::MET;
                }
            }
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
    tri: Vec<[u32; 3]>,
    verts: Vec<u32>,
    seen: SeenList,
    pos: Vec<DVec3>,
}

/// [`NearFaces`] of the `candidates` within `reach` ([`Near::within`]). Branch-free: whether a
/// face or a vertex stays is close to a coin toss, and the mispredicted branches of a
/// filter-and-push took a third of this step.
fn keep_near(
    candidates: &[u32],
    tri: Vec<[u32; 3]>,
    mut verts: Vec<u32>,
    mut seen: SeenList,
    mut pos: Vec<DVec3>,
    near: &[Near],
    reach: f64,
) -> NearFaces {
    let lim2 = keep_radius(reach) * keep_radius(reach);
    // Each index written, the count advanced by the test.
    let mut kept = vec![0u32; candidates.len()];
    let mut k = 0usize;
    for (i, &n) in near.iter().enumerate() {
        kept[k] = i as u32;
        k += n.within(lim2) as usize;
    }
    kept.truncate(k);
    let nv = verts.len();
    let mut used = vec![false; nv];
    for &i in &kept {
        for v in tri[i as usize] {
            used[v as usize] = true;
        }
    }
    // Likewise each vertex moved to the next slot, which only a used one keeps: in place
    // (slot c is at most v), so no array is made and filled for it.
    let mut new_id = vec![0u32; nv];
    let mut c = 0usize;
    for v in 0..nv {
        new_id[v] = c as u32;
        verts[c] = verts[v];
        seen.screen[c] = seen.screen[v];
        seen.depth[c] = seen.depth[v];
        pos[c] = pos[v];
        c += used[v] as usize;
    }
    verts.truncate(c);
    seen.screen.truncate(c);
    seen.depth.truncate(c);
    pos.truncate(c);
    let faces = kept.iter().map(|&i| candidates[i as usize]).collect();
    let tri2 = kept
        .iter()
        .map(|&i| tri[i as usize].map(|v| new_id[v as usize]))
        .collect();
    NearFaces {
        faces,
        tri: tri2,
        verts,
        seen,
        pos,
    }
}

/// [`Region::lift`] on triangle `t` of vertices seen as `seen` at `pos`.
pub(crate) fn lift_with(seen: &SeenList, pos: &[DVec3], t: [u32; 3], l: [f64; 3]) -> (f64, DVec3) {
    debug_assert!(seen.front3(t), "a candidate face is projectable");
    // (z, w) of each corner.
    let d = map3(t, |v| seen.depth[v as usize]);
    let z = l[0] * d[0].x + l[1] * d[1].x + l[2] * d[2].x;
    let m = [l[0] / d[0].y, l[1] / d[1].y, l[2] / d[2].y];
    let x = (pos[t[0] as usize] * m[0] + pos[t[1] as usize] * m[1] + pos[t[2] as usize] * m[2])
        / (m[0] + m[1] + m[2]);
    (z, x)
}

/// The distinct vertices of faces with `corners` (global ids, ascending) and each face's
/// corners as indices into them, through a bitmap over the mesh's `nv` vertices: a vertex's local id is
/// the number of marked vertices below it (a prefix count per 64-bit word plus a popcount).
/// Linear and cache-resident (nv / 8 bytes); a radix sort of the corners took three times
/// as long (its counters form dependency chains on nearly sorted ids).
fn local_ids(corners: Vec<[u32; 3]>, nv: usize) -> (Vec<u32>, Vec<[u32; 3]>) {
    let mut tri = corners;
    let mut bits = vec![0u64; nv.div_ceil(64)];
    // Four quarters of the corners interleaved: consecutive corners mostly mark one word,
    // and each read-modify-write of it waited for the last (a tenth of the region's build).
    let flat = tri.as_flattened();
    let q = flat.len() / 4;
    let mut mark = |v: u32| bits[(v >> 6) as usize] |= 1 << (v & 63);
    for i in 0..q {
        mark(flat[i]);
        mark(flat[q + i]);
        mark(flat[2 * q + i]);
        mark(flat[3 * q + i]);
    }
    for &v in &flat[4 * q..] {
        mark(v);
    }
    let mut below = Vec::with_capacity(bits.len());
    let mut verts = Vec::with_capacity(flat.len() / 2);
    for (w, &word) in bits.iter().enumerate() {
        below.push(verts.len() as u32);
        let mut x = word;
        while x != 0 {
            verts.push((w as u32) << 6 | x.trailing_zeros());
            x &= x - 1;
        }
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("popcnt") {
        // SAFETY: the CPU has POPCNT.
        unsafe { rank_popcnt(tri.as_flattened_mut(), &bits, &below) };
        return (verts, tri);
    }
    rank(tri.as_flattened_mut(), &bits, &below);
    (verts, tri)
}

/// Global ids to ranks among the marked bits ([`local_ids`]).
#[inline(always)]
fn rank(ids: &mut [u32], bits: &[u64], below: &[u32]) {
    for v in ids {
        let w = (*v >> 6) as usize;
        *v = below[w] + (bits[w] & ((1u64 << (*v & 63)) - 1)).count_ones();
    }
}

/// [`rank`] with the POPCNT instruction, which the baseline x86-64 target lacks (its
/// portable popcount made this loop three times as slow).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "popcnt")]
unsafe fn rank_popcnt(ids: &mut [u32], bits: &[u64], below: &[u32]) {
    rank(ids, bits, below)
}

/// A region's edge table: each face's edge per corner, each edge's ends and its faces
/// ([`Region::face_edges`], [`Region::edges`], [`Region::edge_faces`]).
pub(crate) type EdgeTable = (Vec<[u32; 3]>, Vec<[u32; 2]>, Vec<[u32; 2]>);

/// The local edges of `tri`: each face's edge per corner, each edge's ends (ascending) and
/// its one or two faces; a non-manifold or inconsistently oriented edge is an error naming
/// its global vertices (`verts`), the first in vertex order. Edges are numbered in order of
/// (smaller end, larger end): the vertices are cut in two halves, whose rows
/// ([`edge_rows`]) are found on two threads and numbered after each other, so the numbers
/// do not depend on the thread count.
fn edge_table(
    tri: &[[u32; 3]],
    verts: &[u32],
    vf_start: &[u32],
    vf_corner: &[u32],
) -> Result<EdgeTable> {
    use std::sync::atomic::{AtomicU32, Ordering::Relaxed};
    const HIGH: u32 = 1 << 31;
    let corner_edge: Vec<AtomicU32> = (0..3 * tri.len()).map(|_| AtomicU32::new(NONE)).collect();
    let nv = verts.len() as u32;
    let mid = nv / 2;
    let (lo, hi) = rayon::join(
        || edge_rows(tri, verts, vf_start, vf_corner, 0..mid, &corner_edge, 0),
        || edge_rows(tri, verts, vf_start, vf_corner, mid..nv, &corner_edge, HIGH),
    );
    let (mut edges, mut edge_faces) = lo?;
    let (e2, ef2) = hi?;
    let offset = edges.len() as u32;
    edges.reserve_exact(e2.len());
    edge_faces.reserve_exact(ef2.len());
    edges.extend_from_slice(&e2);
    edge_faces.extend_from_slice(&ef2);
    let face_edges = corner_edge
        .chunks_exact(3)
        .map(|c| {
            [0, 1, 2].map(|i| {
                let e = c[i].load(Relaxed);
                if e != NONE && e & HIGH != 0 {
                    (e & !HIGH) + offset
                } else {
                    e
                }
            })
        })
        .collect();
    Ok((face_edges, edges, edge_faces))
}

/// The edges at the vertices `rows` as their smaller end ([`edge_table`]), numbered from 0,
/// each corner's edge stored in `corner_edge[3·face + corner]` with `tag` or-ed in. Found
/// vertex by vertex from the corners around each (`vf_start`, `vf_corner`): each corner's
/// edge is listed at its smaller end, the few there sorted in place (a counting sort of all
/// corner edges by their smaller end scattered them through a table three times larger).
#[allow(clippy::type_complexity)]
fn edge_rows(
    tri: &[[u32; 3]],
    verts: &[u32],
    vf_start: &[u32],
    vf_corner: &[u32],
    rows: std::ops::Range<u32>,
    corner_edge: &[std::sync::atomic::AtomicU32],
    tag: u32,
) -> Result<(Vec<[u32; 2]>, Vec<[u32; 2]>)> {
    use std::sync::atomic::Ordering::Relaxed;
    let n = rows.len();
    let mut edges = Vec::with_capacity(n * 3 + 16);
    let mut edge_faces = Vec::with_capacity(n * 3 + 16);
    // (neighbour, corner, kind) packed as neighbour · 2³² + corner · 2 + kind: one comparison
    // each in the sort (a pair's derived order was two, with a branch between). The kind
    // tells which end of the edge the corner is at: 0 at `a` (the edge to the next corner),
    // 1 at the neighbour (from the previous corner), so the orientation check reads no face.
    debug_assert!(tri.len() < 1 << 30, "corners fit in 31 bits");
    let mut at: Vec<u64> = Vec::with_capacity(32);
    let flat = tri.as_flattened();
    for a in rows {
        // The edges to the next and previous corner of each corner at `a`, kept when `a` is
        // their smaller end: written either way, the count advanced by the test (whether a
        // neighbour's id is larger is a coin toss; a search for `a` among each face's corners
        // and a push per kept edge took 5% of the region's build more).
        let corners = &vf_corner[vf_start[a as usize] as usize..vf_start[a as usize + 1] as usize];
        at.clear();
        at.resize(2 * corners.len(), 0);
        let mut n = 0;
        for &k in corners {
            let (f, c) = (k / 3, k % 3);
            let (cn, cp) = (
                if c == 2 { 0 } else { c + 1 },
                if c == 0 { 2 } else { c - 1 },
            );
            let (next, prev) = (flat[(3 * f + cn) as usize], flat[(3 * f + cp) as usize]);
            at[n] = (next as u64) << 32 | (k as u64) << 1;
            n += (next > a) as usize;
            at[n] = (prev as u64) << 32 | ((3 * f + cp) as u64) << 1 | 1;
            n += (prev > a) as usize;
        }
        at.truncate(n);
        super::fast::radix::small_sort(&mut at);
        let mut i = 0;
        while i < at.len() {
            let b = (at[i] >> 32) as u32;
            let mut j = i + 1;
            while j < at.len() && (at[j] >> 32) as u32 == b {
                j += 1;
            }
            let global = || (verts[a as usize], verts[b as usize]);
            if j - i > 2 {
                let (ga, gb) = global();
                return Err(Error::NonManifoldEdge {
                    a: ga,
                    b: gb,
                    uses: (j - i) as u32,
                });
            }
            let corner_of = |k: usize| at[k] as u32 >> 1;
            // Both uses run the same way: from `a` (kind 0) or from the neighbour (1).
            if j - i == 2 && (at[i] ^ at[i + 1]) & 1 == 0 {
                let (ga, gb) = global();
                let (fa, fb) = if at[i] & 1 == 0 { (ga, gb) } else { (gb, ga) };
                return Err(Error::InconsistentOrientation { a: fa, b: fb });
            }
            let e = edges.len() as u32;
            debug_assert!(e & tag == 0, "an edge number reaches the tag bit");
            edges.push([a, b]);
            let mut ef = [NONE; 2];
            for k in i..j {
                corner_edge[corner_of(k) as usize].store(e | tag, Relaxed);
                ef[k - i] = corner_of(k) / 3;
            }
            edge_faces.push(ef);
            i = j;
        }
    }
    Ok((edges, edge_faces))
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
    tri: &[[u32; 3]],
    nv: usize,
    cuttable: &[bool],
    projectable: &[bool],
) -> (Vec<u32>, Vec<u32>, Vec<u32>, Vec<u8>) {
    let mut vf_start = vec![0u32; nv + 1];
    for t in tri {
        for &v in t {
            vf_start[v as usize + 1] += 1;
        }
    }
    for k in 0..nv {
        vf_start[k + 1] += vf_start[k];
    }
    let mut fill = vf_start.clone();
    let mut vf_list = vec![0u32; vf_start[nv] as usize];
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
            let at = fill[v as usize] as usize;
            vf_list[at] = lf as u32;
            vf_corner[at] = 3 * lf as u32 + c as u32;
            fill[v as usize] += 1;
            around[v as usize] |= flags;
        }
    }
    (vf_start, vf_list, vf_corner, around)
}

/// Each face's screen orientation sign (0 for a degenerate or clipped face), whether the
/// cut may split it and whether it is in front of the eye, on rayon.
#[allow(clippy::type_complexity)]
fn face_signs(
    tri: &[[u32; 3]],
    seen: &SeenList,
    pos: &[DVec3],
    mode: CutMode,
) -> (Vec<f64>, (Vec<bool>, Vec<bool>)) {
    tri.par_iter()
        .with_min_len(2048)
        .map(|t| {
            if !seen.front3(*t) {
                return (0.0, (false, false));
            }
            let [a, b, c] = map3(*t, |v| seen.screen[v as usize]);
            let p = [pos[t[0] as usize], pos[t[1] as usize], pos[t[2] as usize]];
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
