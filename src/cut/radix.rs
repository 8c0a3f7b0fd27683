//! A stable LSD radix sort of (key, value) pairs by key, for the few-thousand-element sorts
//! of a cut region (corners by vertex id, faces by depth): several times faster there than
//! a comparison sort, and `std` has none.

const BITS: u32 = 11;
const MASK: u32 = (1 << BITS) - 1;

/// Sorts `pairs` by `.0`, keeping the order of equal keys.
pub(crate) fn sort_by_key(pairs: &mut Vec<(u32, u32)>) {
    let max = pairs.iter().map(|k| k.0).max().unwrap_or(0);
    let mut tmp = vec![(0u32, 0u32); pairs.len()];
    let mut shift = 0;
    while shift < 32 && (max >> shift) > 0 {
        let mut count = [0u32; 1 << BITS];
        for k in pairs.iter() {
            count[((k.0 >> shift) & MASK) as usize] += 1;
        }
        let mut sum = 0;
        for c in count.iter_mut() {
            (*c, sum) = (sum, sum + *c);
        }
        for &k in pairs.iter() {
            let d = ((k.0 >> shift) & MASK) as usize;
            tmp[count[d] as usize] = k;
            count[d] += 1;
        }
        std::mem::swap(pairs, &mut tmp);
        shift += BITS;
    }
}

/// A key whose unsigned order is `f32::total_cmp`'s.
#[inline]
pub(crate) fn f32_key(x: f32) -> u32 {
    let b = x.to_bits();
    if b >> 31 == 1 {
        !b
    } else {
        b | 0x8000_0000
    }
}
