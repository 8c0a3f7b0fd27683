//! File I/O: OBJ, PLY and OFF readers and writers, chosen by extension.
//!
//! Every reader takes the whole file as bytes ([`read_bytes`], or the per-format
//! `read_bytes`), so the C ABI and tests can read from memory; [`read`] is
//! `std::fs::read` plus the format's reader. Every writer writes to any [`Write`]
//! ([`write_to`]), and [`write()`] to a file: into a temporary file beside it, renamed over
//! it once complete, so a failed write (a full disk, a file-size limit) leaves the old file
//! as it was ([`write_bytes`] does the same for any bytes).
//!
//! What the formats keep:
//!
//! | format | positions | faces | sharpness | faces with holes |
//! | --- | --- | --- | --- | --- |
//! | OBJ | decimal, shortest round-trip (bit-exact) | polygons, never triangulated | OpenSubdiv `t crease` / `t corner` tags | no |
//! | PLY | `double` in binary (bit-exact) or shortest decimal in ASCII | polygons | no | no |
//! | OFF | decimal, shortest round-trip (bit-exact) | polygons | no | no |
//!
//! None of the three formats has a standard way to store a face with holes (the P and
//! C loops of seed 001 §2): bridging the holes with a seam edge, as some exporters do,
//! would change the topology and the file would not read back as the same mesh. So the
//! writers refuse such a mesh with [`Error::InvalidArgument`] naming the face and the
//! format, before writing any byte.
//!
//! Malformed input gives [`Error::Parse`] with the file name and the 1-based line (text)
//! or the byte offset (binary PLY). When the parsed data fails [`PolyMesh`] validation
//! (an index out of range, a repeated vertex…), the error names the line or byte of the
//! face and carries the validation message. No input bytes make a reader panic.
//!
//! The readers are written by hand; each module's docs say why no crate does the job.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::mesh::PolyMesh;

mod atomic;
mod build;
pub mod obj;
pub mod off;
pub mod ply;
mod text;

pub use ply::PlyEncoding;

/// A mesh file format katachi reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum Format {
    /// Wavefront OBJ, with OpenSubdiv's `t crease` / `t corner` tags for sharpness.
    Obj,
    /// Stanford PLY, ASCII or binary.
    Ply,
    /// Geomview OFF (ASCII).
    Off,
}

impl Format {
    /// The format named by an extension (`"obj"`, `"PLY"`, …; case-insensitive, no dot).
    pub fn from_extension(ext: &str) -> Option<Format> {
        match ext.to_ascii_lowercase().as_str() {
            "obj" => Some(Format::Obj),
            "ply" => Some(Format::Ply),
            "off" => Some(Format::Off),
            _ => None,
        }
    }

    /// The format of `path` by its extension, or [`Error::UnknownFormat`].
    pub fn from_path(path: &Path) -> Result<Format> {
        path.extension()
            .and_then(|e| e.to_str())
            .and_then(Format::from_extension)
            .ok_or_else(|| Error::UnknownFormat {
                path: path.to_path_buf(),
            })
    }

    /// The usual extension, lower case, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Ply => "ply",
            Format::Off => "off",
        }
    }

    /// The name used in messages ("OBJ", "PLY", "OFF").
    pub fn name(self) -> &'static str {
        match self {
            Format::Obj => "OBJ",
            Format::Ply => "PLY",
            Format::Off => "OFF",
        }
    }
}

/// How [`write_with`] and [`write_to`] write; `Default` gives what [`write()`] does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub struct WriteOptions {
    /// The encoding of PLY files. Default value: [`PlyEncoding::BinaryLittleEndian`]
    /// (bit-exact, compact and what most tools read fastest).
    pub ply_encoding: PlyEncoding,
}

impl Default for WriteOptions {
    fn default() -> Self {
        WriteOptions {
            ply_encoding: PlyEncoding::BinaryLittleEndian,
        }
    }
}

impl WriteOptions {
    /// Default options with the given PLY encoding.
    pub fn with_ply_encoding(ply_encoding: PlyEncoding) -> Self {
        WriteOptions { ply_encoding }
    }
}

/// Reads a mesh from `path`; the format comes from the extension (.obj, .ply, .off,
/// case-insensitive). Vertex numbering is the file's, unreferenced vertices included.
pub fn read(path: &Path) -> Result<PolyMesh> {
    let format = Format::from_path(path)?;
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read_bytes(&bytes, format, path)
}

/// Reads a mesh of `format` from the bytes of a whole file; `path` only names the file
/// in error messages.
pub fn read_bytes(bytes: &[u8], format: Format, path: &Path) -> Result<PolyMesh> {
    match format {
        Format::Obj => obj::read_bytes(bytes, path),
        Format::Ply => ply::read_bytes(bytes, path),
        Format::Off => off::read_bytes(bytes, path),
    }
}

/// Writes `mesh` to `path`; the format comes from the extension (.obj, .ply, .off).
/// PLY is written binary little-endian. A mesh with holes in a face is refused before
/// the file is opened (see the module docs). The file is replaced only once the whole mesh
/// is written: on any error, a file already at `path` is left as it was.
pub fn write(path: &Path, mesh: &PolyMesh) -> Result<()> {
    write_with(path, mesh, &WriteOptions::default())
}

/// [`write()`] with options (the PLY encoding).
pub fn write_with(path: &Path, mesh: &PolyMesh, options: &WriteOptions) -> Result<()> {
    let format = Format::from_path(path)?;
    // Refuse what cannot be written before creating (and truncating) the file.
    reject_holes(mesh, format)?;
    atomic::write_file(path, |w| write_format(w, format, mesh, options, path))
}

/// Writes `bytes` to the file at `path` as [`write()`] writes a mesh: into a temporary file
/// beside it, renamed over it once complete, so on any error a file already at `path` is
/// left as it was. For the files front ends write beside meshes (reports, strokes).
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<()> {
    atomic::write_file(path, |w| {
        w.write_all(bytes).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })
    })
}

/// Writes `mesh` in `format` to any writer (a `Vec<u8>`, a socket, a C caller's buffer).
/// I/O failures are reported as [`Error::Io`] with the path `<writer>`.
pub fn write_to<W: Write>(
    w: W,
    format: Format,
    mesh: &PolyMesh,
    options: &WriteOptions,
) -> Result<()> {
    write_format(w, format, mesh, options, Path::new(WRITER_PATH))
}

/// The path named in I/O errors of writers that are not files.
pub(crate) const WRITER_PATH: &str = "<writer>";

fn write_format<W: Write>(
    w: W,
    format: Format,
    mesh: &PolyMesh,
    options: &WriteOptions,
    path: &Path,
) -> Result<()> {
    match format {
        Format::Obj => obj::write_impl(w, mesh, path),
        Format::Ply => ply::write_impl(w, mesh, options.ply_encoding, path),
        Format::Off => off::write_impl(w, mesh, path),
    }
}

/// Fails with [`Error::InvalidArgument`] naming the first face with a hole: OBJ, PLY
/// and OFF have no way to store it (see the module docs).
pub(crate) fn reject_holes(mesh: &PolyMesh, format: Format) -> Result<()> {
    let offsets = mesh.face_loop_offsets();
    if offsets.len() - 1 == mesh.loop_count() as usize {
        return Ok(());
    }
    for (f, w) in offsets.windows(2).enumerate() {
        let holes = w[1] - w[0] - 1;
        if holes > 0 {
            return Err(Error::InvalidArgument(format!(
                "face {f} has {holes} hole{}: {} cannot store faces with holes \
                 (split or triangulate the face first)",
                if holes == 1 { "" } else { "s" },
                format.name()
            )));
        }
    }
    Ok(())
}

/// Maps an I/O error of a writer to [`Error::Io`] naming `path`.
pub(crate) fn io_error(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io {
        path: PathBuf::from(path),
        source,
    }
}
