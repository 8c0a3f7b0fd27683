//! Second normalization (seed 002 §3.3, Fig. 9; spec §4 step 6): no triangle is crossed
//! twice. For each face t in ascending id, the elements of A strictly between the first and
//! the last element belonging to t are removed; repeated to a fixed point (gap-fill: one
//! pass can leave violations created by later removals; it terminates because A shrinks).
//! Before it, spec §4 step 5's clean-up: consecutive duplicates (E_i, E_i), (V_j, V_j)
//! collapse, and a crossing of an edge next to one of that edge's own end vertices is dropped.

use super::first_normalization::{elem_faces, Elem, Occ};
use super::ids::Lf;
use super::region::Region;

/// A normalized element array: consecutive elements share `faces[k]` ([`Lf::NONE`] when they
/// are the two ends of one edge, or on one edge: the path runs along it).
#[derive(Debug, Clone)]
pub(crate) struct Normalized {
    pub occ: Vec<u32>,
    pub faces: Vec<Lf>,
}

fn same_class(x: Elem, y: Elem) -> bool {
    match (x, y) {
        (Elem::V(a), Elem::V(b)) => a == b,
        (Elem::E { edge: a, .. }, Elem::E { edge: b, .. }) => a == b,
        (a, b) => a == b,
    }
}

/// Spec §4 step 5's clean-up. The chain's first and last elements are its ends (a piece
/// end, or where it enters or leaves the cuttable faces) and are kept, so pieces still
/// meet at their shared corners: a run of one class keeps its first element, or its last
/// when the run ends the chain.
fn collapse(region: &Region, occ: &[Occ], a: &mut Vec<u32>) {
    let n = a.len();
    let class = |k: usize| occ[a[k] as usize].elem;
    let mut keep = vec![true; n];
    let mut k = 0;
    while k < n {
        let mut j = k + 1;
        while j < n && same_class(class(k), class(j)) {
            j += 1;
        }
        // Run k..j: keep its first, and its last if it is the chain's end.
        for (i, kept) in keep.iter_mut().enumerate().take(j).skip(k + 1) {
            *kept = i == n - 1;
        }
        k = j;
    }
    let ends_of = |e, v| region.ends(e).contains(&v);
    let mut idx: Vec<usize> = Vec::with_capacity(n);
    idx.extend((0..n).filter(|&i| keep[i]));
    for (p, &i) in idx.iter().enumerate() {
        if i == 0 || i == n - 1 {
            continue;
        }
        if let Elem::E { edge, .. } = class(i) {
            let near_end = |q: usize| matches!(class(q), Elem::V(v) if ends_of(edge, v));
            if (p > 0 && near_end(idx[p - 1])) || (p + 1 < idx.len() && near_end(idx[p + 1])) {
                keep[i] = false;
            }
        }
    }
    let mut k = 0;
    a.retain(|_| {
        k += 1;
        keep[k - 1]
    });
}

/// Fig. 9 over the faces of A in ascending order, repeated until a pass removes nothing.
/// Returns whether anything was removed. Most arrays need no removal, which
/// [`crossed_twice`] tells without ordering the elements by face.
fn fig9(region: &Region, occ: &[Occ], a: &mut Vec<u32>) -> bool {
    if !crossed_twice(region, occ, a) {
        debug_assert!(
            !fig9_passes(region, occ, &mut a.clone()),
            "a face is crossed twice"
        );
        return false;
    }
    fig9_passes(region, occ, a)
}

/// [`fig9`]'s passes. Each face keeps the positions of its elements; removals unlink a
/// linked list, so a pass costs O(|A| + Σ elements per face) instead of a scan of A per face.
fn fig9_passes(region: &Region, occ: &[Occ], a: &mut Vec<u32>) -> bool {
    let n = a.len();
    // Each face's positions in A, ascending (a counting sort by face: the faces are the
    // region's, a few thousand).
    let nf = region.face_count();
    let mut scratch = Vec::new();
    let mut entries: Vec<(u32, u32)> = Vec::new();
    for (k, &o) in a.iter().enumerate() {
        elem_faces(region, occ[o as usize].elem, &mut scratch);
        entries.extend(scratch.iter().map(|&f| (f.0, k as u32)));
    }
    let (start, at) = super::fast::radix::group_by_key(nf, &entries);
    let mut alive = vec![true; n];
    let mut next: Vec<usize> = (1..=n).collect();
    let mut removed_any = false;
    loop {
        let mut removed = false;
        for t in 0..nf {
            let group = &at[start[t] as usize..start[t + 1] as usize];
            if group.len() < 2 {
                continue;
            }
            let first = group
                .iter()
                .find(|&&k| alive[k as usize])
                .map(|&k| k as usize);
            let last = group
                .iter()
                .rev()
                .find(|&&k| alive[k as usize])
                .map(|&k| k as usize);
            if let (Some(i), Some(j)) = (first, last) {
                if next[i] < j {
                    let mut k = next[i];
                    while k < j {
                        alive[k] = false;
                        k = next[k];
                    }
                    next[i] = j;
                    removed = true;
                }
            }
        }
        if !removed {
            break;
        }
        removed_any = true;
    }
    if removed_any {
        let mut k = 0;
        a.retain(|_| {
            k += 1;
            alive[k - 1]
        });
    }
    removed_any
}

/// Whether [`fig9`]'s first pass removes something: some face's first and last elements
/// in `a` have an element between them. The usual answer is no, found here from each face's
/// first position alone, without ordering the elements by face.
fn crossed_twice(region: &Region, occ: &[Occ], a: &[u32]) -> bool {
    const NONE: u32 = u32::MAX;
    let mut first = vec![NONE; region.face_count()];
    let mut faces = Vec::new();
    for (k, &o) in a.iter().enumerate() {
        elem_faces(region, occ[o as usize].elem, &mut faces);
        for &f in &faces {
            let at = &mut first[f.idx()];
            if *at == NONE {
                *at = k as u32;
            } else if k as u32 > *at + 1 {
                return true;
            }
        }
    }
    false
}

/// Normalizes one chain; a pair left without a common cuttable face splits it.
pub(crate) fn normalize(region: &Region, occ: &[Occ], chain: &[u32]) -> Vec<Normalized> {
    let mut a = chain.to_vec();
    loop {
        let before = a.len();
        collapse(region, occ, &mut a);
        if !fig9(region, occ, &mut a) {
            // Nothing changed since the last clean-up: done (it would change nothing).
            if a.len() == before {
                break;
            }
            let before = a.len();
            collapse(region, occ, &mut a);
            if a.len() == before {
                break;
            }
        }
    }
    let mut out = Vec::new();
    let mut cur = Normalized {
        occ: Vec::with_capacity(a.len()),
        faces: Vec::with_capacity(a.len()),
    };
    let (mut fx, mut fy) = (Vec::new(), Vec::new());
    for (k, &o) in a.iter().enumerate() {
        // This element's faces; the previous one's are those of the last turn.
        std::mem::swap(&mut fx, &mut fy);
        elem_faces(region, occ[o as usize].elem, &mut fy);
        if k > 0 {
            let prev = a[k - 1];
            let (x, y) = (occ[prev as usize].elem, occ[o as usize].elem);
            let common = fx.iter().copied().find(|f| fy.contains(f));
            // Two vertices of one triangle are the ends of one of its sides: with a face in
            // common they are along an edge, without one only if a face the cut may not
            // split joins them.
            let along = match (x, y) {
                (Elem::V(u), Elem::V(w)) => {
                    common.is_some()
                        || region
                            .vertex_faces(u)
                            .iter()
                            .any(|&f| region.corners(f).contains(&w))
                }
                _ => false,
            };
            match (common, along) {
                (_, true) => cur.faces.push(Lf::NONE),
                (Some(f), false) => cur.faces.push(f),
                (None, false) => {
                    if cur.occ.len() >= 2 {
                        out.push(std::mem::replace(
                            &mut cur,
                            Normalized {
                                occ: Vec::new(),
                                faces: Vec::new(),
                            },
                        ));
                    } else {
                        cur.occ.clear();
                        cur.faces.clear();
                    }
                }
            }
        }
        cur.occ.push(o);
    }
    if cur.occ.len() >= 2 {
        out.push(cur);
    }
    out
}
