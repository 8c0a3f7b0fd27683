//! Opening the cut (spec §4 step 8, T5; as libigl's `cut_mesh` does): around each path
//! vertex the faces fall into wedges separated by path edges; the first wedge keeps the
//! vertex, every other wedge gets a copy. A slit's ends (one path edge, inside the mesh) have
//! one wedge and stay whole; a path end on the boundary splits; a closed loop duplicates
//! every vertex on it and may separate the mesh. A path vertex whose faces already formed
//! several fans (a non-manifold vertex) gets a copy per wedge too, which separates the fans.

use super::split_patterns::Splitter;

/// Duplicates the path vertices; `is_cut(a, b)`: whether `a`-`b` is a path edge. Returns, for
/// each copy made (in creation order), the local vertex it copies.
pub(crate) fn open(
    sp: &mut Splitter,
    path_vertices: &[u32],
    is_cut: &dyn Fn(u32, u32) -> bool,
) -> Vec<u32> {
    let n0 = sp.r.verts.len() as u32;
    let mut faces: Vec<u32> = sp.touched.clone();
    for &v in path_vertices {
        if v < n0 {
            faces.extend_from_slice(sp.r.vertex_faces(v));
        }
    }
    faces.sort_unstable();
    faces.dedup();
    // (vertex, face, sub-triangle) for every corner at a path vertex.
    let mut inc: Vec<(u32, u32, u32)> = Vec::new();
    for &lf in &faces {
        for (i, t) in sp.face_subs(lf).iter().enumerate() {
            for &c in t {
                if path_vertices.binary_search(&c).is_ok() {
                    inc.push((c, lf, i as u32));
                }
            }
        }
    }
    inc.sort_unstable();
    let mut copies = Vec::new();
    // Wedges are found on the sub-triangles as they are, then corners are replaced at once,
    // so each vertex sees its neighbours (and the cut edges) by their original ids.
    let mut replace: Vec<(u32, u32, u32, u32)> = Vec::new();
    let mut i = 0;
    while i < inc.len() {
        let v = inc[i].0;
        let mut j = i;
        while j < inc.len() && inc[j].0 == v {
            j += 1;
        }
        let items = &inc[i..j];
        // Union-find over the items: joined across a shared, uncut edge at v.
        let mut parent: Vec<usize> = (0..items.len()).collect();
        fn root(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        let mut by_other: Vec<(u32, usize)> = Vec::new();
        for (k, &(_, lf, si)) in items.iter().enumerate() {
            let t = sp.face_subs(lf)[si as usize];
            let r = t.iter().position(|&c| c == v).expect("the corner is v");
            for x in [t[(r + 1) % 3], t[(r + 2) % 3]] {
                if !is_cut(v, x) {
                    by_other.push((x, k));
                }
            }
        }
        by_other.sort_unstable();
        for w in by_other.windows(2) {
            if w[0].0 == w[1].0 {
                let (a, b) = (root(&mut parent, w[0].1), root(&mut parent, w[1].1));
                if a != b {
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
        // Wedges in order of their first item; the first keeps v.
        let mut label: Vec<Option<u32>> = vec![None; items.len()];
        let mut first_root = None;
        for (k, &(_, lf, si)) in items.iter().enumerate() {
            let rk = root(&mut parent, k);
            if first_root.is_none() {
                first_root = Some(rk);
            }
            if Some(rk) == first_root {
                continue;
            }
            let copy = match label[rk] {
                Some(c) => c,
                None => {
                    let c = sp.copy_vertex(v);
                    copies.push(v);
                    label[rk] = Some(c);
                    c
                }
            };
            replace.push((lf, si, v, copy));
        }
        i = j;
    }
    for (lf, si, v, copy) in replace {
        sp.replace_corner(lf, si as usize, v, copy);
    }
    copies
}
