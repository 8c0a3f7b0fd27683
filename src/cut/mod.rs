//! Cutting a triangle mesh along a hand-drawn screen stroke (seed 002: Mitani, Suzuki, "A
//! method for cutting a mesh model by hand drawn stroke achieved by a simple implementation";
//! spec `spec/stroke_cut.md`).
//!
//! The paper trades exactness for robustness and mesh quality: model vertices near the
//! stroke move onto it (§3.2, Fig. 4), the stroke is simplified so that it meets every
//! triangle at most twice (§3.3, first and second normalization, Figs. 5-10) and is split at
//! sharp corners whose ends may lie inside a face (§3.4, Figs. 11-13); three split patterns
//! then do all the work, so no triangle is cut into more than 3 pieces (4 with a stroke end
//! inside it) and no sliver or near-duplicate vertex appears where a snap was possible.
//!
//! [`cut_by_stroke`] runs the paper's steps (§3.4's list) in order: (1) snap model vertices
//! to stroke vertices, then to stroke segments; (2) split the stroke at sharp corners (the
//! spec lists this first; the corners are found on the stroke before snapping, which never
//! changes them, so the order is immaterial); (3) per piece: the end points inside faces,
//! first and second normalization, the split patterns; then (spec §4 step 8) the cut path and
//! optional opening.
//!
//! Gap-fills (the paper leaves these open; the spec's choices unless noted):
//! - L is the mean *screen* edge length of the faces the stroke meets (spec §4).
//! - Visible-only: front-facing faces, and a crossing is seen when no face under it is nearer
//!   by more than `depth_eps_rel` × the cut region's diagonal (spec §3: per crossing, a ray);
//!   a crossing that snapping did not move must also have been seen before snapping, so a
//!   snapped occluder sliding aside exposes nothing (katachi's choice).
//! - Second normalization runs to a fixed point, faces in ascending id (spec §4 step 6); the
//!   stretches of one piece that follow each other along the stroke (split by a silhouette
//!   or a hole) are normalized together, so a face left and re-entered is still crossed once
//!   (katachi's choice).
//! - A piece end within a third of the segment snap distance of an edge goes onto the edge
//!   (no sliver from the 1 → 3 split; reported in [`CutReport::ends_moved_to_edges`]), and a
//!   constructed point a rounding error from a vertex is that vertex (katachi's choice).
//! - Crossings of one edge by different chains get their own vertices; one crossing shared by
//!   chains (a silhouette, a corner) gets one (the spec's "once per edge", per crossing).
//! - Pieces are normalized apart, so two of them can cross one face on chords that cross;
//!   the later one then follows that face's edges ([`CutReport::rerouted`]).
//! - A closed stroke (last point within `min_stroke_px` of the first) without two sharp
//!   corners is cut as two halves meeting at points that hold model vertices when it can.
//! - Strokes that touch themselves, or come within 1e-9 × their size of doing so, are rejected.
//!
//! Cost: two streaming passes over the mesh (project each vertex into a grid cell about one
//! edge long; keep each face whose cell box meets the stroke's band), an exact distance test
//! on those candidates, local work on the faces within the snap margin of the stroke, and
//! one bulk copy for the output (`candidates` and `assemble` have the details). Written by
//! hand because no crate implements this paper; predicates are `robust::orient2d`.
//!
//! ```
//! use katachi::cut::{cut_by_stroke, CutMode, CutOptions, Stroke, View};
//! use katachi::mesh::shapes;
//! use glam::{DMat4, DVec2, DVec3};
//!
//! // A 4 × 4 grid of unit quads (triangulated first), seen from above.
//! let grid = shapes::grid(4, 4).unwrap();
//! let view_proj = DMat4::orthographic_rh_gl(-0.5, 4.5, -0.5, 4.5, -10.0, 10.0)
//!     * DMat4::look_at_rh(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, DVec3::Y);
//! let view = View::new(view_proj, [0.0, 0.0, 500.0, 500.0]);
//! let stroke = Stroke::new(vec![DVec2::new(20.0, 330.0), DVec2::new(480.0, 140.0)]);
//! let out = cut_by_stroke(&grid, &stroke, &view, &CutOptions::with_mode(CutMode::ThroughAll)).unwrap();
//! assert!(out.mesh.face_count() > 32); // the 32 triangles, some split
//! assert!(out.report.moved.iter().all(|m| m.pixels <= 0.3 * out.report.mean_edge_length_px));
//! assert_eq!(out.face_origin.len(), out.mesh.face_count() as usize);
//! assert_eq!(out.report.paths.len(), 1);
//! ```

mod assemble;
mod edits;
mod fast;
mod first_normalization;
mod geom;
mod interpolate;
mod locate;
mod options;
mod path_and_opening;
mod region;
mod report;
mod second_normalization;
mod snap;
mod split_patterns;
mod stroke_checks;
mod triangulate;
mod view;
mod visibility;

pub use edits::CutEdits;
pub use options::{CutMode, CutOptions};
pub use report::{CutOutput, CutPath, CutReport, DroppedPoints, VertexMove};
pub use view::{Stroke, View};

use glam::DVec2;
use rayon::prelude::*;

use crate::error::Result;
use crate::mesh::{FaceId, PolyMesh, VertexId};
use fast::grid::CellGrid;
use first_normalization::{Elem, Occ};
use region::{Region, NONE};
use visibility::Before;

use std::sync::atomic::{AtomicBool, Ordering};

/// Cuts `mesh` along `stroke` drawn over `view` (seed 002; spec §4). Never changes `mesh`.
///
/// N-gons are triangulated first (faces with holes split by their bridges first), and
/// `face_origin` maps every output face to the input face it lies in.
///
/// Errors, all before anything is computed on the mesh: [`crate::Error::InvalidOption`],
/// [`crate::Error::NonFiniteStrokePoint`], [`crate::Error::StrokeTooShort`] (fewer than two
/// points `min_stroke_px` apart), [`crate::Error::StrokeSelfIntersects`],
/// [`crate::Error::NonFiniteMatrixEntry`], [`crate::Error::SingularViewProjection`],
/// [`crate::Error::InvalidViewport`], [`crate::Error::EmptyMesh`]; then
/// [`crate::Error::NonManifoldEdge`] or [`crate::Error::InconsistentOrientation`] for an edge
/// near the stroke (the rest of the mesh is not inspected), and
/// [`crate::Error::InvalidFaceWithHoles`] for a face with holes that cannot be bridged.
pub fn cut_by_stroke(
    mesh: &PolyMesh,
    stroke: &Stroke,
    view: &View,
    options: &CutOptions,
) -> Result<CutOutput> {
    on_pool(|| {
        let (edits, tris) = plan(mesh, stroke, view, options)?;
        edits.apply_to(mesh, &tris)
    })
}

/// [`cut_by_stroke`] without building the new mesh: what the cut changes, as edits to the
/// triangulated input ([`CutEdits`]), for callers that keep their own mesh and apply them
/// in O(changes). [`CutEdits::apply`] gives [`cut_by_stroke`]'s result. Same errors.
pub fn cut_edits(
    mesh: &PolyMesh,
    stroke: &Stroke,
    view: &View,
    options: &CutOptions,
) -> Result<CutEdits> {
    on_pool(|| Ok(plan(mesh, stroke, view, options)?.0))
}

/// Runs `f` on a worker of the current rayon pool (in place when already on one). The cut's
/// dozen parallel steps then start from inside the pool: called from outside, each would
/// hand its work over to the pool and put the caller to sleep until it is done, a round
/// trip through the scheduler that costs more than a small step itself.
///
/// Beside the cut, one more worker is kept awake ([`keep_warm`]) until it is done (or
/// panics: the flag is set on unwinding too).
fn on_pool<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    struct SetOnDrop<'a>(&'a AtomicBool);
    impl Drop for SetOnDrop<'_> {
        fn drop(&mut self) {
            self.0.store(true, Ordering::Release);
        }
    }
    let done = AtomicBool::new(false);
    rayon::scope(|s| {
        if rayon::current_num_threads() > 1 {
            let caller = rayon::current_thread_index();
            let done = &done;
            s.spawn(move |_| keep_warm(caller, done));
        }
        let _done = SetOnDrop(&done);
        f()
    })
}

/// Runs the pool's pending jobs until `done`. Between its parallel steps the cut works on one
/// thread for tens of microseconds; an idle rayon worker falls asleep after a few, and waking
/// it (a futex call by the cut's thread, then a reschedule) cost each following step more
/// than its share of the work (seventeen context switches a cut). This worker stays awake
/// and takes each step's jobs at once. Never on the cut's own thread: there it would keep
/// that thread from returning to the cut. It also gives up after a millisecond without a
/// job (longer than the cut's longest serial step): a worker that runs it while its own job
/// waits for another cut on the same pool must not wait for that cut to end.
fn keep_warm(caller: Option<usize>, done: &AtomicBool) {
    if rayon::current_thread_index() == caller {
        return;
    }
    let mut last_job = std::time::Instant::now();
    while !done.load(Ordering::Acquire) {
        if rayon::yield_now() == Some(rayon::Yield::Executed) {
            last_job = std::time::Instant::now();
        } else if last_job.elapsed() > std::time::Duration::from_millis(1) {
            return;
        } else {
            std::hint::spin_loop();
        }
    }
}

/// The cut's steps (seed 002 §3.4's list, spec §4), up to the edits.
fn plan<'a>(
    mesh: &'a PolyMesh,
    stroke: &Stroke,
    view: &View,
    options: &CutOptions,
) -> Result<(CutEdits, triangulate::Triangles<'a>)> {
    let mut trace = fast::trace::Trace::start();
    options.validate()?;
    let proj = view::Projector::new(view)?;
    let prep = stroke_checks::prepare(stroke, options)?;
    mesh.require_faces("a stroke cut")?;
    let tris = triangulate::triangles(mesh)?;
    let tm: &PolyMesh = &tris.mesh;
    let n = prep.points.len();
    let segs: Vec<(DVec2, DVec2)> = (0..prep.segment_count())
        .map(|k| (prep.points[k], prep.points[(k + 1) % n]))
        .collect();
    let max_ratio = options.snap_vertex_ratio.max(options.snap_segment_ratio);

    // The region near the stroke. Its margin must cover the snap distance max_ratio · L, but
    // L is measured on the region: start from a sampled guess, grow if it was too small. The
    // faces L is measured on (those the stroke meets) are in the region whatever the margin,
    // so L does not change and a second round always suffices.
    trace.mark("prepare");
    let l_guess = fast::grid::sample_edge_length(tm.positions(), tm.corners(), &proj);
    let mut margin = 1.5 * max_ratio * l_guess;
    let (grid, clipped, mut region, vf_corner, buckets, length, reach) = loop {
        let grid = CellGrid::new(&segs, margin, margin.max(l_guess));
        trace.mark("grid");
        let codes = fast::grid::vertex_codes(tm.positions(), &proj, &grid);
        trace.mark("codes");
        let (kept, clipped) = fast::grid::candidate_faces(tm.corners(), &codes, &grid);
        trace.count("candidates", kept.faces.len());
        trace.mark("candidates");
        let built = Region::build(tm, kept, &grid, &segs, margin, max_ratio, &proj, options)?;
        trace.mark("region");
        match built {
            region::Built::Region {
                region,
                vf_corner,
                buckets,
                length,
                reach,
            } => break (grid, clipped, *region, vf_corner, buckets, length, reach),
            region::Built::Grow(l_px) => margin = 2.0 * max_ratio * l_px,
        }
    };
    let (l_px, l_world) = (length.px, length.world);
    trace.count("faces", region.faces.len());
    trace.count("verts", region.verts.len());
    let visible_only = options.mode == CutMode::VisibleOnly;

    // The edge table beside the snap, which moves vertices but changes no face (nothing
    // before the occurrences reads it): a fifth of the region's build, where the snap's
    // serial loop left the other thread idle.
    let edges_job = region.edges_job(vf_corner);
    let (edge_table, (before, snapped)) = fast::schedule::join(edges_job, || {
        // Which vertices may move: those the region's faces allow, and in visible-only mode
        // only if seen before snapping (tested only for vertices within reach of the stroke).
        let allowed: Vec<bool> = match &buckets {
            None => std::mem::take(&mut region.movable),
            Some(buckets) => (0..region.verts.len() as u32)
                .into_par_iter()
                .with_min_len(256)
                .map(|v| {
                    let (Some(seen), true) = (region.seen.get(v), region.movable[v as usize])
                    else {
                        return false;
                    };
                    grid.distance_to(seen.screen, &segs) >= reach
                        || !buckets.hidden(
                            &region,
                            seen.screen,
                            seen.z,
                            region.pos[v as usize],
                            None,
                            region.vertex_faces(v),
                        )
                })
                .collect(),
        };
        let mut before = visible_only.then(|| Before::new(&region));
        let snapped = snap::snap(
            &mut region,
            &allowed,
            &prep,
            &segs,
            &grid,
            l_px,
            options,
            &proj,
        );
        if let Some(b) = before.as_mut() {
            b.mark_moved(snapped.moves.iter().map(|m| m.0));
        }
        (before, snapped)
    });
    region.set_edges(edge_table)?;
    trace.mark("snap");
    let line = &snapped.line;
    let last = line.pts.len() as u32 - 1;

    // Pieces: split at sharp corners (seed 002 §3.4); a closed stroke without two corners is
    // cut in two halves whose ends are shared, like corners (gap-fill).
    let mut bounds: Vec<u32> = vec![0, last];
    bounds.extend(prep.corners.iter().map(|&c| snapped.start_of[c]));
    bounds.sort_unstable();
    bounds.dedup();
    let artificial = prep.closed && bounds.len() < 3;
    if artificial {
        bounds.push(middle_point(line));
        bounds.sort_unstable();
        bounds.dedup();
    }
    let pieces: Vec<(u32, u32)> = bounds.windows(2).map(|w| (w[0], w[1])).collect();

    let mut ends_moved: Vec<u32> = Vec::new();
    // The faces under piece ends and stroke points (for the report): the buckets, or
    // through all a table for just those points.
    let make_locate = || match &buckets {
        Some(b) => locate::Locator::Buckets(b),
        None => locate::Locator::Points(locate::PointFaces::new(
            &region,
            (0..line.pts.len())
                .filter(|j| line.src[*j].is_some() || bounds.contains(&(*j as u32)))
                .map(|j| line.pts[j]),
        )),
    };
    let (occ, locate) = first_normalization::find_occurrences(
        &region,
        &snapped,
        prep.closed,
        &grid,
        &bounds,
        make_locate,
        buckets.as_ref().zip(before.as_ref()),
        options.snap_segment_ratio * l_px / 3.0,
        &mut ends_moved,
    );
    ends_moved.sort_unstable();
    ends_moved.dedup();
    trace.mark("occurrences");
    trace.count("occ", occ.len());

    // Chains, normalization, split vertices.
    let mut sp = split_patterns::Splitter::new(&region, l_px);
    let mut in_chain = vec![false; occ.len()];
    let mut in_final = vec![false; occ.len()];
    let mut paths: Vec<LocalPath> = Vec::new();
    for (pi, &(j0, j1)) in pieces.iter().enumerate() {
        // Chains of one piece that follow each other along the stroke are normalized as one
        // array (gap-fill): a face the stroke leaves (through a silhouette or the boundary)
        // and re-enters is then still crossed once, as Fig. 9 intends; chains that overlap in
        // stroke order (other sheets) stay apart.
        let mut runs: Vec<Vec<u32>> = Vec::new();
        for chain in first_normalization::chains(&region, line, &occ, j0, j1) {
            for &o in &chain.occ {
                in_chain[o as usize] = true;
            }
            let first = occ[chain.occ[0] as usize].key;
            let after = |r: &Vec<u32>| {
                first_normalization::key_cmp(occ[*r.last().unwrap() as usize].key, first).is_lt()
            };
            match runs.iter_mut().find(|r| after(r)) {
                Some(r) => r.extend_from_slice(&chain.occ),
                None => runs.push(chain.occ),
            }
        }
        // Runs are normalized apart (read-only) on rayon and placed in order, each as soon
        // as it is ready: this thread places one run while the pool normalizes the next.
        let (region, occ) = (&region, &occ);
        fast::schedule::in_order(
            runs.len(),
            |r| second_normalization::normalize(region, occ, &runs[r]),
            |_, nzs| {
                for nz in nzs {
                    let mut verts: Vec<u32> = Vec::with_capacity(nz.occ.len());
                    let mut faces = Vec::with_capacity(nz.faces.len());
                    for (k, &o) in nz.occ.iter().enumerate() {
                        in_final[o as usize] = true;
                        let v = sp.vertex_for(&occ[o as usize]);
                        // A piece end merged into a neighbouring vertex adds no step.
                        if verts.last() == Some(&v) {
                            continue;
                        }
                        if k > 0 {
                            faces.push(nz.faces[k - 1]);
                        }
                        verts.push(v);
                    }
                    if verts.len() >= 2 {
                        paths.push(LocalPath {
                            piece: pi as u32,
                            verts,
                            faces,
                        });
                    }
                }
            },
        );
    }
    let split_count = sp.new_pos.len();
    trace.mark("normalize");

    // Along-edge pairs whose edge another path split run through the split vertex; chords
    // are made edges.
    let mut unjoined = Vec::new();
    let mut rerouted = Vec::new();
    let mut protected: Vec<(u32, u32)> = Vec::new();
    for p in paths.iter_mut() {
        let mut verts = Vec::with_capacity(p.verts.len());
        let mut faces = Vec::with_capacity(p.faces.len());
        for k in 0..p.verts.len() {
            if k > 0 {
                let (u, w, f) = (p.verts[k - 1], p.verts[k], p.faces[k - 1]);
                if f == NONE {
                    if let Some(e) = edge_between(&region, u, w) {
                        let mut on: Vec<u32> = sp.edge_vertices(e).iter().map(|x| x.1).collect();
                        if region.edges[e as usize][0] != u {
                            on.reverse();
                        }
                        for m in on {
                            verts.push(m);
                            faces.push(NONE);
                        }
                    }
                    faces.push(f);
                } else if sp.ensure_chord(f, u, w, &protected) {
                    protected.push((u.min(w), u.max(w)));
                    faces.push(f);
                } else if let Some(inner) = sp.route(f, u, w) {
                    // The chord crosses another piece's path in this face: follow edges.
                    rerouted.push((p.piece, u, w));
                    let mut a = u;
                    for m in inner {
                        protected.push((a.min(m), a.max(m)));
                        verts.push(m);
                        faces.push(f);
                        a = m;
                    }
                    protected.push((a.min(w), a.max(w)));
                    faces.push(f);
                } else {
                    unjoined.push((p.piece, u, w));
                    faces.push(f);
                }
            }
            verts.push(p.verts[k]);
        }
        p.verts = verts;
        p.faces = faces;
    }
    // Each path edge listed at its smaller end (a counting sort by that end, repeats kept):
    // the flips ask of every inner diagonal whether it is a path edge, and a binary search
    // of all the path edges for each took a quarter of that step; sorting the edges whole
    // for it cost a quarter of this one.
    let nv_local = region.verts.len() + sp.new_pos.len();
    let path_edges = || {
        paths
            .iter()
            .flat_map(|p| p.verts.windows(2).map(|w| (w[0].min(w[1]), w[0].max(w[1]))))
    };
    let mut path_from = vec![0u32; nv_local + 1];
    for (a, _) in path_edges() {
        path_from[a as usize + 1] += 1;
    }
    for v in 0..nv_local {
        path_from[v + 1] += path_from[v];
    }
    let mut path_to = vec![0u32; path_from[nv_local] as usize];
    let mut fill = path_from.clone();
    for (a, b) in path_edges() {
        path_to[fill[a as usize] as usize] = b;
        fill[a as usize] += 1;
    }
    drop(fill);
    let is_path_edge = |a: u32, b: u32| {
        let (x, y) = (a.min(b) as usize, a.max(b));
        path_to[path_from[x] as usize..path_from[x + 1] as usize].contains(&y)
    };
    trace.mark("route");

    // The report's parts that do not read the splitter, beside the flips (which only change
    // the pieces of split faces): output ids are the region's mesh ids, new vertices after.
    let nv_in = tm.vertex_count();
    let n0 = region.verts.len() as u32;
    let gid = |lv: u32| {
        VertexId(if lv < n0 {
            region.verts[lv as usize]
        } else {
            nv_in + lv - n0
        })
    };
    let ((), report) = rayon::join(
        || sp.improve(&is_path_edge),
        || {
            report_parts(
                &prep,
                line,
                &snapped,
                &paths,
                artificial,
                &unjoined,
                &rerouted,
                &ends_moved,
                &clipped,
                &length,
                &tris,
                &occ,
                &in_chain,
                &in_final,
                &region,
                &locate,
                &gid,
            )
        },
    );

    trace.mark("improve");
    let split_faces = sp
        .touched
        .iter()
        .filter(|&&lf| sp.pieces_of(lf).is_some_and(|s| s.len() > 1))
        .count() as u32;
    if split_faces > options.max_faces_split {
        return Err(crate::Error::CutTooLarge {
            split_faces,
            limit: options.max_faces_split,
        });
    }

    let copies_of = if options.open && !path_to.is_empty() {
        let mut pv: Vec<u32> = paths.iter().flat_map(|p| p.verts.iter().copied()).collect();
        pv.sort_unstable();
        pv.dedup();
        path_and_opening::open(&mut sp, &pv, &is_path_edge)
    } else {
        Vec::new()
    };

    // The edits, in output ids; the faces beside the split edges' lists.
    let spr = &sp;
    let ((rewritten_faces, appended_faces), (split_ends, split_start, split_on)) = rayon::join(
        || {
            let to_global = |t: &[u32; 3]| geom::map3(*t, gid);
            let n = spr.touched.len();
            let mut rewritten_faces = Vec::with_capacity(n);
            let mut appended_faces = Vec::with_capacity(2 * n);
            // Ascending local faces are ascending triangles: rewritten in order.
            for (lf, subs) in spr.touched_in_order() {
                let slot = FaceId(region.faces[lf as usize]);
                rewritten_faces.push((slot, to_global(&subs[0])));
                appended_faces.extend(subs[1..].iter().map(|t| (to_global(t), slot)));
            }
            debug_assert!(rewritten_faces.is_sorted_by_key(|x| x.0));
            (rewritten_faces, appended_faces)
        },
        || {
            let n_split = spr.new_pos.len();
            let (mut split_ends, mut split_start, mut split_on) = (
                Vec::with_capacity(n_split),
                Vec::with_capacity(n_split + 1),
                Vec::with_capacity(n_split),
            );
            split_start.push(0u32);
            for (e, &[u, w]) in region.edges.iter().enumerate() {
                let on = spr.edge_vertices(e as u32);
                if !on.is_empty() {
                    split_ends.push((gid(u), gid(w)));
                    split_on.extend(on.iter().map(|&(_, m)| gid(m)));
                    split_start.push(split_on.len() as u32);
                }
            }
            (split_ends, split_start, split_on)
        },
    );
    let report = CutReport {
        pieces: pieces.len() as u32,
        new_vertices: sp.new_pos.len() as u32,
        new_faces: appended_faces.len() as u32,
        split_faces,
        mean_edge_length_px: l_px,
        mean_edge_length_world: l_world,
        ..report
    };
    let edits = CutEdits {
        input_vertex_count: mesh.vertex_count(),
        input_triangle_count: tm.face_count(),
        new_vertices: std::mem::take(&mut sp.new_pos),
        rewritten_faces,
        appended_faces,
        split_ends,
        split_start,
        split_on,
        report,
        first_copy: nv_in + split_count as u32,
        copy_of: copies_of.iter().map(|&lv| gid(lv).0).collect(),
    };
    drop(sp);
    trace.mark("edits");
    Ok((edits, tris))
}

/// The polyline point closest to half the length of a closed stroke, preferring points that
/// hold a model vertex (no interior vertex is then needed there).
fn middle_point(line: &snap::Polyline) -> u32 {
    let n = line.pts.len();
    let mut acc = vec![0.0; n];
    for i in 1..n {
        acc[i] = acc[i - 1] + (line.pts[i] - line.pts[i - 1]).length();
    }
    let half = acc[n - 1] / 2.0;
    let pick = |pred: &dyn Fn(usize) -> bool| {
        (1..n - 1)
            .filter(|&i| pred(i))
            .min_by(|&a, &b| (acc[a] - half).abs().total_cmp(&(acc[b] - half).abs()))
    };
    // An on-vertex point within the middle half of the loop, else the nearest point.
    pick(&|i| line.on_vertex[i] && (acc[i] - half).abs() < half / 2.0)
        .or_else(|| pick(&|_| true))
        .unwrap_or(1) as u32
}

/// A cut path in local ids: the piece it cuts, its vertices, and the face of each step
/// (`NONE` along an edge).
struct LocalPath {
    piece: u32,
    verts: Vec<u32>,
    faces: Vec<u32>,
}

/// The parts of the report that do not read the splitter ([`plan`] builds them beside the
/// flips); `gid` maps local vertices to output ids.
#[allow(clippy::too_many_arguments)]
fn report_parts(
    prep: &stroke_checks::Prepared,
    line: &snap::Polyline,
    snapped: &snap::Snapped,
    paths: &[LocalPath],
    artificial: bool,
    unjoined: &[(u32, u32, u32)],
    rerouted: &[(u32, u32, u32)],
    ends_moved: &[u32],
    clipped: &[u32],
    length: &region::EdgeLength,
    tris: &triangulate::Triangles<'_>,
    occ: &[Occ],
    in_chain: &[bool],
    in_final: &[bool],
    region: &Region,
    locate: &locate::Locator,
    gid: &(dyn Fn(u32) -> VertexId + Sync),
) -> CutReport {
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
    if artificial && paths.len() == 2 && paths[0].piece == 0 && paths[1].piece == 1 {
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
    let mut ends_moved_to_edges: Vec<u32> = ends_moved
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
    let global_steps = |steps: &[(u32, u32, u32)]| -> Vec<(u32, VertexId, VertexId)> {
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
        dropped: dropped_points(prep, line, occ, in_chain, in_final, region, locate),
        ..Default::default()
    }
}

/// The local edge joining two region vertices, if any.
fn edge_between(region: &Region, u: u32, w: u32) -> Option<u32> {
    let n0 = region.verts.len() as u32;
    if u >= n0 || w >= n0 {
        return None;
    }
    // The side of a face around `u` from one to the other (an edge has one number,
    // whichever face names it); the faces' corners, not every side's ends, are read.
    region.vertex_faces(u).iter().find_map(|&f| {
        let t = region.tri[f as usize];
        (0..3)
            .find(|&i| {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                (a == u && b == w) || (a == w && b == u)
            })
            .map(|i| region.face_edges[f as usize][i])
    })
}

/// Sorts every input stroke point by what became of it.
#[allow(clippy::too_many_arguments)]
fn dropped_points(
    prep: &stroke_checks::Prepared,
    line: &snap::Polyline,
    occ: &[Occ],
    in_chain: &[bool],
    in_final: &[bool],
    region: &Region,
    locate: &locate::Locator,
) -> DroppedPoints {
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
        let lo = occ.partition_point(|o| first_normalization::key_cmp(o.key, (j as u32, 0.0)).is_lt());
        let hi = occ.partition_point(|o| first_normalization::key_cmp(o.key, (j as u32, 0.0)).is_le());
        let here = lo..hi;
        if here.clone().any(|i| in_final[i]) {
            continue;
        }
        if here.clone().any(|i| in_chain[i]) {
            d.second_normalization.push(input);
            continue;
        }
        let s = line.pts[j];
        let inside = locate.faces_at(region, s).into_iter().any(|lf| {
            if !region.cuttable[lf as usize] {
                return false;
            }
            let [a, b, c] = region.face_screen(lf);
            geom::in_triangle(a, b, c, region.sign[lf as usize], s) == Some(true)
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

#[cfg(test)]
mod tests {
    use super::on_pool;

    /// A panic inside the cut reaches the caller (the C ABI catches it) instead of leaving
    /// the kept-awake worker spinning and the pool's scope waiting for it forever; the pool
    /// still works afterwards.
    #[test]
    fn a_panic_inside_the_pool_ends_the_kept_worker() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        for _ in 0..20 {
            let r = pool.install(|| {
                std::panic::catch_unwind(|| on_pool(|| -> u32 { panic!("inside the cut") }))
            });
            assert!(r.is_err());
            let (a, b) = pool.install(|| on_pool(|| rayon::join(|| 1u64, || 2u64)));
            assert_eq!(a + b, 3);
        }
    }
}
