//! A stable LSD radix sort of (key, value) pairs by key, for the few-thousand-element sorts
//! of a cut region (links by occurrence, faces by depth): `std` has none.
//!
//! The input is cut in four quarters, each with its own counters, walked side by side: the
//! keys come nearly sorted, so one set of counters would bump the same counter over and
//! over, each increment waiting for the last. Quarter q's elements of a digit go after
//! quarter q − 1's, so the sort stays stable.

use std::mem::MaybeUninit;

const MAX_BITS: u32 = 11;
const WAYS: usize = 4;

/// Sorts a few entries in place by insertion (a vertex's edges, an index's occurrences, where
/// the library sort's set-up outweighs the sorting); `sort_unstable` beyond 16.
/// Unstable: for entries whose equal ones are indistinguishable.
#[inline]
pub(crate) fn small_sort<T: Ord + Copy>(v: &mut [T]) {
    if v.len() > 16 {
        v.sort_unstable();
        return;
    }
    for i in 1..v.len() {
        let x = v[i];
        let mut j = i;
        while j > 0 && v[j - 1] > x {
            v[j] = v[j - 1];
            j -= 1;
        }
        v[j] = x;
    }
}

/// Sorts `pairs` by `.0`, keeping the order of equal keys.
pub(crate) fn sort_by_key(pairs: &mut Vec<(u32, u32)>) {
    let n = pairs.len();
    if n < 256 {
        pairs.sort_by_key(|p| p.0);
        return;
    }
    let max = pairs.iter().map(|k| k.0).max().unwrap_or(0);
    let key_bits = 32 - max.leading_zeros();
    if key_bits == 0 {
        return;
    }
    // Digits as wide as pays: each pass reads and writes every pair and zeroes and sums
    // WAYS × 2^bits counters, so a few thousand 13-bit keys sort in two passes of 7 bits
    // rather than two of 11.
    let (passes, bits) = (1..=4u32)
        .map(|p| (p, key_bits.div_ceil(p)))
        .filter(|&(_, b)| b <= MAX_BITS)
        .min_by_key(|&(p, b)| p as usize * (2 * n + 2 * WAYS * (1usize << b)))
        .expect("four passes of 8 bits cover 32");
    let mask = (1u32 << bits) - 1;
    let mut tmp = vec![(0u32, 0u32); n];
    // Quarters [start[w], start[w + 1]); the first three are q long, the last takes the rest.
    let q = n / WAYS;
    let start = [0, q, 2 * q, 3 * q, n];
    let mut count = vec![[0u32; WAYS]; 1 << bits];
    for pass in 0..passes {
        let shift = pass * bits;
        let digit = |k: u32| ((k >> shift) & mask) as usize;
        count.iter_mut().for_each(|c| *c = [0; WAYS]);
        for i in 0..q {
            for w in 0..WAYS {
                count[digit(pairs[start[w] + i].0)][w] += 1;
            }
        }
        for k in &pairs[start[3] + q..] {
            count[digit(k.0)][3] += 1;
        }
        // Offsets: by digit, then by quarter.
        let mut sum = 0;
        for c in count.iter_mut() {
            for x in c.iter_mut() {
                (*x, sum) = (sum, sum + *x);
            }
        }
        for i in 0..q {
            for w in 0..WAYS {
                let k = pairs[start[w] + i];
                let c = &mut count[digit(k.0)][w];
                tmp[*c as usize] = k;
                *c += 1;
            }
        }
        for &k in &pairs[start[3] + q..] {
            let c = &mut count[digit(k.0)][3];
            tmp[*c as usize] = k;
            *c += 1;
        }
        std::mem::swap(pairs, &mut tmp);
    }
}

/// Sorts `items` stably by `(index(item), key(item))`: a stable radix sort by index, then
/// each index's few items by key (with their positions, so ties keep their order), the
/// items moved once at the end; above a few hundred items the runs are sorted in two halves
/// on rayon.
pub(crate) fn sort_by_index_then_key<T, K>(
    items: &mut Vec<T>,
    index: impl Fn(&T) -> u32 + Sync,
    key: impl Fn(&T) -> K + Sync,
) where
    T: Copy + Send + Sync,
    K: Ord + Copy,
{
    let mut by_index: Vec<(u32, u32)> = items
        .iter()
        .enumerate()
        .map(|(i, x)| (index(x), i as u32))
        .collect();
    sort_by_key(&mut by_index);
    // Two halves split between two indices.
    let mut mid = by_index.len() / 2;
    while mid > 0 && mid < by_index.len() && by_index[mid].0 == by_index[mid - 1].0 {
        mid += 1;
    }
    let mut sorted: Vec<T> = Vec::with_capacity(items.len());
    let (lo, hi) = sorted.spare_capacity_mut()[..items.len()].split_at_mut(mid);
    let from = &items[..];
    let runs = |by_index: &[(u32, u32)], out: &mut dyn Iterator<Item = &mut MaybeUninit<T>>| {
        let mut keys: Vec<(K, u32)> = Vec::new();
        for run in by_index.chunk_by(|a, b| a.0 == b.0) {
            keys.clear();
            keys.extend(run.iter().map(|&(_, i)| (key(&from[i as usize]), i)));
            small_sort(&mut keys);
            for k in &keys {
                out.next()
                    .expect("a slot per entry")
                    .write(from[k.1 as usize]);
            }
        }
    };
    if by_index.len() < 512 {
        runs(&by_index, &mut lo.iter_mut().chain(hi.iter_mut()));
    } else {
        rayon::join(
            || runs(&by_index[..mid], &mut lo.iter_mut()),
            || runs(&by_index[mid..], &mut hi.iter_mut()),
        );
    }
    // SAFETY: `runs` wrote one item per entry of `by_index`, `items.len()` in all.
    unsafe { sorted.set_len(items.len()) };
    *items = sorted;
}

/// `(key, value)` pairs grouped by key with a counting sort, for keys below `keys`: CSR
/// `(start, values)`, key `k`'s values being `values[start[k]..start[k + 1]]` in the pairs'
/// order.
pub(crate) fn group_by_key(keys: usize, pairs: &[(u32, u32)]) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; keys + 1];
    for &(k, _) in pairs {
        start[k as usize + 1] += 1;
    }
    for k in 0..keys {
        start[k + 1] += start[k];
    }
    let mut fill = start.clone();
    let mut values = vec![0u32; pairs.len()];
    for &(k, v) in pairs {
        values[fill[k as usize] as usize] = v;
        fill[k as usize] += 1;
    }
    (start, values)
}

/// A key whose unsigned order is `f64::total_cmp`'s.
#[inline]
pub(crate) fn f64_key(x: f64) -> u64 {
    let b = x.to_bits();
    if b >> 63 == 1 {
        !b
    } else {
        b | 1 << 63
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

#[cfg(test)]
pub(crate) mod tests {
    use super::{group_by_key, small_sort, sort_by_key};

    /// A deterministic xorshift64 stream from `seed` (non-zero), for the cut's unit tests.
    pub(crate) fn xorshift(mut seed: u64) -> impl FnMut() -> u64 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        }
    }

    /// The same order as `sort_unstable`, on both sides of the insertion sort's limit, with
    /// repeated keys.
    #[test]
    fn small_sort_sorts() {
        let mut rnd = xorshift(0x2545_f491_4f6c_dd1d);
        for n in [0usize, 1, 2, 3, 7, 16, 17, 40] {
            for _ in 0..50 {
                let mut v: Vec<(u32, u32)> = (0..n)
                    .map(|_| ((rnd() % 5) as u32, (rnd() % 3) as u32))
                    .collect();
                let mut want = v.clone();
                want.sort_unstable();
                small_sort(&mut v);
                assert_eq!(v, want, "n = {n}");
            }
        }
    }

    /// Each key's values in the pairs' order, as a stable sort by key lays them out.
    #[test]
    fn group_by_key_is_a_stable_grouping() {
        let pairs: Vec<(u32, u32)> = (0..500u32).map(|i| ((i * 37) % 11, i)).collect();
        let (start, values) = group_by_key(13, &pairs);
        let mut sorted = pairs.clone();
        sorted.sort_by_key(|p| p.0);
        assert_eq!(values, sorted.iter().map(|p| p.1).collect::<Vec<_>>());
        for k in 0..13u32 {
            let want = pairs.iter().filter(|p| p.0 == k).count() as u32;
            assert_eq!(start[k as usize + 1] - start[k as usize], want, "key {k}");
        }
        assert_eq!(start[13], 500);
    }

    /// The order of a stable comparison sort by index then key, below and above the size at
    /// which the runs are sorted in two halves, with ties in both.
    #[test]
    fn sort_by_index_then_key_is_a_stable_sort() {
        let mut rnd = xorshift(0x1234_5678_9abc_def1);
        for n in [0usize, 1, 5, 300, 511, 512, 2000] {
            // (index, key, position)
            let items: Vec<(u32, (u64, u8), u32)> = (0..n)
                .map(|i| {
                    let r = rnd();
                    let index = (r >> 40) as u32 % (n as u32 / 4 + 1);
                    (index, ((r >> 8) % 5, (r >> 16) as u8 % 3), i as u32)
                })
                .collect();
            let mut want = items.clone();
            want.sort_by_key(|x| (x.0, x.1));
            let mut got = items;
            super::sort_by_index_then_key(&mut got, |x| x.0, |x| x.1);
            assert_eq!(got, want, "n = {n}");
        }
    }

    /// Stable and sorted, as `sort_by_key` of std: small and large inputs, nearly sorted,
    /// reversed, few distinct keys, keys using all 32 bits, lengths not divisible by four.
    #[test]
    fn radix_sort_is_a_stable_sort() {
        let mut rnd = xorshift(0x9e37_79b9_7f4a_7c15);
        for n in [0usize, 1, 5, 255, 256, 257, 1000, 4099, 30_001] {
            let inputs: [Vec<u32>; 4] = [
                (0..n)
                    .map(|i| (i as u32) / 3 + (rnd() % 5) as u32)
                    .collect(),
                (0..n).map(|i| (n - i) as u32).collect(),
                (0..n).map(|_| (rnd() % 7) as u32).collect(),
                (0..n).map(|_| rnd() as u32).collect(),
            ];
            for keys in inputs {
                let mut pairs: Vec<(u32, u32)> = keys
                    .iter()
                    .enumerate()
                    .map(|(i, &k)| (k, i as u32))
                    .collect();
                let mut want = pairs.clone();
                want.sort_by_key(|p| p.0);
                sort_by_key(&mut pairs);
                assert_eq!(pairs, want, "n = {n}");
            }
        }
    }
}
