//! Byte-level mutations of valid OBJ, PLY and OFF files, for fuzzing the readers in the
//! project's own tests (`tests/fuzz_readers.rs` through the library, `cli/tests/fuzz.rs`
//! through the `katachi` binary). Deterministic: case `i` of a format is a function of the
//! seed (`KATACHI_FUZZ_SEED`, default 0) and `i`, so a failure names what reproduces it.
//! `KATACHI_FUZZ_CASES` (set by `cargo xtask test --fuzz-cases N`) sets how many cases per
//! format; the default keeps `cargo xtask test` short.

use std::path::Path;

use katachi::io::{self, Format, PlyEncoding, WriteOptions};
use katachi::mesh::shapes;
use katachi::VertexId;

/// Cases per format: `KATACHI_FUZZ_CASES`, else `default`.
pub fn cases(default: u32) -> u32 {
    match std::env::var("KATACHI_FUZZ_CASES") {
        Ok(v) => v
            .parse()
            .unwrap_or_else(|_| panic!("KATACHI_FUZZ_CASES={v} is not a count")),
        Err(_) => default,
    }
}

/// The base seed: `KATACHI_FUZZ_SEED`, else 0.
pub fn seed() -> u64 {
    std::env::var("KATACHI_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0)
}

/// SplitMix64: small, fast, and the same on every machine.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64, format: Format, case: u32) -> Rng {
        Rng(seed ^ ((format as u64) << 56) ^ (case as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15))
    }
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `0..n` (`n` > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Tokens that stress a reader: counts and indices at and past the limits, numbers that do
/// not fit, non-finite values, control characters and terminal escapes, line breaks, and
/// header words in the wrong place.
const INTERESTING: &[&[u8]] = &[
    b"-1",
    b"0",
    b"3",
    b"4294967295",
    b"4294967296",
    b"18446744073709551616",
    b"99999999999999999999999",
    b"1e309",
    b"-1e309",
    b"nan",
    b"inf",
    b"1e-400",
    b"0x10",
    b"\x1b[31m",
    b"\x1b]0;title\x07",
    b"\0",
    b"\n",
    b"\r\n",
    b"\r",
    b"\t",
    b" ",
    b"/",
    b"//",
    b"\xff\xfe",
    b"element face 1\n",
    b"property list uchar int vertex_indices\n",
    b"property list uint uint vertex_indices\n",
    b"end_header\n",
    b"format binary_big_endian 1.0\n",
    b"f 1 2 3\n",
    b"f -1 -2 -3\n",
    b"t crease 2/1/0 1 2 10\n",
    b"OFF\n",
    b"COFF\n",
];

/// `bytes` after one to eight random edits.
pub fn mutate(rng: &mut Rng, mut bytes: Vec<u8>) -> Vec<u8> {
    let edits = 1 + rng.below(8);
    for _ in 0..edits {
        let len = bytes.len();
        let at = if len == 0 { 0 } else { rng.below(len + 1) };
        match rng.below(9) {
            0 if len > 0 => {
                let i = rng.below(len);
                bytes[i] = rng.next() as u8;
            }
            1 if len > 0 => {
                let i = rng.below(len);
                bytes[i] ^= 1 << rng.below(8);
            }
            2 if len > 0 => {
                let i = rng.below(len);
                let n = (1 + rng.below(16)).min(len - i);
                bytes.drain(i..i + n);
            }
            3 => {
                let n = 1 + rng.below(8);
                let new: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
                bytes.splice(at..at, new);
            }
            4 => {
                let t = INTERESTING[rng.below(INTERESTING.len())];
                bytes.splice(at..at, t.iter().copied());
            }
            5 if len > 0 => {
                // A chunk copied elsewhere: repeated records, headers or lines.
                let i = rng.below(len);
                let n = (1 + rng.below(64)).min(len - i);
                let chunk = bytes[i..i + n].to_vec();
                let to = rng.below(bytes.len() + 1);
                bytes.splice(to..to, chunk);
            }
            6 if len > 0 => bytes.truncate(rng.below(len)),
            7 => {
                // A number replaced by an interesting token.
                let starts: Vec<usize> = (0..len)
                    .filter(|&i| {
                        bytes[i].is_ascii_digit() && (i == 0 || !bytes[i - 1].is_ascii_digit())
                    })
                    .collect();
                if !starts.is_empty() {
                    let s = starts[rng.below(starts.len())];
                    let e = (s..len)
                        .find(|&i| !bytes[i].is_ascii_digit())
                        .unwrap_or(len);
                    let t = INTERESTING[rng.below(INTERESTING.len())];
                    bytes.splice(s..e, t.iter().copied());
                }
            }
            _ => {
                // Two lines swapped.
                let lines: Vec<usize> = std::iter::once(0)
                    .chain((0..len).filter(|&i| bytes[i] == b'\n').map(|i| i + 1))
                    .filter(|&i| i < len)
                    .collect();
                if lines.len() >= 2 {
                    let a = lines[rng.below(lines.len())];
                    let b = lines[rng.below(lines.len())];
                    let end =
                        |s: usize| (s..len).find(|&i| bytes[i] == b'\n').map_or(len, |i| i + 1);
                    let (a, b) = (a.min(b), a.max(b));
                    let (ae, be) = (end(a), end(b));
                    if ae <= b {
                        let mut out = bytes[..a].to_vec();
                        out.extend_from_slice(&bytes[b..be]);
                        out.extend_from_slice(&bytes[ae..b]);
                        out.extend_from_slice(&bytes[a..ae]);
                        out.extend_from_slice(&bytes[be..]);
                        bytes = out;
                    }
                }
            }
        }
    }
    bytes
}

/// Valid files of each format to mutate: bundled models, katachi's own output in every
/// encoding (with sharpness tags), and hand-written files using what the readers skip or
/// accept besides (texture and normal indices, negative indices, extra PLY elements and
/// properties, OFF's colour variants).
pub fn seeds() -> Vec<(Format, &'static str, Vec<u8>)> {
    let bundled = |name: &str| {
        std::fs::read(super::models::bundled(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
    };
    let mut creased = shapes::cube(2.0).unwrap();
    creased
        .set_edge_sharpness(VertexId(0), VertexId(1), 2.5)
        .unwrap();
    creased.set_vertex_sharpness(VertexId(7), 10.0).unwrap();
    let plate = katachi::mesh::holes::split_faces_with_holes(
        &shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap(),
    )
    .unwrap()
    .0;
    let written = |format: Format, enc: PlyEncoding, mesh: &katachi::PolyMesh| {
        let mut buf = Vec::new();
        io::write_to(
            &mut buf,
            format,
            mesh,
            &WriteOptions::with_ply_encoding(enc),
        )
        .unwrap();
        buf
    };
    let mut v = vec![
        (Format::Obj, "rhombicosidodecahedron.obj", bundled("rhombicosidodecahedron.obj")),
        (Format::Obj, "creased cube", written(Format::Obj, PlyEncoding::Ascii, &creased)),
        (
            Format::Obj,
            "hand-written OBJ",
            b"# comment\no cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\nvt 0 0\nvt 1 0\nvn 0 0 1\n\
              g top\nusemtl m\ns off\nf 1/1/1 2/2/1 3//1 4\nf -4 -2 -3\nl 1 2\nt crease 2/1/0 1 2 3.5\n\
              t corner 1/1/0 3 10\n"
                .to_vec(),
        ),
        (Format::Off, "L.off", bundled("L.off")),
        (Format::Off, "chamfer-cube.off", bundled("chamfer-cube.off")),
        (Format::Off, "plate", written(Format::Off, PlyEncoding::Ascii, &plate)),
        (
            Format::Off,
            "hand-written COFF",
            b"COFF\n# comment\n4 2 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n\
              0 1 0 9 9 9 255\n3 0 1 2 1 0 0\n3 0 2 3\n"
                .to_vec(),
        ),
        (Format::Ply, "plate ascii", written(Format::Ply, PlyEncoding::Ascii, &plate)),
        (
            Format::Ply,
            "cube binary little-endian",
            written(Format::Ply, PlyEncoding::BinaryLittleEndian, &creased),
        ),
        (
            Format::Ply,
            "cube binary big-endian",
            written(Format::Ply, PlyEncoding::BinaryBigEndian, &creased),
        ),
        (
            Format::Ply,
            "hand-written PLY",
            b"ply\nformat ascii 1.0\ncomment made by hand\nobj_info x\nelement material 1\n\
              property list uchar float rgb\nelement vertex 4\nproperty float x\nproperty float y\n\
              property double z\nproperty uchar red\nproperty list uchar int junk\n\
              element face 2\nproperty list uchar uint vertex_indices\nproperty float quality\n\
              end_header\n3 0.1 0.2 0.3\n0 0 0 9 0\n1 0 0 9 2 5 6\n1 1 0 9 1 7\n0 1 0 9 0\n\
              3 0 1 2 0.5\n3 0 2 3 0.25\n"
                .to_vec(),
        ),
    ];
    // Spot's first lines too: UVs, a material library, quads.
    let spot = bundled("spot_quadrangulated.obj");
    let cut = spot
        .iter()
        .enumerate()
        .filter(|&(_, &b)| b == b'\n')
        .nth(400)
        .map_or(spot.len(), |(i, _)| i + 1);
    v.push((Format::Obj, "spot (first 400 lines)", spot[..cut].to_vec()));
    for (format, name, bytes) in &v {
        io::read_bytes(bytes, *format, Path::new(name))
            .unwrap_or_else(|e| panic!("seed {name} does not read: {e}"));
    }
    v
}
