//! Numbering the region's vertices and edges: the plain definitions (a sort of every corner,
//! a sort of every face side) and the fast forms the cut runs on (a bitmap rank, edges found
//! vertex by vertex on two threads), which give the same numbers.

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use super::radix::small_sort;
use crate::cut::ids::{Le, Lf, Lv};
use crate::error::{Error, Result};

/// A region's edge table: each face's edge per corner (corner i → i + 1), each edge's ends
/// (ascending) and its one or two faces (ascending, [`Lf::NONE`] for a missing second).
pub(crate) type EdgeTable = (Vec<[Le; 3]>, Vec<[Lv; 2]>, Vec<[Lf; 2]>);

/// The local edges of faces `tri`, numbered in order of (smaller end, larger end); an edge
/// used by more than two faces, or by two running the same way, is an error naming its
/// global vertices (`verts`), the first such edge in that order. The definition: every face
/// side sorted by its ends, then by the corner it starts at.
pub(crate) fn edge_table_plain(tri: &[[Lv; 3]], verts: &[u32]) -> Result<EdgeTable> {
    // (smaller end, larger end, 3 · face + corner it starts at, whether it starts at the
    // larger end)
    let mut sides: Vec<(u32, u32, u32, bool)> = Vec::with_capacity(3 * tri.len());
    for (f, t) in tri.iter().enumerate() {
        for i in 0..3 {
            let (u, w) = (t[i].0, t[(i + 1) % 3].0);
            if u != w {
                sides.push((u.min(w), u.max(w), 3 * f as u32 + i as u32, u > w));
            }
        }
    }
    sides.sort_unstable();
    let mut face_edges = vec![[Le::NONE; 3]; tri.len()];
    let (mut edges, mut edge_faces) = (Vec::new(), Vec::new());
    for run in sides.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
        let (ga, gb) = (verts[run[0].0 as usize], verts[run[0].1 as usize]);
        if run.len() > 2 {
            return Err(Error::NonManifoldEdge {
                a: ga,
                b: gb,
                uses: run.len() as u32,
            });
        }
        if run.len() == 2 && run[0].3 == run[1].3 {
            let (a, b) = if run[0].3 { (gb, ga) } else { (ga, gb) };
            return Err(Error::InconsistentOrientation { a, b });
        }
        let e = Le(edges.len() as u32);
        edges.push([Lv(run[0].0), Lv(run[0].1)]);
        let mut faces = [Lf::NONE; 2];
        for (k, side) in run.iter().enumerate() {
            faces[k] = Lf(side.2 / 3);
            face_edges[(side.2 / 3) as usize][(side.2 % 3) as usize] = e;
        }
        edge_faces.push(faces);
    }
    Ok((face_edges, edges, edge_faces))
}

/// [`edge_table_plain`]'s table, found vertex by vertex from the corners around each
/// (`vf_start`, `vf_corner`: CSR, beside each face around a vertex its corner there,
/// 3 · face + corner): each side is listed at its smaller end and the few there sorted in
/// place. The vertices are cut in two halves, whose edges are found on two threads and
/// numbered after each other.
pub(crate) fn edge_table(
    tri: &[[Lv; 3]],
    verts: &[u32],
    vf_start: &[u32],
    vf_corner: &[u32],
) -> Result<EdgeTable> {
    const HIGH: u32 = 1 << 31;
    const NONE: u32 = u32::MAX;
    let flat = raw(tri);
    let corner_edge: Vec<AtomicU32> = (0..3 * tri.len()).map(|_| AtomicU32::new(NONE)).collect();
    let nv = verts.len() as u32;
    let mid = nv / 2;
    let (lo, hi) = rayon::join(
        || edge_rows(flat, verts, vf_start, vf_corner, 0..mid, &corner_edge, 0),
        || {
            edge_rows(
                flat,
                verts,
                vf_start,
                vf_corner,
                mid..nv,
                &corner_edge,
                HIGH,
            )
        },
    );
    let (mut edges, mut edge_faces) = lo?;
    let (e2, ef2) = hi?;
    let offset = edges.len() as u32;
    edges.extend_from_slice(&e2);
    edge_faces.extend_from_slice(&ef2);
    let face_edges = corner_edge
        .chunks_exact(3)
        .map(|c| {
            [0, 1, 2].map(|i| {
                let e = c[i].load(Relaxed);
                Le(if e != NONE && e & HIGH != 0 {
                    (e & !HIGH) + offset
                } else {
                    e
                })
            })
        })
        .collect();
    Ok((face_edges, edges, edge_faces))
}

/// The edges whose smaller end is one of the vertices `rows`, numbered from 0, each
/// corner's edge stored in `corner_edge[3·face + corner]` with `tag` or-ed in.
#[allow(clippy::type_complexity)]
fn edge_rows(
    flat: &[u32],
    verts: &[u32],
    vf_start: &[u32],
    vf_corner: &[u32],
    rows: std::ops::Range<u32>,
    corner_edge: &[AtomicU32],
    tag: u32,
) -> Result<(Vec<[Lv; 2]>, Vec<[Lf; 2]>)> {
    let n = rows.len();
    let mut edges = Vec::with_capacity(n * 3 + 16);
    let mut edge_faces = Vec::with_capacity(n * 3 + 16);
    // (neighbour, corner, kind) packed as neighbour · 2³² + corner · 2 + kind, the kind
    // telling which end of the edge the corner is at: 0 at `a` (the side to the next
    // corner), 1 at the neighbour (the side from the previous corner).
    debug_assert!(flat.len() < 3 << 30, "corners fit in 31 bits");
    let mut at: Vec<u64> = Vec::with_capacity(32);
    for a in rows {
        let corners = &vf_corner[vf_start[a as usize] as usize..vf_start[a as usize + 1] as usize];
        at.clear();
        at.resize(2 * corners.len(), 0);
        // Each side written, the count advanced when `a` is its smaller end.
        let mut n = 0;
        for &k in corners {
            let (f, c) = (k / 3, k % 3);
            let (cn, cp) = (
                if c == 2 { 0 } else { c + 1 },
                if c == 0 { 2 } else { c - 1 },
            );
            let (next, prev) = (flat[(3 * f + cn) as usize], flat[(3 * f + cp) as usize]);
            at[n] = (next as u64) << 32 | (k as u64) << 1;
            n += (next > a) as usize;
            at[n] = (prev as u64) << 32 | ((3 * f + cp) as u64) << 1 | 1;
            n += (prev > a) as usize;
        }
        at.truncate(n);
        small_sort(&mut at);
        let mut i = 0;
        while i < at.len() {
            let b = (at[i] >> 32) as u32;
            let mut j = i + 1;
            while j < at.len() && (at[j] >> 32) as u32 == b {
                j += 1;
            }
            let global = || (verts[a as usize], verts[b as usize]);
            if j - i > 2 {
                let (ga, gb) = global();
                return Err(Error::NonManifoldEdge {
                    a: ga,
                    b: gb,
                    uses: (j - i) as u32,
                });
            }
            let corner_of = |k: usize| at[k] as u32 >> 1;
            if j - i == 2 && (at[i] ^ at[i + 1]) & 1 == 0 {
                let (ga, gb) = global();
                let (fa, fb) = if at[i] & 1 == 0 { (ga, gb) } else { (gb, ga) };
                return Err(Error::InconsistentOrientation { a: fa, b: fb });
            }
            let e = edges.len() as u32;
            debug_assert!(e & tag == 0, "an edge number reaches the tag bit");
            edges.push([Lv(a), Lv(b)]);
            let mut ef = [Lf::NONE; 2];
            for k in i..j {
                corner_edge[corner_of(k) as usize].store(e | tag, Relaxed);
                ef[k - i] = Lf(corner_of(k) / 3);
            }
            edge_faces.push(ef);
            i = j;
        }
    }
    Ok((edges, edge_faces))
}

/// Faces' corners as plain ids.
fn raw(tri: &[[Lv; 3]]) -> &[u32] {
    // SAFETY: `Lv` is a transparent `u32`, so `[[Lv; 3]]` is laid out as `3 · len` u32s.
    unsafe { std::slice::from_raw_parts(tri.as_ptr().cast(), 3 * tri.len()) }
}

/// [`super::Machinery::local_ids`] through a bitmap over the mesh's `nv` vertices: a
/// vertex's local id is the number of marked vertices below it (a prefix count per 64-bit
/// word plus a popcount).
pub(crate) fn local_ids(corners: Vec<[u32; 3]>, nv: usize) -> (Vec<u32>, Vec<[u32; 3]>) {
    let mut tri = corners;
    let mut bits = vec![0u64; nv.div_ceil(64)];
    // Four quarters of the corners interleaved, so consecutive marks of one word do not
    // wait for each other.
    let flat = tri.as_flattened();
    let q = flat.len() / 4;
    let mut mark = |v: u32| bits[(v >> 6) as usize] |= 1 << (v & 63);
    for i in 0..q {
        mark(flat[i]);
        mark(flat[q + i]);
        mark(flat[2 * q + i]);
        mark(flat[3 * q + i]);
    }
    for &v in &flat[4 * q..] {
        mark(v);
    }
    let mut below = Vec::with_capacity(bits.len());
    let mut verts = Vec::with_capacity(flat.len() / 2);
    for (w, &word) in bits.iter().enumerate() {
        below.push(verts.len() as u32);
        let mut x = word;
        while x != 0 {
            verts.push((w as u32) << 6 | x.trailing_zeros());
            x &= x - 1;
        }
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("popcnt") {
        // SAFETY: the CPU has POPCNT.
        unsafe { rank_popcnt(tri.as_flattened_mut(), &bits, &below) };
        return (verts, tri);
    }
    rank(tri.as_flattened_mut(), &bits, &below);
    (verts, tri)
}

/// Global ids to ranks among the marked bits ([`local_ids`]).
#[inline(always)]
fn rank(ids: &mut [u32], bits: &[u64], below: &[u32]) {
    for v in ids {
        let w = (*v >> 6) as usize;
        *v = below[w] + (bits[w] & ((1u64 << (*v & 63)) - 1)).count_ones();
    }
}

/// [`rank`] with the POPCNT instruction, which the baseline x86-64 target lacks.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "popcnt")]
unsafe fn rank_popcnt(ids: &mut [u32], bits: &[u64], below: &[u32]) {
    rank(ids, bits, below)
}
