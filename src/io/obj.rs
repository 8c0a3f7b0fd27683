//! Wavefront OBJ: polygons (never triangulated) and OpenSubdiv's sharpness tags.
//!
//! # Why this reader is written by hand and not with `tobj`
//!
//! DESIGN.md names `tobj` for OBJ. We checked tobj 4.0.5 on the shared models and on
//! small files, and it cannot give what katachi must keep:
//!
//! - **Vertex numbering.** tobj renumbers vertices in the order faces first use them,
//!   separately for every `o`/`g` group, and drops vertices no face uses
//!   (`stanford-bunny.obj` loads with 34834 of its 35947 vertices). Sharpness tags, the
//!   C ABI and round trips all address vertices by the file's numbers.
//! - **Precision.** Without its `use_f64` feature tobj parses coordinates as `f32`, so a
//!   round trip cannot be bit-exact.
//! - **Error places.** tobj's `LoadError` is a bare enum (`FaceParseError`, …) with no
//!   line, so no message could say where the file is wrong.
//! - **Tags.** It skips `t` lines, which carry creases and corners.
//!
//! What is left to write is small: a line splitter, `v`, `f` (with `v/vt/vn` forms and
//! negative, relative indices) and `t`. Every other statement (`vt`, `vn`, `o`, `g`, `s`,
//! `usemtl`, `mtllib`, `l`, `p`, free-form geometry…) is ignored, so a missing `.mtl`
//! never fails a load. The 4th (`w`) or colour values of `v` lines are ignored as well:
//! they do not move a polygon vertex. Lines ending in `\` continue on the next line.
//! tobj stays useful as an independent oracle in the tests (face sizes and corner
//! positions of every shared model agree with it).
//!
//! # Sharpness tags
//!
//! OpenSubdiv's regression shapes carry sharpness in `t` lines,
//! `t name nints/nfloats/nstrings ints… floats… strings…`, with 0-based vertex indices.
//! katachi reads
//!
//! - `t crease 2/1/0 a b s`: edge `a–b` gets sharpness `s` (the only form OpenSubdiv's
//!   own shapes use, and the only form katachi writes);
//! - `t crease N/1/0 v0 … vN-1 s`: the chain of edges `v0–v1, v1–v2, …` all get `s`;
//! - `t crease N/(N-1)/0 v0 … vN-1 s0 … sN-2`: edge `vi–vi+1` gets `si`;
//! - `t corner N/1/0 v0 … s` and `t corner N/N/0 v0 … s0 …`: vertex sharpness.
//!
//! Multi-vertex creases are read as chains, as RenderMan and USD (`creaseLengths`)
//! define them. OpenSubdiv's regression reader (`far_utils.h`) reads their indices as
//! separate pairs instead; the two agree on `2/1/0`, which is why the writer emits only
//! that form. Other tags (`interpolateboundary`, `hole`, …) are ignored. A crease on a
//! pair of vertices that no face edge joins, a corner on a missing vertex, or a
//! negative or non-finite sharpness is an error naming the line.

use std::io::{BufWriter, Write};
use std::path::Path;

use super::build::{at_line, parse_xyz, Element, Location, RawMesh, MAX_ELEMENTS};
use super::text::{self, parse_f64, parse_i64, show, strip_comment, Float, Lines};
use super::{io_error, reject_holes, Format, WRITER_PATH};
use crate::error::{Error, Result};
use crate::mesh::{PolyMesh, VertexId};

/// Reads an OBJ file from its bytes; `path` only names the file in error messages.
///
/// Vertices keep the file's numbering (unreferenced ones included), faces keep their
/// polygons, `t crease` / `t corner` tags become edge and vertex sharpness.
pub fn read_bytes(bytes: &[u8], path: &Path) -> Result<PolyMesh> {
    let mut raw = RawMesh::with_capacity(0, 0, 0);
    let mut face_lines: Vec<usize> = Vec::new();
    let mut creases: Vec<Crease> = Vec::new();
    let mut corners: Vec<Corner> = Vec::new();
    let mut lines = Lines::new(bytes);
    let mut joined: Vec<u8> = Vec::new();

    while let Some((no, physical)) = lines.next() {
        let mut line = strip_comment(physical);
        if ends_with_backslash(line) {
            // A statement continued over several lines: join them, report its first line.
            joined.clear();
            let mut cur = line;
            loop {
                match trim_end(cur).strip_suffix(b"\\") {
                    Some(body) => {
                        joined.extend_from_slice(body);
                        joined.push(b' ');
                        match lines.next() {
                            Some((_, next)) => cur = strip_comment(next),
                            None => break,
                        }
                    }
                    None => {
                        joined.extend_from_slice(cur);
                        break;
                    }
                }
            }
            line = &joined;
        }
        let mut toks = text::tokens(line);
        let Some(keyword) = toks.next() else {
            continue;
        };
        match keyword {
            b"v" => {
                let v = raw.positions.len();
                if v as u64 >= MAX_ELEMENTS {
                    return Err(at_line(
                        path,
                        no,
                        format!("more than {MAX_ELEMENTS} vertices, more than katachi's 32-bit indices address"),
                    ));
                }
                let p = parse_xyz(&mut toks, path, no, v as u64, &|| {
                    format!("vertex {v}: a 'v' line needs 3 coordinates, this one has fewer")
                })?;
                raw.positions.push(p);
            }
            b"f" | b"fo" => {
                let face = raw.face_count();
                let nv = raw.positions.len() as i64;
                for t in toks {
                    let index = t.split(|&b| b == b'/').next().unwrap_or_default();
                    let i = parse_i64(index).ok_or_else(|| {
                        at_line(
                            path,
                            no,
                            format!("face {face}: {} is not a vertex reference (expected v, v/vt, v//vn or v/vt/vn)", show(t)),
                        )
                    })?;
                    let resolved = match i {
                        0 => {
                            return Err(at_line(
                                path,
                                no,
                                format!("face {face}: vertex index 0 is invalid (OBJ indices count from 1, or back from -1)"),
                            ))
                        }
                        i if i < 0 => {
                            let r = nv + i;
                            if r < 0 {
                                return Err(at_line(
                                    path,
                                    no,
                                    format!("face {face}: relative vertex index {i} reaches before the first vertex (only {nv} vertices precede this line)"),
                                ));
                            }
                            r
                        }
                        i => i - 1,
                    };
                    if resolved as u64 >= MAX_ELEMENTS {
                        return Err(at_line(
                            path,
                            no,
                            format!("face {face}: vertex index {i} is out of range (katachi addresses at most {MAX_ELEMENTS} vertices)"),
                        ));
                    }
                    raw.corners.push(VertexId(resolved as u32));
                }
                raw.end_face().map_err(|m| at_line(path, no, m))?;
                face_lines.push(no);
            }
            b"t" => parse_tag(toks, no, path, &mut creases, &mut corners)?,
            _ => {
                let is_word = keyword
                    .iter()
                    .all(|&b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-');
                if !is_word {
                    return Err(at_line(
                        path,
                        no,
                        format!("{} is not an OBJ statement", show(keyword)),
                    ));
                }
                // vt, vn, vp, o, g, s, usemtl, mtllib, l, p, curves…: not mesh geometry.
            }
        }
    }

    let locate = |e: Element| match e {
        Element::Face(f) => face_lines
            .get(f as usize)
            .map_or(Location::Unknown, |&l| Location::Line(l)),
        Element::Vertex(_) => Location::Unknown, // coordinates are checked while parsing
    };
    let mut mesh = raw.into_mesh(path, locate).map_err(obj_index_hint)?;
    apply_tags(&mut mesh, &creases, &corners, path)?;
    Ok(mesh)
}

/// Out-of-range messages speak of 0-based indices; say how they relate to the file's.
fn obj_index_hint(e: Error) -> Error {
    match e {
        Error::Parse {
            path,
            line,
            byte,
            message,
        } if message.contains("is out of range") => Error::Parse {
            path,
            line,
            byte,
            message: format!("{message}; OBJ indices count from 1, so the file wrote it 1 higher"),
        },
        e => e,
    }
}

fn ends_with_backslash(line: &[u8]) -> bool {
    trim_end(line).last() == Some(&b'\\')
}

fn trim_end(line: &[u8]) -> &[u8] {
    let end = line
        .iter()
        .rposition(|&b| !text::is_space(b))
        .map_or(0, |i| i + 1);
    &line[..end]
}

/// An edge sharpness from a `t crease` tag, with its line.
struct Crease {
    a: u32,
    b: u32,
    sharpness: f64,
    line: usize,
}

/// A vertex sharpness from a `t corner` tag, with its line.
struct Corner {
    v: u32,
    sharpness: f64,
    line: usize,
}

fn parse_tag(
    mut toks: text::Tokens<'_>,
    no: usize,
    path: &Path,
    creases: &mut Vec<Crease>,
    corners: &mut Vec<Corner>,
) -> Result<()> {
    let name = toks.next().unwrap_or_default();
    let is_crease = match name {
        b"crease" => true,
        b"corner" => false,
        _ => return Ok(()), // interpolateboundary, hole, creasemethod…: not ours
    };
    let tag = if is_crease { "crease" } else { "corner" };
    let err = |m: String| at_line(path, no, format!("tag '{tag}': {m}"));
    let counts_tok = toks.next().unwrap_or_default();
    let counts: Vec<u64> = counts_tok
        .split(|&b| b == b'/')
        .map(text::parse_u64)
        .collect::<Option<_>>()
        .filter(|c: &Vec<u64>| c.len() == 3)
        .ok_or_else(|| {
            err(format!(
                "expected argument counts like 2/1/0, found {}",
                show(counts_tok)
            ))
        })?;
    let (n_ints, n_floats) = (counts[0], counts[1]);
    let mut ints = Vec::new();
    for _ in 0..n_ints {
        let t = toks.next().ok_or_else(|| {
            err(format!(
                "{n_ints} vertex indices announced, only {} given",
                ints.len()
            ))
        })?;
        let i = parse_i64(t).ok_or_else(|| err(format!("{} is not a vertex index", show(t))))?;
        if i < 0 || i as u64 >= MAX_ELEMENTS {
            return Err(err(format!(
                "vertex index {i} is out of range (tag indices count from 0)"
            )));
        }
        ints.push(i as u32);
    }
    let mut floats = Vec::new();
    for _ in 0..n_floats {
        let t = toks.next().ok_or_else(|| {
            err(format!(
                "{n_floats} sharpness values announced, only {} given",
                floats.len()
            ))
        })?;
        let s = parse_f64(t).ok_or_else(|| err(format!("{} is not a number", show(t))))?;
        if !s.is_finite() || s < 0.0 {
            return Err(err(format!(
                "sharpness {s} is invalid (it must be finite and at least 0)"
            )));
        }
        floats.push(s);
    }
    let n = ints.len();
    if is_crease {
        if n < 2 {
            return Err(err(format!("a crease needs at least 2 vertices, got {n}")));
        }
        if floats.len() != 1 && floats.len() != n - 1 {
            return Err(err(format!(
                "a crease through {n} vertices needs 1 or {} sharpness values, got {}",
                n - 1,
                floats.len()
            )));
        }
        for (k, w) in ints.windows(2).enumerate() {
            let s = if floats.len() == 1 {
                floats[0]
            } else {
                floats[k]
            };
            creases.push(Crease {
                a: w[0],
                b: w[1],
                sharpness: s,
                line: no,
            });
        }
    } else {
        if n < 1 {
            return Err(err("a corner needs at least 1 vertex, got 0".into()));
        }
        if floats.len() != 1 && floats.len() != n {
            return Err(err(format!(
                "a corner on {n} vertices needs 1 or {n} sharpness values, got {}",
                floats.len()
            )));
        }
        for (k, &v) in ints.iter().enumerate() {
            let s = if floats.len() == 1 {
                floats[0]
            } else {
                floats[k]
            };
            corners.push(Corner {
                v,
                sharpness: s,
                line: no,
            });
        }
    }
    Ok(())
}

fn apply_tags(
    mesh: &mut PolyMesh,
    creases: &[Crease],
    corners: &[Corner],
    path: &Path,
) -> Result<()> {
    if !creases.is_empty() {
        let values = creases
            .iter()
            .map(|c| (VertexId(c.a), VertexId(c.b), c.sharpness));
        mesh.set_edge_sharpnesses(values).map_err(|e| {
            let line = match e {
                Error::NoSuchEdge { a, b } => creases
                    .iter()
                    .find(|c| (c.a, c.b) == (a, b) || (c.b, c.a) == (a, b))
                    .map_or(Location::Unknown, |c| Location::Line(c.line)),
                _ => Location::Unknown,
            };
            super::build::parse_error(path, line, format!("tag 'crease': {e}"))
        })?;
    }
    let nv = mesh.vertex_count();
    for c in corners {
        if c.v >= nv {
            return Err(at_line(
                path,
                c.line,
                format!(
                    "tag 'corner': vertex {} is out of range (the mesh has {nv} vertices)",
                    c.v
                ),
            ));
        }
        mesh.set_vertex_sharpness(VertexId(c.v), c.sharpness)
            .map_err(|e| at_line(path, c.line, format!("tag 'corner': {e}")))?;
    }
    Ok(())
}

/// Writes `mesh` as OBJ to any writer: `v` lines with the shortest decimals that read
/// back bit-exact, 1-based `f` lines, then one `t crease 2/1/0 a b s` per sharp edge and
/// one `t corner 1/1/0 v s` per sharp vertex. A face with holes is refused
/// ([`Error::InvalidArgument`]) before anything is written.
pub fn write_to<W: Write>(w: W, mesh: &PolyMesh) -> Result<()> {
    write_impl(w, mesh, Path::new(WRITER_PATH))
}

pub(crate) fn write_impl<W: Write>(w: W, mesh: &PolyMesh, path: &Path) -> Result<()> {
    reject_holes(mesh, Format::Obj)?;
    let mut w = BufWriter::with_capacity(1 << 16, w);
    write_body(&mut w, mesh).map_err(io_error(path))?;
    w.flush().map_err(io_error(path))
}

fn write_body<W: Write>(w: &mut W, mesh: &PolyMesh) -> std::io::Result<()> {
    writeln!(
        w,
        "# katachi: {} vertices, {} faces",
        mesh.vertex_count(),
        mesh.face_count()
    )?;
    for p in mesh.positions() {
        writeln!(w, "v {} {} {}", Float(p.x), Float(p.y), Float(p.z))?;
    }
    for f in mesh.faces() {
        w.write_all(b"f")?;
        for v in mesh.face_outer(f) {
            write!(w, " {}", v.0 as u64 + 1)?;
        }
        w.write_all(b"\n")?;
    }
    for (a, b, s) in mesh.sharp_edges() {
        writeln!(w, "t crease 2/1/0 {a} {b} {}", Float(s))?;
    }
    for (v, &s) in mesh.vertex_sharpness().iter().enumerate() {
        if s > 0.0 {
            writeln!(w, "t corner 1/1/0 {v} {}", Float(s))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(s: &str) -> Result<PolyMesh> {
        read_bytes(s.as_bytes(), Path::new("t.obj"))
    }

    #[test]
    fn continuation_lines_join() {
        let m = read("v 0 0 0\nv 1 0 0\nv 0 1 \\\n 0\nf 1 2 \\\n3\n").unwrap();
        assert_eq!(m.vertex_count(), 3);
        assert_eq!(m.face_count(), 1);
    }

    #[test]
    fn chain_crease_with_per_edge_values() {
        let m = read(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n\
             t crease 3/2/0 0 1 2 1.5 2.5\nt corner 2/2/0 0 3 4 5\n",
        )
        .unwrap();
        assert_eq!(m.edge_sharpness(VertexId(0), VertexId(1)), 1.5);
        assert_eq!(m.edge_sharpness(VertexId(2), VertexId(1)), 2.5);
        assert_eq!(m.vertex_sharpness(), &[4.0, 0.0, 0.0, 5.0]);
    }
}
