//! The test models. Bundled ones (`tests/data/models`, whose licenses allow shipping them;
//! sources and licenses in its README) are always there, and a test that needs one and does
//! not find it fails. The corpus (further models whose licenses do not allow shipping them)
//! is optional: the folder named by `KATACHI_CORPUS`, or else `../shared/data/models` beside
//! the checkout when it exists (`KATACHI_CORPUS=none` turns the default off). Tests over the
//! corpus record which models ran; without a corpus they record that they did not run, and
//! `cargo xtask test` says so in its summary.

use std::path::{Path, PathBuf};

use super::record::record;

/// The repository's root: the nearest folder above the including crate that holds
/// `tests/data/models`.
pub fn root() -> PathBuf {
    let start = Path::new(env!("CARGO_MANIFEST_DIR"));
    start
        .ancestors()
        .find(|d| d.join("tests/data/models/README.md").is_file())
        .unwrap_or_else(|| {
            panic!(
                "no tests/data/models/README.md in {} or above",
                start.display()
            )
        })
        .to_path_buf()
}

/// The folder of the bundled models.
pub fn bundled_dir() -> PathBuf {
    root().join("tests/data/models")
}

/// A bundled model's path; a missing one fails the test.
pub fn bundled(name: &str) -> PathBuf {
    let path = bundled_dir().join(name);
    assert!(
        path.is_file(),
        "bundled test model {} is missing",
        path.display()
    );
    path
}

/// A bundled model, read.
pub fn read_bundled(name: &str) -> katachi::PolyMesh {
    let path = bundled(name);
    katachi::io::read(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The corpus folder, if one is given: `KATACHI_CORPUS` (which must then be a folder, or
/// `none`), else `../shared/data/models` beside the checkout if it exists.
pub fn corpus() -> Option<PathBuf> {
    match std::env::var_os("KATACHI_CORPUS") {
        Some(v) if v == "none" || v.is_empty() => None,
        Some(v) => {
            let dir = PathBuf::from(&v);
            let dir = if dir.is_relative() {
                root().join(dir)
            } else {
                dir
            };
            assert!(
                dir.is_dir(),
                "KATACHI_CORPUS={} is not a folder",
                v.to_string_lossy()
            );
            Some(dir)
        }
        None => {
            let beside = root().join("../shared/data/models");
            beside.is_dir().then_some(beside)
        }
    }
}

/// The corpus models `names` for `test`: their paths when a corpus is given (a given corpus
/// lacking one of them fails the test), or `None`, recorded as not run, when none is.
pub fn corpus_models(test: &str, names: &[&str]) -> Option<Vec<PathBuf>> {
    let Some(dir) = corpus() else {
        not_run(test, &names.join(" "));
        return None;
    };
    let paths: Vec<PathBuf> = names.iter().map(|n| dir.join(n)).collect();
    for p in &paths {
        assert!(
            p.is_file(),
            "the corpus {} has no {} (set KATACHI_CORPUS to a folder with it, or to `none`)",
            dir.display(),
            p.file_name().unwrap().to_string_lossy()
        );
    }
    Some(paths)
}

/// Records that `test` ran corpus model `name`.
pub fn ran(test: &str, name: &str) {
    record(&["corpus-ran", test, name]);
}

/// Records that `test` did not run over `what` for want of a corpus.
pub fn not_run(test: &str, what: &str) {
    record(&["corpus-not-run", test, what]);
}
