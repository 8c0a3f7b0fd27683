//! Assembling a [`PolyMesh`] from what a reader parsed, and turning errors into
//! [`Error::Parse`] that name the file and the line or byte at fault.
//!
//! Readers collect flat arrays (positions, one loop per face, corners) and hand them to
//! the mesh's single validating constructor, so a file can never build a mesh the rest
//! of katachi would reject. When validation fails, the error names a face or a vertex
//! by index; the reader's `locate` callback turns that index into the line or byte
//! where the element was written, so the user sees
//! `teapot.obj:1234: face 17, loop 0: vertex index 1203 is out of range (…)`.

use std::path::Path;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::mesh::{PolyMesh, VertexId};

/// The largest number of vertices or corners a file may hold: indices are `u32` and
/// `u32::MAX` is the "no element" value.
pub(crate) const MAX_ELEMENTS: u64 = u32::MAX as u64 - 1;

/// Where an element was written in a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Location {
    /// 1-based line of a text file.
    Line(usize),
    /// Byte offset in a binary file.
    Byte(u64),
    /// Unknown.
    Unknown,
}

/// An element that validation complained about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Element {
    Vertex(u32),
    Face(u32),
}

/// A parse error at `loc` in `path`.
pub(crate) fn parse_error(path: &Path, loc: Location, message: impl Into<String>) -> Error {
    let (line, byte) = match loc {
        Location::Line(l) => (l, None),
        Location::Byte(b) => (0, Some(b)),
        Location::Unknown => (0, None),
    };
    Error::Parse {
        path: path.to_path_buf(),
        line,
        byte,
        message: message.into(),
    }
}

/// A parse error at a 1-based line.
pub(crate) fn at_line(path: &Path, line: usize, message: impl Into<String>) -> Error {
    parse_error(path, Location::Line(line), message)
}

/// A parse error at a byte offset.
pub(crate) fn at_byte(path: &Path, byte: u64, message: impl Into<String>) -> Error {
    parse_error(path, Location::Byte(byte), message)
}

/// Flat arrays of a mesh whose faces have one loop each, as a reader collects them.
#[derive(Debug, Default)]
pub(crate) struct RawMesh {
    pub(crate) positions: Vec<DVec3>,
    /// `F + 1` offsets into `corners`, starting with 0.
    pub(crate) loop_offsets: Vec<u32>,
    pub(crate) corners: Vec<VertexId>,
}

impl RawMesh {
    /// Empty arrays with room for the given counts (callers cap them by the file size,
    /// so a header that lies about its counts cannot make us allocate gigabytes).
    pub(crate) fn with_capacity(vertices: usize, faces: usize, corners: usize) -> Self {
        let mut loop_offsets = Vec::with_capacity(faces + 1);
        loop_offsets.push(0);
        RawMesh {
            positions: Vec::with_capacity(vertices),
            loop_offsets,
            corners: Vec::with_capacity(corners),
        }
    }

    /// Number of faces so far.
    pub(crate) fn face_count(&self) -> usize {
        self.loop_offsets.len() - 1
    }

    /// Closes the face whose corners were pushed since the last call. Fails (with a
    /// message for the caller to place) when the corners no longer fit 32-bit indices.
    #[inline]
    pub(crate) fn end_face(&mut self) -> std::result::Result<(), String> {
        if self.corners.len() as u64 > MAX_ELEMENTS {
            return Err(format!(
                "the file has more than {MAX_ELEMENTS} face corners, more than katachi's 32-bit indices address"
            ));
        }
        self.loop_offsets.push(self.corners.len() as u32);
        Ok(())
    }

    /// Validates and builds the mesh. A validation error is turned into a parse error at
    /// the place `locate` gives for the face or vertex it names.
    pub(crate) fn into_mesh(
        self,
        path: &Path,
        locate: impl FnOnce(Element) -> Location,
    ) -> Result<PolyMesh> {
        if self.positions.len() as u64 > MAX_ELEMENTS {
            return Err(parse_error(
                path,
                Location::Unknown,
                format!(
                    "the file has more than {MAX_ELEMENTS} vertices, more than katachi's 32-bit indices address"
                ),
            ));
        }
        if self.face_count() as u64 > MAX_ELEMENTS {
            return Err(parse_error(
                path,
                Location::Unknown,
                format!(
                    "the file has more than {MAX_ELEMENTS} faces, more than katachi's 32-bit indices address"
                ),
            ));
        }
        let faces = self.face_count() as u32;
        let face_loop_offsets: Vec<u32> = (0..=faces).collect();
        PolyMesh::from_parts(
            self.positions,
            face_loop_offsets,
            self.loop_offsets,
            self.corners,
        )
        .map_err(|e| {
            let element = match e {
                Error::VertexOutOfRange { face, .. }
                | Error::DegenerateLoop { face, .. }
                | Error::RepeatedVertex { face, .. }
                | Error::FaceWithoutLoops { face } => Some(Element::Face(face)),
                Error::NonFiniteCoordinate { vertex, .. } => Some(Element::Vertex(vertex)),
                _ => None,
            };
            let loc = element.map_or(Location::Unknown, locate);
            parse_error(path, loc, e.to_string())
        })
    }
}

/// The three coordinates of vertex `v` from the next tokens of line `line` of `path`;
/// `fewer` is the message when the line has fewer than three.
pub(crate) fn parse_xyz<'a>(
    toks: &mut impl Iterator<Item = &'a [u8]>,
    path: &Path,
    line: usize,
    v: u64,
    fewer: &dyn Fn() -> String,
) -> crate::error::Result<glam::DVec3> {
    use super::text::{not_finite, parse_f64, show};
    let mut xyz = [0.0; 3];
    for (axis, c) in ["x", "y", "z"].into_iter().zip(xyz.iter_mut()) {
        let t = toks.next().ok_or_else(|| at_line(path, line, fewer()))?;
        *c = parse_f64(t).ok_or_else(|| {
            at_line(
                path,
                line,
                format!("vertex {v}: coordinate {axis} {} is not a number", show(t)),
            )
        })?;
        if !c.is_finite() {
            return Err(at_line(
                path,
                line,
                format!(
                    "vertex {v}: {}",
                    not_finite(&format!("coordinate {axis}"), *c)
                ),
            ));
        }
    }
    Ok(glam::DVec3::from_array(xyz))
}
