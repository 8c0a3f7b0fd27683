//! Large arrays backed by transparent huge pages where the operating system offers them.
//!
//! Subdividing a 32k-quad torus three levels writes about 200 MB of fresh arrays. With 4 KiB
//! pages about a third of the single-thread time went to page faults and the kernel's page
//! zeroing (measured with `perf`: one fault per 4 KiB written). Linux's default
//! transparent-huge-page mode (`madvise`) hands 2 MiB pages only to memory that asks for
//! them, which cuts those faults 512-fold. Asking must happen between allocation and first
//! write, which `Vec` does not offer, hence this module:
//! - [`with_capacity`] and [`filled`] make `Vec`s (for arrays handed to callers) and advise
//!   the whole 2 MiB pages inside them; their unaligned ends keep small pages.
//! - [`Buf`] holds a level's internal arrays; a large one gets its own 2 MiB-aligned mapping,
//!   all huge pages. On the torus, faults per call fell from 37k to 2.4k at level 3 and
//!   from 11.7k to 4.1k at level 2 (`getrusage`), where the rest are output `Vec`s.
//!
//! No crate we know does this for ordinary arrays (memmap2 maps files and gives bytes, not
//! typed arrays with this alignment policy). Elsewhere than Linux, everything is a plain
//! `Vec`.

/// Arrays smaller than this cannot hold an aligned 2 MiB page whole.
#[cfg(target_os = "linux")]
const MIN_BYTES: usize = HUGE_PAGE;
#[cfg(target_os = "linux")]
const HUGE_PAGE: usize = 2 << 20;
/// A [`Buf`] this large gets its own mapping: one huge-page fault costs less than the
/// 256 small ones it replaces.
#[cfg(target_os = "linux")]
const MAP_MIN_BYTES: usize = 1 << 20;

/// An empty vector with room for `n` elements, its pages advised huge before any is touched.
pub(crate) fn with_capacity<T>(n: usize) -> Vec<T> {
    let v: Vec<T> = Vec::with_capacity(n);
    advise(v.as_ptr().cast(), v.capacity() * std::mem::size_of::<T>());
    v
}

/// `n` zero points, from zeroed memory (calloc): no pass writes the zeros, fresh pages are
/// zeroed by the kernel when first written (in parallel passes), huge where advised.
pub(crate) fn zero_points(n: usize) -> Vec<glam::DVec3> {
    let mut flat = std::mem::ManuallyDrop::new(vec![0.0f64; 3 * n]);
    advise(
        flat.as_ptr().cast(),
        flat.capacity() * std::mem::size_of::<f64>(),
    );
    assert_eq!(flat.capacity(), 3 * n, "vec! allocates exactly");
    // SAFETY: DVec3 is three f64 (repr(C), align 8), so 3n f64 are n DVec3 with the same
    // allocation layout; all-zero bits are DVec3::ZERO.
    unsafe { Vec::from_raw_parts(flat.as_mut_ptr().cast(), n, n) }
}

/// `n` copies of `value` (as `vec![value; n]`), written after the pages are advised huge.
pub(crate) fn filled<T: Clone>(n: usize, value: T) -> Vec<T> {
    let mut v = with_capacity(n);
    v.resize(n, value);
    v
}

/// A fixed-length array for a level's internal data: large ones live in their own mapping,
/// aligned to and rounded up to 2 MiB and advised huge, so every page of them is a huge
/// page (a `Vec`'s unaligned start and end keep small pages, and at level 2 of the torus
/// those were most of the remaining faults). Small ones, and arrays handed to callers, are
/// ordinary `Vec`s (`Buf::from`, [`Buf::into_vec`]).
pub(crate) struct Buf<T> {
    repr: Repr<T>,
}

enum Repr<T> {
    Heap(Vec<T>),
    #[cfg(target_os = "linux")]
    Mapped {
        ptr: std::ptr::NonNull<T>,
        len: usize,
        map: usize,
    },
}

// SAFETY: a mapped `Buf` owns its elements exactly as a `Vec` does.
unsafe impl<T: Send> Send for Buf<T> {}
unsafe impl<T: Sync> Sync for Buf<T> {}

/// Types whose all-zero bytes are a valid value (fresh mappings are zero-filled).
///
/// # Safety
/// The all-zero bit pattern must be a valid value of the type.
pub(crate) unsafe trait Zeroable: Copy {}
// SAFETY: zero is 0, 0.0 and false.
unsafe impl Zeroable for u32 {}
unsafe impl Zeroable for f32 {}
unsafe impl Zeroable for bool {}
unsafe impl Zeroable for [u32; 2] {}
unsafe impl Zeroable for [f32; 2] {}

impl<T> Buf<T> {
    /// Room for `n` elements in a fresh zero-filled mapping, or `None` when the array is
    /// small (or mapping fails): the caller then makes a `Vec`.
    #[cfg(target_os = "linux")]
    fn map(n: usize) -> Option<(std::ptr::NonNull<T>, usize)> {
        let bytes = n.checked_mul(std::mem::size_of::<T>())?;
        if bytes < MAP_MIN_BYTES || std::mem::align_of::<T>() > HUGE_PAGE {
            return None;
        }
        let map = bytes.next_multiple_of(HUGE_PAGE);
        // SAFETY: a fresh private anonymous mapping, trimmed to its 2 MiB-aligned middle;
        // nothing else refers to it.
        unsafe {
            let raw = libc::mmap(
                std::ptr::null_mut(),
                map + HUGE_PAGE,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
                -1,
                0,
            );
            if raw == libc::MAP_FAILED {
                return None;
            }
            let start = (raw as usize).next_multiple_of(HUGE_PAGE);
            let head = start - raw as usize;
            if head > 0 {
                libc::munmap(raw, head);
            }
            if HUGE_PAGE - head > 0 {
                libc::munmap((start + map) as *mut libc::c_void, HUGE_PAGE - head);
            }
            libc::madvise(start as *mut libc::c_void, map, libc::MADV_HUGEPAGE);
            Some((std::ptr::NonNull::new_unchecked(start as *mut T), map))
        }
    }

    #[cfg(not(target_os = "linux"))]
    fn map(_n: usize) -> Option<(std::ptr::NonNull<T>, usize)> {
        None
    }

    /// `n` zeros; a large one is not even touched until written.
    pub fn zeroed(n: usize) -> Self
    where
        T: Zeroable,
    {
        match Self::map(n) {
            #[cfg(target_os = "linux")]
            Some((ptr, map)) => Buf {
                repr: Repr::Mapped { ptr, len: n, map },
            },
            _ => Buf {
                // SAFETY: `T: Zeroable`. `vec!` of a zero value allocates zeroed memory
                // (calloc) for these types, which is not touched until written.
                repr: Repr::Heap(vec![unsafe { std::mem::zeroed::<T>() }; n]),
            },
        }
    }

    /// `n` copies of `value`.
    pub fn filled(n: usize, value: T) -> Self
    where
        T: Clone,
    {
        match Self::map(n) {
            #[cfg(target_os = "linux")]
            Some((ptr, map)) => {
                for i in 0..n {
                    // SAFETY: `i < n` lies inside the mapping; the slots are uninitialised.
                    unsafe { ptr.as_ptr().add(i).write(value.clone()) };
                }
                Buf {
                    repr: Repr::Mapped { ptr, len: n, map },
                }
            }
            _ => Buf {
                repr: Repr::Heap(filled(n, value)),
            },
        }
    }

    /// The elements as a `Vec` (a copy when they live in a mapping).
    pub fn into_vec(mut self) -> Vec<T>
    where
        T: Clone,
    {
        match &mut self.repr {
            Repr::Heap(v) => std::mem::take(v),
            #[cfg(target_os = "linux")]
            Repr::Mapped { .. } => self.to_vec(),
        }
    }
}

impl<T> From<Vec<T>> for Buf<T> {
    fn from(v: Vec<T>) -> Self {
        Buf {
            repr: Repr::Heap(v),
        }
    }
}

impl<T> Default for Buf<T> {
    fn default() -> Self {
        Buf {
            repr: Repr::Heap(Vec::new()),
        }
    }
}

impl<T> std::ops::Deref for Buf<T> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        match &self.repr {
            Repr::Heap(v) => v,
            // SAFETY: `len` initialised elements at `ptr`, owned by `self`.
            #[cfg(target_os = "linux")]
            Repr::Mapped { ptr, len, .. } => unsafe {
                std::slice::from_raw_parts(ptr.as_ptr(), *len)
            },
        }
    }
}

impl<T> std::ops::DerefMut for Buf<T> {
    fn deref_mut(&mut self) -> &mut [T] {
        match &mut self.repr {
            Repr::Heap(v) => v,
            // SAFETY: as in `deref`, borrowed mutably through `self`.
            #[cfg(target_os = "linux")]
            Repr::Mapped { ptr, len, .. } => unsafe {
                std::slice::from_raw_parts_mut(ptr.as_ptr(), *len)
            },
        }
    }
}

impl<T: Clone> Clone for Buf<T> {
    fn clone(&self) -> Self {
        match &self.repr {
            Repr::Heap(v) => Buf::from(v.clone()),
            #[cfg(target_os = "linux")]
            Repr::Mapped { .. } => {
                let mut out: Buf<T> = match Self::map(self.len()) {
                    Some((ptr, map)) => Buf {
                        repr: Repr::Mapped { ptr, len: 0, map },
                    },
                    None => return Buf::from(self.to_vec()),
                };
                for x in self.iter() {
                    if let Repr::Mapped { ptr, len, .. } = &mut out.repr {
                        // SAFETY: `*len < self.len()` slots fit in the mapping.
                        unsafe { ptr.as_ptr().add(*len).write(x.clone()) };
                        *len += 1;
                    }
                }
                out
            }
        }
    }
}

impl<T: std::fmt::Debug> std::fmt::Debug for Buf<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        (**self).fmt(f)
    }
}

impl<T> Drop for Buf<T> {
    fn drop(&mut self) {
        #[cfg(target_os = "linux")]
        if let Repr::Mapped { ptr, len, map } = self.repr {
            // SAFETY: the elements are initialised and owned; the mapping is ours.
            unsafe {
                std::ptr::drop_in_place(std::ptr::slice_from_raw_parts_mut(ptr.as_ptr(), len));
                libc::munmap(ptr.as_ptr().cast(), map);
            }
        }
    }
}

/// Asks the CPU to bring the cache line holding `p` closer (no-op off x86-64). Never reads
/// memory and cannot fault, so any address will do, even one past an allocation's end; the
/// cut's whole-mesh passes use it where the hardware's own prefetch falls behind.
#[inline(always)]
pub(crate) fn prefetch<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch is a hint; it neither reads nor writes memory, whatever the address.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(p.cast())
    };
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
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
    use super::Buf;

    #[test]
    fn bufs_small_and_mapped_behave_as_vecs() {
        for n in [0usize, 3, 1 << 20] {
            let mut z = Buf::<u32>::zeroed(n);
            assert_eq!(&z[..], &vec![0u32; n][..]);
            if n > 0 {
                z[n - 1] = 9;
            }
            let c = z.clone();
            assert_eq!(&c[..], &z[..]);
            let v = z.into_vec();
            assert_eq!(v.len(), n);
            assert_eq!(v.last().copied(), (n > 0).then_some(9));
            // Elements that own memory are cloned and dropped one by one.
            let s = Buf::filled(n / 16, vec![1u8, 2]);
            let t = s.clone();
            assert!(t.iter().all(|x| x == &[1, 2]) && t.len() == n / 16);
            assert_eq!(Buf::from(vec![5u32; 4]).into_vec(), vec![5; 4]);
        }
    }

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
