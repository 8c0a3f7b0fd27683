//! File I/O: OBJ, PLY and OFF, chosen by extension.

use std::path::Path;

use crate::error::Result;
use crate::mesh::PolyMesh;

/// Reads a mesh from `path`; the format comes from the extension (.obj, .ply, .off).
pub fn read(path: &Path) -> Result<PolyMesh> {
    let _ = path;
    todo!("io::read")
}

/// Writes `mesh` to `path`; the format comes from the extension (.obj, .ply, .off).
pub fn write(path: &Path, mesh: &PolyMesh) -> Result<()> {
    let _ = (path, mesh);
    todo!("io::write")
}
