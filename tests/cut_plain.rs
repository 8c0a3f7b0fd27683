//! Stroke cut: the plain path (`cut_edits_plain`: every face and stroke segment scanned, the
//! standard library's sorts; no grid, SIMD passes, buckets, windows or radix sorts) gives the
//! fast path's edits bit for bit, on the random cuts `examples/cut_digest.rs` fingerprints.
//! 400 cases here, `KATACHI_CUT_PLAIN_CASES` for more (`cargo run --release --example
//! cut_digest -- 30000 --plain` prints the fast path's digest of all 30,000).

use katachi::cut::{cut_edits, cut_edits_plain, CutEdits};

mod cut_meshes;
use cut_meshes::{RandomCut, RandomCuts};

fn cases() -> u64 {
    std::env::var("KATACHI_CUT_PLAIN_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(400)
}

fn text(r: katachi::Result<CutEdits>) -> String {
    match r {
        Ok(e) => format!("{e:?}"),
        Err(e) => format!("error {e}"),
    }
}

#[test]
fn the_plain_path_gives_the_fast_paths_edits_on_random_cuts() {
    let mut cuts = RandomCuts::new();
    let (n, mut cut, mut refused) = (cases(), 0, 0);
    for case in 0..n {
        let RandomCut {
            key,
            mesh,
            view,
            stroke,
            options,
            ..
        } = cuts.next_cut();
        let fast = text(cut_edits(&mesh, &stroke, &view, &options));
        let plain = text(cut_edits_plain(&mesh, &stroke, &view, &options));
        assert!(
            fast == plain,
            "case {case} ({key}, {options:?}): the plain path differs\nfast  {fast}\nplain {plain}"
        );
        if fast.starts_with("error") {
            refused += 1;
        } else {
            cut += 1;
        }
    }
    // Most random strokes make a cut (the others cross themselves or miss the mesh).
    assert!(cut > 8 * n / 10, "{cut} cuts and {refused} errors of {n}");
    eprintln!("{cut} cuts and {refused} errors compared");
}
