//! A cut as a list of edits to the triangulated input, the result of [`super::cut_edits`].
//!
//! A stroke touches a few thousand faces of a mesh that may have millions; building the new
//! mesh is then most of the cost of a cut (a copy of every array). The edits are what
//! changed — moved vertices, new vertices, rewritten and appended triangles — so a caller
//! that keeps its own mesh (an editor's undo stack, a viewport buffer) applies them in
//! O(changes), and [`CutEdits::apply`] builds the whole new mesh when one is wanted.

use glam::DVec3;

use super::geom::map3;
use super::ids::Lv;
use super::interpolate::Provenance;
use super::region::Region;
use super::report::{CutOutput, CutReport};
use super::split_patterns::Splitter;
use super::{assemble, triangulate};
use crate::error::{Error, Result};
use crate::mesh::{FaceId, PolyMesh, VertexId};

/// What a cut changes in the triangulated input (a triangle mesh is its own triangulation:
/// faces keep their ids). Vertex ids are the output's: input vertices keep theirs, new ones
/// follow from [`CutEdits::input_vertex_count`] on.
#[derive(Clone)]
pub struct CutEdits {
    /// Vertices of the input.
    pub input_vertex_count: u32,
    /// Triangles of the triangulated input (the input's face count for a triangle mesh).
    pub input_triangle_count: u32,
    /// Positions of the vertices the cut adds, in id order: split vertices, then the copies
    /// opening made. The moved vertices and their new positions are [`CutReport::moved`].
    pub new_vertices: Vec<DVec3>,
    /// Triangles rewritten in place: (slot, new corners), ascending slot. The slot's face of
    /// the input is its source (materials, UVs).
    pub rewritten_faces: Vec<(FaceId, [VertexId; 3])>,
    /// Triangles added, with the slot of the triangle each one lies in; their ids follow
    /// `input_triangle_count` in this order.
    pub appended_faces: Vec<([VertexId; 3], FaceId)>,
    /// The split input edges' ends and, CSR by `split_start`, the new vertices on each
    /// ([`CutEdits::split_edges`]): one array, not one per edge.
    pub(crate) split_ends: Vec<(VertexId, VertexId)>,
    pub(crate) split_start: Vec<u32>,
    pub(crate) split_on: Vec<VertexId>,
    /// What was done.
    pub report: CutReport,
    /// Opening copies are vertices `first_copy..`; `copy_of[i]` is the vertex copied.
    pub(crate) first_copy: u32,
    pub(crate) copy_of: Vec<u32>,
}

/// As if the split edges were a field of `(end, end, vertices on it)`.
impl std::fmt::Debug for CutEdits {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CutEdits")
            .field("input_vertex_count", &self.input_vertex_count)
            .field("input_triangle_count", &self.input_triangle_count)
            .field("new_vertices", &self.new_vertices)
            .field("rewritten_faces", &self.rewritten_faces)
            .field("appended_faces", &self.appended_faces)
            .field("split_edges", &self.split_edges().collect::<Vec<_>>())
            .field("report", &self.report)
            .field("first_copy", &self.first_copy)
            .field("copy_of", &self.copy_of)
            .finish()
    }
}

impl CutEdits {
    /// The edits of a cut of a mesh with `input_vertex_count` vertices and
    /// `input_triangle_count` triangles once triangulated: the faces the splitter touched,
    /// its new vertices (split vertices, then the opening copies of `copy_of`), the edges it
    /// split; `gid` maps the region's vertices and the new ones to output ids.
    pub(crate) fn collect(
        (input_vertex_count, input_triangle_count): (u32, u32),
        region: &Region,
        mut sp: Splitter,
        copy_of: &[Lv],
        gid: &dyn Fn(Lv) -> VertexId,
        report: CutReport,
    ) -> Self {
        let to_global = |t: &[Lv; 3]| map3(*t, gid);
        let n = sp.touched.len();
        let mut rewritten_faces = Vec::with_capacity(n);
        let mut appended_faces = Vec::with_capacity(2 * n);
        // Ascending faces of the region are ascending triangles: rewritten in order.
        for (f, subs) in sp.touched_in_order() {
            let slot = FaceId(region.triangle(f));
            rewritten_faces.push((slot, to_global(&subs[0])));
            appended_faces.extend(subs[1..].iter().map(|t| (to_global(t), slot)));
        }
        debug_assert!(rewritten_faces.is_sorted_by_key(|x| x.0));
        let n_split = sp.new_pos.len() - copy_of.len();
        let (mut split_ends, mut split_start, mut split_on) = (
            Vec::with_capacity(n_split),
            Vec::with_capacity(n_split + 1),
            Vec::with_capacity(n_split),
        );
        split_start.push(0u32);
        for e in (0..region.edge_count() as u32).map(super::ids::Le) {
            let on = sp.edge_vertices(e);
            if !on.is_empty() {
                let [u, w] = region.ends(e);
                split_ends.push((gid(u), gid(w)));
                split_on.extend(on.iter().map(|&(_, m)| gid(m)));
                split_start.push(split_on.len() as u32);
            }
        }
        let report = CutReport {
            new_vertices: sp.new_pos.len() as u32,
            new_faces: appended_faces.len() as u32,
            ..report
        };
        CutEdits {
            input_vertex_count,
            input_triangle_count,
            new_vertices: std::mem::take(&mut sp.new_pos),
            rewritten_faces,
            appended_faces,
            split_ends,
            split_start,
            split_on,
            report,
            first_copy: input_vertex_count + n_split as u32,
            copy_of: copy_of.iter().map(|&v| gid(v).0).collect(),
        }
    }

    /// Input edges the cut split: (end, end, the new vertices on it from the first end to the
    /// second), ascending by (smaller end, larger end). Edge attributes (sharpness) follow
    /// the pieces.
    pub fn split_edges(&self) -> impl ExactSizeIterator<Item = (VertexId, VertexId, &[VertexId])> {
        self.split_ends.iter().enumerate().map(|(i, &(u, w))| {
            let on = &self.split_on[self.split_start[i] as usize..self.split_start[i + 1] as usize];
            (u, w, on)
        })
    }

    /// Builds the cut mesh from `mesh`, the mesh that was cut: the untouched triangles are
    /// copied in bulk, so this costs about a copy of the mesh.
    ///
    /// Errors: [`Error::InvalidArgument`] when `mesh` is not the mesh that was cut (counts
    /// differ).
    pub fn apply(&self, mesh: &PolyMesh) -> Result<CutOutput> {
        let tris = triangulate::triangles(mesh)?;
        self.apply_to(mesh, &tris)
    }

    pub(crate) fn apply_to(
        &self,
        mesh: &PolyMesh,
        tris: &triangulate::Triangles<'_>,
    ) -> Result<CutOutput> {
        if mesh.vertex_count() != self.input_vertex_count
            || tris.mesh.face_count() != self.input_triangle_count
        {
            return Err(Error::InvalidArgument(format!(
                "the mesh given has {} vertices and {} triangles once triangulated, but the cut \
                 mesh had {} and {}: apply the edits to the mesh that was cut",
                mesh.vertex_count(),
                tris.mesh.face_count(),
                self.input_vertex_count,
                self.input_triangle_count
            )));
        }
        let (mesh_out, face_origin) = assemble::assemble(mesh, tris, self);
        Ok(CutOutput {
            mesh: mesh_out,
            face_origin,
            report: self.report.clone(),
            provenance: Provenance::of(self, &tris.mesh),
        })
    }
}
