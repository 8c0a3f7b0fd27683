//! The OBJ, PLY and OFF readers fuzzed with byte-level mutations of valid files (file I/O
//! module): no input makes a reader panic; a refused input gets a typed error (never an
//! internal one) and one line of message, with no control character in it; an accepted
//! input is a valid mesh that writes and reads back the same. 2,000 cases per format by
//! default (`cargo xtask test --fuzz-cases N` or `KATACHI_FUZZ_CASES` for more;
//! `KATACHI_FUZZ_SEED` for other cases). A failing case is saved under the target directory
//! and named with what reproduces it.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use katachi::io::{self, Format, PlyEncoding, WriteOptions};
use katachi::ErrorKind;

mod support;
use support::fuzz::{cases, mutate, seed, seeds, Rng};
use support::record::record;

/// What is wrong with reading `bytes`, if anything.
fn fault(bytes: &[u8], format: Format) -> Option<String> {
    let name = format!("fuzz.{}", format.extension());
    let read = catch_unwind(AssertUnwindSafe(|| {
        io::read_bytes(bytes, format, Path::new(&name))
    }));
    let mesh = match read {
        Err(_) => return Some("the reader panicked".into()),
        Ok(Err(e)) => {
            if e.kind() == ErrorKind::Internal {
                return Some(format!("refused as a bug in katachi: {e}"));
            }
            let m = e.to_string();
            if m.is_empty() {
                return Some("an empty message".into());
            }
            if let Some(c) = m.chars().find(|c| c.is_control()) {
                return Some(format!("the message holds control character {c:?}: {m:?}"));
            }
            return None;
        }
        Ok(Ok(mesh)) => mesh,
    };
    // Accepted: it must write and read back as the same mesh, bit for bit.
    let enc = PlyEncoding::BinaryLittleEndian;
    let mut buf = Vec::new();
    if let Err(e) = io::write_to(
        &mut buf,
        format,
        &mesh,
        &WriteOptions::with_ply_encoding(enc),
    ) {
        return Some(format!("accepted, but does not write back: {e}"));
    }
    match io::read_bytes(&buf, format, Path::new(&name)) {
        Err(e) => Some(format!("accepted, but its rewrite does not read: {e}")),
        Ok(back) if back != mesh => Some("accepted, but reads back different".into()),
        Ok(_) => None,
    }
}

#[test]
fn mutated_files_never_panic_and_are_refused_in_one_line() {
    let n = cases(2000);
    let base = seed();
    let seeds = seeds();
    let mut failures = Vec::new();
    let hook = std::panic::take_hook();
    // Panics are caught and reported below, not printed as they happen.
    std::panic::set_hook(Box::new(|_| {}));
    for format in [Format::Obj, Format::Ply, Format::Off] {
        let of_format: Vec<_> = seeds.iter().filter(|s| s.0 == format).collect();
        for case in 0..n {
            let mut rng = Rng::new(base, format, case);
            let (_, name, bytes) = of_format[rng.below(of_format.len())];
            let input = mutate(&mut rng, bytes.clone());
            if let Some(why) = fault(&input, format) {
                let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-failures");
                std::fs::create_dir_all(&dir).unwrap();
                let saved = dir.join(format!(
                    "{}-{base}-{case}.{}",
                    format.name(),
                    format.extension()
                ));
                std::fs::write(&saved, &input).unwrap();
                failures.push(format!(
                    "{} case {case} (KATACHI_FUZZ_SEED={base}, from {name}): {why}; input saved as {}",
                    format.name(),
                    saved.display()
                ));
            }
        }
        record(&["fuzz", format.name(), &n.to_string()]);
    }
    std::panic::set_hook(hook);
    assert!(
        failures.is_empty(),
        "{} of {} mutated files failed:\n{}",
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
