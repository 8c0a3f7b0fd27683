//! What the tool prints. Results go to stdout, and a failed write there (a closed pipe, as
//! under `| head -1`, or a full disk) is an I/O error like any other: one line on stderr and
//! exit status 2. Notes and errors go to stderr, whose own failures are ignored (there is
//! nowhere left to report them). Every line printed escapes control characters, so a name
//! from an input file cannot carry terminal escape codes or break the line.

use std::fmt::Display;
use std::io::Write;
use std::path::PathBuf;

use katachi::error::escape_control_characters;
use katachi::Error;

fn stdout_error(source: std::io::Error) -> Error {
    Error::Io {
        path: PathBuf::from("<stdout>"),
        source,
    }
}

/// Prints one line of results on stdout.
pub fn line(text: impl Display) -> Result<(), Error> {
    let text = text.to_string();
    let text = escape_control_characters(&text);
    writeln!(std::io::stdout().lock(), "{text}").map_err(stdout_error)
}

/// Flushes stdout: a write error held in its buffer comes out here, not at exit.
pub fn flush() -> Result<(), Error> {
    std::io::stdout().flush().map_err(stdout_error)
}

/// Prints one line on stderr; a failure to print it is ignored.
pub fn note(text: impl Display) {
    let text = text.to_string();
    let text = escape_control_characters(&text);
    let _ = writeln!(std::io::stderr().lock(), "{text}");
}
