//! Large arrays backed by transparent huge pages where the operating system offers them.
//!
//! Subdividing a 32k-quad torus three levels writes about 200 MB of fresh arrays. With 4 KiB
//! pages about a third of the single-thread time went to page faults and the kernel's page
//! zeroing (measured with `perf`; the fault count is one per 4 KiB written). Linux's default
//! transparent-huge-page mode (`madvise`) hands 2 MiB pages only to memory that asks for them,
//! which cuts those faults 512-fold: level 3 of that torus went from 157 ms to about 107 ms on one
//! thread. Asking must happen between allocation and first write, which neither `Vec` nor a
//! crate we know offers for ordinary `Vec`s (memmap2 gives file-style maps, not `Vec`s), hence
//! these few lines. Elsewhere, and for small arrays, they are plain allocations.

/// Arrays smaller than this cannot hold an aligned 2 MiB page whole.
const MIN_BYTES: usize = HUGE_PAGE;
const HUGE_PAGE: usize = 2 << 20;

/// An empty vector with room for `n` elements, its pages advised huge before any is touched.
pub(crate) fn with_capacity<T>(n: usize) -> Vec<T> {
    let v: Vec<T> = Vec::with_capacity(n);
    advise(v.as_ptr().cast(), v.capacity() * std::mem::size_of::<T>());
    v
}

/// `n` copies of `value` (as `vec![value; n]`), written after the pages are advised huge.
pub(crate) fn filled<T: Clone>(n: usize, value: T) -> Vec<T> {
    let mut v = with_capacity(n);
    v.resize(n, value);
    v
}

#[cfg(target_os = "linux")]
fn advise(ptr: *const u8, bytes: usize) {
    if bytes < MIN_BYTES {
        return;
    }
    // The whole 2 MiB pages inside the allocation (madvise needs aligned ranges); the
    // unaligned head and tail keep ordinary pages.
    let start = (ptr as usize).next_multiple_of(HUGE_PAGE);
    let end = (ptr as usize + bytes) / HUGE_PAGE * HUGE_PAGE;
    if end > start {
        // SAFETY: the range lies inside a live allocation of ours; MADV_HUGEPAGE changes only
        // how the kernel backs those pages, never their contents. A failure (a kernel without
        // THP) leaves ordinary pages, so the result is ignored.
        unsafe {
            libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_ptr: *const u8, _bytes: usize) {}

#[cfg(test)]
mod tests {
    #[test]
    fn filled_equals_vec_macro_above_and_below_the_threshold() {
        for n in [0usize, 5, 3 << 20] {
            let v = super::filled(n, 7u32);
            assert_eq!(v, vec![7u32; n]);
            let w: Vec<[f32; 2]> = super::with_capacity(n);
            assert!(w.is_empty() && w.capacity() >= n);
        }
    }
}
