//! Stanford PLY: ASCII, binary little-endian and binary big-endian.
//!
//! Read: the `vertex` element's `x`, `y`, `z` (any scalar type, any position among the
//! element's properties; other properties ignored) and the `face` element's
//! `vertex_indices` (or `vertex_index`) list (any integer count and index types; other
//! properties ignored). Every other element (edges, materials, …) is skipped, in binary
//! by computing its records' sizes, lists included. Elements after both `vertex` and
//! `face` are not read at all. A `tristrips` element (no `face`) is refused, not dropped.
//!
//! Written: `double` coordinates (bit-exact), `uchar` counts (`uint` when a face has
//! more than 255 corners), `int` indices (`uint` past 2^31 vertices) — the layout
//! MeshLab, Blender and libigl read.
//!
//! # Why by hand
//!
//! The PLY crate of the Rust ecosystem, `ply-rs`, has had no release since 2020 and
//! builds a map of named properties for every element it reads: a million-face file
//! costs millions of allocations. Here the file is read into memory once, the header is
//! parsed, and the binary body is decoded with slice operations straight into the
//! mesh's flat arrays (no per-element allocation), which keeps reading within a small
//! factor of `std::fs::read` of the same file (see `benches/io.rs`).
//!
//! Errors name the header line, the body line (ASCII) or the byte offset of the record
//! (binary) at fault.

use std::io::{BufWriter, Write};
use std::path::Path;

use glam::DVec3;

use super::build::{at_byte, at_line, Element, Location, RawMesh, MAX_ELEMENTS};
use super::text::{self, not_finite, parse_f64, parse_i64, show, Float};
use super::{io_error, reject_holes, Format, WRITER_PATH};
use crate::error::Result;
use crate::mesh::{PolyMesh, VertexId};

/// How a PLY file stores its body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum PlyEncoding {
    /// Text: readable, larger, slower; still bit-exact (shortest round-trip decimals).
    Ascii,
    /// Binary little-endian: the usual choice.
    BinaryLittleEndian,
    /// Binary big-endian: for old tools that want it.
    BinaryBigEndian,
}

impl PlyEncoding {
    fn header_name(self) -> &'static str {
        match self {
            PlyEncoding::Ascii => "ascii",
            PlyEncoding::BinaryLittleEndian => "binary_little_endian",
            PlyEncoding::BinaryBigEndian => "binary_big_endian",
        }
    }
}

/// A PLY scalar type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ty {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Ty {
    fn parse(name: &[u8]) -> Option<Ty> {
        Some(match name {
            b"char" | b"int8" => Ty::I8,
            b"uchar" | b"uint8" => Ty::U8,
            b"short" | b"int16" => Ty::I16,
            b"ushort" | b"uint16" => Ty::U16,
            b"int" | b"int32" => Ty::I32,
            b"uint" | b"uint32" => Ty::U32,
            b"float" | b"float32" => Ty::F32,
            b"double" | b"float64" => Ty::F64,
            _ => return None,
        })
    }

    #[inline]
    fn size(self) -> usize {
        match self {
            Ty::I8 | Ty::U8 => 1,
            Ty::I16 | Ty::U16 => 2,
            Ty::I32 | Ty::U32 | Ty::F32 => 4,
            Ty::F64 => 8,
        }
    }

    fn is_int(self) -> bool {
        !matches!(self, Ty::F32 | Ty::F64)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Scalar(Ty),
    List { count: Ty, item: Ty },
}

#[derive(Debug, Clone)]
struct Property {
    name: String,
    kind: Kind,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    Vertex { x: usize, y: usize, z: usize },
    Face { indices: usize },
    Other,
}

#[derive(Debug, Clone)]
struct ElementDef {
    name: String,
    count: u64,
    props: Vec<Property>,
    line: usize,
    role: Role,
}

impl ElementDef {
    /// Bytes per record when no property is a list.
    fn fixed_stride(&self) -> Option<usize> {
        self.props
            .iter()
            .map(|p| match p.kind {
                Kind::Scalar(t) => Some(t.size()),
                Kind::List { .. } => None,
            })
            .sum()
    }
}

struct Header {
    encoding: PlyEncoding,
    elements: Vec<ElementDef>,
    /// Byte offset of the body.
    body: usize,
    /// Number of header lines (the body's first line is `lines + 1`).
    lines: usize,
}

/// Reads a PLY file (ASCII or binary) from its bytes; `path` only names the file in
/// error messages.
pub fn read_bytes(bytes: &[u8], path: &Path) -> Result<PolyMesh> {
    let header = parse_header(bytes, path)?;
    match header.encoding {
        PlyEncoding::Ascii => read_ascii(bytes, &header, path),
        PlyEncoding::BinaryLittleEndian => read_binary::<Le>(bytes, &header, path),
        PlyEncoding::BinaryBigEndian => read_binary::<Be>(bytes, &header, path),
    }
}

fn parse_header(bytes: &[u8], path: &Path) -> Result<Header> {
    let mut pos = 0usize;
    let mut line_no = 0usize;
    let next_line = |pos: &mut usize| -> Option<&[u8]> {
        if *pos >= bytes.len() {
            return None;
        }
        let rest = &bytes[*pos..];
        let (line, adv) = match rest.iter().position(|&b| b == b'\n') {
            Some(i) => (&rest[..i], i + 1),
            None => (rest, rest.len()),
        };
        *pos += adv;
        Some(line.strip_suffix(b"\r").unwrap_or(line))
    };
    let first = next_line(&mut pos);
    line_no += 1;
    if first.map(|l| text::tokens(l).collect::<Vec<_>>()) != Some(vec![&b"ply"[..]]) {
        return Err(at_line(
            path,
            1,
            "not a PLY file: the first line must be 'ply'",
        ));
    }
    let mut encoding = None;
    let mut elements: Vec<ElementDef> = Vec::new();
    loop {
        let Some(line) = next_line(&mut pos) else {
            return Err(at_line(
                path,
                line_no,
                "the header has no 'end_header' line",
            ));
        };
        line_no += 1;
        let err = |m: String| at_line(path, line_no, m);
        let mut toks = text::tokens(line);
        let Some(kw) = toks.next() else { continue };
        match kw {
            b"end_header" => break,
            b"comment" | b"obj_info" => {}
            b"format" => {
                let enc = match toks.next().unwrap_or_default() {
                    b"ascii" => PlyEncoding::Ascii,
                    b"binary_little_endian" => PlyEncoding::BinaryLittleEndian,
                    b"binary_big_endian" => PlyEncoding::BinaryBigEndian,
                    other => {
                        return Err(err(format!(
                            "unknown format {} (expected ascii, binary_little_endian or binary_big_endian)",
                            show(other)
                        )))
                    }
                };
                let version = toks.next().unwrap_or_default();
                if !version.starts_with(b"1") {
                    return Err(err(format!(
                        "PLY version {} is not supported (expected 1.0)",
                        show(version)
                    )));
                }
                encoding = Some(enc);
            }
            b"element" => {
                let name = toks.next().unwrap_or_default();
                let count_tok = toks.next().unwrap_or_default();
                if name.is_empty() {
                    return Err(err("'element' needs a name and a count".into()));
                }
                let count = text::parse_u64(count_tok).ok_or_else(|| {
                    err(format!(
                        "element '{}': count {} is not a non-negative integer",
                        text::name(name),
                        show(count_tok)
                    ))
                })?;
                let name = text::name(name);
                if elements.iter().any(|e| e.name == name) {
                    return Err(err(format!("element '{name}' is declared twice")));
                }
                elements.push(ElementDef {
                    name,
                    count,
                    props: Vec::new(),
                    line: line_no,
                    role: Role::Other,
                });
            }
            b"property" => {
                let Some(el) = elements.last_mut() else {
                    return Err(err("'property' before any 'element'".into()));
                };
                let ty_tok = toks.next().unwrap_or_default();
                let ty = |t: &[u8]| {
                    Ty::parse(t).ok_or_else(|| err(format!("unknown property type {}", show(t))))
                };
                let kind = if ty_tok == b"list" {
                    let count = ty(toks.next().unwrap_or_default())?;
                    let item = ty(toks.next().unwrap_or_default())?;
                    if !count.is_int() {
                        return Err(err("a list's count type must be an integer type".into()));
                    }
                    Kind::List { count, item }
                } else {
                    Kind::Scalar(ty(ty_tok)?)
                };
                let name = toks
                    .next()
                    .ok_or_else(|| err("property without a name".into()))?;
                el.props.push(Property {
                    name: text::name(name),
                    kind,
                });
            }
            other => return Err(err(format!("{} is not a PLY header keyword", show(other)))),
        }
    }
    let Some(encoding) = encoding else {
        return Err(at_line(path, line_no, "the header has no 'format' line"));
    };
    let has_face = elements.iter().any(|e| e.name == "face");
    for el in &mut elements {
        let err = |m: String| at_line(path, el.line, m);
        let find = |n: &str| el.props.iter().position(|p| p.name == n);
        match el.name.as_str() {
            "vertex" => {
                let mut xyz = [0usize; 3];
                for (slot, n) in xyz.iter_mut().zip(["x", "y", "z"]) {
                    let i = find(n)
                        .ok_or_else(|| err(format!("element 'vertex' has no property '{n}'")))?;
                    if !matches!(el.props[i].kind, Kind::Scalar(_)) {
                        return Err(err(format!(
                            "element 'vertex': property '{n}' must be a number, not a list"
                        )));
                    }
                    *slot = i;
                }
                if el.count > MAX_ELEMENTS {
                    return Err(err(format!(
                        "{} vertices are more than katachi's 32-bit indices address",
                        el.count
                    )));
                }
                el.role = Role::Vertex {
                    x: xyz[0],
                    y: xyz[1],
                    z: xyz[2],
                };
            }
            "face" => {
                let i = find("vertex_indices")
                    .or_else(|| find("vertex_index"))
                    .ok_or_else(|| {
                        err("element 'face' has no list property 'vertex_indices'".into())
                    })?;
                match el.props[i].kind {
                    Kind::List { item, .. } if item.is_int() => {}
                    _ => {
                        return Err(err(format!(
                            "element 'face': property '{}' must be a list of integers",
                            el.props[i].name
                        )))
                    }
                }
                if el.count > MAX_ELEMENTS {
                    return Err(err(format!(
                        "{} faces are more than katachi's 32-bit indices address",
                        el.count
                    )));
                }
                el.role = Role::Face { indices: i };
            }
            "tristrips" if !has_face && el.count > 0 => {
                return Err(err(
                    "triangle strips ('tristrips') are not supported; convert them to a 'face' element"
                        .into(),
                ));
            }
            _ => {}
        }
    }
    Ok(Header {
        encoding,
        elements,
        body: pos,
        lines: line_no,
    })
}

// ---------------------------------------------------------------------------------------
// ASCII body

/// Whitespace-separated tokens across lines, with the line of each.
struct Scanner<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
    /// The line of the last token returned (where an unexpected end is reported).
    token_line: usize,
}

impl<'a> Scanner<'a> {
    /// Skips whitespace, so `line` is the line of the next token.
    #[inline]
    fn skip_space(&mut self) {
        let b = self.bytes;
        while self.pos < b.len() && text::is_space(b[self.pos]) {
            if b[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
    }

    #[inline]
    fn next(&mut self) -> Option<&'a [u8]> {
        let b = self.bytes;
        self.skip_space();
        if self.pos >= b.len() {
            return None;
        }
        let start = self.pos;
        while self.pos < b.len() && !text::is_space(b[self.pos]) {
            self.pos += 1;
        }
        self.token_line = self.line;
        Some(&b[start..self.pos])
    }
}

fn read_ascii(bytes: &[u8], header: &Header, path: &Path) -> Result<PolyMesh> {
    let mut sc = Scanner {
        bytes,
        pos: header.body,
        line: header.lines + 1,
        token_line: header.lines,
    };
    let remaining = bytes.len() - header.body;
    let mut raw = RawMesh::with_capacity(0, 0, 0);
    let mut face_lines: Vec<usize> = Vec::new();
    let (mut have_vertices, mut have_faces) = (false, false);
    let count_of = |role: fn(&Role) -> bool| {
        header
            .elements
            .iter()
            .find(|e| role(&e.role))
            .map_or(0, |e| e.count as usize)
    };
    // Capacity capped by what the body could hold (2 bytes per value at least).
    raw.positions
        .reserve(count_of(|r| matches!(r, Role::Vertex { .. })).min(remaining / 6));
    let nf = count_of(|r| matches!(r, Role::Face { .. })).min(remaining / 8);
    raw.loop_offsets.reserve(nf);
    raw.corners.reserve(nf * 3);
    face_lines.reserve(nf);

    for el in &header.elements {
        if have_vertices && have_faces {
            break;
        }
        if el.props.is_empty() {
            continue; // records without properties hold no data, however many there are
        }
        for r in 0..el.count {
            sc.skip_space();
            let rec_line = sc.line;
            let mut xyz = [0.0f64; 3];
            for (k, p) in el.props.iter().enumerate() {
                match p.kind {
                    Kind::Scalar(_) => {
                        let t = need(&mut sc, path, el, r, &p.name)?;
                        if let Role::Vertex { x, y, z } = el.role {
                            if let Some(axis) = [x, y, z].iter().position(|&i| i == k) {
                                let line = sc.line;
                                let v = parse_f64(t).ok_or_else(|| {
                                    at_line(
                                        path,
                                        line,
                                        format!(
                                            "vertex {r}: {} {} is not a number",
                                            p.name,
                                            show(t)
                                        ),
                                    )
                                })?;
                                if !v.is_finite() {
                                    return Err(at_line(
                                        path,
                                        line,
                                        format!("vertex {r}: {}", not_finite(&p.name, v)),
                                    ));
                                }
                                xyz[axis] = v;
                            }
                        }
                    }
                    Kind::List { .. } => {
                        let t = need(&mut sc, path, el, r, &p.name)?;
                        let line = sc.line;
                        let n = text::parse_u64(t).ok_or_else(|| {
                            at_line(
                                path,
                                line,
                                format!(
                                    "{} {r}: list length {} of '{}' is not a non-negative integer",
                                    el.name,
                                    show(t),
                                    p.name
                                ),
                            )
                        })?;
                        let is_indices = el.role == Role::Face { indices: k };
                        for _ in 0..n {
                            let t = need(&mut sc, path, el, r, &p.name)?;
                            if is_indices {
                                let line = sc.line;
                                let i = parse_i64(t)
                                    .filter(|&i| i >= 0 && (i as u64) < MAX_ELEMENTS)
                                    .ok_or_else(|| {
                                        at_line(
                                            path,
                                            line,
                                            format!(
                                                "face {r}: {} is not a valid vertex index",
                                                show(t)
                                            ),
                                        )
                                    })?;
                                raw.corners.push(VertexId(i as u32));
                            }
                        }
                    }
                }
            }
            match el.role {
                Role::Vertex { .. } => raw.positions.push(DVec3::from_array(xyz)),
                Role::Face { .. } => {
                    raw.end_face().map_err(|m| at_line(path, rec_line, m))?;
                    face_lines.push(rec_line);
                }
                Role::Other => {}
            }
        }
        match el.role {
            Role::Vertex { .. } => have_vertices = true,
            Role::Face { .. } => have_faces = true,
            Role::Other => {}
        }
    }
    raw.into_mesh(path, |e| match e {
        Element::Face(f) => face_lines
            .get(f as usize)
            .map_or(Location::Unknown, |&l| Location::Line(l)),
        Element::Vertex(_) => Location::Unknown, // checked while parsing
    })
}

/// The next token, or an error saying which record the file ends in.
fn need<'a>(
    sc: &mut Scanner<'a>,
    path: &Path,
    el: &ElementDef,
    r: u64,
    what: &str,
) -> Result<&'a [u8]> {
    sc.next().ok_or_else(|| {
        at_line(
            path,
            sc.token_line,
            format!(
                "the file ends inside {} {r} of {} (reading '{what}')",
                el.name, el.count
            ),
        )
    })
}

// ---------------------------------------------------------------------------------------
// Binary body

/// Byte order of a binary body.
trait Order {
    fn u16(b: [u8; 2]) -> u16;
    fn u32(b: [u8; 4]) -> u32;
    fn u64(b: [u8; 8]) -> u64;
}

struct Le;
struct Be;

impl Order for Le {
    #[inline(always)]
    fn u16(b: [u8; 2]) -> u16 {
        u16::from_le_bytes(b)
    }
    #[inline(always)]
    fn u32(b: [u8; 4]) -> u32 {
        u32::from_le_bytes(b)
    }
    #[inline(always)]
    fn u64(b: [u8; 8]) -> u64 {
        u64::from_le_bytes(b)
    }
}

impl Order for Be {
    #[inline(always)]
    fn u16(b: [u8; 2]) -> u16 {
        u16::from_be_bytes(b)
    }
    #[inline(always)]
    fn u32(b: [u8; 4]) -> u32 {
        u32::from_be_bytes(b)
    }
    #[inline(always)]
    fn u64(b: [u8; 8]) -> u64 {
        u64::from_be_bytes(b)
    }
}

/// `N` bytes at `at`; the caller has checked the bounds.
#[inline(always)]
fn arr<const N: usize>(b: &[u8], at: usize) -> [u8; N] {
    let mut a = [0u8; N];
    a.copy_from_slice(&b[at..at + N]);
    a
}

/// A scalar as `f64` (exact for every PLY type).
#[inline(always)]
fn read_f64<O: Order>(b: &[u8], at: usize, ty: Ty) -> f64 {
    match ty {
        Ty::I8 => b[at] as i8 as f64,
        Ty::U8 => b[at] as f64,
        Ty::I16 => O::u16(arr(b, at)) as i16 as f64,
        Ty::U16 => O::u16(arr(b, at)) as f64,
        Ty::I32 => O::u32(arr(b, at)) as i32 as f64,
        Ty::U32 => O::u32(arr(b, at)) as f64,
        Ty::F32 => f32::from_bits(O::u32(arr(b, at))) as f64,
        Ty::F64 => f64::from_bits(O::u64(arr(b, at))),
    }
}

/// An integer scalar as `i64` (float types, excluded by the header checks, read as 0).
#[inline(always)]
fn read_int<O: Order>(b: &[u8], at: usize, ty: Ty) -> i64 {
    match ty {
        Ty::I8 => b[at] as i8 as i64,
        Ty::U8 => b[at] as i64,
        Ty::I16 => O::u16(arr(b, at)) as i16 as i64,
        Ty::U16 => O::u16(arr(b, at)) as i64,
        Ty::I32 => O::u32(arr(b, at)) as i32 as i64,
        Ty::U32 => O::u32(arr(b, at)) as i64,
        Ty::F32 | Ty::F64 => 0,
    }
}

/// Why a record could not be read.
enum RecordError {
    /// The file ends inside the record.
    Truncated,
    /// A list has a negative length.
    NegativeLength(String),
}

/// The length of the record at `at`.
fn record_len<O: Order>(
    b: &[u8],
    at: usize,
    props: &[Property],
) -> std::result::Result<usize, RecordError> {
    let mut p = at;
    for prop in props {
        match prop.kind {
            Kind::Scalar(t) => p += t.size(),
            Kind::List { count, item } => {
                if p + count.size() > b.len() {
                    return Err(RecordError::Truncated);
                }
                let n = read_int::<O>(b, p, count);
                if n < 0 {
                    return Err(RecordError::NegativeLength(prop.name.clone()));
                }
                p += count.size();
                let len = (n as u64).saturating_mul(item.size() as u64);
                if len > (b.len() - p.min(b.len())) as u64 {
                    return Err(RecordError::Truncated);
                }
                p += len as usize;
            }
        }
    }
    if p > b.len() {
        return Err(RecordError::Truncated);
    }
    Ok(p - at)
}

fn record_error(
    path: &Path,
    el: &ElementDef,
    r: u64,
    at: usize,
    file_len: usize,
    e: RecordError,
) -> crate::Error {
    match e {
        RecordError::Truncated => at_byte(
            path,
            at as u64,
            format!(
                "the file ends inside {} {r} of {} (the file has {file_len} bytes)",
                el.name, el.count
            ),
        ),
        RecordError::NegativeLength(name) => at_byte(
            path,
            at as u64,
            format!("{} {r}: list '{name}' has a negative length", el.name),
        ),
    }
}

/// The offset of record `n` of an element that starts at `start` (records before it
/// were read successfully, so this walk cannot fail).
fn nth_record<O: Order>(b: &[u8], start: usize, el: &ElementDef, n: u64) -> u64 {
    if let Some(stride) = el.fixed_stride() {
        return start as u64 + n * stride as u64;
    }
    let mut p = start;
    for _ in 0..n {
        match record_len::<O>(b, p, &el.props) {
            Ok(len) => p += len,
            Err(_) => break,
        }
    }
    p as u64
}

/// Skips all records of `el` starting at `at`, returning the offset after them.
fn skip_element<O: Order>(b: &[u8], at: usize, el: &ElementDef, path: &Path) -> Result<usize> {
    if let Some(stride) = el.fixed_stride() {
        let need = el.count.saturating_mul(stride as u64);
        let have = (b.len() - at) as u64;
        if need > have {
            let r = have / stride.max(1) as u64;
            let rec = at + (r as usize) * stride;
            return Err(record_error(
                path,
                el,
                r,
                rec,
                b.len(),
                RecordError::Truncated,
            ));
        }
        return Ok(at + need as usize);
    }
    let mut p = at;
    for r in 0..el.count {
        p += record_len::<O>(b, p, &el.props)
            .map_err(|e| record_error(path, el, r, p, b.len(), e))?;
    }
    Ok(p)
}

fn read_binary<O: Order>(bytes: &[u8], header: &Header, path: &Path) -> Result<PolyMesh> {
    let mut raw = RawMesh::with_capacity(0, 0, 0);
    let mut pos = header.body;
    let mut vertex_at: Option<(usize, &ElementDef)> = None;
    let mut face_at: Option<(usize, &ElementDef)> = None;
    for el in &header.elements {
        if vertex_at.is_some() && face_at.is_some() {
            break;
        }
        let start = pos;
        pos = match el.role {
            Role::Vertex { x, y, z } => {
                vertex_at = Some((start, el));
                read_vertices::<O>(bytes, start, el, [x, y, z], &mut raw, path)?
            }
            Role::Face { indices } => {
                face_at = Some((start, el));
                read_faces::<O>(bytes, start, el, indices, &mut raw, path)?
            }
            Role::Other => skip_element::<O>(bytes, start, el, path)?,
        };
    }
    raw.into_mesh(path, |e| {
        let (at, n) = match e {
            Element::Face(f) => (face_at, f),
            Element::Vertex(v) => (vertex_at, v),
        };
        at.map_or(Location::Unknown, |(start, el)| {
            Location::Byte(nth_record::<O>(bytes, start, el, n as u64))
        })
    })
}

/// Offsets of the x, y, z properties within a fixed-size record, with their types.
fn xyz_layout(el: &ElementDef, xyz: [usize; 3]) -> [(usize, Ty); 3] {
    let offset = |k: usize| -> usize {
        el.props[..k]
            .iter()
            .map(|p| match p.kind {
                Kind::Scalar(t) => t.size(),
                Kind::List { .. } => 0,
            })
            .sum()
    };
    xyz.map(|k| match el.props[k].kind {
        Kind::Scalar(t) => (offset(k), t),
        Kind::List { .. } => (0, Ty::U8), // excluded by the header checks
    })
}

fn read_vertices<O: Order>(
    b: &[u8],
    start: usize,
    el: &ElementDef,
    xyz: [usize; 3],
    raw: &mut RawMesh,
    path: &Path,
) -> Result<usize> {
    let n = el.count as usize;
    if let Some(stride) = el.fixed_stride() {
        let end = skip_element::<O>(b, start, el, path)?;
        let [(ox, tx), (oy, ty), (oz, tz)] = xyz_layout(el, xyz);
        raw.positions = Vec::with_capacity(n);
        if stride == 24 && [ox, oy, oz] == [0, 8, 16] && [tx, ty, tz] == [Ty::F64; 3] {
            // The layout katachi and most tools write: three doubles.
            raw.positions
                .extend(b[start..end].chunks_exact(24).map(|r| {
                    DVec3::new(
                        f64::from_bits(O::u64(arr(r, 0))),
                        f64::from_bits(O::u64(arr(r, 8))),
                        f64::from_bits(O::u64(arr(r, 16))),
                    )
                }));
        } else if stride == 12 && [ox, oy, oz] == [0, 4, 8] && [tx, ty, tz] == [Ty::F32; 3] {
            raw.positions
                .extend(b[start..end].chunks_exact(12).map(|r| {
                    DVec3::new(
                        f32::from_bits(O::u32(arr(r, 0))) as f64,
                        f32::from_bits(O::u32(arr(r, 4))) as f64,
                        f32::from_bits(O::u32(arr(r, 8))) as f64,
                    )
                }));
        } else {
            raw.positions
                .extend(b[start..end].chunks_exact(stride.max(1)).take(n).map(|r| {
                    DVec3::new(
                        read_f64::<O>(r, ox, tx),
                        read_f64::<O>(r, oy, ty),
                        read_f64::<O>(r, oz, tz),
                    )
                }));
            // A record of zero bytes cannot exist: x, y and z take at least 3.
        }
        return Ok(end);
    }
    // Records with lists: walk them one by one.
    raw.positions = Vec::with_capacity(n.min(b.len().saturating_sub(start) / 3));
    let mut p = start;
    for r in 0..el.count {
        let len = record_len::<O>(b, p, &el.props)
            .map_err(|e| record_error(path, el, r, p, b.len(), e))?;
        let mut c = [0.0; 3];
        let mut q = p;
        for (k, prop) in el.props.iter().enumerate() {
            match prop.kind {
                Kind::Scalar(t) => {
                    if let Some(axis) = xyz.iter().position(|&i| i == k) {
                        c[axis] = read_f64::<O>(b, q, t);
                    }
                    q += t.size();
                }
                Kind::List { count, item } => {
                    let m = read_int::<O>(b, q, count) as usize;
                    q += count.size() + m * item.size();
                }
            }
        }
        raw.positions.push(DVec3::from_array(c));
        p += len;
    }
    Ok(p)
}

fn read_faces<O: Order>(
    b: &[u8],
    start: usize,
    el: &ElementDef,
    indices: usize,
    raw: &mut RawMesh,
    path: &Path,
) -> Result<usize> {
    let avail = b.len() - start;
    let n = (el.count as usize).min(avail);
    raw.loop_offsets.reserve(n);
    let negative = |r: u64, at: usize, i: i64| {
        at_byte(
            path,
            at as u64,
            format!("face {r}: vertex index {i} is negative"),
        )
    };
    let mut p = start;
    if let [Property {
        kind:
            Kind::List {
                count: Ty::U8,
                item: item @ (Ty::I32 | Ty::U32),
            },
        ..
    }] = el.props[..]
    {
        // The common layout (`list uchar int vertex_indices` and nothing else).
        raw.corners.reserve(avail / 4);
        let signed = item == Ty::I32;
        for r in 0..el.count {
            let Some(&m) = b.get(p) else {
                return Err(record_error(
                    path,
                    el,
                    r,
                    p,
                    b.len(),
                    RecordError::Truncated,
                ));
            };
            let end = p + 1 + 4 * m as usize;
            if end > b.len() {
                return Err(record_error(
                    path,
                    el,
                    r,
                    p,
                    b.len(),
                    RecordError::Truncated,
                ));
            }
            let first = raw.corners.len();
            raw.corners.extend(
                b[p + 1..end]
                    .chunks_exact(4)
                    .map(|c| VertexId(O::u32(arr(c, 0)))),
            );
            if signed {
                if let Some(v) = raw.corners[first..].iter().find(|v| (v.0 as i32) < 0) {
                    return Err(negative(r, p, v.0 as i32 as i64));
                }
            }
            raw.end_face().map_err(|m| at_byte(path, p as u64, m))?;
            p = end;
        }
        return Ok(p);
    }
    raw.corners.reserve((n * 3).min(avail));
    for r in 0..el.count {
        let len = record_len::<O>(b, p, &el.props)
            .map_err(|e| record_error(path, el, r, p, b.len(), e))?;
        let mut q = p;
        for (k, prop) in el.props.iter().enumerate() {
            match prop.kind {
                Kind::Scalar(t) => q += t.size(),
                Kind::List { count, item } => {
                    let m = read_int::<O>(b, q, count) as usize;
                    q += count.size();
                    if k == indices {
                        for j in 0..m {
                            let i = read_int::<O>(b, q + j * item.size(), item);
                            if i < 0 {
                                return Err(negative(r, p, i));
                            }
                            // Values ≥ 2^32 - 1 are out of range for any mesh; validation
                            // reports them with this face's offset.
                            raw.corners.push(VertexId(i.min(u32::MAX as i64) as u32));
                        }
                    }
                    q += m * item.size();
                }
            }
        }
        raw.end_face().map_err(|m| at_byte(path, p as u64, m))?;
        p += len;
    }
    Ok(p)
}

// ---------------------------------------------------------------------------------------
// Writing

/// Writes `mesh` as PLY to any writer, in the given encoding: `double` x, y, z and a
/// `vertex_indices` list per face. A face with holes is refused
/// ([`crate::Error::InvalidArgument`]) before anything is written.
pub fn write_to<W: Write>(w: W, mesh: &PolyMesh, encoding: PlyEncoding) -> Result<()> {
    write_impl(w, mesh, encoding, Path::new(WRITER_PATH))
}

pub(crate) fn write_impl<W: Write>(
    w: W,
    mesh: &PolyMesh,
    encoding: PlyEncoding,
    path: &Path,
) -> Result<()> {
    reject_holes(mesh, Format::Ply)?;
    let mut w = BufWriter::with_capacity(1 << 16, w);
    write_body(&mut w, mesh, encoding).map_err(io_error(path))?;
    w.flush().map_err(io_error(path))
}

fn write_body<W: Write>(w: &mut W, mesh: &PolyMesh, encoding: PlyEncoding) -> std::io::Result<()> {
    let max_size = mesh
        .loop_offsets()
        .windows(2)
        .map(|w| w[1] - w[0])
        .max()
        .unwrap_or(0);
    let count_ty = if max_size <= u8::MAX as u32 {
        "uchar"
    } else {
        "uint"
    };
    let index_ty = if mesh.vertex_count() <= i32::MAX as u32 {
        "int"
    } else {
        "uint"
    };
    write!(
        w,
        "ply\nformat {} 1.0\ncomment written by katachi\n\
         element vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
         element face {}\nproperty list {count_ty} {index_ty} vertex_indices\nend_header\n",
        encoding.header_name(),
        mesh.vertex_count(),
        mesh.face_count()
    )?;
    let big = encoding == PlyEncoding::BinaryBigEndian;
    let u32b = |v: u32| {
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    match encoding {
        PlyEncoding::Ascii => {
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
        }
        PlyEncoding::BinaryLittleEndian | PlyEncoding::BinaryBigEndian => {
            let mut buf = Vec::with_capacity(1 << 16);
            for p in mesh.positions() {
                for c in [p.x, p.y, p.z] {
                    let bits = c.to_bits();
                    buf.extend_from_slice(&if big {
                        bits.to_be_bytes()
                    } else {
                        bits.to_le_bytes()
                    });
                }
                if buf.len() >= 1 << 16 {
                    w.write_all(&buf)?;
                    buf.clear();
                }
            }
            for f in mesh.faces() {
                let lp = mesh.face_outer(f);
                if count_ty == "uchar" {
                    buf.push(lp.len() as u8);
                } else {
                    buf.extend_from_slice(&u32b(lp.len() as u32));
                }
                for v in lp {
                    buf.extend_from_slice(&u32b(v.0));
                }
                if buf.len() >= 1 << 16 {
                    w.write_all(&buf)?;
                    buf.clear();
                }
            }
            w.write_all(&buf)?;
        }
    }
    Ok(())
}
