//! `cargo xtask test`: every test, in order of cost, stopping at the first failure, then a
//! summary of what the tests recorded: which corpus models ran (or that none did), how many
//! property-test cases were accepted, how many mutated files the reader fuzzing tried.
//!
//! Options:
//! - `--corpus DIR`: run the corpus tests over DIR (a folder of models with a `MANIFEST.md`,
//!   as `../shared/data/models`); it must exist. Default: `$KATACHI_CORPUS`, else
//!   `../shared/data/models` beside the checkout when it exists, else none.
//! - `--no-corpus`: run no corpus test, even with `../shared` beside the checkout.
//! - `--fuzz-cases N`: mutated files per format in the reader fuzzing (default 2000).
//! - `--no-c`: skip the C, installed-library, Windows and MeshLab steps.

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::process::Command;
use std::time::Instant;

use crate::util;

type Step = Box<dyn Fn() -> Result<(), String>>;

/// The value after `flag` in `args`, if the flag is there.
fn value<'a>(args: &[&'a str], flag: &str) -> Result<Option<&'a str>, String> {
    match args.iter().position(|a| *a == flag) {
        None => Ok(None),
        Some(i) => args
            .get(i + 1)
            .copied()
            .map(Some)
            .ok_or_else(|| format!("{flag} needs a value")),
    }
}

/// Sets `KATACHI_CORPUS`, `KATACHI_FUZZ_CASES` and `KATACHI_TEST_RECORD` for every step's
/// processes; returns the record file (emptied).
fn environment(args: &[&str]) -> Result<PathBuf, String> {
    let known = ["--corpus", "--no-corpus", "--fuzz-cases", "--no-c"];
    for (i, a) in args.iter().enumerate() {
        let is_value = i > 0 && ["--corpus", "--fuzz-cases"].contains(&args[i - 1]);
        if !is_value && !known.contains(a) {
            return Err(format!(
                "unknown option `{a}` (known: {})",
                known.join(", ")
            ));
        }
    }
    if let Some(dir) = value(args, "--corpus")? {
        let path = util::root().join(dir);
        if !path.join("MANIFEST.md").is_file() {
            return Err(format!(
                "--corpus {dir}: {} has no MANIFEST.md (a corpus is a folder of models with their table, as ../shared/data/models)",
                path.display()
            ));
        }
        let path = path.canonicalize().map_err(|e| format!("{dir}: {e}"))?;
        std::env::set_var("KATACHI_CORPUS", path);
    }
    if args.contains(&"--no-corpus") {
        std::env::set_var("KATACHI_CORPUS", "none");
    }
    if let Some(n) = value(args, "--fuzz-cases")? {
        n.parse::<u32>()
            .map_err(|_| format!("--fuzz-cases {n}: not a count"))?;
        std::env::set_var("KATACHI_FUZZ_CASES", n);
    }
    let record = crate::ctest::target_dir().join("test-record.tsv");
    std::fs::create_dir_all(record.parent().unwrap()).map_err(|e| e.to_string())?;
    std::fs::write(&record, "").map_err(|e| format!("{}: {e}", record.display()))?;
    std::env::set_var("KATACHI_TEST_RECORD", &record);
    Ok(record)
}

/// The lines of the summary, from the record the tests wrote.
fn summary(record: &str) -> Vec<String> {
    let mut ran: BTreeMap<&str, BTreeSet<&str>> = BTreeMap::new();
    let mut not_run: BTreeSet<&str> = BTreeSet::new();
    let (mut properties, mut accepted, mut rejected) = (BTreeSet::new(), 0u64, 0u64);
    let mut fuzz: BTreeMap<&str, u64> = BTreeMap::new();
    for line in record.lines() {
        let f: Vec<&str> = line.split('\t').collect();
        match f.as_slice() {
            ["corpus-ran", test, model] => {
                ran.entry(*model).or_default().insert(*test);
            }
            ["corpus-not-run", test, _] => {
                not_run.insert(*test);
            }
            ["property", name, a, r] => {
                properties.insert(*name);
                accepted += a.parse::<u64>().unwrap_or(0);
                rejected += r.parse::<u64>().unwrap_or(0);
            }
            ["fuzz", format, cases] => {
                *fuzz.entry(*format).or_default() += cases.parse::<u64>().unwrap_or(0)
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    let corpus = std::env::var("KATACHI_CORPUS").ok();
    if ran.is_empty() {
        let why = match corpus.as_deref() {
            Some("none") => "turned off (--no-corpus)".to_string(),
            _ => "none given (--corpus DIR or KATACHI_CORPUS; ../shared/data/models is not beside the checkout)".to_string(),
        };
        out.push(format!(
            "corpus: {why}: 0 corpus models ran; {} tests did not run over it: {}",
            not_run.len(),
            not_run.iter().copied().collect::<Vec<_>>().join(", ")
        ));
    } else {
        let tests: BTreeSet<&str> = ran.values().flatten().copied().collect();
        let dir = corpus.unwrap_or_else(|| "../shared/data/models".into());
        out.push(format!(
            "corpus {dir}: {} corpus models ran in {} tests",
            ran.len(),
            tests.len()
        ));
        if !not_run.is_empty() {
            out.push(format!(
                "corpus: {} tests did not run over it: {}",
                not_run.len(),
                not_run.iter().copied().collect::<Vec<_>>().join(", ")
            ));
        }
    }
    out.push(format!(
        "property tests: {} properties, {accepted} accepted cases checked ({rejected} inputs rejected by prop_assume!)",
        properties.len()
    ));
    let total: u64 = fuzz.values().sum();
    let per: Vec<String> = fuzz.iter().map(|(f, n)| format!("{f} {n}")).collect();
    out.push(format!(
        "reader fuzzing: {total} mutated files ({}), no panic, every refusal one line",
        per.join(", ")
    ));
    out
}

pub fn run(args: &[&str]) -> Result<(), String> {
    let record = environment(args)?;
    let skip_c = args.contains(&"--no-c");
    let start = Instant::now();
    let mut steps: Vec<(&str, Step)> = vec![
        ("system packages", Box::new(|| crate::deps::run(&[]))),
        (
            "format",
            Box::new(|| {
                util::run(Command::new(util::cargo()).args(["fmt", "--all", "--", "--check"]))
            }),
        ),
        (
            "clippy",
            Box::new(|| {
                util::run(Command::new(util::cargo()).args([
                    "clippy",
                    "--workspace",
                    "--all-targets",
                    "--",
                    "-D",
                    "warnings",
                ]))
            }),
        ),
        (
            "macOS: the library and CLI type-check (clippy, aarch64-apple-darwin)",
            Box::new(|| crate::macos::check(&[])),
        ),
        ("header", Box::new(crate::header::check)),
        (
            "docs",
            Box::new(|| {
                util::run(
                    Command::new(util::cargo())
                        .args(["doc", "--no-deps", "-p", "katachi"])
                        .env("RUSTDOCFLAGS", "-D warnings"),
                )
            }),
        ),
        (
            "cargo test",
            Box::new(|| util::run(Command::new(util::cargo()).args(["test", "--workspace"]))),
        ),
    ];
    if !skip_c {
        steps.push(("C/C++ link tests", Box::new(|| crate::ctest::run(&[]))));
        steps.push((
            "installed C library (pkg-config, C and C++, valgrind)",
            Box::new(|| crate::install::test(&[])),
        ));
        steps.push((
            "Windows: katachi.dll and katachi.exe cross-built; C/C++ link tests, installed files, CLI tests under Wine",
            Box::new(|| crate::windows::test(&[])),
        ));
        steps.push((
            "MeshLab plugin (2020.09 through meshlabserver under xvfb-run, 2025.07 in pymeshlab)",
            Box::new(crate::meshlab::test),
        ));
    }
    steps.push((
        "Blender add-on (Blender 3.4 and bpy 5.0, headless)",
        Box::new(|| crate::blender::run(&[])),
    ));
    let total = steps.len();
    for (i, (name, step)) in steps.iter().enumerate() {
        eprintln!("xtask test: [{}/{total}] {name}", i + 1);
        let t = Instant::now();
        step().map_err(|e| format!("step `{name}` failed: {e}"))?;
        eprintln!(
            "xtask test: [{}/{total}] {name} ok ({:.0?})",
            i + 1,
            t.elapsed()
        );
    }
    eprintln!(
        "xtask test: all {total} steps passed in {:.0?}",
        start.elapsed()
    );
    let text =
        std::fs::read_to_string(&record).map_err(|e| format!("{}: {e}", record.display()))?;
    for line in summary(&text) {
        eprintln!("xtask test: {line}");
    }
    if skip_c {
        eprintln!(
            "xtask test: not run (--no-c): the C/C++ link tests, the installed C library, the Windows build under Wine, the MeshLab plugin"
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::summary;

    #[test]
    fn the_summary_counts_corpus_models_properties_and_fuzz_cases() {
        let record = "corpus-ran\ta\tbunny.obj\ncorpus-ran\tb\tbunny.obj\ncorpus-ran\ta\tbeast.obj\n\
                      property\tp\t300\t12\nproperty\tq\t256\t0\nfuzz\tOBJ\t2000\nfuzz\tPLY\t2000\n";
        let s = summary(record);
        assert!(s[0].contains("2 corpus models ran in 2 tests"), "{s:?}");
        assert!(
            s[1].contains("2 properties, 556 accepted cases checked (12 inputs rejected"),
            "{s:?}"
        );
        assert!(
            s[2].contains("4000 mutated files (OBJ 2000, PLY 2000)"),
            "{s:?}"
        );
        let none = summary("corpus-not-run\tio_models::x\tall\ncorpus-not-run\tcgal\tbunny\n");
        assert!(
            none[0].contains("0 corpus models ran; 2 tests did not run over it"),
            "{none:?}"
        );
    }
}
