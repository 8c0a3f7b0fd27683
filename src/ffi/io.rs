//! Reading and writing mesh files through the C ABI: OBJ, PLY and OFF, chosen by extension.
//! Conversion and error mapping only; the work is [`crate::io`]'s.

use std::ffi::c_char;
use std::path::Path;

use super::boundary::{c_str, guard, FfiError, FfiResult};
use super::mesh::{mesh_ref, reset_out, KatachiMesh};
use super::status::KatachiStatus;

/// A path parameter: UTF-8 and not empty.
///
/// # Safety
/// A non-NULL `p` must be a NUL-terminated string.
unsafe fn path_arg<'a>(p: *const c_char) -> FfiResult<&'a Path> {
    // SAFETY: forwarded to the caller.
    let s = unsafe { c_str(p, "path") }?;
    if s.is_empty() {
        return Err(FfiError::invalid("path is the empty string"));
    }
    Ok(Path::new(s))
}

/// Reads a mesh from the file at `path` (a NUL-terminated UTF-8 string), in the format its
/// extension names: `.obj` (polygons kept, with OpenSubdiv crease and corner tags), `.ply`
/// (ASCII or binary) or `.off`.
///
/// On success `*out` receives a new mesh owned by the caller (free it with
/// `katachi_mesh_free`); on failure `*out` is set to NULL.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`path` or `out` NULL);
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`path` empty or not UTF-8); `KATACHI_STATUS_IO_ERROR`
/// (the file cannot be read, has an unknown extension, is malformed or describes an invalid
/// mesh, e.g. a vertex index out of range; the message gives the file and the line, or the
/// byte offset in a binary PLY).
///
/// # Safety
/// `path` must be NULL or a NUL-terminated string; `out` NULL or writable storage for one
/// pointer.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_read(
    path: *const c_char,
    out: *mut *mut KatachiMesh,
) -> KatachiStatus {
    guard("katachi_mesh_read", || {
        // SAFETY: the caller's promises above.
        let out = unsafe { reset_out(out) }?;
        let path = unsafe { path_arg(path) }?;
        let mesh = crate::io::read(path)?;
        *out = KatachiMesh::into_raw(mesh);
        Ok(())
    })
}

/// Writes `mesh` to the file at `path` (a NUL-terminated UTF-8 string), replacing it, in the
/// format its extension names: `.obj` (with OpenSubdiv crease and corner tags for sharpness),
/// `.ply` (binary little-endian, positions as doubles) or `.off`. None of the three formats
/// can store a face with holes, so such a mesh is refused before any byte is written.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` or `path` NULL);
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`path` empty or not UTF-8, or the mesh has a face with
/// holes; the message names the face and the format); `KATACHI_STATUS_IO_ERROR` (the file
/// cannot be written, or the extension is unknown). The mesh is never changed.
///
/// # Safety
/// `mesh` must be NULL or a live handle; `path` NULL or a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_write(
    mesh: *const KatachiMesh,
    path: *const c_char,
) -> KatachiStatus {
    guard("katachi_mesh_write", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_ref(mesh) }?;
        let path = unsafe { path_arg(path) }?;
        crate::io::write(path, mesh)?;
        Ok(())
    })
}
