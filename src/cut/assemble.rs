//! The output mesh from the edits: the untouched faces are copied in bulk (slot `f` stays face
//! `f`), rewritten slots overwritten, appended faces added; positions are copied with the
//! snapped vertices moved and the new ones appended. No whole-mesh validation (the pieces are
//! valid by construction; debug builds check).

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;
use rayon::prelude::*;

use super::edits::CutEdits;
use super::interpolate::original;
use super::triangulate::Triangles;
use crate::mem;
use crate::mesh::{FaceId, PolyMesh, VertexId};

/// The cut mesh and each face's input face.
pub(crate) fn assemble(
    input: &PolyMesh,
    tris: &Triangles<'_>,
    edits: &CutEdits,
) -> (PolyMesh, Vec<FaceId>) {
    let tm: &PolyMesh = &tris.mesh;
    // Output arrays: pages advised huge before the first write (crate::mem), filled by
    // rayon in place — at 1M faces the copy is page faults more than bytes.
    let nv = tm.vertex_count() as usize;
    let mut positions: Vec<DVec3> = mem::with_capacity(nv + edits.new_vertices.len());
    positions.par_extend(tm.positions().par_iter().copied());
    for m in &edits.report.moved {
        positions[m.vertex.idx()] = m.to;
    }
    positions.extend_from_slice(&edits.new_vertices);

    let nf = tm.face_count() as usize;
    let nf_out = nf + edits.appended_faces.len();
    let mut corners: Vec<VertexId> = mem::with_capacity(3 * nf_out);
    corners.par_extend(tm.corners().par_iter().copied());
    for (slot, t) in &edits.rewritten_faces {
        corners[3 * slot.idx()..3 * slot.idx() + 3].copy_from_slice(t);
    }
    for (t, _) in &edits.appended_faces {
        corners.extend_from_slice(t);
    }
    let mut face_loop_offsets: Vec<u32> = mem::with_capacity(nf_out + 1);
    face_loop_offsets.par_extend((0..nf_out as u32 + 1).into_par_iter());
    let mut loop_offsets: Vec<u32> = mem::with_capacity(nf_out + 1);
    loop_offsets.par_extend((0..nf_out as u32 + 1).into_par_iter().map(|i| 3 * i));
    let origin_of = |t: u32| match &tris.origin {
        Some(o) => o[t as usize],
        None => FaceId(t),
    };
    let mut face_origin: Vec<FaceId> = mem::with_capacity(nf_out);
    face_origin.par_extend((0..nf as u32).into_par_iter().map(origin_of));
    face_origin.extend(edits.appended_faces.iter().map(|&(_, s)| origin_of(s.0)));
    let mut mesh =
        PolyMesh::from_parts_unchecked(positions, face_loop_offsets, loop_offsets, corners);
    carry_attributes(input, &mut mesh, &face_origin, edits);
    (mesh, face_origin)
}

/// Face labels and selections follow `face_origin`; vertex sharpness and selection stay on
/// the input's vertices (an opening copy takes its original's); a sharp edge split in two
/// stays sharp on both halves.
fn carry_attributes(input: &PolyMesh, out: &mut PolyMesh, face_origin: &[FaceId], e: &CutEdits) {
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
    // The input vertex a new vertex copies, if it is an opening copy of one.
    let source = |k: usize| -> Option<usize> {
        let v = original(e.first_copy, &e.copy_of, (nv_in + k) as u32) as usize;
        (v < nv_in).then_some(v)
    };
    if a.vertex_sharpness.par_iter().any(|&s| s != 0.0) {
        let o = &mut out.attributes.vertex_sharpness;
        o[..nv_in].copy_from_slice(&a.vertex_sharpness);
        for k in 0..e.new_vertices.len() {
            o[nv_in + k] = source(k).map_or(0.0, |v| a.vertex_sharpness[v]);
        }
    }
    if a.vertex_selection.par_iter().any(|&s| s) {
        let o = &mut out.attributes.vertex_selection;
        o[..nv_in].copy_from_slice(&a.vertex_selection);
        for k in 0..e.new_vertices.len() {
            o[nv_in + k] = source(k).is_some_and(|v| a.vertex_selection[v]);
        }
    }
    let mut sharp = a.edge_sharpness.clone();
    for (u, w, on) in e.split_edges() {
        if let Some(s) = sharp.remove(&(u.0.min(w.0), u.0.max(w.0))) {
            let chain: Vec<u32> = std::iter::once(u.0)
                .chain(on.iter().map(|m| m.0))
                .chain(std::iter::once(w.0))
                .collect();
            for w in chain.windows(2) {
                sharp.insert((w[0].min(w[1]), w[0].max(w[1])), s);
            }
        }
    }
    follow_opening(&mut sharp, out, e);
    out.attributes.edge_sharpness = sharp;
}

/// A sharp edge at a vertex the opening copied: after the opening the edge runs between the
/// vertices or copies whose faces hold it (one side of the slit, or both for an edge along
/// it), and the sharpness goes to each edge that exists, none to one that no longer does
/// (a crease on a missing edge makes an OBJ katachi cannot read back).
fn follow_opening(sharp: &mut BTreeMap<(u32, u32), f64>, out: &PolyMesh, e: &CutEdits) {
    if e.copy_of.is_empty() || sharp.is_empty() {
        return;
    }
    // Each copied vertex with its copies.
    let mut variants: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for (i, &v) in e.copy_of.iter().enumerate() {
        variants
            .entry(v)
            .or_insert_with(|| vec![v])
            .push(e.first_copy + i as u32);
    }
    let at_copied: Vec<((u32, u32), f64)> = sharp
        .iter()
        .filter(|(&(a, b), _)| variants.contains_key(&a) || variants.contains_key(&b))
        .map(|(&k, &s)| (k, s))
        .collect();
    if at_copied.is_empty() {
        return;
    }
    let touched: BTreeSet<u32> = variants.values().flatten().copied().collect();
    let mut edges: BTreeSet<(u32, u32)> = BTreeSet::new();
    for t in out.corners().chunks_exact(3) {
        if t.iter().any(|v| touched.contains(&v.0)) {
            for i in 0..3 {
                let (a, b) = (t[i].0, t[(i + 1) % 3].0);
                edges.insert((a.min(b), a.max(b)));
            }
        }
    }
    let of = |v: u32| variants.get(&v).cloned().unwrap_or_else(|| vec![v]);
    for ((a, b), s) in at_copied {
        sharp.remove(&(a, b));
        for &x in &of(a) {
            for &y in &of(b) {
                let k = (x.min(y), x.max(y));
                if edges.contains(&k) {
                    sharp.insert(k, s);
                }
            }
        }
    }
}
