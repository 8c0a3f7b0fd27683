//! Pass 1 of [`super::grid`] (every vertex's grid code) four vertices at a time with AVX2, or
//! eight with AVX-512, on CPUs that have them (detected at run time; the portable loop
//! otherwise).
//!
//! The lanes do the same IEEE operations in the same order as [`CellGrid::code`] (products
//! and sums apart, no fused multiply-add; `max`/`min` that drop NaN the same way; truncating
//! conversions), so the codes are bit-identical whichever path runs (unit test
//! `simd_codes_match_the_portable_ones`) and the cut does not depend on the machine. Every
//! lane's table index is clamped into the table before it is read, whatever the point (NaN,
//! huge, behind the eye). Written by hand because the compiler vectorizes neither the
//! array-of-structs positions nor the table lookup.
//!
//! [`CellGrid::code`]: super::grid::CellGrid::code

use std::arch::x86_64::*;
use std::mem::MaybeUninit;

use glam::{DVec3, DVec4};

use super::grid::GridPlace;
use crate::cut::view::{ScreenRows, SCREEN_RANGE_PX};

/// How far ahead (in f64s: 4.5 KiB of positions) the passes ask for their input, which the
/// hardware's stream prefetch does not reach in time.
const AHEAD: usize = 576;

/// Asks for the `lines` cache lines from `p` on.
#[inline(always)]
fn ahead(p: *const f64, lines: usize) {
    for k in 0..lines {
        crate::mem::prefetch(p.wrapping_add(8 * k));
    }
}

/// Codes of `ps[..4k]` into `out[..4k]` (k = `ps.len() / 4`), returning 4k; the caller does
/// the rest with the portable code. `near` is the grid's table of near flags,
/// (nx + 2) × (ny + 2) and three bytes of padding.
///
/// # Safety
/// The CPU has AVX2; `out.len() >= ps.len()`; `near.len() == (nx + 2) * (ny + 2) + 3` for
/// `place`'s `nx` and `ny`.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn codes(
    view: &ScreenRows,
    place: &GridPlace,
    near: &[u8],
    ps: &[DVec3],
    out: &mut [MaybeUninit<u32>],
) -> usize {
    let (nx, ny) = (place.nx, place.ny);
    debug_assert!(out.len() >= ps.len());
    debug_assert_eq!(near.len(), ((nx + 2) * (ny + 2)) as usize + 3);
    let b = |v: f64| _mm256_set1_pd(v);
    let row = |r: DVec4| (b(r.x), b(r.y), b(r.z), b(r.w));
    let (rx, ry, rw) = (row(view.x), row(view.y), row(view.w));
    let (zero, one, inf) = (_mm256_setzero_pd(), b(1.0), b(f64::INFINITY));
    let (x0, y0, hw, hh) = (b(view.x0), b(view.y0), b(view.half_w), b(view.half_h));
    let (ox, oy, ic) = (b(place.origin.x), b(place.origin.y), b(place.inv_cell));
    let range = b(SCREEN_RANGE_PX);
    let sign = b(-0.0);
    let (hx, hy) = (b(nx as f64 + 1.0), b(ny as f64 + 1.0));
    let stride = _mm_set1_epi32(nx + 2);
    let ones = _mm_set1_epi32(-1);
    let n4 = ps.len() / 4;
    let src = ps.as_ptr() as *const f64;
    let dst = out.as_mut_ptr() as *mut __m128i;
    for i in 0..n4 {
        // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3 → x, y, z of the four.
        let p = src.add(12 * i);
        // A line and a half per step: two prefetches cover it wherever it starts.
        ahead(p.wrapping_add(AHEAD), 2);
        let (v0, v1, v2) = (
            _mm256_loadu_pd(p),
            _mm256_loadu_pd(p.add(4)),
            _mm256_loadu_pd(p.add(8)),
        );
        let xy = _mm256_permute2f128_pd::<0x30>(v0, v1); // x0 y0 x2 y2
        let zx = _mm256_permute2f128_pd::<0x21>(v0, v2); // z0 x1 z2 x3
        let yz = _mm256_permute2f128_pd::<0x30>(v1, v2); // y1 z1 y3 z3
        let x = _mm256_blend_pd::<0b1010>(xy, zx);
        let y = _mm256_shuffle_pd::<0b0101>(xy, yz);
        let z = _mm256_blend_pd::<0b1010>(zx, yz);
        // ((a.x·x + a.y·y) + a.z·z) + a.w, as glam's `DVec4::dot` with w = 1.
        let dot = |a: (__m256d, __m256d, __m256d, __m256d)| {
            _mm256_add_pd(
                _mm256_add_pd(
                    _mm256_add_pd(_mm256_mul_pd(a.0, x), _mm256_mul_pd(a.1, y)),
                    _mm256_mul_pd(a.2, z),
                ),
                a.3,
            )
        };
        let w = dot(rw);
        let front = _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_GT_OQ>(w, zero),
            _mm256_cmp_pd::<_CMP_LT_OQ>(w, inf),
        );
        let inv = _mm256_div_pd(one, w);
        // The screen point, as `Projector::screen_of`: x0 + (x/w + 1)·hw, y0 + (1 − y/w)·hh.
        let sx = _mm256_add_pd(
            x0,
            _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(dot(rx), inv), one), hw),
        );
        let sy = _mm256_add_pd(
            y0,
            _mm256_mul_pd(_mm256_sub_pd(one, _mm256_mul_pd(dot(ry), inv)), hh),
        );
        let within = |s: __m256d| _mm256_cmp_pd::<_CMP_LE_OQ>(_mm256_andnot_pd(sign, s), range);
        let seen = _mm256_castpd_si256(_mm256_and_pd(front, _mm256_and_pd(within(sx), within(sy))));
        // The cell plus one, clamped into [0, n + 1] (`max_pd(v, 0)` is 0 for NaN v, as
        // `f64::max`), so every lane's index is in the table.
        let cell = |s: __m256d, o: __m256d, h: __m256d| {
            let q = _mm256_add_pd(_mm256_mul_pd(_mm256_sub_pd(s, o), ic), one);
            _mm256_cvttpd_epi32(_mm256_min_pd(_mm256_max_pd(q, zero), h))
        };
        let (cx, cy) = (cell(sx, ox, hx), cell(sy, oy, hy));
        let at = _mm_add_epi32(_mm_mullo_epi32(cy, stride), cx);
        let near_at = |k: i32| *near.get_unchecked(k as usize) as i32;
        let nb = _mm_setr_epi32(
            near_at(_mm_extract_epi32::<0>(at)),
            near_at(_mm_extract_epi32::<1>(at)),
            near_at(_mm_extract_epi32::<2>(at)),
            near_at(_mm_extract_epi32::<3>(at)),
        );
        let code = _mm_or_si128(
            _mm_or_si128(cx, _mm_slli_epi32::<16>(cy)),
            _mm_slli_epi32::<24>(nb),
        );
        // The 64-bit "seen" masks narrowed to 32 bits; unseen: all ones (BEHIND).
        let seen32 = _mm_castps_si128(_mm_shuffle_ps::<0b10_00_10_00>(
            _mm_castsi128_ps(_mm256_castsi256_si128(seen)),
            _mm_castsi128_ps(_mm256_extracti128_si256::<1>(seen)),
        ));
        let code = _mm_or_si128(code, _mm_xor_si128(seen32, ones));
        _mm_storeu_si128(dst.add(i), code);
    }
    4 * n4
}

/// [`codes`] eight vertices at a time with AVX-512 (F, VL), the same operations lane by lane.
///
/// # Safety
/// As [`codes`], and the CPU also has AVX-512 F and VL.
#[target_feature(enable = "avx512f,avx512vl,avx2")]
pub(crate) unsafe fn codes8(
    view: &ScreenRows,
    place: &GridPlace,
    near: &[u8],
    ps: &[DVec3],
    out: &mut [MaybeUninit<u32>],
) -> usize {
    let (nx, ny) = (place.nx, place.ny);
    debug_assert!(out.len() >= ps.len());
    debug_assert_eq!(near.len(), ((nx + 2) * (ny + 2)) as usize + 3);
    let b = |v: f64| _mm512_set1_pd(v);
    let row = |r: DVec4| (b(r.x), b(r.y), b(r.z), b(r.w));
    let (rx, ry, rw) = (row(view.x), row(view.y), row(view.w));
    let (zero, one, inf) = (_mm512_setzero_pd(), b(1.0), b(f64::INFINITY));
    let (x0, y0, hw, hh) = (b(view.x0), b(view.y0), b(view.half_w), b(view.half_h));
    let (ox, oy, ic) = (b(place.origin.x), b(place.origin.y), b(place.inv_cell));
    let range = b(SCREEN_RANGE_PX);
    let (hx, hy) = (b(nx as f64 + 1.0), b(ny as f64 + 1.0));
    let stride = _mm256_set1_epi32(nx + 2);
    let ones = _mm256_set1_epi32(-1);
    // Lanes of x, y, z: first from the first two loads (0..16), then the third (8 + k).
    let pick = |a: [i64; 8]| _mm512_setr_epi64(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]);
    let (ax, ay, az) = (
        pick([0, 3, 6, 9, 12, 15, 0, 0]),
        pick([1, 4, 7, 10, 13, 0, 0, 0]),
        pick([2, 5, 8, 11, 14, 0, 0, 0]),
    );
    let (bx, by, bz) = (
        pick([0, 1, 2, 3, 4, 5, 10, 13]),
        pick([0, 1, 2, 3, 4, 8, 11, 14]),
        pick([0, 1, 2, 3, 4, 9, 12, 15]),
    );
    let n8 = ps.len() / 8;
    let src = ps.as_ptr() as *const f64;
    let dst = out.as_mut_ptr() as *mut __m256i;
    for i in 0..n8 {
        let p = src.add(24 * i);
        ahead(p.wrapping_add(AHEAD), 3);
        let (v0, v1, v2) = (
            _mm512_loadu_pd(p),
            _mm512_loadu_pd(p.add(8)),
            _mm512_loadu_pd(p.add(16)),
        );
        let x = _mm512_permutex2var_pd(_mm512_permutex2var_pd(v0, ax, v1), bx, v2);
        let y = _mm512_permutex2var_pd(_mm512_permutex2var_pd(v0, ay, v1), by, v2);
        let z = _mm512_permutex2var_pd(_mm512_permutex2var_pd(v0, az, v1), bz, v2);
        let dot = |a: (__m512d, __m512d, __m512d, __m512d)| {
            _mm512_add_pd(
                _mm512_add_pd(
                    _mm512_add_pd(_mm512_mul_pd(a.0, x), _mm512_mul_pd(a.1, y)),
                    _mm512_mul_pd(a.2, z),
                ),
                a.3,
            )
        };
        let w = dot(rw);
        let front =
            _mm512_cmp_pd_mask::<_CMP_GT_OQ>(w, zero) & _mm512_cmp_pd_mask::<_CMP_LT_OQ>(w, inf);
        let inv = _mm512_div_pd(one, w);
        let sx = _mm512_add_pd(
            x0,
            _mm512_mul_pd(_mm512_add_pd(_mm512_mul_pd(dot(rx), inv), one), hw),
        );
        let sy = _mm512_add_pd(
            y0,
            _mm512_mul_pd(_mm512_sub_pd(one, _mm512_mul_pd(dot(ry), inv)), hh),
        );
        let within = |s: __m512d| _mm512_cmp_pd_mask::<_CMP_LE_OQ>(_mm512_abs_pd(s), range);
        let seen = front & within(sx) & within(sy);
        let cell = |s: __m512d, o: __m512d, h: __m512d| {
            let q = _mm512_add_pd(_mm512_mul_pd(_mm512_sub_pd(s, o), ic), one);
            _mm512_cvttpd_epi32(_mm512_min_pd(_mm512_max_pd(q, zero), h))
        };
        let (cx, cy) = (cell(sx, ox, hx), cell(sy, oy, hy));
        let at = _mm256_add_epi32(_mm256_mullo_epi32(cy, stride), cx);
        // Each cell's flags as the low byte of a four-byte gather (the table's padding keeps
        // the last cell's read inside it).
        let nb = _mm256_and_si256(
            _mm256_i32gather_epi32::<1>(near.as_ptr() as *const i32, at),
            _mm256_set1_epi32(0xff),
        );
        let code = _mm256_or_si256(
            _mm256_or_si256(cx, _mm256_slli_epi32::<16>(cy)),
            _mm256_slli_epi32::<24>(nb),
        );
        _mm256_storeu_si256(dst.add(i), _mm256_mask_mov_epi32(ones, seen, code));
    }
    8 * n8
}
