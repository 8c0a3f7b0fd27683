//! [`Refiner`]: the subdivision hierarchy of one mesh, built once, through which positions,
//! vertex data, face-varying data and the stencil matrix are interpolated (libigl's
//! "return the operator so any attribute follows"; OpenSubdiv's refiner + primvar split).

use std::collections::BTreeMap;

use glam::DVec3;

use super::face_varying::{self, FaceVarying};
use super::level::Level;
use super::options::SubdivideOptions;
use super::prepare::{prepare, Prepared};
use super::primvar::{Primvar, SparseRow};
use super::refine::{self, Step};
use super::SubdivideReport;
use crate::error::{Error, Result};
use crate::mem::Buf;
use crate::mesh::{validate, FaceId, PolyMesh, VertexId};

/// The refined topology of a mesh, every level kept, ready to interpolate data.
#[derive(Debug, Clone)]
pub struct Refiner {
    /// Levels 0..=L; the last is built without edges.
    levels: Vec<Level>,
    steps: Vec<Step>,
    options: SubdivideOptions,
    report: SubdivideReport,
    /// Level 0's maps to the caller's mesh.
    prepared: Prepared,
    input: Input,
}

/// What a [`Refiner`] keeps of its input: counts for checking callers' data, and level 0's
/// user sharpness (which level 0 itself overrides where the topology forces a crease) for
/// face-varying topologies, which have their own boundaries.
#[derive(Debug, Clone, Default)]
pub(crate) struct Input {
    pub vertices: u32,
    pub faces: u32,
    pub corners: u32,
    /// Per level-0 edge; empty when no edge has sharpness.
    pub user_edge_sharpness: Vec<f32>,
    /// Per level-0 vertex; `None` when no vertex has sharpness.
    pub user_vertex_sharpness: Option<Vec<f32>>,
}

/// Rejects 0 levels and more than 8 (the face count grows 4× per level).
fn check_levels(levels: u32) -> Result<()> {
    if levels == 0 || levels > 8 {
        return Err(Error::InvalidOption {
            option: "levels",
            message: format!("{levels} is outside 1..=8"),
        });
    }
    Ok(())
}

/// The subdivision as a sparse matrix: row `i` gives output vertex `i` as a weighted sum of
/// input vertices (compressed rows: `offsets` has #output + 1 entries).
#[derive(Debug, Clone, PartialEq)]
pub struct Stencils {
    pub offsets: Vec<u32>,
    pub sources: Vec<VertexId>,
    pub weights: Vec<f64>,
}

impl Stencils {
    /// Applies the matrix to per-input-vertex values.
    pub fn apply<T: Primvar>(&self, values: &[T]) -> Vec<T> {
        self.offsets
            .windows(2)
            .map(|w| {
                let mut v = T::zero();
                for k in w[0] as usize..w[1] as usize {
                    v.add_scaled(&values[self.sources[k].idx()], self.weights[k]);
                }
                v
            })
            .collect()
    }
}

impl Refiner {
    /// Builds the hierarchy (topology and rules only, no positions).
    pub fn new(mesh: &PolyMesh, options: &SubdivideOptions) -> Result<Refiner> {
        Self::with_progress(mesh, options, &mut |_, _| {})
    }

    /// [`Refiner::new`], calling `progress(levels_done, levels)` after each level.
    pub fn with_progress(
        mesh: &PolyMesh,
        options: &SubdivideOptions,
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<Refiner> {
        Ok(Self::build(mesh, options, None, progress)?.0)
    }

    /// [`Refiner::with_progress`] that also refines `mesh`'s positions, at the same time:
    /// level l + 1's topology and level l's positions are independent, so they run in
    /// parallel (`rayon::join`). The arithmetic is the same whatever the thread count.
    /// Returns the refiner and the output positions, one per output vertex.
    ///
    /// Errors as [`Refiner::new`], and [`Error::CoordinateOverflow`] when coordinates near
    /// `f64::MAX` make the sums overflow.
    pub fn with_positions(
        mesh: &PolyMesh,
        options: &SubdivideOptions,
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<(Refiner, Vec<DVec3>)> {
        let (refiner, positions) = Self::build(mesh, options, Some(mesh.positions()), progress)?;
        validate::result_positions("subdivision", mesh.positions(), &positions)?;
        Ok((refiner, positions))
    }

    /// Builds the hierarchy and, when `positions` are given, interpolates them alongside
    /// (empty when not given).
    fn build(
        mesh: &PolyMesh,
        options: &SubdivideOptions,
        positions: Option<&[DVec3]>,
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<(Refiner, Vec<DVec3>)> {
        mesh.require_faces("subdivision")?;
        check_levels(options.levels)?;
        let mut report = SubdivideReport::default();
        let prepared = prepare(mesh, options, &mut report)?;
        let m0 = prepared.mesh(mesh);
        let (level0, user_edge_sharpness) = Level::from_mesh(m0, options)?;
        let user_vertex_sharpness = m0
            .vertex_sharpness()
            .iter()
            .any(|&s| s > 0.0)
            .then(|| m0.vertex_sharpness().iter().map(|&s| s as f32).collect());
        let pos: Option<Buf<DVec3>> = positions.map(|p| match &prepared.vertex_origin {
            None => p.to_vec().into(),
            Some(o) => o.iter().map(|&v| p[v as usize]).collect::<Vec<_>>().into(),
        });
        let input = Input {
            vertices: mesh.vertex_count(),
            faces: mesh.face_count(),
            corners: mesh.corner_count(),
            user_edge_sharpness,
            user_vertex_sharpness,
        };
        let (refiner, positions) =
            Self::from_level0(level0, prepared, input, options, report, pos, progress);
        Ok((refiner, positions.unwrap_or_default()))
    }

    /// The hierarchy over a level 0 already built (and its maps to the caller's mesh);
    /// `values` given are interpolated beside the topology, as in [`Refiner::build`].
    pub(crate) fn from_level0<T: Primvar>(
        level0: Level,
        prepared: Prepared,
        input: Input,
        options: &SubdivideOptions,
        report: SubdivideReport,
        mut values: Option<Buf<T>>,
        progress: &mut dyn FnMut(u32, u32),
    ) -> (Refiner, Option<Vec<T>>) {
        let mut levels = vec![level0];
        let mut steps = vec![refine::plan(
            &levels[0],
            options.crease_method,
            prepared.face_points.clone(),
        )];
        for l in 0..options.levels as usize {
            let last = l + 1 == options.levels as usize;
            let (parent, step) = (&levels[l], &steps[l]);
            let ((child, child_step), child_values) = rayon::join(
                || {
                    let child = refine::child_level(parent, step, last);
                    let s =
                        (!last).then(|| refine::plan(&child, options.crease_method, Vec::new()));
                    (child, s)
                },
                || {
                    values
                        .as_deref()
                        .map(|p| refine::interpolate(parent, step, p, last))
                },
            );
            levels.push(child);
            if let Some(s) = child_step {
                steps.push(s);
            }
            values = child_values;
            progress(l as u32 + 1, options.levels);
        }
        let refiner = Refiner {
            levels,
            steps,
            options: options.clone(),
            report,
            prepared,
            input,
        };
        (refiner, values.map(Buf::into_vec))
    }

    /// Number of levels.
    pub fn levels(&self) -> u32 {
        self.steps.len() as u32
    }
    /// Number of vertices of the refined mesh.
    pub fn vertex_count(&self) -> u32 {
        self.last().vertex_count
    }
    /// Number of face corners of the refined mesh.
    pub fn corner_count(&self) -> u32 {
        self.last().corner_verts.len() as u32
    }
    /// What was done differently from what was asked.
    pub fn report(&self) -> &SubdivideReport {
        &self.report
    }
    /// The options the hierarchy was built with.
    pub fn options(&self) -> &SubdivideOptions {
        &self.options
    }
    fn last(&self) -> &Level {
        self.levels.last().expect("a refiner has levels")
    }

    /// For each output face, the input face it comes from.
    pub fn face_origin(&self) -> Vec<FaceId> {
        let last = &self.last().face_origin;
        match &self.prepared.face_origin {
            None => last.iter().map(|&f| FaceId(f)).collect(),
            Some(o) => last.iter().map(|&f| FaceId(o[f as usize])).collect(),
        }
    }

    /// Number of face corners of the input mesh (face-varying indices expected).
    pub fn input_corner_count(&self) -> u32 {
        self.input.corners
    }

    /// Number of vertices of the input mesh.
    pub fn input_vertex_count(&self) -> u32 {
        self.input.vertices
    }

    /// Number of faces of the input mesh.
    pub fn input_face_count(&self) -> u32 {
        self.input.faces
    }

    /// What the refiner keeps of its input.
    pub(crate) fn input(&self) -> &Input {
        &self.input
    }

    /// Input corner of each level-0 corner (`None`: the identity).
    pub(crate) fn corner_origin(&self) -> Option<&[u32]> {
        self.prepared.corner_origin.as_deref()
    }

    /// Interpolates per-input-vertex data (positions, colours, weights) to the output
    /// vertices with the subdivision rules (OpenSubdiv's "vertex" interpolation).
    pub fn refine_vertex_data<T: Primvar>(&self, values: &[T]) -> Result<Vec<T>> {
        if values.len() != self.input.vertices as usize {
            return Err(Error::AttributeLength {
                attribute: "vertex data",
                per: "input vertex",
                expected: self.input.vertices as usize,
                got: values.len(),
            });
        }
        Ok(self.interpolate_with_progress(values, &mut |_, _| {}))
    }

    /// Interpolation of values known to have the right length.
    pub(crate) fn interpolate_with_progress<T: Primvar>(
        &self,
        values: &[T],
        progress: &mut dyn FnMut(u32, u32),
    ) -> Vec<T> {
        let n = self.levels();
        let mapped: Vec<T>;
        let values = match &self.prepared.vertex_origin {
            None => values,
            Some(o) => {
                mapped = o.iter().map(|&v| values[v as usize].clone()).collect();
                &mapped
            }
        };
        let mut cur = refine::interpolate(&self.levels[0], &self.steps[0], values, n == 1);
        progress(1, n);
        for l in 1..n as usize {
            let last = l + 1 == n as usize;
            cur = refine::interpolate(&self.levels[l], &self.steps[l], &cur, last);
            progress(l as u32 + 1, n);
        }
        cur.into_vec()
    }

    /// The stencil matrix from input vertices to output vertices.
    pub fn stencils(&self) -> Stencils {
        let identity: Vec<SparseRow> = (0..self.input.vertices)
            .map(|v| SparseRow(vec![(v, 1.0)]))
            .collect();
        let rows = self.interpolate_with_progress(&identity, &mut |_, _| {});
        let mut s = Stencils {
            offsets: Vec::with_capacity(rows.len() + 1),
            sources: Vec::new(),
            weights: Vec::new(),
        };
        s.offsets.push(0);
        for r in rows {
            for (v, w) in r.0 {
                s.sources.push(VertexId(v));
                s.weights.push(w);
            }
            s.offsets.push(s.sources.len() as u32);
        }
        s
    }

    /// Interpolates face-varying data (UVs): `values` indexed by `indices`, one index per
    /// input face corner in [`PolyMesh::corners`] order. Returns one value per output corner,
    /// in the output mesh's corner order.
    pub fn refine_face_varying<T: Primvar>(
        &self,
        values: &[T],
        indices: &[u32],
        mode: FaceVarying,
    ) -> Result<Vec<T>> {
        face_varying::refine(self, values, indices, mode)
    }

    /// Level `l` (0 to [`Refiner::levels`]).
    pub(crate) fn level(&self, l: usize) -> &Level {
        &self.levels[l]
    }

    /// The refinement of level `l` into level `l + 1`.
    pub(crate) fn step(&self, l: usize) -> &Step {
        &self.steps[l]
    }

    /// The last level's corner vertices, consuming the refiner.
    pub(crate) fn into_last_corners(mut self) -> Vec<u32> {
        let last = self.levels.pop().expect("a refiner has levels");
        last.corner_verts.into_vec()
    }

    /// The output mesh with the given positions (one per output vertex, all finite), carrying
    /// the creases that remain after refinement. Errors: [`Error::AttributeLength`] for a
    /// wrong count, [`Error::NonFiniteCoordinate`] naming the first non-finite position.
    pub fn mesh(&self, positions: Vec<DVec3>) -> Result<PolyMesh> {
        self.check_positions(&positions)?;
        Ok(Self::assemble(self.last().clone(), positions))
    }

    /// [`Refiner::mesh`], consuming the refiner to reuse its arrays.
    pub fn into_mesh(self, positions: Vec<DVec3>) -> Result<PolyMesh> {
        self.check_positions(&positions)?;
        Ok(self.into_parts(positions).0)
    }

    fn check_positions(&self, positions: &[DVec3]) -> Result<()> {
        let expected = self.vertex_count() as usize;
        if positions.len() != expected {
            return Err(Error::AttributeLength {
                attribute: "positions",
                per: "output vertex",
                expected,
                got: positions.len(),
            });
        }
        validate::positions(positions)
    }

    /// The output mesh and [`Refiner::face_origin`], consuming the refiner: its arrays become
    /// the result's without copies. `positions` must have passed [`Refiner::check_positions`].
    pub(crate) fn into_parts(mut self, positions: Vec<DVec3>) -> (PolyMesh, Vec<FaceId>) {
        let mut last = self.levels.pop().expect("a refiner has levels");
        let origin = std::mem::take(&mut last.face_origin).into_vec();
        let face_origin: Vec<FaceId> = match self.prepared.face_origin.take() {
            // u32 → FaceId in place (same layout).
            None => origin.into_iter().map(FaceId).collect(),
            Some(o) => origin.into_iter().map(|f| FaceId(o[f as usize])).collect(),
        };
        // Freeing the other levels (unmapping their pages) overlaps the assembly.
        let mesh = rayon::join(move || drop(self), || Self::assemble(last, positions)).1;
        (mesh, face_origin)
    }

    fn assemble(level: Level, positions: Vec<DVec3>) -> PolyMesh {
        debug_assert_eq!(positions.len(), level.vertex_count as usize);
        let edge_sharpness: BTreeMap<(u32, u32), f64> = level
            .last_creases
            .iter()
            .map(|&([a, b], s)| ((a.min(b), a.max(b)), s as f64))
            .collect();
        // Only when some vertex keeps a user's sharpness: the zeroed default costs nothing.
        let user_sharp = level.any_vertex_sharp
            && level
                .vertex_sharpness
                .iter()
                .zip(level.vertex_forced.iter())
                .any(|(&s, &forced)| s > 0.0 && !forced);
        let vertex_sharpness: Option<Vec<f64>> = user_sharp.then(|| {
            level
                .vertex_sharpness
                .iter()
                .zip(level.vertex_forced.iter())
                .map(|(&s, &forced)| if forced { 0.0 } else { s as f64 })
                .collect()
        });
        let corners = level
            .corner_verts
            .into_vec()
            .into_iter()
            .map(VertexId)
            .collect();
        let mut mesh = PolyMesh::from_parts_unchecked(
            positions,
            level.face_loops.into_vec(),
            level.loop_offsets.into_vec(),
            corners,
        );
        mesh.attributes.edge_sharpness = edge_sharpness;
        if let Some(vs) = vertex_sharpness {
            mesh.attributes.vertex_sharpness = vs;
        }
        mesh
    }
}
