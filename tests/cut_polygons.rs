//! The cut in the input's own layout (`CutOutput::polygons`): on random cuts of triangle
//! meshes and of the same shapes as quads, every face, edge and corner says where it came
//! from, the edges are the faces' sides, untouched faces come back whole, and the polygons
//! cover what the cut's triangles cover.

use std::collections::{BTreeMap, BTreeSet};

use katachi::cut::{cut_by_stroke, CutOutput, CutPolygons, InputEdges, NONE};
use katachi::mesh::shapes;
use katachi::{Error, PolyMesh};

mod cut_meshes;
use cut_meshes::RandomCuts;

/// The input's edges in the order a host might keep them: by first use, then shuffled and
/// some reversed (deterministic), with one loose edge at the end.
fn host_edges(mesh: &PolyMesh, shuffle: bool) -> (Vec<[u32; 2]>, Vec<u32>) {
    let c = mesh.corners();
    let mut ids: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    let mut edges: Vec<[u32; 2]> = Vec::new();
    let mut corner_edges = vec![0; c.len()];
    for w in mesh.loop_offsets().windows(2) {
        let (a, b) = (w[0] as usize, w[1] as usize);
        for k in a..b {
            let (u, v) = (c[k].0, c[if k + 1 < b { k + 1 } else { a }].0);
            let next = edges.len() as u32;
            let e = *ids.entry((u.min(v), u.max(v))).or_insert(next);
            if e == next {
                edges.push([u, v]);
            }
            corner_edges[k] = e;
        }
    }
    if shuffle {
        let n = edges.len();
        // A permutation: i -> (i * step) mod n with step coprime to n.
        let step = (1..n.max(2)).rev().find(|s| gcd(*s, n) == 1).unwrap_or(1);
        let perm: Vec<u32> = (0..n).map(|i| ((i * step) % n) as u32).collect();
        let mut shuffled = vec![[0, 0]; n];
        for (i, &p) in perm.iter().enumerate() {
            let [a, b] = edges[i];
            shuffled[p as usize] = if i % 3 == 0 { [b, a] } else { [a, b] };
        }
        for e in &mut corner_edges {
            *e = perm[*e as usize];
        }
        edges = shuffled;
    }
    if mesh.vertex_count() >= 2 {
        edges.push([0, mesh.vertex_count() - 1]); // loose (or a duplicate of a side: unused)
    }
    (edges, corner_edges)
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// Every property the module docs promise.
fn check(input: &PolyMesh, out: &CutOutput, p: &CutPolygons, host: &[[u32; 2]], keep: bool) {
    let nf_in = input.face_count() as usize;
    let nv_in = input.vertex_count();
    let original: Vec<u32> = out.vertex_original().iter().map(|v| v.0).collect();
    let nf = p.face_offsets.len() - 1;
    assert_eq!(p.face_origin.len(), nf);
    assert_eq!(p.corners.len(), *p.face_offsets.last().unwrap() as usize);
    assert_eq!(p.corner_origin.len(), p.corners.len());
    assert_eq!(p.corner_edges.len(), p.corners.len());
    assert_eq!(p.edges.len(), p.edge_origin.len());
    assert_eq!(p.positions, out.mesh.positions());
    assert!(nf >= nf_in);
    let (flo, lo, ic) = (
        input.face_loop_offsets(),
        input.loop_offsets(),
        input.corners(),
    );
    let input_range = |f: usize| lo[flo[f] as usize] as usize..lo[flo[f + 1] as usize] as usize;
    let mut kept = 0;
    let mut uses: BTreeMap<u32, u32> = BTreeMap::new();
    let mut directed: BTreeSet<(u32, u32)> = BTreeSet::new();
    for f in 0..nf {
        let (s, e) = (p.face_offsets[f] as usize, p.face_offsets[f + 1] as usize);
        assert!(e - s >= 3, "face {f} has {} corners", e - s);
        let origin = p.face_origin[f] as usize;
        if f < nf_in {
            assert_eq!(origin, f, "face {f} is in its own slot");
        }
        let range = input_range(origin);
        if e - s > 3
            || (keep
                && range.len() == 3
                && p.corners[s..e] == ic[range.clone()].iter().map(|v| v.0).collect::<Vec<_>>()[..])
        {
            // A polygon is a kept face (a triangle may be too).
            if e - s > 3 {
                assert!(keep && f < nf_in);
                let own: Vec<u32> = ic[range.clone()].iter().map(|v| v.0).collect();
                assert_eq!(&p.corners[s..e], &own[..], "face {f} kept whole");
                kept += 1;
            }
        }
        for k in s..e {
            let (a, b) = (p.corners[k], p.corners[if k + 1 < e { k + 1 } else { s }]);
            assert!(directed.insert((a, b)), "half-edge {a}->{b} twice");
            let edge = p.corner_edges[k];
            let [x, y] = p.edges[edge as usize];
            assert_eq!(
                key(x, y),
                key(a, b),
                "corner {k}'s edge {edge} is {x}-{y}, not {a}-{b}"
            );
            *uses.entry(edge).or_default() += 1;
            let c = p.corner_origin[k];
            if c != NONE {
                assert!(
                    range.contains(&(c as usize)),
                    "corner {k}'s origin {c} is in its face"
                );
                assert_eq!(
                    ic[c as usize].0, original[a as usize],
                    "corner {k}'s origin"
                );
            } else {
                assert!(
                    original[a as usize] >= nv_in,
                    "a corner at an input vertex has an origin"
                );
            }
        }
    }
    assert!(kept <= p.kept_faces as usize);
    // Edges: each used at most twice, once per pair of vertices; the host's keep their slot.
    let mut pairs = BTreeSet::new();
    for (&e, &n) in &uses {
        assert!(n <= 2, "edge {e} used {n} times");
        let [a, b] = p.edges[e as usize];
        assert!(pairs.insert(key(a, b)), "edge {a}-{b} twice");
    }
    for (e, &[a, b]) in host.iter().enumerate() {
        let [x, y] = p.edges[e];
        if p.edge_origin[e] == e as u32 && [x, y] != [a, b] {
            // A split edge keeps the piece at its first vertex.
            assert_eq!(x, a, "edge {e} keeps its first vertex");
            assert!(y >= nv_in, "edge {e}'s piece ends at a new vertex");
        }
    }
    for (e, &o) in p.edge_origin.iter().enumerate() {
        if e < host.len() {
            assert_eq!(o, e as u32);
            continue;
        }
        if o == NONE {
            continue;
        }
        let [a, b] = p.edges[e];
        let [u, w] = host[o as usize];
        for v in [original[a as usize], original[b as usize]] {
            assert!(
                v >= nv_in || v == u || v == w,
                "edge {e} lies on host edge {o}"
            );
        }
    }
    // The polygons cover the cut's triangles: every half-edge of a polygon is one of the
    // triangles', and the triangles' others are the diagonals of kept polygons, in pairs.
    let mut tri: BTreeSet<(u32, u32)> = BTreeSet::new();
    for t in out.mesh.corners().chunks_exact(3) {
        for i in 0..3 {
            tri.insert((t[i].0, t[(i + 1) % 3].0));
        }
    }
    for h in &directed {
        assert!(tri.contains(h), "half-edge {h:?} is no triangle's");
    }
    for &(a, b) in tri.difference(&directed) {
        assert!(
            tri.contains(&(b, a)) && !directed.contains(&(b, a)),
            "{a}->{b} is a diagonal"
        );
    }
    // The paths' edges, both sides of an opened cut.
    let mut steps = BTreeSet::new();
    for path in &out.report.paths {
        let v = &path.vertices;
        let n = v.len();
        let count = if path.closed && n > 2 { n } else { n - 1 };
        for i in 0..count {
            steps.insert(key(v[i].0, v[(i + 1) % n].0));
        }
    }
    let mut seen = BTreeSet::new();
    for &e in &p.path_edges {
        let [a, b] = p.edges[e as usize];
        let k = key(original[a as usize], original[b as usize]);
        assert!(steps.contains(&k), "path edge {e} ({a}-{b}) is on a path");
        seen.insert(k);
    }
    assert_eq!(seen, steps, "every path step has its edge");
}

#[test]
fn random_cuts_of_triangle_meshes_in_the_hosts_layout() {
    let mut cuts = RandomCuts::new();
    let mut cut = 0;
    for _ in 0..100 {
        let c = cuts.next_cut();
        let Ok(out) = cut_by_stroke(&c.mesh, &c.stroke, &c.view, &c.options) else {
            continue;
        };
        cut += 1;
        for shuffle in [false, true] {
            let (edges, corner_edges) = host_edges(&c.mesh, shuffle);
            let host = InputEdges {
                edges: &edges,
                corner_edges: &corner_edges,
            };
            for keep in [true, false] {
                let p = out.polygons(&c.mesh, Some(host), keep).unwrap();
                check(&c.mesh, &out, &p, &edges, keep);
                // A triangle mesh: the same faces and corners as the cut's triangles.
                assert_eq!(
                    p.corners,
                    out.mesh.corners().iter().map(|v| v.0).collect::<Vec<_>>()
                );
            }
        }
        let p = out.polygons(&c.mesh, None, true).unwrap();
        let (edges, _) = host_edges(&c.mesh, false);
        check(&c.mesh, &out, &p, &edges[..edges.len() - 1], true);
        // Corner data: as the kernel's own interpolation (to f32 rounding).
        let values: Vec<f64> = (0..c.mesh.corner_count() as usize * 2)
            .map(|i| ((i * 7919) % 1000) as f64 / 1000.0)
            .collect();
        let want = out.interpolate_corner_data(&c.mesh, &values, 2).unwrap();
        let got = p
            .carry_corner_data(&values.iter().map(|&x| x as f32).collect::<Vec<_>>(), 2)
            .unwrap();
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert!(
                (f64::from(*g) - w).abs() < 1e-5,
                "corner value {i}: {g} vs {w}"
            );
        }
    }
    assert!(cut > 60, "only {cut} of 100 random cuts succeeded");
}

#[test]
fn random_cuts_of_quad_meshes_keep_the_untouched_quads() {
    let mut cuts = RandomCuts::new();
    let (mut cut, mut kept_some, mut split_some) = (0, false, false);
    for _ in 0..200 {
        let c = cuts.next_cut();
        let w: Vec<&str> = c.key.split(' ').collect();
        let quads = match w[0] {
            "grid" => {
                let n = w[1].parse().unwrap();
                shapes::grid(n, n).unwrap()
            }
            "torus" => {
                let n = w[1].parse().unwrap();
                shapes::torus(n, n, 2.0, 0.7).unwrap()
            }
            _ => continue,
        };
        let Ok(out) = cut_by_stroke(&quads, &c.stroke, &c.view, &c.options) else {
            continue;
        };
        cut += 1;
        let (edges, corner_edges) = host_edges(&quads, true);
        let host = InputEdges {
            edges: &edges,
            corner_edges: &corner_edges,
        };
        for keep in [true, false] {
            let p = out.polygons(&quads, Some(host), keep).unwrap();
            check(&quads, &out, &p, &edges, keep);
            if keep {
                let touched = p.face_offsets.len() - 1 - quads.face_count() as usize;
                kept_some |= p.kept_faces > 0;
                split_some |= touched > 0 && p.kept_faces < quads.face_count();
            } else {
                assert_eq!(p.kept_faces, 0);
                assert_eq!(p.corners.len(), out.mesh.corner_count() as usize);
            }
        }
    }
    assert!(cut > 15 && kept_some && split_some, "{cut} quad cuts");
}

#[test]
fn host_edges_that_do_not_match_the_faces_are_refused_naming_the_corner() {
    let mut cuts = RandomCuts::new();
    let c = (0..50)
        .map(|_| cuts.next_cut())
        .find(|c| cut_by_stroke(&c.mesh, &c.stroke, &c.view, &c.options).is_ok())
        .unwrap();
    let out = cut_by_stroke(&c.mesh, &c.stroke, &c.view, &c.options).unwrap();
    let (edges, mut corner_edges) = host_edges(&c.mesh, false);
    corner_edges[5] = corner_edges[6];
    let host = InputEdges {
        edges: &edges,
        corner_edges: &corner_edges,
    };
    match out.polygons(&c.mesh, Some(host), true) {
        Err(Error::InvalidArgument(m)) => assert!(m.contains("corner 5"), "{m}"),
        other => panic!("expected an error naming corner 5, got {other:?}"),
    }
    corner_edges[5] = edges.len() as u32 + 3;
    let host = InputEdges {
        edges: &edges,
        corner_edges: &corner_edges,
    };
    assert!(matches!(
        out.polygons(&c.mesh, Some(host), true),
        Err(Error::InvalidArgument(m)) if m.contains("corner 5")
    ));
    let other = shapes::grid(2, 2).unwrap();
    assert!(matches!(
        out.polygons(&other, None, true),
        Err(Error::InvalidArgument(_))
    ));
}
