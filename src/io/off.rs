//! Geomview OFF (ASCII).
//!
//! Layout: a header keyword (`OFF`, or a variant with per-vertex extras: `COFF`,
//! `NOFF`, `CNOFF`, `STOFF`, `STCNOFF`…, or `nOFF` with dimension 3), the counts
//! `V F [E]` (on the header line or the next), then one vertex per line (`x y z`, extra
//! values such as colours or normals ignored) and one face per line
//! (`n i0 … in-1`, trailing colour values ignored). `#` starts a comment anywhere; blank
//! lines are skipped. Binary OFF and 4-dimensional OFF are refused with a clear error.
//!
//! Written: `OFF`, `V F 0` (the edge count is optional and 0 by convention), vertices as
//! shortest round-trip decimals (bit-exact), faces as `n i0 …`.
//!
//! # Why by hand
//!
//! No maintained Rust crate reads OFF; the format is a few dozen lines of parsing, kept
//! here with line numbers in every error.

use std::io::{BufWriter, Write};
use std::path::Path;

use super::build::{at_line, parse_xyz, Element, Location, RawMesh, MAX_ELEMENTS};
use super::text::{self, show, strip_comment, Float, Lines};
use super::{io_error, reject_holes, Format, WRITER_PATH};
use crate::error::Result;
use crate::mesh::{PolyMesh, VertexId};

/// Reads an OFF file from its bytes; `path` only names the file in error messages.
pub fn read_bytes(bytes: &[u8], path: &Path) -> Result<PolyMesh> {
    let mut lines = Lines::new(bytes);
    // Non-blank lines with comments removed.
    let mut next = move || -> (usize, Option<&[u8]>) {
        for (no, l) in lines.by_ref() {
            let l = strip_comment(l);
            if text::tokens(l).next().is_some() {
                return (no, Some(l));
            }
        }
        (lines.number(), None)
    };

    // Header.
    let (no, first) = next();
    let Some(first) = first else {
        return Err(at_line(
            path,
            no.max(1),
            "the file is empty (expected 'OFF')",
        ));
    };
    let mut toks = text::tokens(first);
    let kw = toks.next().unwrap_or_default();
    let Some(prefix) = kw.strip_suffix(b"OFF") else {
        return Err(at_line(
            path,
            no,
            format!(
                "not an OFF file: it starts with {} instead of 'OFF'",
                show(kw)
            ),
        ));
    };
    let mut p = prefix;
    for part in [&b"ST"[..], b"C", b"N", b"4", b"n"] {
        if let Some(rest) = p.strip_prefix(part) {
            if part == b"4" {
                return Err(at_line(
                    path,
                    no,
                    "4-dimensional OFF (4OFF) is not supported",
                ));
            }
            if part == b"n" {
                let dim = toks.next().unwrap_or_default();
                if dim != b"3" {
                    return Err(at_line(
                        path,
                        no,
                        format!(
                            "nOFF with dimension {} is not supported (only 3)",
                            show(dim)
                        ),
                    ));
                }
            }
            p = rest;
        }
    }
    if !p.is_empty() {
        return Err(at_line(
            path,
            no,
            format!("unknown OFF variant {}", show(kw)),
        ));
    }
    let mut counts_line = no;
    let mut rest: Vec<&[u8]> = toks.collect();
    if rest.first() == Some(&&b"BINARY"[..]) {
        return Err(at_line(path, no, "binary OFF is not supported"));
    }
    if rest.is_empty() {
        let (n2, l) = next();
        counts_line = n2;
        let Some(l) = l else {
            return Err(at_line(
                path,
                n2.max(no),
                "the file ends before the counts line 'V F E'",
            ));
        };
        rest = text::tokens(l).collect();
    }
    let count = |k: usize, what: &str| -> Result<u64> {
        let t = rest.get(k).copied().unwrap_or_default();
        text::parse_u64(t).ok_or_else(|| {
            at_line(
                path,
                counts_line,
                format!(
                    "the {what} count {} is not a non-negative integer (expected 'V F E')",
                    show(t)
                ),
            )
        })
    };
    let (nv, nf) = (count(0, "vertex")?, count(1, "face")?);
    if nv > MAX_ELEMENTS || nf > MAX_ELEMENTS {
        return Err(at_line(
            path,
            counts_line,
            format!("{nv} vertices and {nf} faces are more than katachi's 32-bit indices address"),
        ));
    }
    // Capacity capped by what the file could hold (a vertex line has at least 6 bytes).
    let cap = bytes.len() / 6;
    let mut raw = RawMesh::with_capacity((nv as usize).min(cap), (nf as usize).min(cap), 0);
    raw.corners.reserve((nf as usize * 3).min(bytes.len() / 2));
    let mut face_lines = Vec::with_capacity((nf as usize).min(cap));

    for v in 0..nv {
        let (no, l) = next();
        let Some(l) = l else {
            return Err(at_line(
                path,
                no,
                format!("the file ends after {v} of {nv} vertices"),
            ));
        };
        let mut toks = text::tokens(l);
        let p = parse_xyz(&mut toks, path, no, v, &|| {
            format!("vertex {v}: expected 3 coordinates")
        })?;
        raw.positions.push(p);
    }
    for f in 0..nf {
        let (no, l) = next();
        let Some(l) = l else {
            return Err(at_line(
                path,
                no,
                format!("the file ends after {f} of {nf} faces"),
            ));
        };
        let mut toks = text::tokens(l);
        let t = toks.next().unwrap_or_default();
        let n = text::parse_u64(t).ok_or_else(|| {
            at_line(
                path,
                no,
                format!(
                    "face {f}: the corner count {} is not a non-negative integer",
                    show(t)
                ),
            )
        })?;
        for k in 0..n {
            let t = toks.next().ok_or_else(|| {
                at_line(
                    path,
                    no,
                    format!("face {f}: {n} corners announced, only {k} given"),
                )
            })?;
            let i = text::parse_u64(t)
                .filter(|&i| i < MAX_ELEMENTS)
                .ok_or_else(|| {
                    at_line(
                        path,
                        no,
                        format!("face {f}: {} is not a valid vertex index", show(t)),
                    )
                })?;
            raw.corners.push(VertexId(i as u32));
        }
        // Anything after the indices is a colour: ignored.
        raw.end_face().map_err(|m| at_line(path, no, m))?;
        face_lines.push(no);
    }
    raw.into_mesh(path, |e| match e {
        Element::Face(f) => face_lines
            .get(f as usize)
            .map_or(Location::Unknown, |&l| Location::Line(l)),
        Element::Vertex(_) => Location::Unknown, // checked while parsing
    })
}

/// Writes `mesh` as OFF to any writer. A face with holes is refused
/// ([`crate::Error::InvalidArgument`]) before anything is written.
pub fn write_to<W: Write>(w: W, mesh: &PolyMesh) -> Result<()> {
    write_impl(w, mesh, Path::new(WRITER_PATH))
}

pub(crate) fn write_impl<W: Write>(w: W, mesh: &PolyMesh, path: &Path) -> Result<()> {
    reject_holes(mesh, Format::Off)?;
    let mut w = BufWriter::with_capacity(1 << 16, w);
    write_body(&mut w, mesh).map_err(io_error(path))?;
    w.flush().map_err(io_error(path))
}

fn write_body<W: Write>(w: &mut W, mesh: &PolyMesh) -> std::io::Result<()> {
    writeln!(w, "OFF\n{} {} 0", mesh.vertex_count(), mesh.face_count())?;
    for p in mesh.positions() {
        writeln!(w, "{} {} {}", Float(p.x), Float(p.y), Float(p.z))?;
    }
    for f in mesh.faces() {
        let lp = mesh.face_outer(f);
        write!(w, "{}", lp.len())?;
        for v in lp {
            write!(w, " {v}")?;
        }
        w.write_all(b"\n")?;
    }
    Ok(())
}
