//! What a test run did that a pass or a fail does not show — corpus models that ran or did
//! not, property-test cases accepted and rejected, fuzz cases — as lines in the file named by
//! `KATACHI_TEST_RECORD` (`cargo xtask test` sets it and prints the summary at the end).
//! Without it, the lines go to stderr, which the test harness shows with `--nocapture`.

use std::io::Write;

/// Appends one record line: tab-separated fields, the first saying what it is.
pub fn record(fields: &[&str]) {
    let line = format!("{}\n", fields.join("\t"));
    match std::env::var_os("KATACHI_TEST_RECORD") {
        Some(path) => {
            // One write of the whole line to a file opened for appending: lines from
            // concurrent tests and test binaries do not interleave.
            let written = std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(&path)
                .and_then(|mut f| f.write_all(line.as_bytes()));
            if let Err(e) = written {
                panic!("KATACHI_TEST_RECORD={}: {e}", path.to_string_lossy());
            }
        }
        None => eprint!("katachi test record: {line}"),
    }
}
