//! A fingerprint of the stroke cut over thousands of random cases, for changes that must
//! not change any result (speed work): each line is a case, the hash of its `cut_edits`
//! (or error) and the counts. Run it before and after a change and compare:
//!
//! ```sh
//! cargo run --release --example cut_digest -- 30000 > before.txt
//! # ... change the cut ...
//! cargo run --release --example cut_digest -- 30000 > after.txt && diff before.txt after.txt
//! ```
//!
//! `--plain` runs the plain path (`cut_edits_plain`: no grid, SIMD, buckets or radix sorts)
//! instead, which must print the same lines. `--detail` adds a second hash per case, of the
//! edits with the report's mean edge lengths left out (a change in how L is rounded then
//! shows apart from a change in the edits), and `--case K` prints case K's edits whole.
//! `--check` prints instead the cases whose result breaks an invariant: a face of zero area,
//! two new vertices at one place (not an opening copy), a path that crosses a face twice, or a
//! non-manifold result.
//!
//! Cases: [`cut_meshes::RandomCuts`] (random meshes, views, strokes and options).

use std::hash::{Hash, Hasher};

use katachi::cut::{cut_edits, cut_edits_plain, CutEdits};
use katachi::mesh::inspect;
use katachi::PolyMesh;

#[path = "../tests/cut_meshes/mod.rs"]
mod cut_meshes;
use cut_meshes::{RandomCut, RandomCuts};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: u64 = args.first().and_then(|s| s.parse().ok()).unwrap_or(3000);
    let detail = args.iter().any(|a| a == "--detail");
    let plain = args.iter().any(|a| a == "--plain");
    let check = args.iter().any(|a| a == "--check");
    let mut broken = 0;
    let only: Option<u64> = args
        .iter()
        .position(|a| a == "--case")
        .and_then(|i| args.get(i + 1))
        .and_then(|s| s.parse().ok());
    let mut lines = String::new();
    let mut cases = RandomCuts::new();
    for case in 0..n {
        let RandomCut {
            key,
            mesh,
            view,
            stroke,
            options: o,
            view_args,
        } = cases.next_cut();
        if only.is_some_and(|k| k != case) {
            continue;
        }
        let r = if plain {
            cut_edits_plain(&mesh, &stroke, &view, &o)
        } else {
            cut_edits(&mesh, &stroke, &view, &o)
        };
        let text = match &r {
            Ok(e) => format!("{e:?}"),
            Err(e) => format!("error {e}"),
        };
        if only.is_some() {
            println!(
                "{case} {key} view {view_args:?} stroke {:?}\n{text}",
                stroke.points
            );
            return;
        }
        if check {
            if let Ok(e) = &r {
                let faults = faults(&mesh, e, o.open);
                if !faults.is_empty() {
                    broken += 1;
                    println!("{case} {key} {o:?}: {}", faults.join(", "));
                }
            }
            continue;
        }
        let hash = |t: &str| {
            let mut h = std::collections::hash_map::DefaultHasher::new();
            t.hash(&mut h);
            h.finish()
        };
        let summary = match &r {
            Ok(e) => format!(
                "nv {} rf {} af {}",
                e.new_vertices.len(),
                e.rewritten_faces.len(),
                e.appended_faces.len()
            ),
            Err(_) => "err".into(),
        };
        if detail {
            lines += &format!(
                "{case} {key} {:016x} {:016x} {summary}\n",
                hash(&text),
                hash(&without_lengths(&text))
            );
        } else {
            lines += &format!("{case} {key} {:016x} {summary}\n", hash(&text));
        }
    }
    if check {
        println!("{broken} of {n} cases break an invariant");
        return;
    }
    print!("{lines}");
}

/// The invariants `--check` finds broken by the cut `e` of `mesh` (`opened`: with opening,
/// whose paths are given before it).
fn faults(mesh: &PolyMesh, e: &CutEdits, opened: bool) -> Vec<String> {
    let out = e.apply(mesh).expect("edits apply to their mesh");
    let mut faults = Vec::new();
    let (before, after) = (inspect(mesh).unwrap(), inspect(&out.mesh).unwrap());
    if after.zero_area_faces.len() > before.zero_area_faces.len() {
        faults.push(format!("zero-area faces {:?}", after.zero_area_faces));
    }
    if !after.defects.is_empty() {
        faults.push(format!("defects {:?}", after.defects));
    }
    let (nv, p, orig) = (
        mesh.vertex_count() as usize,
        out.mesh.positions(),
        out.vertex_original(),
    );
    for a in nv..p.len() {
        for b in a + 1..p.len() {
            let copies = orig[b].0 as usize == a || orig[a] == orig[b];
            if !copies && (p[a] - p[b]).length() <= 1e-9 {
                faults.push(format!("new vertices {a} and {b} coincide"));
            }
        }
    }
    // A path crossing a face twice: steps inside one input face that do not follow each other.
    if !opened {
        let mut sides: std::collections::HashMap<(u32, u32), Vec<u32>> = Default::default();
        for (t, f) in out.mesh.faces().zip(&out.face_origin) {
            let l = out.mesh.face_outer(t);
            for i in 0..3 {
                let (a, b) = (l[i].0, l[(i + 1) % 3].0);
                sides.entry((a.min(b), a.max(b))).or_default().push(f.0);
            }
        }
        // (piece, face) → the paths with a step inside the face.
        let mut by_piece: std::collections::BTreeMap<(u32, u32), Vec<usize>> = Default::default();
        for (pi, path) in e.report.paths.iter().enumerate() {
            let v = &path.vertices;
            let mut steps: std::collections::BTreeMap<u32, Vec<usize>> = Default::default();
            for k in 0..v.len().saturating_sub(1) {
                let (a, b) = (v[k].0, v[k + 1].0);
                // Inside a face: both sides of the step's edge lie in it (not along an edge).
                if let Some(fs) = sides.get(&(a.min(b), a.max(b))) {
                    if fs.len() == 2 && fs[0] == fs[1] {
                        steps.entry(fs[0]).or_default().push(k);
                    }
                }
            }
            if let Some((f, ks)) = steps
                .iter()
                .find(|(_, ks)| ks.windows(2).any(|w| w[1] > w[0] + 1))
            {
                faults.push(format!("path {pi} crosses face {f} at steps {ks:?}"));
            }
            for &f in steps.keys() {
                by_piece.entry((path.piece, f)).or_default().push(pi);
            }
        }
        if let Some(((piece, f), paths)) = by_piece.iter().find(|(_, p)| p.len() > 1) {
            faults.push(format!("piece {piece} crosses face {f} on paths {paths:?}"));
        }
    }
    faults
}

/// The edits' text without the report's mean edge lengths (their values up to the next
/// field).
fn without_lengths(text: &str) -> String {
    let mut out = text.to_string();
    for field in ["mean_edge_length_px: ", "mean_edge_length_world: "] {
        if let Some(at) = out.find(field) {
            let end = out[at..].find(',').map_or(out.len(), |e| at + e);
            out.replace_range(at..end, field);
        }
    }
    out
}
