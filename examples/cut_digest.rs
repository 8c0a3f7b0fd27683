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
//! instead, which must print the same lines. `--detail` adds a second hash per case, of the edits with the report's mean edge lengths
//! left out (a change in how L is rounded then shows apart from a change in the edits), and
//! `--case K` prints case K's edits whole.
//!
//! Cases: [`cut_meshes::RandomCuts`] (random meshes, views, strokes and options).

use std::hash::{Hash, Hasher};

use katachi::cut::{cut_edits, cut_edits_plain};

#[path = "../tests/cut_meshes/mod.rs"]
mod cut_meshes;
use cut_meshes::{RandomCut, RandomCuts};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: u64 = args.first().and_then(|s| s.parse().ok()).unwrap_or(3000);
    let detail = args.iter().any(|a| a == "--detail");
    let plain = args.iter().any(|a| a == "--plain");
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
            println!("{case} {key}\n{text}");
            return;
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
    print!("{lines}");
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
