//! Pass 2 of [`super::grid`] sixteen faces at a time with AVX-512, on CPUs that have
//! it (detected at run time; the face-by-face loop otherwise): the block test on every block
//! ([`block_not_away`]: the scalar fold is bound by its instructions, 48 loads and some 150
//! more a block), and the faces of the "near" blocks (with a corner near the stroke's band,
//! about one block in twenty).
//!
//! Each lane decides what the face-by-face loop decides from the three corner codes alone:
//! rejected by the block test or by [`far_for_span`], kept outright (a corner in a marked
//! cell, or straddling the eye plane), or left for the scan of its cell box, which stays
//! scalar (a few faces a block). The same integer tests on the same codes, so the same faces
//! (unit test `simd_near_blocks_match_the_face_loop`). Written by hand: face by face, the
//! near blocks' faces go through unpredictable branches. The kept lanes are appended
//! compressed ([`append`]), and the whole run of blocks is one function ([`scan_blocks`]) so
//! that all of this is inlined.
//!
//! [`far_for_span`]: super::grid

use std::arch::x86_64::*;

use super::grid::{
    cell_box, prefetch_blocks_ahead, CellGrid, Kept, BEHIND, BLOCK, CLOSE, CLOSE_RING, MARKED, MID,
    MID_RING, NEAR, NEAR_RING,
};

/// Lanes of a near block: `keep`, the faces kept from their codes; `scan`, those whose cell
/// box must be scanned for a marked cell; `straddles`, the faces with one or two corners
/// behind the eye (in `keep` too). Bit i is face i of the block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Lanes {
    pub keep: u16,
    pub scan: u16,
    pub straddles: u16,
}

/// The codes of the three corners of a block's 16 faces, lane i for face i ([`gather`]):
/// what the block test and the near blocks' classifier both read; and the corners' vertex
/// ids, lane by lane, for the kept faces.
#[derive(Clone, Copy)]
pub(crate) struct Corners {
    codes: [__m512i; 3],
    ids: [__m512i; 3],
}

/// Whether some face of the block is not surely away from the marked cells (the block
/// test's [`not_away`](super::grid) on all 16 faces at once): a few lane operations on
/// three gathers, where the face-by-face fold takes 48 loads and some 150 instructions.
///
/// # Safety
/// The CPU has AVX-512 F.
#[target_feature(enable = "avx512f")]
#[inline]
pub(crate) unsafe fn block_not_away(c: &Corners) -> bool {
    let [c0, c1, c2] = c.codes;
    not_away(c0, c1, c2) != 0
}

/// The block test's `not_away`, lane by lane, on the corners' codes.
#[target_feature(enable = "avx512f")]
#[inline]
fn not_away(c0: __m512i, c1: __m512i, c2: __m512i) -> u16 {
    let set = |v: u32| _mm512_set1_epi32(v as i32);
    let origin = _mm512_sub_epi32(c0, set(NEAR_RING | NEAR_RING << 16));
    let spread = _mm512_or_si512(_mm512_sub_epi32(c1, origin), _mm512_sub_epi32(c2, origin));
    let any = _mm512_or_si512(c0, _mm512_or_si512(c1, c2));
    _mm512_test_epi32_mask(spread, set(0xfff8_fff8)) | _mm512_test_epi32_mask(any, set(1 << 31))
}

/// The corners' codes of the 16 faces whose corners are `block` (vertex ids, three a face).
///
/// # Safety
/// The CPU has AVX-512 F; every id in `block` is below `codes.len()`, which is at most
/// `i32::MAX` (the gathers' offsets are signed).
#[target_feature(enable = "avx512f")]
#[inline]
pub(crate) unsafe fn gather(block: &[u32; 48], codes: &[u32]) -> Corners {
    debug_assert!(codes.len() <= i32::MAX as usize);
    debug_assert!(block.iter().all(|&v| (v as usize) < codes.len()));
    let lanes = |a: [i32; 16]| {
        _mm512_setr_epi32(
            a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8], a[9], a[10], a[11], a[12], a[13],
            a[14], a[15],
        )
    };
    // Corner k of face i is id 3i + k: from the first two loads (0..32), then the third
    // (16 + j picks its j-th).
    let (a0, a1, a2) = (
        lanes([0, 3, 6, 9, 12, 15, 18, 21, 24, 27, 30, 0, 0, 0, 0, 0]),
        lanes([1, 4, 7, 10, 13, 16, 19, 22, 25, 28, 31, 0, 0, 0, 0, 0]),
        lanes([2, 5, 8, 11, 14, 17, 20, 23, 26, 29, 0, 0, 0, 0, 0, 0]),
    );
    let (b0, b1, b2) = (
        lanes([0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 17, 20, 23, 26, 29]),
        lanes([0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 18, 21, 24, 27, 30]),
        lanes([0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 16, 19, 22, 25, 28, 31]),
    );
    let p = block.as_ptr() as *const __m512i;
    let (u, v, w) = (
        _mm512_loadu_si512(p),
        _mm512_loadu_si512(p.add(1)),
        _mm512_loadu_si512(p.add(2)),
    );
    let ids = |a, b| _mm512_permutex2var_epi32(_mm512_permutex2var_epi32(u, a, v), b, w);
    let base = codes.as_ptr() as *const i32;
    let ids = [ids(a0, b0), ids(a1, b1), ids(a2, b2)];
    Corners {
        codes: ids.map(|ix| _mm512_i32gather_epi32::<4>(ix, base)),
        ids,
    }
}

/// Classifies a block's 16 faces from their corners' codes ([`gather`]).
///
/// # Safety
/// The CPU has AVX-512 F.
#[target_feature(enable = "avx512f")]
#[inline]
pub(crate) unsafe fn near_block(c: &Corners) -> Lanes {
    let set = |v: u32| _mm512_set1_epi32(v as i32);
    let [c0, c1, c2] = c.codes;

    let not_away = not_away(c0, c1, c2);
    let any = _mm512_or_si512(c0, _mm512_or_si512(c1, c2));
    // Corners behind the eye.
    let behind = |c| _mm512_cmpeq_epi32_mask(c, set(BEHIND));
    let (h0, h1, h2) = (behind(c0), behind(c1), behind(c2));
    let some_behind = h0 | h1 | h2;
    let straddles = some_behind & !(h0 & h1 & h2);
    // `any_marked` up to its scan: a corner in a marked cell, else `far_for_span`.
    let flag = |c, f: u8| _mm512_test_epi32_mask(c, set((f as u32) << 24));
    let marked = flag(any, MARKED);
    let all = _mm512_and_si512(c0, _mm512_and_si512(c1, c2));
    let lo = |x, y, z| _mm512_min_epu32(x, _mm512_min_epu32(y, z));
    let hi = |x, y, z| _mm512_max_epu32(x, _mm512_max_epu32(y, z));
    let (mx, my) = (set(0xffff), set(0xfff));
    let xs = [c0, c1, c2].map(|c| _mm512_and_si512(c, mx));
    let ys = [c0, c1, c2].map(|c| _mm512_and_si512(_mm512_srli_epi32::<16>(c), my));
    let span = _mm512_max_epu32(
        _mm512_sub_epi32(hi(xs[0], xs[1], xs[2]), lo(xs[0], xs[1], xs[2])),
        _mm512_sub_epi32(hi(ys[0], ys[1], ys[2]), lo(ys[0], ys[1], ys[2])),
    );
    let within = |r: u32| _mm512_cmple_epu32_mask(span, set(r));
    let far = (!flag(all, NEAR) & within(NEAR_RING))
        | (!flag(all, MID) & within(MID_RING))
        | (!flag(all, CLOSE) & within(CLOSE_RING));
    let open = not_away & !some_behind;
    Lanes {
        keep: (open & marked) | straddles,
        scan: open & !marked & !far,
        straddles,
    }
}

/// Pass 2 ([`candidate_faces`]) over the whole blocks of `ids` (three corners a face, the
/// first face being `base`): each kept face and its corners appended to `keep`, and to
/// `clipped` if it straddles the eye plane, in face order. Returns how many faces it did (the
/// caller does the rest). One function for the whole run, so that the block test and the
/// classifier are inlined into the loop (called per block, they pass their vectors through
/// memory).
///
/// [`candidate_faces`]: super::grid::candidate_faces
///
/// # Safety
/// The CPU has AVX-512 F; every id is below `codes.len()`, which is at most `i32::MAX`.
#[target_feature(enable = "avx512f")]
pub(crate) unsafe fn scan_blocks(
    ids: &[u32],
    codes: &[u32],
    grid: &CellGrid,
    base: u32,
    keep: &mut Kept,
    clipped: &mut Vec<u32>,
) -> usize {
    let blocks = ids.len() / (3 * BLOCK);
    for (bi, b) in ids.as_chunks::<{ 3 * BLOCK }>().0.iter().enumerate() {
        prefetch_blocks_ahead(b.as_ptr());
        // SAFETY: the caller's guarantees.
        let corners = unsafe { gather(b, codes) };
        if !unsafe { block_not_away(&corners) } {
            continue;
        }
        keep.reserve_first();
        let lanes = unsafe { near_block(&corners) };
        // The lanes did `any_marked`'s tests up to its scan of the cell box.
        let mut kept = lanes.keep;
        let mut scan = lanes.scan;
        while scan != 0 {
            let i = scan.trailing_zeros() as usize;
            scan &= scan - 1;
            // SAFETY: the caller's guarantees (ids name codes).
            let code = |k: usize| unsafe { *codes.get_unchecked(b[3 * i + k] as usize) };
            if grid.box_marked(cell_box([code(0), code(1), code(2)])) {
                kept |= 1 << i;
            }
        }
        let first = base + (bi * BLOCK) as u32;
        append(&corners, kept, first, keep);
        let mut straddles = lanes.straddles;
        while straddles != 0 {
            clipped.push(first + straddles.trailing_zeros());
            straddles &= straddles - 1;
        }
    }
    blocks * BLOCK
}

/// Lane `l` of output vector `m` of the interleaving of three lane vectors into 48 values
/// (corner k of face f at 3f + k): stage 1 picks corners 0 and 1 from the first two
/// vectors, stage 2 keeps those and picks corner 2 from the third.
const fn interleave(m: usize, stage: usize) -> [i32; 16] {
    let mut out = [0i32; 16];
    let mut l = 0;
    while l < 16 {
        let e = 16 * m + l;
        let (f, k) = ((e / 3) as i32, e % 3);
        out[l] = match (stage, k) {
            (1, 0) => f,
            (1, 1) => 16 + f,
            (1, _) => 0,
            (_, 2) => 16 + f,
            _ => l as i32,
        };
        l += 1;
    }
    out
}

/// Appends the faces of lanes `mask` of a block whose first face is `first` to `keep`, in
/// lane order: compressed, without a branch per face.
#[target_feature(enable = "avx512f")]
#[inline]
fn append(c: &Corners, mask: u16, first: u32, keep: &mut Kept) {
    if mask == 0 {
        return;
    }
    let n = mask.count_ones() as usize;
    keep.faces.reserve(BLOCK);
    keep.corners.reserve(BLOCK);
    let iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    let faces = _mm512_add_epi32(_mm512_set1_epi32(first as i32), iota);
    let len = keep.faces.len();
    // SAFETY: room for BLOCK more was reserved; the first n are written.
    unsafe {
        let at = keep.faces.as_mut_ptr().add(len);
        _mm512_mask_compressstoreu_epi32(at.cast(), mask, faces);
        keep.faces.set_len(len + n);
    }
    let [x, y, z] = c.ids.map(|v| _mm512_maskz_compress_epi32(mask, v));
    let table = |a: &[i32; 16]| unsafe { _mm512_loadu_si512(a.as_ptr().cast()) };
    const STAGES: [[[i32; 16]; 2]; 3] = [
        [interleave(0, 1), interleave(0, 2)],
        [interleave(1, 1), interleave(1, 2)],
        [interleave(2, 1), interleave(2, 2)],
    ];
    let len = keep.corners.len();
    // SAFETY: room for BLOCK more corner triples (48 values) was reserved; the first n are
    // written.
    unsafe {
        let at = keep.corners.as_mut_ptr().add(len) as *mut __m512i;
        for (m, [s1, s2]) in STAGES.iter().enumerate() {
            let v =
                _mm512_permutex2var_epi32(_mm512_permutex2var_epi32(x, table(s1), y), table(s2), z);
            _mm512_storeu_si512(at.add(m), v);
        }
        keep.corners.set_len(len + n);
    }
}
