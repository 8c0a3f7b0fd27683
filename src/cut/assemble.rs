//! The output mesh: the untouched faces are copied in bulk (slot `f` stays face `f`), split
//! faces write their first piece into their slot and append the others; positions are copied
//! with the snapped vertices moved and the new ones appended. No whole-mesh validation (the
//! pieces are valid by construction; debug builds check).

use glam::DVec3;
use rayon::prelude::*;

use super::region::Region;
use super::split::Splitter;
use crate::mem;
use crate::mesh::{FaceId, PolyMesh, VertexId};

pub(crate) struct Assembled {
    pub mesh: PolyMesh,
    pub face_origin: Vec<FaceId>,
    /// Output id of each local vertex (region vertices, then new ones).
    pub global: Vec<u32>,
    pub appended_faces: u32,
    /// Source triangle of each appended face.
    pub appended_from: Vec<u32>,
    /// Slots whose triangle was rewritten, ascending.
    pub rewritten: Vec<u32>,
}

/// `positions`: a copy of `tris`'s positions (made by the vertex pass, which reads them
/// anyway); `copies_of[i]`: the local vertex that new vertex `split_count + i` copies
/// (opening).
#[allow(clippy::too_many_arguments)]
pub(crate) fn assemble(
    input: &PolyMesh,
    tris: &PolyMesh,
    mut positions: Vec<DVec3>,
    tri_origin: Option<&[FaceId]>,
    region: &Region,
    moved: &[u32],
    sp: &Splitter,
    split_count: usize,
    copies_of: &[u32],
) -> Assembled {
    let nv_in = tris.vertex_count();
    let n0 = region.verts.len() as u32;
    let global: Vec<u32> = (0..n0 + sp.new_pos.len() as u32)
        .map(|lv| {
            if lv < n0 {
                region.verts[lv as usize]
            } else {
                nv_in + lv - n0
            }
        })
        .collect();

    // Output arrays: pages advised huge before the first write (crate::mem), filled by
    // rayon in place — at 1M faces the copy is page faults more than bytes. The positions
    // were copied by the vertex pass.
    debug_assert_eq!(positions.as_slice(), tris.positions());
    for &lv in moved {
        positions[region.verts[lv as usize] as usize] = region.pos[lv as usize];
    }
    positions.extend_from_slice(&sp.new_pos);
    let mut touched = sp.touched.clone();
    touched.sort_unstable();
    let appended: usize = touched
        .iter()
        .map(|&lf| sp.subs[lf as usize].as_ref().map_or(0, |s| s.len() - 1))
        .sum();
    let nf = tris.face_count() as usize;
    let nf_out = nf + appended;
    let mut corners: Vec<VertexId> = mem::with_capacity(3 * nf_out);
    corners.par_extend(tris.corners().par_iter().copied());
    let mut appended_from: Vec<u32> = Vec::with_capacity(appended);
    for &lf in &touched {
        let subs = sp.subs[lf as usize].as_ref().expect("touched");
        let slot = region.faces[lf as usize] as usize;
        for (k, t) in subs.iter().enumerate() {
            let t = t.map(|v| VertexId(global[v as usize]));
            if k == 0 {
                corners[3 * slot..3 * slot + 3].copy_from_slice(&t);
            } else {
                corners.extend_from_slice(&t);
                appended_from.push(slot as u32);
            }
        }
    }
    let mut rewritten: Vec<u32> = touched
        .iter()
        .map(|&lf| region.faces[lf as usize])
        .collect();
    rewritten.sort_unstable();
    let mut face_loop_offsets: Vec<u32> = mem::with_capacity(nf_out + 1);
    face_loop_offsets.par_extend((0..nf_out as u32 + 1).into_par_iter());
    let mut loop_offsets: Vec<u32> = mem::with_capacity(nf_out + 1);
    loop_offsets.par_extend((0..nf_out as u32 + 1).into_par_iter().map(|i| 3 * i));
    let origin_of = |t: u32| match tri_origin {
        Some(o) => o[t as usize],
        None => FaceId(t),
    };
    let mut face_origin: Vec<FaceId> = mem::with_capacity(nf_out);
    face_origin.par_extend((0..nf as u32).into_par_iter().map(origin_of));
    face_origin.extend(appended_from.iter().map(|&t| origin_of(t)));
    let mut mesh =
        PolyMesh::from_parts_unchecked(positions, face_loop_offsets, loop_offsets, corners);
    carry_attributes(
        input,
        &mut mesh,
        &face_origin,
        sp,
        region,
        &global,
        split_count,
        copies_of,
    );
    Assembled {
        mesh,
        face_origin,
        global,
        appended_faces: appended_from.len() as u32,
        appended_from,
        rewritten,
    }
}

/// Face labels and selections follow `face_origin`; vertex sharpness and selection stay on
/// the input's vertices (an opening copy takes its original's); a sharp edge split in two
/// stays sharp on both halves.
#[allow(clippy::too_many_arguments)]
fn carry_attributes(
    input: &PolyMesh,
    out: &mut PolyMesh,
    face_origin: &[FaceId],
    sp: &Splitter,
    region: &Region,
    global: &[u32],
    split_count: usize,
    copies_of: &[u32],
) {
    let a = &input.attributes;
    if a.face_labels.par_iter().any(|&l| l != 0) {
        out.attributes.face_labels = face_origin
            .par_iter()
            .map(|f| a.face_labels[f.idx()])
            .collect();
    }
    if a.face_selection.par_iter().any(|&s| s) {
        out.attributes.face_selection = face_origin
            .par_iter()
            .map(|f| a.face_selection[f.idx()])
            .collect();
    }
    let nv_in = input.vertex_count() as usize;
    let n0 = region.verts.len();
    let source = |k: usize| -> Option<usize> {
        // New vertex k (0-based among new ones): an opening copy points to its original.
        let c = k.checked_sub(split_count)?;
        let v = copies_of[c] as usize;
        if v < n0 {
            Some(region.verts[v] as usize)
        } else {
            None
        }
    };
    for (values, default) in [(&a.vertex_sharpness, 0.0)] {
        if values.par_iter().any(|&s| s != 0.0) {
            let o = &mut out.attributes.vertex_sharpness;
            o[..nv_in].copy_from_slice(values);
            for k in 0..sp.new_pos.len() {
                o[nv_in + k] = source(k).map_or(default, |v| values[v]);
            }
        }
    }
    if a.vertex_selection.par_iter().any(|&s| s) {
        let o = &mut out.attributes.vertex_selection;
        o[..nv_in].copy_from_slice(&a.vertex_selection);
        for k in 0..sp.new_pos.len() {
            o[nv_in + k] = source(k).is_some_and(|v| a.vertex_selection[v]);
        }
    }
    let mut sharp = a.edge_sharpness.clone();
    for (e, &[u, w]) in region.edges.iter().enumerate() {
        let on = sp.edge_vertices(e as u32);
        if on.is_empty() {
            continue;
        }
        let (gu, gw) = (global[u as usize], global[w as usize]);
        if let Some(s) = sharp.remove(&(gu.min(gw), gu.max(gw))) {
            let chain: Vec<u32> = std::iter::once(gu)
                .chain(on.iter().map(|&(_, m)| global[m as usize]))
                .chain(std::iter::once(gw))
                .collect();
            for w in chain.windows(2) {
                sharp.insert((w[0].min(w[1]), w[0].max(w[1])), s);
            }
        }
    }
    out.attributes.edge_sharpness = sharp;
}
