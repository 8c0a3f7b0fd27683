//! Stroke files fuzzed through `katachi cut`, as a user meets them (issue 34: fuzz the cut's
//! C ABI and its stroke files; the C ABI is `tests/c/cut_fuzz.c`). Valid stroke files over
//! the chamfer cube, then byte-level mutations (`tests/support/fuzz.rs`) or numbers replaced
//! by extreme ones (1e300, the largest finite double, the smallest subnormal, 1e309, -0…):
//! `katachi cut` exits 0 with the cut written, or 2 with one line `error: …` without control
//! characters; never anything else (a panic exits 101), never "internal error". A twentieth
//! of the library's fuzzing cases (100 by default; `KATACHI_FUZZ_CASES` sets the library's
//! count); `KATACHI_FUZZ_SEED` varies them.

use std::path::Path;
use std::process::Command;

use glam::{DMat4, DVec3};
use katachi::io::Format;

#[allow(dead_code)]
#[path = "../../tests/support/fuzz.rs"]
mod fuzz;
#[allow(dead_code)]
#[path = "../../tests/support/models.rs"]
mod models;
#[allow(dead_code)]
#[path = "../../tests/support/record.rs"]
mod record;
use fuzz::{cases, mutate, seed, Rng};
use record::record;

/// Numbers at the edges of what a stroke file can say.
const EXTREME: &[&str] = &[
    "1e300",
    "-1e300",
    "1.7976931348623157e308",
    "-1.7976931348623157e308",
    "5e-324",
    "2.2250738585072014e-308",
    "1e309",
    "-0",
    "0",
    "1099511627776",
    "1099511627777",
    "4294967296",
    "1e-300",
];

/// A stroke file: an orthographic view of [-1.6, 1.6]² from `eye` (400 × 400 pixels), a
/// stroke of `n` points from `a` to `b` with a wiggle, and `extra` fields.
fn stroke_file(eye: [f64; 3], a: [f64; 2], b: [f64; 2], n: usize, extra: &str) -> String {
    let vp = DMat4::orthographic_rh_gl(-1.6, 1.6, -1.6, 1.6, 0.1, 20.0)
        * DMat4::look_at_rh(DVec3::from(eye).normalize() * 5.0, DVec3::ZERO, DVec3::Y);
    let points: Vec<String> = (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64;
            let w = 6.0 * (t * 9.0).sin();
            format!(
                "[{}, {}]",
                a[0] + t * (b[0] - a[0]),
                a[1] + t * (b[1] - a[1]) + w
            )
        })
        .collect();
    let m: Vec<String> = vp.to_cols_array().iter().map(|x| x.to_string()).collect();
    format!(
        "{{\"stroke\": [{}], \"view_proj\": [{}], \"viewport\": [0, 0, 400, 400]{extra}}}",
        points.join(", "),
        m.join(", ")
    )
}

/// The byte ranges of the numbers in a JSON text.
fn numbers(text: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < text.len() {
        if text[i].is_ascii_digit() || text[i] == b'-' {
            let start = i;
            while i < text.len() && (text[i].is_ascii_alphanumeric() || b"+-.".contains(&text[i])) {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

/// `text` with one to four of its numbers replaced by extreme ones.
fn extreme_numbers(rng: &mut Rng, text: &[u8]) -> Vec<u8> {
    let mut spans = numbers(text);
    let mut picks: Vec<((usize, usize), &str)> = (0..1 + rng.below(4))
        .map(|_| {
            let s = spans.swap_remove(rng.below(spans.len()));
            (s, EXTREME[rng.below(EXTREME.len())])
        })
        .collect();
    picks.sort_by_key(|p| std::cmp::Reverse(p.0 .0));
    let mut out = text.to_vec();
    for ((a, b), x) in picks {
        out.splice(a..b, x.bytes());
    }
    out
}

#[test]
fn katachi_cut_on_mutated_stroke_files_exits_0_or_2_with_one_line() {
    let n = (cases(2000) / 20).max(1);
    let base = seed();
    let seeds = [
        stroke_file([0.3, 0.4, 1.0], [40.0, 200.0], [360.0, 220.0], 20, ""),
        stroke_file(
            [1.0, 1.0, 1.0],
            [60.0, 80.0],
            [340.0, 330.0],
            40,
            ", \"mode\": \"through-all\"",
        ),
        stroke_file(
            [0.0, 0.2, 1.0],
            [30.0, 250.0],
            [370.0, 150.0],
            12,
            ", \"open\": true",
        ),
    ];
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/models/chamfer-cube.off");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-cut-fuzz");
    std::fs::create_dir_all(&dir).unwrap();
    let (mut failures, mut cut, mut refused) = (Vec::new(), 0, 0);
    for case in 0..n {
        // Other cases than the readers' fuzzing: case numbers from 2,000,000 up.
        let case = case + 2_000_000;
        let mut rng = Rng::new(base, Format::Obj, case);
        let text = seeds[rng.below(seeds.len())].as_bytes();
        let input = if rng.below(2) == 0 {
            mutate(&mut rng, text.to_vec())
        } else {
            extreme_numbers(&mut rng, text)
        };
        let stroke = dir.join(format!("stroke-{base}-{case}.json"));
        let out = dir.join(format!("cut-{base}-{case}.obj"));
        std::fs::write(&stroke, &input).unwrap();
        let o = Command::new(env!("CARGO_BIN_EXE_katachi"))
            .arg("cut")
            .arg(&model)
            .arg(&out)
            .arg("--stroke")
            .arg(&stroke)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        let fault = match o.status.code() {
            Some(0) if !out.is_file() => Some("status 0 without the cut written".to_string()),
            Some(0) => {
                cut += 1;
                None
            }
            Some(2) => {
                refused += 1;
                let line = err.strip_suffix('\n').unwrap_or(&err);
                if !line.starts_with("error: ") || line.contains('\n') {
                    Some(format!("not one error line: {err:?}"))
                } else if line.chars().any(char::is_control) {
                    Some(format!("control characters: {line:?}"))
                } else if line.contains("internal error") {
                    Some(line.to_string())
                } else {
                    None
                }
            }
            other => Some(format!("status {other:?}: {err:?}")),
        };
        let _ = std::fs::remove_file(&out);
        match fault {
            Some(why) => failures.push(format!(
                "case {case} (KATACHI_FUZZ_SEED={base}): {why}; stroke file kept as {}",
                stroke.display()
            )),
            None => std::fs::remove_file(&stroke).unwrap(),
        }
    }
    record(&["fuzz", "stroke files via katachi cut", &n.to_string()]);
    eprintln!("{n} stroke files: {cut} cut, {refused} refused");
    assert!(
        failures.is_empty(),
        "{} of {n} runs failed:\n{}",
        failures.len(),
        failures
            .iter()
            .take(20)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
    // Both outcomes happen, or the mutations test nothing.
    assert!(
        n < 20 || (cut > 0 && refused > 0),
        "{cut} cut, {refused} refused"
    );
}
