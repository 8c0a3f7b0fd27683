//! Writing a file so that a failed write leaves what was there: the bytes go to a temporary
//! file in the same folder, which replaces the target (a `rename`, atomic within one file
//! system) only once every byte is written and synced. A full disk or a file-size limit
//! then costs the new file, never the old one; a truncated file that reads back as a
//! smaller, valid mesh cannot happen.
//!
//! A target that exists and is not a regular file (`/dev/null`, `/dev/full`, a pipe, a
//! terminal) is written in place: it cannot be replaced, and nothing of it can be lost.

use std::fs::{self, File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

use crate::error::{Error, Result};

/// Writes the file at `path` with `write`, atomically as the module docs say. Errors are
/// [`Error::Io`] naming `path`, or whatever `write` returns; on any error the temporary
/// file is removed and `path` is as it was.
pub(crate) fn write_file(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    let io_err = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let target = match fs::metadata(path) {
        // A device, a pipe or a terminal: written in place.
        Ok(m) if !m.is_file() => {
            let file = OpenOptions::new()
                .write(true)
                .truncate(true)
                .open(path)
                .map_err(io_err)?;
            let mut w = BufWriter::with_capacity(1 << 16, file);
            write(&mut w)?;
            return w.flush().map_err(io_err);
        }
        // A regular file, maybe through symlinks: the real file is replaced, the links kept.
        Ok(_) => fs::canonicalize(path).map_err(io_err)?,
        // Nothing there yet (or a link to nothing): the file is made where `path` says.
        Err(_) => match fs::symlink_metadata(path) {
            Ok(m) if m.file_type().is_symlink() => {
                let file = File::create(path).map_err(io_err)?;
                let mut w = BufWriter::with_capacity(1 << 16, file);
                write(&mut w)?;
                return w.flush().map_err(io_err);
            }
            _ => path.to_path_buf(),
        },
    };
    let (temp, file) = create_temp(&target).map_err(io_err)?;
    let result = (|| {
        // The old file's permissions carry over to the new one.
        if let Ok(old) = fs::metadata(&target) {
            file.set_permissions(old.permissions()).map_err(io_err)?;
        }
        let mut w = BufWriter::with_capacity(1 << 16, file);
        write(&mut w)?;
        let file = w.into_inner().map_err(|e| io_err(e.into_error()))?;
        file.sync_all().map_err(io_err)?;
        drop(file);
        fs::rename(&temp, &target).map_err(io_err)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&temp);
    }
    result
}

/// A new, empty file beside `target` named `.NAME.katachi-PID-N.tmp`.
fn create_temp(target: &Path) -> std::io::Result<(PathBuf, File)> {
    static COUNTER: AtomicU32 = AtomicU32::new(0);
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let temp = dir.join(format!(".{name}.katachi-{}-{n}.tmp", std::process::id()));
        match OpenOptions::new().write(true).create_new(true).open(&temp) {
            Ok(file) => return Ok((temp, file)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}
