//! The readers fuzzed through the `katachi` binary, as a user meets them: `katachi info` on
//! byte-level mutations of valid OBJ, PLY and OFF files (`tests/support/fuzz.rs`) exits 0 with
//! a report, or 2 with one line `error: …` without control characters; never anything else,
//! never "internal error". A tenth of the library fuzzing's cases (200 per format by
//! default; `KATACHI_FUZZ_CASES` sets the library's count).

use std::path::Path;
use std::process::Command;

use katachi::io::Format;

// The root crate's test helpers (tests/support) this test needs.
#[allow(dead_code)]
#[path = "../../tests/support/fuzz.rs"]
mod fuzz;
#[allow(dead_code)]
#[path = "../../tests/support/models.rs"]
mod models;
#[allow(dead_code)]
#[path = "../../tests/support/record.rs"]
mod record;
use fuzz::{cases, mutate, seed, seeds, Rng};
use record::record;

#[test]
fn katachi_info_on_mutated_files_exits_0_or_2_with_one_line() {
    let n = cases(2000) / 10;
    let base = seed();
    let seeds = seeds();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-fuzz");
    std::fs::create_dir_all(&dir).unwrap();
    let mut failures = Vec::new();
    for format in [Format::Obj, Format::Ply, Format::Off] {
        let of_format: Vec<_> = seeds.iter().filter(|s| s.0 == format).collect();
        for case in 0..n {
            // Other cases than the library test's: case numbers from n up.
            let case = case + 1_000_000;
            let mut rng = Rng::new(base, format, case);
            let (_, name, bytes) = of_format[rng.below(of_format.len())];
            let input = mutate(&mut rng, bytes.clone());
            let path = dir.join(format!(
                "{}-{base}-{case}.{}",
                format.name(),
                format.extension()
            ));
            std::fs::write(&path, &input).unwrap();
            let o = Command::new(env!("CARGO_BIN_EXE_katachi"))
                .arg("info")
                .arg(&path)
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&o.stderr);
            let fault = match o.status.code() {
                Some(0) if o.stdout.is_empty() => Some("status 0 without a report".to_string()),
                Some(0) => None,
                Some(2) => {
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
            match fault {
                Some(why) => failures.push(format!(
                    "{} case {case} (KATACHI_FUZZ_SEED={base}, from {name}): {why}; input kept as {}",
                    format.name(),
                    path.display()
                )),
                None => std::fs::remove_file(&path).unwrap(),
            }
        }
        record(&[
            "fuzz",
            &format!("{} via katachi info", format.name()),
            &n.to_string(),
        ]);
    }
    assert!(
        failures.is_empty(),
        "{} of {} runs failed:\n{}",
        failures.len(),
        3 * n,
        failures
            .iter()
            .take(20)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
}
