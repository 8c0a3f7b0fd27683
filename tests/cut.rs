//! Stroke cut (seed 002): worked cases, bad input, and the paper's invariants as properties
//! over random meshes, views and strokes.

use std::collections::{BTreeMap, BTreeSet};

use glam::{DMat4, DVec2, DVec3};
use katachi::cut::{
    cut_by_stroke, cut_edits, cut_edits_plain, CutMode, CutOptions, CutOutput, Stroke, View,
};
use katachi::mesh::{inspect, shapes};
use katachi::{Error, FaceId, PolyMesh, VertexId};
use proptest::prelude::*;

mod cut_meshes;
mod support;
use cut_meshes::{icosphere, perturbed_grid, tri_grid, view_for};
use support::property::counted_proptest;

// ---------------------------------------------------------------- meshes, views, strokes

/// Looking down −z at the rectangle [x0, x1] × [y0, y1], orthographic, `px` units per pixel.
fn top_view(x0: f64, x1: f64, y0: f64, y1: f64, px: f64) -> View {
    let vp = DMat4::orthographic_rh_gl(x0, x1, y0, y1, 0.1, 100.0)
        * DMat4::look_at_rh(DVec3::new(0.0, 0.0, 10.0), DVec3::ZERO, DVec3::Y);
    View::new(vp, [0.0, 0.0, (x1 - x0) / px, (y1 - y0) / px])
}

/// A perspective camera at `eye` looking at `target`, 60° field of view, 800 × 600 pixels.
fn perspective(eye: DVec3, target: DVec3) -> View {
    let up = if (eye - target).cross(DVec3::Y).length() < 1e-9 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    let vp = DMat4::perspective_rh_gl(60f64.to_radians(), 800.0 / 600.0, 0.05, 100.0)
        * DMat4::look_at_rh(eye, target, up);
    View::new(vp, [0.0, 0.0, 800.0, 600.0])
}

/// Screen position and (w, z_ndc) of a world point, `None` behind the eye.
fn project(view: &View, p: DVec3) -> Option<(DVec2, f64, f64)> {
    let c = view.view_proj * p.extend(1.0);
    if c.w <= 0.0 {
        return None;
    }
    let n = c.truncate() / c.w;
    let v = view.viewport;
    Some((
        DVec2::new(
            v[0] + (n.x + 1.0) / 2.0 * v[2],
            v[1] + (1.0 - n.y) / 2.0 * v[3],
        ),
        c.w,
        n.z,
    ))
}

fn screen(view: &View, p: DVec3) -> DVec2 {
    project(view, p).unwrap().0
}

fn stroke(pts: &[(f64, f64)]) -> Stroke {
    Stroke::new(pts.iter().map(|&(x, y)| DVec2::new(x, y)).collect())
}

fn through_all() -> CutOptions {
    CutOptions::with_mode(CutMode::ThroughAll)
}

fn cut(mesh: &PolyMesh, pts: &[(f64, f64)], view: &View, o: &CutOptions) -> CutOutput {
    cut_by_stroke(mesh, &stroke(pts), view, o).unwrap()
}

// ---------------------------------------------------------------- checks

fn faces_of(m: &PolyMesh) -> Vec<[u32; 3]> {
    m.faces()
        .map(|f| {
            let l = m.face_outer(f);
            assert_eq!(l.len(), 3, "the output is all triangles");
            [l[0].0, l[1].0, l[2].0]
        })
        .collect()
}

fn edge_set(m: &PolyMesh) -> BTreeSet<(u32, u32)> {
    let mut s = BTreeSet::new();
    for t in faces_of(m) {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            s.insert((a.min(b), a.max(b)));
        }
    }
    s
}

/// Per connected component (through shared vertices): (V, E, F, boundary edges), counted by
/// brute force over the face list.
fn components(m: &PolyMesh) -> Vec<(i64, i64, i64, i64)> {
    let tris = faces_of(m);
    let nv = m.vertex_count() as usize;
    let mut parent: Vec<usize> = (0..nv).collect();
    fn root(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    for t in &tris {
        for i in 1..3 {
            let (a, b) = (
                root(&mut parent, t[0] as usize),
                root(&mut parent, t[i] as usize),
            );
            parent[a] = b;
        }
    }
    let mut uses: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    for t in &tris {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut comp: BTreeMap<usize, (BTreeSet<u32>, i64, i64, i64)> = BTreeMap::new();
    for t in &tris {
        let r = root(&mut parent, t[0] as usize);
        let c = comp.entry(r).or_default();
        c.0.extend(t.iter().copied());
        c.3 += 1;
    }
    for (&(a, _), &u) in &uses {
        let r = root(&mut parent, a as usize);
        let c = comp.get_mut(&r).unwrap();
        c.1 += 1;
        if u == 1 {
            c.2 += 1;
        }
    }
    let mut v: Vec<_> = comp
        .into_values()
        .map(|(vs, e, b, f)| (vs.len() as i64, e, f, b))
        .collect();
    v.sort();
    v
}

fn euler(c: &[(i64, i64, i64, i64)]) -> i64 {
    c.iter().map(|&(v, e, f, _)| v - e + f).sum()
}

/// Valid, manifold, consistently oriented, no zero-area face, origins in range.
fn check_valid(input: &PolyMesh, out: &CutOutput) {
    assert_eq!(out.face_origin.len(), out.mesh.face_count() as usize);
    assert!(out.face_origin.iter().all(|f| f.0 < input.face_count()));
    let r = inspect(&out.mesh).unwrap();
    assert!(r.defects.is_empty(), "{:?}", r.defects);
    let ri = inspect(input).unwrap();
    assert!(r.unreferenced_vertices <= ri.unreferenced_vertices);
    // No duplicate faces.
    let mut seen = BTreeSet::new();
    for mut t in faces_of(&out.mesh) {
        t.sort_unstable();
        assert!(seen.insert(t), "duplicate face {t:?}");
    }
}

fn path_edges(out: &CutOutput) -> Vec<(u32, u32)> {
    let mut v = Vec::new();
    for p in &out.report.paths {
        let n = p.vertices.len();
        let m = if p.closed { n } else { n - 1 };
        for k in 0..m {
            let (a, b) = (p.vertices[k].0, p.vertices[(k + 1) % n].0);
            v.push((a.min(b), a.max(b)));
        }
    }
    v
}

/// Every path edge is an edge of the output (T1): the cut runs along mesh edges.
fn check_paths_are_edges(out: &CutOutput) {
    if out.report.paths.is_empty() {
        return;
    }
    let edges = edge_set(&out.mesh);
    for e in path_edges(out) {
        assert!(
            edges.contains(&e),
            "path edge {e:?} is not an edge of the output"
        );
    }
}

fn dist_to_polyline(p: DVec2, pts: &[DVec2]) -> f64 {
    pts.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let ab = b - a;
            let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
            (a + ab * t - p).length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// How many output faces each input face became.
fn pieces_per_face(out: &CutOutput) -> BTreeMap<FaceId, u32> {
    let mut m = BTreeMap::new();
    for &f in &out.face_origin {
        *m.entry(f).or_default() += 1;
    }
    m
}

// ---------------------------------------------------------------- worked cases

/// 8 × 8 grid seen from above at 50 px per unit (pixel (x, y) = (50 (X + 0.5), 50 (8.5 − Y))).
fn grid_scene() -> (PolyMesh, View) {
    (tri_grid(8, 8), top_view(-0.5, 8.5, -0.5, 8.5, 0.02))
}

fn px(x: f64, y: f64) -> (f64, f64) {
    (50.0 * (x + 0.5), 50.0 * (8.5 - y))
}

#[test]
fn stroke_along_an_edge_adds_no_vertex() {
    let (g, v) = grid_scene();
    let out = cut(&g, &[px(1.0, 4.0), px(6.0, 4.0)], &v, &through_all());
    check_valid(&g, &out);
    assert_eq!(out.report.new_vertices, 0);
    assert_eq!(out.mesh.face_count(), g.face_count());
    assert_eq!(out.report.paths.len(), 1);
    let ids: Vec<u32> = out.report.paths[0].vertices.iter().map(|v| v.0).collect();
    assert_eq!(ids, (37..=42).collect::<Vec<u32>>());
    assert!(out.report.moved.iter().all(|m| m.pixels < 1e-9));
    check_paths_are_edges(&out);
}

#[test]
fn stroke_through_a_vertex_keeps_it_on_the_path() {
    let (g, v) = grid_scene();
    // Diagonal crossing vertex (4, 4) exactly, between grid lines elsewhere; no snapping.
    let mut o = through_all();
    o.snap_vertex_ratio = 0.0;
    o.snap_segment_ratio = 0.0;
    let out = cut(&g, &[px(1.3, 2.1), px(4.0, 4.0), px(6.7, 5.9)], &v, &o);
    check_valid(&g, &out);
    let center = VertexId(4 * 9 + 4);
    assert_eq!(out.report.paths.len(), 1);
    assert!(out.report.paths[0].vertices.contains(&center));
    assert_eq!(out.mesh.position(center), DVec3::new(4.0, 4.0, 0.0));
    check_paths_are_edges(&out);
}

#[test]
fn stroke_ending_inside_a_face_splits_it_around_the_end() {
    let (g, v) = grid_scene();
    // From outside the grid to (3.3, 4.6), well inside the triangle (3,4)-(4,5)-(3,5).
    let end = px(3.3, 4.6);
    let out = cut(&g, &[px(-0.4, 4.55), end], &v, &through_all());
    check_valid(&g, &out);
    assert_eq!(out.report.paths.len(), 1);
    let path = &out.report.paths[0].vertices;
    let last = *path.last().unwrap();
    assert!(last.0 >= g.vertex_count(), "the end is a new vertex");
    let s = screen(&v, out.mesh.position(last));
    assert!((s - DVec2::new(end.0, end.1)).length() < 1e-9, "{s}");
    // The face holding the end: ≤ 4 pieces; every other face ≤ 3.
    let end_face = FaceId(2 * (4 * 8 + 3) + 1);
    let pieces = pieces_per_face(&out);
    assert!(
        pieces[&end_face] >= 3 && pieces[&end_face] <= 4,
        "{}",
        pieces[&end_face]
    );
    for (f, &n) in &pieces {
        if *f != end_face {
            assert!(n <= 3, "face {f} in {n} pieces");
        }
    }
    check_paths_are_edges(&out);
}

#[test]
fn sharp_corner_splits_the_stroke_and_is_kept() {
    let (g, v) = grid_scene();
    let corner = px(4.35, 5.6);
    let out = cut(
        &g,
        &[px(1.6, 2.35), corner, px(7.4, 2.45)],
        &v,
        &through_all(),
    );
    check_valid(&g, &out);
    assert_eq!(out.report.pieces, 2);
    assert_eq!(out.report.paths.len(), 2);
    let (a, b) = (&out.report.paths[0].vertices, &out.report.paths[1].vertices);
    assert_eq!(a.last(), b.first(), "the pieces meet at the corner");
    let s = screen(&v, out.mesh.position(*a.last().unwrap()));
    assert!(
        (s - DVec2::new(corner.0, corner.1)).length() < 1e-6,
        "the corner is on the cut: {s}"
    );
    // With corners ignored, the corner is normalized away.
    let mut o = through_all();
    o.corner_angle_deg = 180.0;
    let smooth = cut(&g, &[px(1.6, 2.35), corner, px(7.4, 2.45)], &v, &o);
    assert_eq!(smooth.report.pieces, 1);
    let on_corner = smooth
        .report
        .paths
        .iter()
        .flat_map(|p| p.vertices.iter())
        .any(|&x| {
            (screen(&v, smooth.mesh.position(x)) - DVec2::new(corner.0, corner.1)).length() < 1e-6
        });
    assert!(!on_corner);
    check_paths_are_edges(&out);
}

#[test]
fn crossing_one_triangle_several_times_is_normalized() {
    // One big triangle pair; a zig-zag crosses the diagonal four times.
    let g = tri_grid(1, 1);
    let v = top_view(-0.5, 1.5, -0.5, 1.5, 0.005); // 400 px
    let pts: Vec<(f64, f64)> = vec![
        (30.0, 200.0),
        (150.0, 180.0),
        (200.0, 230.0),
        (250.0, 160.0),
        (300.0, 210.0),
        (370.0, 200.0),
    ];
    let mut o = through_all();
    o.corner_angle_deg = 180.0;
    let out = cut(&g, &pts, &v, &o);
    check_valid(&g, &out);
    for (f, n) in pieces_per_face(&out) {
        assert!(n <= 3, "face {f}: {n} pieces");
    }
    let d = &out.report.dropped;
    assert!(!d.first_normalization.is_empty(), "{d:?}");
    assert!(
        !d.second_normalization.is_empty() || out.report.new_vertices <= 3,
        "{d:?}"
    );
    check_paths_are_edges(&out);
}

#[test]
fn leaving_the_screen_cuts_what_is_seen() {
    let (g, v) = grid_scene();
    let out = cut(
        &g,
        &[(-300.0, 210.0), px(4.2, 4.3), (900.0, 260.0)],
        &v,
        &through_all(),
    );
    check_valid(&g, &out);
    assert_eq!(out.report.paths.len(), 1);
    assert!(!out.report.dropped.off_mesh.is_empty());
    // Boundary to boundary: the path starts and ends on the grid's border.
    let p = &out.report.paths[0].vertices;
    let r = inspect(&out.mesh).unwrap();
    assert_eq!(r.boundary_loops, 1);
    let mut uses: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    for t in faces_of(&out.mesh) {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    for end in [p[0], *p.last().unwrap()] {
        assert!(
            uses.iter()
                .any(|(&(a, b), &u)| u == 1 && (a == end.0 || b == end.0)),
            "{end}"
        );
    }
}

#[test]
fn faces_behind_the_camera_are_never_cut() {
    // A long strip along -z, the eye inside it: the far part is in front, the near behind.
    let g = tri_grid(4, 40);
    let to_strip = DMat4::from_translation(DVec3::new(-2.0, -20.0, 0.0));
    let cam = perspective(DVec3::new(0.0, -10.0, 1.0), DVec3::new(0.0, 10.0, 0.0));
    let view = View::new(cam.view_proj * to_strip, cam.viewport);
    let o = through_all();
    let out = cut(
        &g,
        &[(100.0, 590.0), (400.0, 320.0), (700.0, 590.0)],
        &view,
        &o,
    );
    check_valid(&g, &out);
    assert!(!out.report.clipped_faces.is_empty());
    // No tear along the faces skipped: the boundary is the strip's, nothing more.
    let (ri, ro) = (inspect(&g).unwrap(), inspect(&out.mesh).unwrap());
    assert_eq!(ro.boundary_edges, ri.boundary_edges);
    assert_eq!(ro.boundary_loops, 1);
    let pieces = pieces_per_face(&out);
    for f in &out.report.clipped_faces {
        assert_eq!(pieces[f], 1, "clipped face {f} was split");
    }
    let behind = |p: DVec3| project(&view, p).is_none();
    for (i, t) in faces_of(&out.mesh).iter().enumerate() {
        let orig = out.face_origin[i];
        let corners = g.face_outer(orig);
        if corners.iter().any(|&c| behind(g.position(c))) {
            assert!(
                t.iter().all(|&c| c < g.vertex_count()),
                "new vertex in clipped face {orig}"
            );
        }
    }
}

#[test]
fn stroke_entirely_outside_is_a_no_op() {
    let (g, v) = grid_scene();
    let out = cut(
        &g,
        &[(500.0, 10.0), (600.0, 40.0), (700.0, 20.0)],
        &v,
        &through_all(),
    );
    assert!(out.report.nothing_cut());
    assert_eq!(out.mesh, g);
    assert_eq!(out.report.dropped.off_mesh, vec![0, 1, 2]);
    assert_eq!(out.report.mean_edge_length_px, 0.0);
}

#[test]
fn near_points_are_dropped_and_reported() {
    let (g, v) = grid_scene();
    let out = cut(
        &g,
        &[px(1.3, 4.4), px(1.31, 4.4), px(4.5, 4.3), px(6.6, 4.35)],
        &v,
        &through_all(),
    );
    assert_eq!(out.report.dropped.preprocessing, vec![1]);
}

#[test]
fn visible_only_cuts_the_front_of_a_sphere_and_through_all_both_sides() {
    let s = icosphere(3);
    let v = perspective(DVec3::new(0.0, 0.0, 4.0), DVec3::ZERO);
    let pts = [(250.0, 280.0), (400.0, 300.0), (550.0, 310.0)];
    let front = cut(&s, &pts, &v, &CutOptions::default());
    check_valid(&s, &front);
    assert_eq!(front.report.paths.len(), 1);
    check_front_only(&s, &v, &front);
    let all = cut(&s, &pts, &v, &through_all());
    check_valid(&s, &all);
    assert_eq!(all.report.paths.len(), 2, "{:?}", all.report.paths);
    assert!(all.report.new_vertices > front.report.new_vertices);
}

/// Visible-only never splits a back face or a hidden one by a path: every path edge lies in
/// a face that was front-facing, and every path vertex is seen (brute-force ray test).
fn check_front_only(input: &PolyMesh, view: &View, out: &CutOutput) {
    let front = |f: FaceId| {
        let c = input.face_outer(f);
        let s: Vec<DVec2> = c.iter().map(|&x| screen(view, input.position(x))).collect();
        (s[1] - s[0]).perp_dot(s[2] - s[0]) < 0.0
    };
    let tris = faces_of(&out.mesh);
    for (a, b) in path_edges(out) {
        let ok = tris
            .iter()
            .enumerate()
            .filter(|(_, t)| t.contains(&a) && t.contains(&b))
            .any(|(i, _)| front(out.face_origin[i]));
        assert!(ok, "path edge {a}-{b} lies in no front face");
    }
    // Seen: no output face in front of the path vertex at its pixel (beyond a tolerance).
    let faces = faces_of(&out.mesh);
    for p in &out.report.paths {
        for &x in &p.vertices {
            let (sx, _, zx) = project(view, out.mesh.position(x)).unwrap();
            for t in &faces {
                let c: Vec<(DVec2, f64, f64)> = t
                    .iter()
                    .map(|&q| project(view, out.mesh.position(VertexId(q))).unwrap())
                    .collect();
                let (a, b, cc) = (c[0].0, c[1].0, c[2].0);
                let area = (b - a).perp_dot(cc - a);
                if area == 0.0 {
                    continue;
                }
                let la = (b - sx).perp_dot(cc - sx) / area;
                let lb = (cc - sx).perp_dot(a - sx) / area;
                let lc = 1.0 - la - lb;
                if la < 1e-9 || lb < 1e-9 || lc < 1e-9 {
                    continue;
                }
                let z = la * c[0].2 + lb * c[1].2 + lc * c[2].2;
                assert!(z > zx - 1e-6, "path vertex {x} is hidden by face {t:?}");
            }
        }
    }
    // Moved vertices: every face around them front-facing.
    for m in &out.report.moved {
        for f in input.faces() {
            if input.face_outer(f).contains(&m.vertex) {
                assert!(front(f), "moved vertex {} touches back face {f}", m.vertex);
            }
        }
    }
}

/// Two m × m triangle grids, the second 1 unit below the first: the mesh, the number of
/// faces of one grid (faces from it on are the lower sheet's) and of vertices (likewise).
fn two_sheets(m: u32) -> (PolyMesh, usize, u32) {
    let top = tri_grid(m, m);
    let mut p = top.positions().to_vec();
    let nv = p.len() as u32;
    p.extend(top.positions().iter().map(|q| *q - DVec3::Z));
    let mut faces: Vec<Vec<u32>> = top
        .faces()
        .map(|f| top.face_outer(f).iter().map(|v| v.0).collect())
        .collect();
    let n = faces.len();
    for k in 0..n {
        let t: Vec<u32> = faces[k].iter().map(|&v| v + nv).collect();
        faces.push(t);
    }
    (PolyMesh::from_polygons(p, faces).unwrap(), n, nv)
}

#[test]
fn a_hidden_sheet_is_not_cut_in_visible_only_mode() {
    // Two grids, one 1 unit below the other, seen from above: only the top one is cut.
    let (two, n, _) = two_sheets(6);
    let v = top_view(-0.5, 6.5, -0.5, 6.5, 0.02);
    let pts = [(40.0, 120.0), (200.0, 150.0), (300.0, 170.0)];
    let vis = cut(&two, &pts, &v, &CutOptions::default());
    check_valid(&two, &vis);
    let lower_split = pieces_per_face(&vis)
        .iter()
        .any(|(f, &c)| f.0 as usize >= n && c > 1);
    assert!(!lower_split, "visible-only split a hidden face");
    assert!(vis.report.paths.len() == 1);
    let all = cut(&two, &pts, &v, &through_all());
    assert_eq!(all.report.paths.len(), 2);
    let lower_split = pieces_per_face(&all)
        .iter()
        .any(|(f, &c)| f.0 as usize >= n && c > 1);
    assert!(lower_split);
}

#[test]
fn a_hidden_sheet_stays_uncut_when_snapping_moves_the_top_sheet() {
    // Occluders are found by screen boxes taken before snapping; wavy strokes over a finer
    // grid move many top vertices, and none of the crossings below may then be seen.
    let (two, n, nv) = two_sheets(12);
    // In perspective, as MeshLab's harness has it: the lower sheet is not exactly under the top one.
    let v = perspective(DVec3::new(6.0, 6.0, 10.0), DVec3::new(6.0, 6.0, 0.0));
    let mut moved = 0;
    for phase in 0..12 {
        let pts: Vec<(f64, f64)> = (0..40)
            .map(|i| {
                let t = i as f64 / 39.0;
                let y = 300.0 + 100.0 * (t * 9.0 + phase as f64 * 0.37).sin();
                (150.0 + 500.0 * t, y)
            })
            .collect();
        let vis = cut(&two, &pts, &v, &CutOptions::default());
        check_valid(&two, &vis);
        moved += vis.report.moved.len();
        let lower_split = pieces_per_face(&vis)
            .iter()
            .any(|(f, &c)| f.0 as usize >= n && c > 1);
        assert!(
            !lower_split,
            "phase {phase}: visible-only split a hidden face"
        );
        for path in &vis.report.paths {
            assert!(
                path.vertices.iter().all(|x| x.0 < nv || x.0 >= 2 * nv),
                "phase {phase}: a hidden vertex is on the cut"
            );
        }
    }
    assert!(
        moved > 100,
        "the strokes should move many vertices ({moved})"
    );
}

#[test]
fn moved_vertices_keep_their_depth_and_stay_within_the_snap_distance() {
    let g = perturbed_grid(10, 10, 0.25, 7);
    let v = perspective(DVec3::new(5.0, -6.0, 9.0), DVec3::new(5.0, 5.0, 0.0));
    let pts = [(150.0, 320.0), (400.0, 300.0), (650.0, 340.0)];
    let o = CutOptions::default();
    let out = cut(&g, &pts, &v, &o);
    check_valid(&g, &out);
    assert!(!out.report.moved.is_empty());
    check_moves(&g, &v, &out, &o);
}

fn check_moves(input: &PolyMesh, v: &View, out: &CutOutput, o: &CutOptions) {
    let l = out.report.mean_edge_length_px;
    let reach = o.snap_vertex_ratio.max(o.snap_segment_ratio) * l;
    for m in &out.report.moved {
        assert_eq!(m.from, input.position(m.vertex));
        assert_eq!(m.to, out.mesh.position(m.vertex));
        let (s0, w0, z0) = project(v, m.from).unwrap();
        let (s1, w1, z1) = project(v, m.to).unwrap();
        assert!(
            (w1 - w0).abs() <= 1e-9 * w0.abs().max(1.0),
            "w {w0} -> {w1}"
        );
        assert!((z1 - z0).abs() <= 1e-9, "z {z0} -> {z1}");
        assert!(
            (s1 - s0).length() <= reach * (1.0 + 1e-9),
            "moved {} px",
            (s1 - s0).length()
        );
        assert!(((s1 - s0).length() - m.pixels).abs() < 1e-6);
    }
    let max = out
        .report
        .moved
        .iter()
        .map(|m| m.pixels)
        .fold(0.0, f64::max);
    assert_eq!(out.report.max_move_px, max);
}

#[test]
fn n_gons_are_triangulated_and_faces_map_back() {
    let quads = shapes::grid(6, 6).unwrap();
    let v = top_view(-0.5, 6.5, -0.5, 6.5, 0.02);
    let out = cut(
        &quads,
        &[(40.0, 120.0), (200.0, 150.0), (300.0, 170.0)],
        &v,
        &through_all(),
    );
    check_valid(&quads, &out);
    // Every output triangle lies inside its origin quad (centroid test in the plane).
    for (i, t) in faces_of(&out.mesh).iter().enumerate() {
        let c = t
            .iter()
            .map(|&x| out.mesh.position(VertexId(x)))
            .sum::<DVec3>()
            / 3.0;
        let q = quads.face_outer(out.face_origin[i]);
        let lo = q
            .iter()
            .map(|&x| quads.position(x))
            .fold(DVec3::INFINITY, DVec3::min);
        let hi = q
            .iter()
            .map(|&x| quads.position(x))
            .fold(DVec3::NEG_INFINITY, DVec3::max);
        assert!(
            c.x >= lo.x - 0.31 && c.x <= hi.x + 0.31 && c.y >= lo.y - 0.31 && c.y <= hi.y + 0.31
        );
    }
    assert!(out.face_origin.iter().all(|f| f.0 < 36));
    let labelled = {
        let mut m = quads.clone();
        m.set_face_labels((0..36).collect()).unwrap();
        m
    };
    let out2 = cut(
        &labelled,
        &[(40.0, 120.0), (200.0, 150.0), (300.0, 170.0)],
        &v,
        &through_all(),
    );
    for (i, f) in out2.face_origin.iter().enumerate() {
        assert_eq!(out2.mesh.face_labels()[i], f.0, "labels follow face_origin");
    }
}

#[test]
fn faces_with_holes_are_bridged_first() {
    let plate = shapes::plate_with_hole(4.0, 2.0, 0.5).unwrap();
    let v = top_view(-2.5, 2.5, -2.5, 2.5, 0.01);
    let out = cut(
        &plate,
        &[(20.0, 100.0), (480.0, 120.0)],
        &v,
        &CutOptions::default(),
    );
    check_valid(&plate, &out);
    assert!(out.face_origin.iter().all(|f| f.0 < plate.face_count()));
    assert!(!out.report.paths.is_empty());
}

#[test]
fn degenerate_faces_are_reported_and_not_cut_through() {
    // Vertex (5, 4) moved onto the diagonal (4,4)-(5,5): face (4,4),(5,4),(5,5) has no area.
    let g = tri_grid(8, 8);
    let mut p = g.positions().to_vec();
    p[4 * 9 + 5] = DVec3::new(4.5, 4.5, 0.0);
    let faces: Vec<Vec<u32>> = g
        .faces()
        .map(|f| g.face_outer(f).iter().map(|v| v.0).collect())
        .collect();
    let m = PolyMesh::from_polygons(p, faces).unwrap();
    let flat = FaceId(2 * (4 * 8 + 4));
    let v = top_view(-0.5, 8.5, -0.5, 8.5, 0.02);
    let mut o = through_all();
    o.snap_vertex_ratio = 0.0;
    o.snap_segment_ratio = 0.0;
    let out = cut(&m, &[px(3.2, 4.3), px(6.7, 4.62)], &v, &o);
    assert!(
        out.report.degenerate_faces.contains(&flat),
        "{:?}",
        out.report.degenerate_faces
    );
    // No path edge inside the flat face: every output piece of it has at most one new
    // vertex and that vertex is on its boundary (a T-junction split), never a chord.
    let tris = faces_of(&out.mesh);
    for (a, b) in path_edges(&out) {
        let inside_flat = tris
            .iter()
            .enumerate()
            .filter(|(_, t)| t.contains(&a) && t.contains(&b))
            .all(|(i, _)| out.face_origin[i] == flat);
        assert!(
            !inside_flat,
            "path edge {a}-{b} runs through the degenerate face"
        );
    }
}

#[test]
fn new_triangles_keep_a_quarter_of_the_grid_angle() {
    // T3 (spec §7, gap-fill target): on a regular grid every new triangle's smallest angle
    // is at least min(45°, 30°) / 4, and none is flat.
    let (g, v) = grid_scene();
    let strokes: [&[(f64, f64)]; 4] = [
        &[px(0.3, 1.2), px(3.1, 3.05), px(7.7, 6.4)],
        &[px(-0.2, 4.49), px(8.3, 4.2)],
        &[px(1.1, 7.2), px(2.9, 4.1), px(4.4, 2.6), px(7.9, 0.7)],
        &[px(2.2, 2.2), px(5.3, 2.9), px(6.1, 5.7)],
    ];
    for pts in strokes {
        let out = cut(&g, pts, &v, &through_all());
        check_valid(&g, &out);
        let l = out.report.mean_edge_length_px;
        for (i, t) in faces_of(&out.mesh).iter().enumerate() {
            if i < g.face_count() as usize && t.iter().all(|&c| c < g.vertex_count()) {
                continue; // untouched
            }
            let p = t.map(|c| out.mesh.position(VertexId(c)));
            let s = t.map(|c| screen(&v, out.mesh.position(VertexId(c))));
            let area = (s[1] - s[0]).perp_dot(s[2] - s[0]).abs() / 2.0;
            assert!(area >= 1e-12 * l * l, "flat face {t:?}");
            let ang = |a: DVec3, b: DVec3, c: DVec3| (b - a).angle_between(c - a).to_degrees();
            let min = ang(p[0], p[1], p[2])
                .min(ang(p[1], p[2], p[0]))
                .min(ang(p[2], p[0], p[1]));
            assert!(min >= 30.0 / 4.0, "face {t:?}: smallest angle {min}°");
        }
    }
}

// ---------------------------------------------------------------- opening (T5)

#[test]
fn opening_a_slit_lowers_euler_by_one_and_adds_a_boundary() {
    let (g, v) = grid_scene();
    let mut o = through_all();
    o.open = true;
    let out = cut(&g, &[px(2.3, 4.45), px(4.5, 4.6), px(5.6, 4.4)], &v, &o);
    check_valid(&g, &out);
    let before = components(&g);
    let after = components(&out.mesh);
    assert_eq!(after.len(), 1);
    assert_eq!(euler(&after), euler(&before) - 1);
    let r = inspect(&out.mesh).unwrap();
    assert_eq!(r.boundary_loops, 2);
    // k interior path vertices gained one copy each.
    let p = &out.report.paths[0].vertices;
    assert_eq!(
        out.report.new_vertices as usize,
        count_split(&out, &g) + p.len() - 2
    );
}

fn count_split(out: &CutOutput, g: &PolyMesh) -> usize {
    // New vertices that are not opening copies: their position differs from every older one.
    let n = g.vertex_count() as usize;
    let pos = out.mesh.positions();
    (n..pos.len())
        .filter(|&i| !pos[..i].contains(&pos[i]))
        .count()
}

#[test]
fn opening_boundary_to_boundary_separates_two_disks() {
    let (g, v) = grid_scene();
    let mut o = through_all();
    o.open = true;
    let out = cut(&g, &[px(-0.4, 4.45), px(4.5, 4.6), px(8.4, 4.4)], &v, &o);
    check_valid(&g, &out);
    let after = components(&out.mesh);
    assert_eq!(after.len(), 2, "{after:?}");
    assert_eq!(euler(&after), euler(&components(&g)) + 1);
    for c in &after {
        assert_eq!(c.0 - c.1 + c.2, 1, "each part is a disk");
    }
}

#[test]
fn opening_a_closed_loop_cuts_out_a_disk() {
    let (g, v) = grid_scene();
    let mut o = through_all();
    o.open = true;
    let c = DVec2::new(4.1, 4.3);
    let pts: Vec<(f64, f64)> = (0..=24)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 24.0;
            px(c.x + 2.2 * a.cos(), c.y + 2.2 * a.sin())
        })
        .collect();
    let unopened = cut(&g, &pts, &v, &through_all());
    assert_eq!(
        unopened.report.paths.len(),
        1,
        "{:?}",
        unopened.report.paths
    );
    assert!(unopened.report.paths[0].closed);
    check_paths_are_edges(&unopened);
    let out = cut(&g, &pts, &v, &o);
    check_valid(&g, &out);
    let after = components(&out.mesh);
    assert_eq!(after.len(), 2, "{after:?}");
    assert_eq!(euler(&after), euler(&components(&g)));
    let k = unopened.report.paths[0].vertices.len() as u32;
    assert_eq!(out.mesh.vertex_count(), unopened.mesh.vertex_count() + k);
}

#[test]
fn a_square_loop_is_four_pieces_and_opens_a_disk() {
    // Four sharp corners: four pieces, each path ending where the next begins.
    let (g, v) = grid_scene();
    let pts = [
        px(2.3, 2.4),
        px(5.6, 2.3),
        px(5.7, 5.6),
        px(2.4, 5.7),
        px(2.3, 2.4),
    ];
    let plain = cut(&g, &pts, &v, &through_all());
    check_valid(&g, &plain);
    check_paths_are_edges(&plain);
    assert_eq!(plain.report.pieces, 4);
    let paths = &plain.report.paths;
    assert_eq!(paths.len(), 4, "{paths:?}");
    for k in 0..4 {
        let (a, b) = (&paths[k].vertices, &paths[(k + 1) % 4].vertices);
        assert_eq!(a.last(), b.first(), "pieces {k} and {} meet", (k + 1) % 4);
    }
    let mut o = through_all();
    o.open = true;
    let out = cut(&g, &pts, &v, &o);
    check_valid(&g, &out);
    let after = components(&out.mesh);
    assert_eq!(after.len(), 2, "{after:?}");
    assert_eq!(euler(&after), euler(&components(&g)));
}

#[test]
fn opening_a_loop_on_a_sphere_gives_two_disks() {
    let s = icosphere(3);
    let v = perspective(DVec3::new(0.0, 0.0, 4.0), DVec3::ZERO);
    let pts: Vec<(f64, f64)> = (0..=30)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 30.0;
            (400.0 + 120.0 * a.cos(), 300.0 + 110.0 * a.sin())
        })
        .collect();
    let mut o = CutOptions::default();
    o.open = true;
    let out = cut(&s, &pts, &v, &o);
    check_valid(&s, &out);
    let after = components(&out.mesh);
    assert_eq!(after.len(), 2, "{after:?}");
    for c in &after {
        assert_eq!(c.0 - c.1 + c.2, 1, "each part is a disk");
    }
}

/// Every edge of the input sharp, then an opened cut, through all sheets and visible only:
/// every sharp edge of the result is an edge of it, so the result writes as an OBJ that reads
/// back with its creases (a through-all opened cut used to keep the crease of an edge whose
/// faces all moved to the copies, and the OBJ reader refused the file). Pieces of split
/// sharp edges and both sides of an opened sharp edge stay sharp, so no crease is lost.
#[test]
fn creases_follow_an_opened_cut_onto_edges_that_exist() {
    use katachi::io::{read_bytes, write_to, Format, WriteOptions};
    let sphere = icosphere(2);
    let grid = tri_grid(8, 8);
    type Case = (PolyMesh, View, Vec<(f64, f64)>);
    let cases: Vec<Case> = vec![
        (
            sphere.clone(),
            perspective(DVec3::new(0.3, 0.2, 4.0), DVec3::ZERO),
            vec![(250.0, 260.0), (400.0, 300.0), (560.0, 330.0)],
        ),
        (
            sphere,
            top_view(-1.5, 1.5, -1.5, 1.5, 0.005),
            (0..=24)
                .map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / 24.0;
                    (300.0 + 110.0 * a.cos(), 300.0 + 90.0 * a.sin())
                })
                .collect(),
        ),
        (
            grid,
            top_view(-0.5, 8.5, -0.5, 8.5, 0.02),
            vec![px(-0.2, 3.0), px(3.0, 3.0), px(5.0, 4.0), px(8.3, 4.5)],
        ),
    ];
    for (k, (mesh, view, pts)) in cases.into_iter().enumerate() {
        let mut m = mesh.clone();
        let all: Vec<(VertexId, VertexId, f64)> = edge_set(&mesh)
            .into_iter()
            .map(|(a, b)| (VertexId(a), VertexId(b), 2.0))
            .collect();
        m.set_edge_sharpnesses(all.iter().copied()).unwrap();
        for mode in [CutMode::ThroughAll, CutMode::VisibleOnly] {
            let mut o = CutOptions::with_mode(mode);
            o.open = true;
            let out = cut(&m, &pts, &view, &o);
            assert!(
                !out.report.paths.is_empty(),
                "case {k} {mode:?}: nothing cut"
            );
            let edges = edge_set(&out.mesh);
            let sharp: Vec<(u32, u32)> =
                out.mesh.sharp_edges().map(|(a, b, _)| (a.0, b.0)).collect();
            let missing: Vec<&(u32, u32)> = sharp.iter().filter(|e| !edges.contains(e)).collect();
            assert!(
                missing.is_empty(),
                "case {k} {mode:?}: creases on missing edges {missing:?}"
            );
            assert!(sharp.len() >= all.len(), "case {k} {mode:?}: creases lost");
            let mut obj = Vec::new();
            write_to(&mut obj, Format::Obj, &out.mesh, &WriteOptions::default()).unwrap();
            let back = read_bytes(&obj, Format::Obj, std::path::Path::new("cut.obj"))
                .unwrap_or_else(|e| panic!("case {k} {mode:?}: {e}"));
            assert_eq!(back.sharp_edges().count(), sharp.len());
        }
    }
}

/// An Archimedean spiral of `n` points about `c`, `step` pixels apart along it and `gap`
/// pixels between its turns: a stroke that never crosses itself, as long as one likes.
fn spiral(n: usize, c: DVec2, step: f64, gap: f64) -> Vec<(f64, f64)> {
    let k = gap / std::f64::consts::TAU;
    let mut t: f64 = 2.0 * std::f64::consts::PI;
    (0..n)
        .map(|_| {
            let r = k * t;
            let p = (c.x + r * t.cos(), c.y + r * t.sin());
            // d(arc)/dθ ≈ r for a loose spiral.
            t += step / (r * r + k * k).sqrt();
            p
        })
        .collect()
}

/// Issue 34: a 200,000-point stroke over a small mesh used to take 27 s (every pair of its
/// segments was tested for crossing); now it is cut (its speed is in `benches/cut.rs`).
/// Every step is reported in order and the result is a valid mesh.
#[test]
fn a_200000_point_stroke_is_cut_with_progress_after_each_step() {
    let m = triangulate_cube();
    let v = perspective(DVec3::new(2.0, 1.5, 3.0), DVec3::ZERO);
    let pts = spiral(200_000, DVec2::new(400.0, 300.0), 2.5, 4.0);
    let mut seen = Vec::new();
    let out = katachi::cut::cut_by_stroke_with_progress(
        &m,
        &stroke(&pts),
        &v,
        &through_all(),
        &mut |done, total| {
            seen.push((done, total));
            true
        },
    )
    .unwrap();
    let total = katachi::cut::CUT_STEPS;
    assert_eq!(seen, (1..=total).map(|k| (k, total)).collect::<Vec<_>>());
    assert!(out.report.split_faces > 0);
    check_valid(&m, &out);
}

/// The unit cube, triangulated (12 faces).
fn triangulate_cube() -> PolyMesh {
    cut_meshes::triangulate_quads(&shapes::cube(1.0).unwrap())
}

/// Cancelling at each step: [`Error::Cancelled`] of kind Cancelled, no more calls after it,
/// and cutting again gives the same result as a cut that was never cancelled.
#[test]
fn cancelling_a_cut_at_any_step_stops_it_with_a_typed_error() {
    let (m, v) = grid_scene();
    let pts = [px(1.2, 2.6), px(4.0, 3.1), px(6.3, 3.4)];
    let mut o = through_all();
    o.open = true;
    let whole = cut(&m, &pts, &v, &o);
    for stop in 1..=katachi::cut::CUT_STEPS {
        let mut calls = 0;
        let r =
            katachi::cut::cut_by_stroke_with_progress(&m, &stroke(&pts), &v, &o, &mut |done, _| {
                calls += 1;
                done < stop
            });
        match r {
            Err(e @ Error::Cancelled { .. }) => {
                assert_eq!(e.kind(), katachi::ErrorKind::Cancelled);
                assert!(e.to_string().contains("cancelled"), "{e}");
            }
            r => panic!("stop at {stop}: {:?}", r.map(|c| c.report)),
        }
        assert_eq!(calls, stop);
    }
    let again = cut(&m, &pts, &v, &o);
    assert_eq!(bits(&again), bits(&whole));
}

// ---------------------------------------------------------------- determinism (T7)

fn bits(out: &CutOutput) -> (Vec<[u64; 3]>, Vec<u32>, Vec<u32>) {
    (
        out.mesh
            .positions()
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect(),
        out.mesh.corners().iter().map(|v| v.0).collect(),
        out.face_origin.iter().map(|f| f.0).collect(),
    )
}

#[test]
fn one_thread_and_all_threads_give_the_same_bits() {
    // Dense enough that the region spans many of the parallel passes' chunks.
    let s = icosphere(6);
    let v = perspective(DVec3::new(0.5, 0.3, 3.0), DVec3::ZERO);
    let pts: Vec<(f64, f64)> = (0..50)
        .map(|i| {
            (
                150.0 + 10.0 * i as f64,
                250.0 + 40.0 * (i as f64 * 0.2).sin(),
            )
        })
        .collect();
    for mode in [CutMode::VisibleOnly, CutMode::ThroughAll] {
        let mut o = CutOptions::with_mode(mode);
        o.open = true;
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let a = one.install(|| cut(&s, &pts, &v, &o));
        let three = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let b = three.install(|| cut(&s, &pts, &v, &o));
        assert!(a.report.new_faces > 200, "{}", a.report.new_faces);
        assert_eq!(bits(&a), bits(&b));
        assert_eq!(a.report, b.report);
    }
}

// ---------------------------------------------------------------- bad input

#[test]
fn bad_input_gets_typed_errors_and_the_mesh_is_untouched() {
    let (g, v) = grid_scene();
    let ok = stroke(&[px(1.0, 1.0), px(5.0, 5.0)]);
    let o = CutOptions::default();
    let err =
        |m: &PolyMesh, s: &Stroke, v: &View, o: &CutOptions| cut_by_stroke(m, s, v, o).unwrap_err();

    let e = err(&g, &stroke(&[px(1.0, 1.0)]), &v, &o);
    assert!(matches!(e, Error::StrokeTooShort { points: 1, .. }), "{e}");
    let e = err(
        &g,
        &stroke(&[px(1.0, 1.0), (px(1.0, 1.0).0 + 1.0, px(1.0, 1.0).1)]),
        &v,
        &o,
    );
    assert!(matches!(e, Error::StrokeTooShort { points: 1, .. }), "{e}");
    let e = err(&g, &stroke(&[px(1.0, 1.0), (f64::NAN, 3.0)]), &v, &o);
    assert!(
        matches!(e, Error::NonFiniteStrokePoint { index: 1, .. }),
        "{e}"
    );
    let bow = stroke(&[(10.0, 10.0), (100.0, 100.0), (100.0, 10.0), (10.0, 100.0)]);
    let e = err(&g, &bow, &v, &o);
    assert!(
        matches!(
            e,
            Error::StrokeSelfIntersects {
                first: 0,
                second: 2
            }
        ),
        "{e}"
    );
    let back = stroke(&[(10.0, 10.0), (100.0, 10.0), (50.0, 10.0)]);
    let e = err(&g, &back, &v, &o);
    assert!(
        matches!(
            e,
            Error::StrokeSelfIntersects {
                first: 0,
                second: 1
            }
        ),
        "{e}"
    );

    let mut sing = v;
    sing.view_proj.z_axis = sing.view_proj.x_axis;
    let e = err(&g, &ok, &sing, &o);
    assert!(matches!(e, Error::SingularViewProjection { .. }), "{e}");
    let mut nan = v;
    nan.view_proj.w_axis.y = f64::INFINITY;
    let e = err(&g, &ok, &nan, &o);
    assert!(
        matches!(
            e,
            Error::NonFiniteMatrixEntry {
                column: 3,
                row: 1,
                ..
            }
        ),
        "{e}"
    );
    let mut vp = v;
    vp.viewport[2] = 0.0;
    assert!(matches!(
        err(&g, &ok, &vp, &o),
        Error::InvalidViewport { .. }
    ));
    vp.viewport = [0.0, f64::NAN, 10.0, 10.0];
    assert!(matches!(
        err(&g, &ok, &vp, &o),
        Error::InvalidViewport { .. }
    ));

    let with = |f: &dyn Fn(&mut CutOptions)| {
        let mut x = o.clone();
        f(&mut x);
        x
    };
    for (name, bad) in [
        ("snap_vertex_ratio", with(&|x| x.snap_vertex_ratio = -0.1)),
        (
            "snap_segment_ratio",
            with(&|x| x.snap_segment_ratio = f64::NAN),
        ),
        ("corner_angle_deg", with(&|x| x.corner_angle_deg = 200.0)),
        ("min_stroke_px", with(&|x| x.min_stroke_px = -1.0)),
        ("depth_eps_rel", with(&|x| x.depth_eps_rel = f64::INFINITY)),
    ] {
        let e = err(&g, &ok, &v, &bad);
        assert!(
            matches!(e, Error::InvalidOption { option, .. } if option == name),
            "{e}"
        );
    }
    assert!(matches!(
        err(&PolyMesh::new(), &ok, &v, &o),
        Error::EmptyMesh { .. }
    ));
}

#[test]
fn a_non_manifold_edge_under_the_stroke_is_an_error_and_elsewhere_is_not() {
    // Grid plus a fin on edge (3,3)-(4,3): three faces share it.
    let g = tri_grid(8, 8);
    let mut p = g.positions().to_vec();
    p.push(DVec3::new(3.5, 3.0, 1.0));
    let fin = p.len() as u32 - 1;
    let mut faces: Vec<Vec<u32>> = g
        .faces()
        .map(|f| g.face_outer(f).iter().map(|v| v.0).collect())
        .collect();
    faces.push(vec![3 * 9 + 3, 3 * 9 + 4, fin]);
    let m = PolyMesh::from_polygons(p, faces).unwrap();
    let v = top_view(-0.5, 8.5, -0.5, 8.5, 0.02);
    let e = cut_by_stroke(
        &m,
        &stroke(&[px(1.2, 2.6), px(6.3, 3.4)]),
        &v,
        &through_all(),
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            Error::NonManifoldEdge {
                a: 30,
                b: 31,
                uses: 3
            }
        ),
        "{e}"
    );
    // A stroke far from the fin cuts.
    let out = cut(&m, &[px(1.2, 6.6), px(6.3, 6.4)], &v, &through_all());
    assert_eq!(out.report.paths.len(), 1);
}

/// A bow-tie vertex under the stroke (spec §1: vertex links are single fans): grid vertex
/// (4, 4) with the faces of cells (3, 4) and (4, 3) removed, so its faces in cells (3, 3) and
/// (4, 4) touch only at it. An error naming it in both modes, opened or not (the cut used to
/// snap and open it as one surface); a stroke far from it cuts.
#[test]
fn a_bow_tie_vertex_under_the_stroke_is_an_error_and_elsewhere_is_not() {
    let g = tri_grid(8, 8);
    let cell_of = |f: &[u32]| {
        let (x, y) = (
            f.iter().map(|v| v % 9).min().unwrap(),
            f.iter().map(|v| v / 9).min().unwrap(),
        );
        (x, y)
    };
    let faces: Vec<Vec<u32>> = g
        .faces()
        .map(|f| g.face_outer(f).iter().map(|v| v.0).collect::<Vec<u32>>())
        .filter(|f| !matches!(cell_of(f), (3, 4) | (4, 3)))
        .collect();
    let m = PolyMesh::from_polygons(g.positions().to_vec(), faces).unwrap();
    assert!(inspect(&m).is_ok(), "edge-manifold");
    let v = top_view(-0.5, 8.5, -0.5, 8.5, 0.02);
    for pts in [[px(2.5, 2.6), px(5.5, 5.4)], [px(1.2, 4.1), px(6.3, 4.2)]] {
        for mode in [CutMode::VisibleOnly, CutMode::ThroughAll] {
            for open in [false, true] {
                let mut o = CutOptions::with_mode(mode);
                o.open = open;
                match cut_by_stroke(&m, &stroke(&pts), &v, &o) {
                    Err(Error::NonManifoldVertex {
                        vertex: 40,
                        fans: 2,
                    }) => {}
                    r => panic!("{pts:?} {mode:?} open {open}: {:?}", r.map(|c| c.report)),
                }
            }
        }
    }
    let out = cut(&m, &[px(1.2, 6.6), px(6.3, 6.4)], &v, &through_all());
    assert_eq!(out.report.paths.len(), 1);
}

/// A face turned the other way under the stroke: the edge it shares with a neighbour runs
/// the same way in both, an error naming that edge as both faces run it (from, to), the
/// first in vertex order; a face turned away from the stroke is no error.
#[test]
fn a_face_turned_over_under_the_stroke_is_an_error_naming_its_edge() {
    let g = tri_grid(8, 8);
    let faces: Vec<Vec<u32>> = g
        .faces()
        .map(|f| g.face_outer(f).iter().map(|v| v.0).collect())
        .collect();
    let v = top_view(-0.5, 8.5, -0.5, 8.5, 0.02);
    let s = [px(1.2, 3.6), px(6.3, 3.4)];
    // The two faces of grid cell (3, 3), under the stroke, and of cell (3, 7), away from it.
    for (cell, under) in [(3 * 8 + 3, true), (7 * 8 + 3, false)] {
        for pick in 0..2 {
            let k = 2 * cell + pick;
            let mut turned = faces.clone();
            turned[k].reverse();
            let m = PolyMesh::from_polygons(g.positions().to_vec(), turned.clone()).unwrap();
            let r = cut_by_stroke(&m, &stroke(&s), &v, &through_all());
            if !under {
                assert_eq!(r.unwrap().report.paths.len(), 1);
                continue;
            }
            // The turned face's sides as it runs them but the one along a grid row (its
            // neighbour there is beyond the snap distance, not in the cut's region); the
            // first by (smaller end, larger end).
            let f = &turned[k];
            let want = (0..3)
                .map(|i| (f[i], f[(i + 1) % 3]))
                .filter(|&(a, b)| a / 9 != b / 9)
                .min_by_key(|&(a, b)| (a.min(b), a.max(b)))
                .unwrap();
            match r.unwrap_err() {
                Error::InconsistentOrientation { a, b } => assert_eq!((a, b), want),
                e => panic!("{e}"),
            }
        }
    }
}

// ---------------------------------------------------------------- fuzz findings

/// Pixel position of grid point (i, j) · n / 20 in the integer-grid property's view.
fn int_grid_stroke(n: u32, pts: &[(i32, i32)]) -> (PolyMesh, View, Vec<(f64, f64)>) {
    let mesh = tri_grid(n, n);
    let view = top_view(
        -0.5,
        n as f64 + 0.5,
        -0.5,
        n as f64 + 0.5,
        (n as f64 + 1.0) / 400.0,
    );
    let px = pts
        .iter()
        .map(|&(i, j)| {
            let s = screen(
                &view,
                DVec3::new(i as f64 * n as f64 / 20.0, j as f64 * n as f64 / 20.0, 0.0),
            );
            (s.x, s.y)
        })
        .collect();
    (mesh, view, px)
}

#[test]
fn regression_stroke_doubling_back_within_rounding_is_self_intersecting() {
    // Segments 0 and 1 are collinear and opposite up to the matrix's rounding.
    let (mesh, view, px) = int_grid_stroke(4, &[(9, 5), (4, 15), (8, 7), (0, 7), (8, 2)]);
    let e = cut_by_stroke(&mesh, &stroke(&px), &view, &through_all()).unwrap_err();
    assert!(
        matches!(
            e,
            Error::StrokeSelfIntersects {
                first: 0,
                second: 1
            }
        ),
        "{e}"
    );
}

#[test]
fn regression_corner_on_an_edge_gives_one_vertex() {
    // The sharp corner (0.75, 4.75) lies on a diagonal up to rounding: the crossings just
    // before and after it and the corner itself are one vertex, the paths joined there.
    let (mesh, view, px) = int_grid_stroke(5, &[(7, 16), (9, 13), (3, 19), (4, 2)]);
    let out = cut(&mesh, &px, &view, &through_all());
    check_valid(&mesh, &out);
    check_paths_are_edges(&out);
    assert!(out.report.unjoined.is_empty());
    let corner = DVec3::new(0.75, 4.75, 0.0);
    let at_corner: Vec<u32> = (0..out.mesh.vertex_count())
        .filter(|&v| (out.mesh.position(VertexId(v)) - corner).length() < 1e-9)
        .collect();
    assert_eq!(at_corner.len(), 1, "{at_corner:?}");
}

#[test]
fn regression_chords_of_two_pieces_crossing_in_one_face_follow_edges() {
    let (mesh, view, px) = int_grid_stroke(5, &[(7, 11), (0, 12), (9, 9)]);
    let out = cut(&mesh, &px, &view, &through_all());
    check_valid(&mesh, &out);
    check_paths_are_edges(&out);
    assert!(out.report.unjoined.is_empty());
    assert_eq!(out.report.pieces, 2);
}

#[test]
fn regression_piece_end_a_rounding_error_past_an_edge_adds_no_vertex() {
    let (mesh, view, px) = int_grid_stroke(5, &[(4, 19), (1, 9)]);
    let out = cut(&mesh, &px, &view, &through_all());
    check_valid(&mesh, &out);
    check_paths_are_edges(&out);
    let r = inspect(&out.mesh).unwrap();
    assert_eq!(r.unreferenced_vertices, 0);
}

#[test]
fn regression_leaving_and_reentering_a_face_through_a_silhouette_crosses_it_once() {
    // Visible-only on a coarse sphere: the stroke leaves a face over the silhouette and
    // comes back into it; the two visible stretches are normalized as one array.
    let s = icosphere(1);
    let v = view_for(&s, false, 0.0, 0.0, 1.9319513657836547);
    let pts = [
        (267.1198930846732, 432.21717082034553),
        (252.29653429071155, 414.4373772870179),
        (231.95286113433153, 403.39256010751416),
        (213.55204078229255, 389.3475312932231),
        (204.07029508920232, 368.23001433137733),
        (202.49289558226232, 345.1353215467183),
        (211.41460657993426, 323.7751694663538),
    ];
    let mut o = CutOptions::default();
    o.corner_angle_deg = 180.0;
    let out = cut(&s, &pts, &v, &o);
    check_valid(&s, &out);
    for (f, n) in pieces_per_face(&out) {
        assert!(n <= 4, "face {f} in {n} pieces");
    }
}

/// No face of zero area and no two new vertices at one place.
fn check_no_slivers(input: &PolyMesh, out: &CutOutput) {
    let r = inspect(&out.mesh).unwrap();
    assert!(
        r.zero_area_faces.is_empty(),
        "zero-area faces {:?}",
        r.zero_area_faces
    );
    let nv = input.vertex_count() as usize;
    let p = out.mesh.positions();
    for a in nv..p.len() {
        for b in a + 1..p.len() {
            let copy = out.vertex_original()[b].0 as usize == a;
            assert!(
                copy || (p[a] - p[b]).length() > 1e-9,
                "new vertices {a} and {b} coincide at {}",
                p[a]
            );
        }
    }
}

#[test]
fn regression_a_stroke_ending_on_a_silhouette_edge_makes_no_sliver() {
    // Icospheres seen from aside: strokes from inside the disc to the screen midpoint of each
    // silhouette edge (an edge between a front and a back face), and to points a rounding
    // error either side of it. A piece end that close to an edge goes onto it, even onto a
    // silhouette, where a face of each sheet holds it.
    for levels in [1, 2] {
        let m = icosphere(levels);
        let tris = faces_of(&m);
        for (ortho, theta, phi) in [(true, 2.0, 1.0), (false, 4.0, 0.9)] {
            let v = view_for(&m, ortho, theta, phi, 3.0);
            let at = |i: u32| screen(&v, m.position(VertexId(i)));
            let front = |t: &[u32; 3]| (at(t[1]) - at(t[0])).perp_dot(at(t[2]) - at(t[0])) < 0.0;
            let mut sides: BTreeMap<(u32, u32), Vec<bool>> = BTreeMap::new();
            for t in &tris {
                for i in 0..3 {
                    let (a, b) = (t[i], t[(i + 1) % 3]);
                    sides
                        .entry((a.min(b), a.max(b)))
                        .or_default()
                        .push(front(t));
                }
            }
            let centre = screen(&v, DVec3::ZERO);
            let mut ends = 0;
            for (&(a, b), f) in &sides {
                if f.len() != 2 || f[0] == f[1] {
                    continue;
                }
                for off in [0.0, 1e-12, -1e-12] {
                    let (sa, sb) = (at(a), at(b));
                    let end = (sa + sb) * 0.5 + (sb - sa).perp().normalize() * off;
                    let start = centre + (end - centre) * 0.2;
                    let mid = start + (end - start) * 0.55 + (end - start).perp() * 0.05;
                    let pts = [(start.x, start.y), (mid.x, mid.y), (end.x, end.y)];
                    for mode in [CutMode::VisibleOnly, CutMode::ThroughAll] {
                        for open in [false, true] {
                            let mut o = CutOptions::with_mode(mode);
                            o.open = open;
                            let out = run(&m, &pts, &v, &o).expect("a simple stroke");
                            check_valid(&m, &out);
                            if !open {
                                check_paths_are_edges(&out);
                            }
                            check_no_slivers(&m, &out);
                        }
                    }
                    ends += 1;
                }
            }
            assert!(ends >= 12, "{ends} stroke ends on silhouette edges");
        }
    }
}

/// For each stroke piece, the faces that more than one of its paths crosses (a step inside
/// the face: both sides of the step's edge lie in it, not along an edge). One piece crosses a
/// face once (seed 002 §3.3), whichever sheets its paths run on.
fn faces_crossed_twice_by_a_piece(out: &CutOutput) -> Vec<(u32, FaceId)> {
    let mut sides: BTreeMap<(u32, u32), Vec<FaceId>> = BTreeMap::new();
    for (t, &f) in faces_of(&out.mesh).iter().zip(&out.face_origin) {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            sides.entry((a.min(b), a.max(b))).or_default().push(f);
        }
    }
    let mut paths_in: BTreeMap<(u32, FaceId), BTreeSet<usize>> = BTreeMap::new();
    for (pi, p) in out.report.paths.iter().enumerate() {
        for w in p.vertices.windows(2) {
            let (a, b) = (w[0].0, w[1].0);
            if let Some(fs) = sides.get(&(a.min(b), a.max(b))) {
                if fs.len() == 2 && fs[0] == fs[1] {
                    paths_in.entry((p.piece, fs[0])).or_default().insert(pi);
                }
            }
        }
    }
    paths_in
        .into_iter()
        .filter(|(_, paths)| paths.len() > 1)
        .map(|(k, _)| k)
        .collect()
}

#[test]
fn regression_one_piece_through_all_sheets_crosses_each_face_once() {
    // Through all sheets of a sphere: the stroke leaves the disc across a silhouette edge,
    // turns outside it and comes back across the same edge. Each sheet's stretch before the
    // turn continues in the stretch after it on the same sheet (they share the face by the
    // edge), not in the other sheet's, which interleaves with it in stroke order.
    let s = icosphere(2);
    let v = view_for(
        &s,
        true,
        4.444594391681799,
        0.8125730413203665,
        3.0311489807602365,
    );
    let pts = [
        (277.38870238182176, 252.0273125553092),
        (266.5332920525967, 249.19346131242565),
        (256.95112275772505, 243.35799407431557),
        (246.6857937438784, 238.83100097512528),
        (237.9126211243977, 231.83799815291565),
        (227.21063157537222, 228.47079367810463),
        (233.61654471280545, 219.2602061203916),
        (235.31128694979185, 208.16973746335043),
        (233.77412429685984, 197.05633216789445),
        (235.75880446098162, 186.01406379003026),
        (240.91685706476557, 176.05087456071038),
        (251.41490759979425, 172.09340298827655),
        (261.66313053298086, 176.6589887113077),
    ];
    let out = run(&s, &pts, &v, &through_all()).expect("a simple stroke");
    check_valid(&s, &out);
    check_paths_are_edges(&out);
    assert_eq!(faces_crossed_twice_by_a_piece(&out), vec![]);
    for (f, n) in pieces_per_face(&out) {
        assert!(n <= 4, "face {f} in {n} pieces");
    }
}

// ---------------------------------------------------------------- properties

/// Property-test cases: 96, or `KATACHI_CUT_CASES` for a longer fuzz.
fn cases() -> u32 {
    std::env::var("KATACHI_CUT_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(96)
}

#[derive(Debug, Clone)]
enum Scene {
    Grid { n: u32, perturb: f64, seed: u64 },
    Sphere { levels: u32 },
}

fn scene_mesh(s: &Scene) -> PolyMesh {
    match *s {
        Scene::Grid { n, perturb, seed } => {
            if perturb == 0.0 {
                tri_grid(n, n)
            } else {
                perturbed_grid(n, n, perturb, seed)
            }
        }
        Scene::Sphere { levels } => icosphere(levels),
    }
}

fn scene_strategy() -> impl Strategy<Value = Scene> {
    prop_oneof![
        (
            4u32..14,
            prop_oneof![Just(0.0), Just(1e-15), 0.05f64..0.35],
            any::<u64>()
        )
            .prop_map(|(n, perturb, seed)| Scene::Grid { n, perturb, seed }),
        (1u32..4).prop_map(|levels| Scene::Sphere { levels }),
    ]
}

/// A smooth random stroke: a walk with bounded turning.
fn stroke_strategy() -> impl Strategy<Value = Vec<(f64, f64)>> {
    (
        (250.0f64..550.0, 180.0f64..420.0),
        0.0f64..std::f64::consts::TAU,
        prop::collection::vec(-0.5f64..0.5, 2..30),
        5.0f64..60.0,
    )
        .prop_map(|((x, y), a0, turns, step)| {
            let mut p = vec![(x, y)];
            let mut a = a0;
            for t in turns {
                a += t;
                let (px, py) = *p.last().unwrap();
                p.push((px + step * a.cos(), py + step * a.sin()));
            }
            p
        })
}

/// The plain path gives the fast path's edits (or error) bit for bit.
fn check_plain_path(mesh: &PolyMesh, pts: &[(f64, f64)], view: &View, o: &CutOptions) {
    let text = |r: katachi::Result<katachi::cut::CutEdits>| match r {
        Ok(e) => format!("{e:?}"),
        Err(e) => format!("error {e}"),
    };
    let s = stroke(pts);
    let (fast, plain) = (
        text(cut_edits(mesh, &s, view, o)),
        text(cut_edits_plain(mesh, &s, view, o)),
    );
    assert!(
        fast == plain,
        "the plain path differs:\nfast  {fast}\nplain {plain}"
    );
}

fn run(mesh: &PolyMesh, pts: &[(f64, f64)], view: &View, o: &CutOptions) -> Option<CutOutput> {
    check_plain_path(mesh, pts, view, o);
    match cut_by_stroke(mesh, &stroke(pts), view, o) {
        Ok(out) => Some(out),
        Err(Error::StrokeSelfIntersects { .. }) => None,
        Err(e) => panic!("unexpected error {e}"),
    }
}

counted_proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), max_global_rejects: 1_000_000, ..ProptestConfig::default() })]

    #[test]
    fn cut_invariants(
        scene in scene_strategy(),
        ortho in any::<bool>(),
        theta in 0.0f64..std::f64::consts::TAU,
        phi in 0.0f64..1.2,
        dist in 1.5f64..4.0,
        pts in stroke_strategy(),
        visible in any::<bool>(),
    ) {
        let mesh = scene_mesh(&scene);
        let view = view_for(&mesh, ortho, theta, phi, dist);
        let mut o = CutOptions::with_mode(if visible { CutMode::VisibleOnly } else { CutMode::ThroughAll });
        o.corner_angle_deg = 180.0;
        let out = run(&mesh, &pts, &view, &o);
        prop_assume!(out.is_some(), "the stroke crosses itself");
        let out = out.unwrap();
        check_valid(&mesh, &out);
        check_paths_are_edges(&out);
        prop_assert!(out.report.unjoined.is_empty(), "{:?}", out.report.unjoined);
        // One piece: no chord can cross another path.
        prop_assert!(out.report.rerouted.is_empty(), "{:?}", out.report.rerouted);
        // Euler characteristic unchanged (not opened).
        prop_assert_eq!(euler(&components(&out.mesh)), euler(&components(&mesh)));
        // Path vertices lie on the stroke.
        let stroke_px: Vec<DVec2> = pts.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
        // (A path's ends may have moved onto an edge, up to a third of the snap distance.)
        let end_reach = o.snap_segment_ratio * out.report.mean_edge_length_px / 3.0;
        for p in &out.report.paths {
            for (k, &x) in p.vertices.iter().enumerate() {
                let s = screen(&view, out.mesh.position(x));
                let tol = if k == 0 || k + 1 == p.vertices.len() { end_reach } else { 0.0 };
                prop_assert!(dist_to_polyline(s, &stroke_px) <= tol + 1e-6 * (1.0 + s.length()), "path vertex {} off the stroke", x);
            }
        }
        // Split bound: ≤ 3 pieces per path crossing the face (through all sheets a stroke can
        // pass over one face on two chains), one more per stroke end in the face or within the
        // reach of an end moved onto one of its edges.
        let ends: Vec<DVec2> = vec![stroke_px[0], *stroke_px.last().unwrap()];
        let out_tris = faces_of(&out.mesh);
        let mut chains_in: BTreeMap<FaceId, BTreeSet<usize>> = BTreeMap::new();
        for (pi, p) in out.report.paths.iter().enumerate() {
            for w in p.vertices.windows(2) {
                for (i, t) in out_tris.iter().enumerate() {
                    if t.contains(&w[0].0) && t.contains(&w[1].0) {
                        chains_in.entry(out.face_origin[i]).or_default().insert(pi);
                    }
                }
            }
        }
        for (f, n) in pieces_per_face(&out) {
            let chains = chains_in.get(&f).map_or(0, |c| c.len()).max(1) as u32;
            // The face as snapping left it (its corners may have moved).
            let c: Vec<DVec2> = mesh.face_outer(f).iter().map(|&q| screen(&view, out.mesh.position(q))).collect();
            let inside = ends.iter().filter(|&&e| {
                let o1 = (c[1] - c[0]).perp_dot(e - c[0]);
                let o2 = (c[2] - c[1]).perp_dot(e - c[1]);
                let o3 = (c[0] - c[2]).perp_dot(e - c[2]);
                let within = (o1 >= 0.0 && o2 >= 0.0 && o3 >= 0.0) || (o1 <= 0.0 && o2 <= 0.0 && o3 <= 0.0);
                within || (0..3).any(|i| dist_to_polyline(e, &[c[i], c[(i + 1) % 3]]) <= end_reach * (1.0 + 1e-9))
            }).count() as u32;
            prop_assert!(n <= 1 + 2 * chains + inside, "face {} in {} pieces ({} ends inside, {} chains)", f, n, inside, chains);
        }
        // T4: every piece turns the way its face does on screen (no flipped triangle).
        for (i, t) in out_tris.iter().enumerate() {
            let f = out.face_origin[i];
            let orig: Vec<u32> = mesh.face_outer(f).iter().map(|v| v.0).collect();
            let sign = |c: &[u32]| -> Option<f64> {
                let s: Option<Vec<DVec2>> = c.iter().map(|&q| project(&view, out.mesh.position(VertexId(q))).map(|x| x.0)).collect();
                let s = s?;
                Some((s[1] - s[0]).perp_dot(s[2] - s[0]))
            };
            if let (Some(a), Some(b)) = (sign(t), sign(&orig)) {
                let tiny = 1e-9 * (1.0 + b.abs());
                prop_assert!(a * b >= 0.0 || a.abs() < tiny || b.abs() < tiny, "face {:?} of {} is flipped ({} vs {})", t, f, a, b);
            }
        }
        check_moves(&mesh, &view, &out, &o);
        if visible {
            check_front_only(&mesh, &view, &out);
        }
        // No near-duplicates: a new vertex is at least the snap distance from every unmoved,
        // unrefused input vertex it shares an edge with (less the reach of a moved end).
        let path_ends: BTreeSet<u32> = out.report.paths.iter().flat_map(|p| [p.vertices[0].0, p.vertices[p.vertices.len() - 1].0]).collect();
        let l = out.report.mean_edge_length_px;
        let reach = o.snap_segment_ratio.min(o.snap_vertex_ratio) * l;
        let moved: BTreeSet<u32> = out.report.moved.iter().map(|m| m.vertex.0).collect();
        let refused: BTreeSet<u32> = out.report.snaps_refused.iter().map(|v| v.0).collect();
        let nv = mesh.vertex_count();
        if !visible {
            for (a, b) in edge_set(&out.mesh) {
                let (old, new) = if a < nv && b >= nv { (a, b) } else if b < nv && a >= nv { (b, a) } else { continue };
                if moved.contains(&old) || refused.contains(&old) {
                    continue;
                }
                let d = (screen(&view, out.mesh.position(VertexId(old))) - screen(&view, out.mesh.position(VertexId(new)))).length();
                let need = if path_ends.contains(&new) { reach - end_reach } else { reach };
                prop_assert!(d >= need * (1.0 - 1e-6), "new vertex {} is {} px from vertex {} (snap distance {})", new, d, old, reach);
            }
        }
    }

    #[test]
    fn opening_changes_euler_as_expected(
        n in 5u32..12,
        perturb in 0.0f64..0.3,
        seed in any::<u64>(),
        pts in stroke_strategy(),
    ) {
        let mesh = perturbed_grid(n, n, perturb, seed);
        let view = view_for(&mesh, true, 0.0, 0.0, 3.0);
        let mut o = through_all();
        o.corner_angle_deg = 180.0;
        let plain = run(&mesh, &pts, &view, &o);
        prop_assume!(plain.is_some(), "the stroke crosses itself");
        let plain = plain.unwrap();
        o.open = true;
        let opened = run(&mesh, &pts, &view, &o).unwrap();
        check_valid(&mesh, &opened);
        let (before, after) = (components(&plain.mesh), components(&opened.mesh));
        // Per path: a slit (ends inside) lowers χ by 1; boundary-to-boundary raises it by 1
        // (a new component); a path with one end on the boundary keeps it.
        let boundary: BTreeSet<u32> = {
            let mut uses: BTreeMap<(u32, u32), u32> = BTreeMap::new();
            for t in faces_of(&plain.mesh) {
                for i in 0..3 {
                    let (a, b) = (t[i], t[(i + 1) % 3]);
                    *uses.entry((a.min(b), a.max(b))).or_default() += 1;
                }
            }
            uses.iter().filter(|(_, &u)| u == 1).flat_map(|(&(a, b), _)| [a, b]).collect()
        };
        let mut expected = euler(&before);
        let paths = &plain.report.paths;
        // Only simple cases: one path.
        prop_assume!(paths.len() == 1 && !paths[0].closed);
        let p = &paths[0].vertices;
        let ends_on_boundary = [p[0], *p.last().unwrap()].iter().filter(|v| boundary.contains(&v.0)).count();
        let interior_on_boundary = p[1..p.len() - 1].iter().any(|v| boundary.contains(&v.0));
        prop_assume!(!interior_on_boundary);
        let along_boundary = p.windows(2).any(|w| boundary.contains(&w[0].0) && boundary.contains(&w[1].0));
        prop_assume!(!along_boundary);
        // A one-edge slit between two interior vertices cannot open (no vertex to split).
        prop_assume!(ends_on_boundary > 0 || p.len() >= 3);
        expected += match ends_on_boundary { 0 => -1, 1 => 0, _ => 1 };
        prop_assert_eq!(euler(&after), expected, "path {:?}", p);
        prop_assert_eq!(after.len() as i64 - before.len() as i64, if ends_on_boundary == 2 { 1 } else { 0 });
    }

    #[test]
    fn opening_a_closed_loop_keeps_euler_and_cuts_out_a_disk(
        n in 8u32..14,
        perturb in prop_oneof![Just(0.0), 0.0f64..0.3],
        seed in any::<u64>(),
        centre in (0.35f64..0.65, 0.35f64..0.65),
        radius in 0.12f64..0.3,
        sides in 6usize..40,
        phase in 0.0f64..1.0,
        wobble in 0.0f64..0.1,
    ) {
        // A closed stroke well inside the grid (a polygon, wobbly), seen from above.
        let mesh = perturbed_grid(n, n, perturb, seed);
        let view = top_view(-0.5, n as f64 + 0.5, -0.5, n as f64 + 0.5, (n as f64 + 1.0) / 600.0);
        let c = DVec2::new(centre.0, centre.1) * n as f64;
        let r = radius * n as f64;
        // At least a unit from the boundary, so snapping cannot pull a boundary vertex in
        // (a loop through the boundary is not a closed cut of a disk).
        let reach = r * (1.0 + wobble);
        prop_assume!(c.min_element() - reach >= 1.0 && c.max_element() + reach <= n as f64 - 1.0);
        let mut pts: Vec<(f64, f64)> = (0..sides)
            .map(|i| {
                let a = std::f64::consts::TAU * (i as f64 + phase) / sides as f64;
                let rr = r * (1.0 + wobble * (3.0 * a).sin());
                let s = screen(&view, DVec3::new(c.x + rr * a.cos(), c.y + rr * a.sin(), 0.0));
                (s.x, s.y)
            })
            .collect();
        pts.push(pts[0]);
        let mut o = through_all();
        check_plain_path(&mesh, &pts, &view, &o);
        let plain = cut(&mesh, &pts, &view, &o);
        check_valid(&mesh, &plain);
        check_paths_are_edges(&plain);
        prop_assert!(plain.report.unjoined.is_empty());
        // A loop about one face across can normalize to a single edge there and back.
        prop_assume!(plain.report.paths.len() == 1 && plain.report.paths[0].closed);
        o.open = true;
        let opened = cut(&mesh, &pts, &view, &o);
        check_valid(&mesh, &opened);
        let (before, after) = (components(&plain.mesh), components(&opened.mesh));
        // T5 (c): a closed loop of k vertices: V += k, E += k, χ unchanged, one more part.
        prop_assert_eq!(euler(&after), euler(&before));
        prop_assert_eq!(after.len(), before.len() + 1, "{:?}", plain.report.paths);
        let k: usize = {
            let mut v: Vec<u32> = plain.report.paths.iter().flat_map(|p| p.vertices.iter().map(|x| x.0)).collect();
            v.sort_unstable();
            v.dedup();
            v.len()
        };
        prop_assert_eq!(opened.mesh.vertex_count() as usize, plain.mesh.vertex_count() as usize + k);
    }

    #[test]
    fn integer_grids_with_strokes_through_vertices(
        n in 3u32..10,
        pts in prop::collection::vec((0i32..=20, 0i32..=20), 2..8),
        visible in any::<bool>(),
    ) {
        // Stroke points on vertices, edge midpoints and face centres of an integer grid.
        let mesh = tri_grid(n, n);
        let view = top_view(-0.5, n as f64 + 0.5, -0.5, n as f64 + 0.5, (n as f64 + 1.0) / 400.0);
        let px: Vec<(f64, f64)> = pts.iter().map(|&(i, j)| {
            let (x, y) = (i as f64 * n as f64 / 20.0, j as f64 * n as f64 / 20.0);
            let s = screen(&view, DVec3::new(x, y, 0.0));
            (s.x, s.y)
        }).collect();
        let o = CutOptions::with_mode(if visible { CutMode::VisibleOnly } else { CutMode::ThroughAll });
        check_plain_path(&mesh, &px, &view, &o);
        let out = match cut_by_stroke(&mesh, &stroke(&px), &view, &o) {
            Ok(out) => out,
            Err(e @ (Error::StrokeSelfIntersects { .. } | Error::StrokeTooShort { .. })) => {
                prop_assume!(false, "{}", e);
                unreachable!()
            }
            Err(e) => panic!("{e}"),
        };
        check_valid(&mesh, &out);
        check_paths_are_edges(&out);
        prop_assert!(out.report.unjoined.is_empty());
        prop_assert_eq!(euler(&components(&out.mesh)), euler(&components(&mesh)));
    }
}

#[test]
fn max_faces_split_refuses_a_larger_cut_and_allows_its_own_size() {
    let (g, v) = grid_scene();
    let pts = [px(0.3, 1.2), px(7.6, 6.3)];
    let full = cut(&g, &pts, &v, &through_all());
    let n = full.report.split_faces;
    assert!(n > 2, "the stroke splits several faces ({n})");
    let mut o = through_all();
    o.max_faces_split = n;
    let same = cut(&g, &pts, &v, &o);
    assert_eq!(same.report.split_faces, n);
    o.max_faces_split = n - 1;
    match cut_by_stroke(&g, &stroke(&pts), &v, &o) {
        Err(Error::CutTooLarge { split_faces, limit }) => {
            assert_eq!((split_faces, limit), (n, n - 1));
        }
        other => panic!("expected CutTooLarge, got {other:?}"),
    }
}

/// Snapping off: no vertex moves, so data linear in the positions must come out equal to the
/// output positions' function exactly (to rounding).
fn no_snap(mode: CutMode) -> CutOptions {
    let mut o = CutOptions::with_mode(mode);
    o.snap_vertex_ratio = 0.0;
    o.snap_segment_ratio = 0.0;
    o
}

#[test]
fn corner_data_is_linear_inside_each_source_face() {
    // Quads (triangulated first), data per corner that jumps between faces (a UV seam on
    // every edge): (x, y) + 10 · face.
    let g = shapes::grid(8, 8).unwrap();
    let v = top_view(-0.5, 8.5, -0.5, 8.5, 0.02);
    let gr = &g;
    let values: Vec<f64> = g
        .faces()
        .flat_map(|f| {
            gr.face_outer(f)
                .iter()
                .flat_map(move |&c| {
                    let p = gr.position(c);
                    [p.x + 10.0 * f.0 as f64, p.y]
                })
                .collect::<Vec<_>>()
        })
        .collect();
    for open in [false, true] {
        let mut o = no_snap(CutMode::ThroughAll);
        o.open = open;
        let out = cut(&g, &[px(0.3, 1.2), px(4.1, 3.3), px(7.6, 6.3)], &v, &o);
        assert!(out.report.new_vertices > 4);
        let data = out.interpolate_corner_data(&g, &values, 2).unwrap();
        assert_eq!(data.len(), 2 * out.mesh.corner_count() as usize);
        for (t, f) in out.face_origin.iter().enumerate() {
            for k in 0..3 {
                let p = out.mesh.position(out.mesh.corners()[3 * t + k]);
                let (u, w) = (data[2 * (3 * t + k)], data[2 * (3 * t + k) + 1]);
                assert!(
                    (u - (p.x + 10.0 * f.0 as f64)).abs() < 1e-9 && (w - p.y).abs() < 1e-9,
                    "face {t} corner {k}: ({u}, {w}) at {p}, source face {f:?}"
                );
            }
        }
    }
}

#[test]
fn vertex_data_follows_split_vertices_and_opening_copies() {
    let (g, v) = grid_scene();
    let values: Vec<f64> = g.positions().iter().flat_map(|p| [p.x, p.y, p.z]).collect();
    let mut o = no_snap(CutMode::ThroughAll);
    o.open = true;
    let out = cut(&g, &[px(0.3, 1.2), px(4.1, 3.3), px(7.6, 6.3)], &v, &o);
    assert!(out.mesh.vertex_count() > g.vertex_count());
    let data = out.interpolate_vertex_data(&g, &values, 3).unwrap();
    for (i, p) in out.mesh.positions().iter().enumerate() {
        let d = DVec3::new(data[3 * i], data[3 * i + 1], data[3 * i + 2]);
        assert!((d - *p).length() < 1e-9, "vertex {i}: {d} vs {p}");
    }
    // With snapping, moved vertices keep their own values.
    let out = cut(
        &g,
        &[px(0.3, 1.2), px(4.1, 3.3), px(7.6, 6.3)],
        &v,
        &through_all(),
    );
    let data = out.interpolate_vertex_data(&g, &values, 3).unwrap();
    for m in &out.report.moved {
        let i = m.vertex.idx();
        assert_eq!(&data[3 * i..3 * i + 3], &values[3 * i..3 * i + 3]);
    }
}

#[test]
fn interpolation_rejects_data_of_the_wrong_size_or_mesh() {
    let (g, v) = grid_scene();
    let out = cut(&g, &[px(0.3, 1.2), px(7.6, 6.3)], &v, &through_all());
    let n = g.corner_count() as usize;
    for (values, dim) in [(vec![0.0; 2 * n - 1], 2), (vec![0.0; 0], 0)] {
        assert!(matches!(
            out.interpolate_corner_data(&g, &values, dim),
            Err(Error::InvalidArgument(_))
        ));
    }
    let other = tri_grid(3, 3);
    let vals = vec![0.0; other.vertex_count() as usize];
    assert!(matches!(
        out.interpolate_vertex_data(&other, &vals, 1),
        Err(Error::InvalidArgument(_))
    ));
}

#[test]
fn edits_applied_by_hand_give_the_cut_mesh() {
    use katachi::cut::cut_edits;
    let (g, v) = grid_scene();
    let s = stroke(&[px(0.3, 1.2), px(4.1, 3.3), px(7.6, 6.3)]);
    let mut o = through_all();
    o.open = true;
    let e = cut_edits(&g, &s, &v, &o).unwrap();
    let out = cut_by_stroke(&g, &s, &v, &o).unwrap();
    assert_eq!(bits(&e.apply(&g).unwrap()), bits(&out));
    assert_eq!(e.report, out.report);
    // By hand: move, append vertices, rewrite slots, append faces.
    let mut pos = g.positions().to_vec();
    for m in &e.report.moved {
        pos[m.vertex.idx()] = m.to;
    }
    pos.extend_from_slice(&e.new_vertices);
    let mut tris = faces_of(&g);
    for (slot, t) in &e.rewritten_faces {
        tris[slot.idx()] = t.map(|v| v.0);
    }
    tris.extend(e.appended_faces.iter().map(|(t, _)| t.map(|v| v.0)));
    assert_eq!(pos, out.mesh.positions());
    assert_eq!(tris, faces_of(&out.mesh));
    assert!(e.split_edges().len() > 0);
    for (u, w, on) in e.split_edges() {
        assert!(!edge_set(&out.mesh).contains(&(u.0.min(w.0), u.0.max(w.0))));
        assert!(on.iter().all(|m| m.0 >= g.vertex_count()));
    }
    // Edits of one mesh do not apply to another.
    assert!(matches!(
        e.apply(&tri_grid(3, 3)),
        Err(Error::InvalidArgument(_))
    ));
}

#[test]
fn vertex_original_names_the_vertex_each_opening_copy_duplicates() {
    let (g, v) = grid_scene();
    let mut o = through_all();
    o.open = true;
    let out = cut(&g, &[px(0.3, 1.2), px(4.1, 3.3), px(7.6, 6.3)], &v, &o);
    let orig = out.vertex_original();
    assert_eq!(orig.len(), out.mesh.vertex_count() as usize);
    let copies: Vec<usize> = (0..orig.len()).filter(|&i| orig[i].idx() != i).collect();
    // A slit (both ends inside faces): every path vertex but the two ends has one copy.
    let p = &out.report.paths[0].vertices;
    let path: BTreeSet<u32> = p[1..p.len() - 1].iter().map(|v| v.0).collect();
    assert_eq!(copies.len(), path.len());
    for &c in &copies {
        let o = orig[c];
        assert!(
            path.contains(&o.0),
            "copy {c} of {o:?} is not of a path vertex"
        );
        assert_eq!(out.mesh.position(VertexId(c as u32)), out.mesh.position(o));
        assert_eq!(orig[o.idx()], o);
    }
    // Not opened: every vertex is its own.
    let out = cut(&g, &[px(0.3, 1.2), px(7.6, 6.3)], &v, &through_all());
    assert!(out
        .vertex_original()
        .iter()
        .enumerate()
        .all(|(i, v)| v.idx() == i));
}

#[test]
fn snapping_that_uncovers_a_hidden_sheet_does_not_cut_it() {
    // Two sheets exactly one above the other in a top view: the lower one is wholly hidden.
    // Strokes entering from off the mesh snap top boundary vertices inwards, which uncovers
    // a sliver of the lower sheet's border; the user never saw it, so it stays uncut.
    for m in [3u32, 6, 12] {
        let (two, n, nv) = two_sheets(m);
        let v = top_view(-0.5, m as f64 + 0.5, -0.5, m as f64 + 0.5, 0.02);
        let w = (m as f64 + 1.0) / 0.02;
        for phase in 0..40 {
            let pts: Vec<(f64, f64)> = if phase % 2 == 0 {
                (0..40)
                    .map(|i| {
                        let t = i as f64 / 39.0;
                        let y = 0.5 + 0.2 * (t * 9.0 + phase as f64 * 0.37).sin();
                        ((0.1 + 0.8 * t) * w, y * w)
                    })
                    .collect()
            } else {
                let a = phase as f64 * 0.13;
                let (c, s) = (0.45 * a.cos(), 0.45 * a.sin());
                vec![
                    ((0.5 - c) * w, (0.5 - s) * w),
                    ((0.5 + c) * w, (0.5 + s) * w),
                ]
            };
            let vis = cut(&two, &pts, &v, &CutOptions::default());
            check_valid(&two, &vis);
            let lower_split: Vec<u32> = pieces_per_face(&vis)
                .iter()
                .filter(|(f, &c)| f.0 as usize >= n && c > 1)
                .map(|(f, _)| f.0)
                .collect();
            assert!(
                lower_split.is_empty(),
                "m {m}, stroke {phase}: hidden faces split: {lower_split:?}"
            );
            assert!(vis
                .report
                .paths
                .iter()
                .all(|p| p.vertices.iter().all(|x| x.0 < nv || x.0 >= 2 * nv)));
            assert!(
                !vis.report.paths.is_empty(),
                "m {m}, stroke {phase}: no cut"
            );
        }
    }
}
