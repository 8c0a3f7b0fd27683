//! # katachi-reference
//!
//! Reference Catmull-Clark subdivision from **OpenSubdiv 3.5** (Far) and **OpenMesh 9**
//! (`CatmullClarkT`), for katachi's tests and benchmarks only. A small C++ shim
//! (`shim/`, C linkage, plain arrays, caller-freed result handles, no C++ exception crosses into
//! Rust) is compiled by `build.rs` and bound with bindgen. Also CGAL's exact stroke cut
//! ([`cgal_stroke_cut`]) and Boost.Graph's Boykov–Kolmogorov max-flow ([`boost_bk_max_flow`],
//! the reference for rough-model segmentation).
//!
//! Building this crate needs the Debian packages libosd-dev, libopenmesh-dev, libcgal-dev (with
//! libgmp-dev and libmpfr-dev), libboost-graph-dev, libclang-dev and g++ (`cargo xtask deps` installs them); plain
//! `cargo build` / `cargo test` at the workspace root never builds it.
//!
//! Everything is `f64`: OpenSubdiv interpolates with `Far::PrimvarRefinerReal<double>` and a
//! double-precision vertex type (the default `Far::PrimvarRefiner` weighs in `float`), and
//! OpenMesh runs on a `PolyMesh_ArrayKernelT` whose points are `OpenMesh::Vec3d`. OpenSubdiv
//! stores sharpness as `float`: values given here are rounded to `f32` on the way in, and the
//! sharpness it reports is widened back to `f64`.
//!
//! ## OpenSubdiv's orderings (observed with libosd-dev 3.5.0; `tests/reference.rs` checks them)
//!
//! - **Child vertices** of a uniform refinement step (default `UniformOptions`,
//!   `orderVerticesFromFacesFirst = false`): first the children of the parent **vertices**
//!   (vertex points, in parent vertex order), then those of the parent **faces** (face points, in
//!   parent face order), then those of the parent **edges** (edge points, in OpenSubdiv's edge
//!   order, see [`OsdLevel::edges`]). So the input vertex `v` is vertex `v` at every level, face
//!   `f` gives vertex `V + f` and edge `e` gives vertex `V + F + e`. [`OsdLevelInfo::refinements`]
//!   gives the maps and [`ChildVertexOrder`] the ranges.
//! - **Child faces**: the children of parent face `f` are consecutive, in parent face order, one
//!   per parent corner. For a parent with corners `(v_0 .. v_{k-1})` and edges
//!   `e_j = (v_j, v_{j+1})`, child face `j` is the quad `(v_j', e_j', f', e_{j-1}')` — starting at
//!   the child of corner `v_j` — **except for quad parents**, where that cycle is rotated so that
//!   `v_j'` is corner `j` of child `j`: child 0 = `(v_0', e_0', f', e_3')`, child 1 =
//!   `(e_0', v_1', e_1', f')`, child 2 = `(f', e_1', v_2', e_2')`, child 3 = `(e_3', f', e_2', v_3')`.
//!   The parent's orientation is kept.
//! - **Edges**: base edges are numbered as OpenSubdiv meets them walking the faces in order, each
//!   face's edges in corner order (`(v_0, v_1)`, `(v_1, v_2)`, ...), keeping the first direction
//!   met. Child edges: first the edges inside each parent face (face point to the edge points of
//!   its edges, in face and edge order), then the two halves of each parent edge (in parent edge
//!   order; half `k` is `(e', v_k')` at the parent edge's vertex `k`).
//!
//! ## Exact stroke cut (CGAL 5)
//!
//! [`cgal_stroke_cut`] is the exact reference for katachi's stroke cut (seed 002, issue 5): every
//! stroke segment clipped to every face under it is a constraint of a constrained Delaunay
//! triangulation of that face's screen image, with exact predicates and constructions, and the new
//! vertices are lifted back onto the face. It counts the new triangles and measures their minimum
//! angles, the figures the paper's simpler cut is compared on. [`cut_setup`] builds views and
//! strokes for a model, so that the kernel's comparison test uses the same ones.
//!
//! OpenMesh keeps the input vertices first, in input order, too; its other vertices and its
//! faces come in its own order (compare meshes by position, as `tests/reference.rs` does).
//!
//! ## Errors
//!
//! Every function returns `Err(String)` instead of panicking: `"bad argument: ..."` for malformed
//! input (indices out of range, sizes that do not add up, non-finite values, a level above
//! [`MAX_LEVEL`]), `"rejected: ..."` when a library refuses the input (OpenMesh's "complex edge";
//! any warning of OpenSubdiv's factory, such as a crease on a vertex pair that is no edge, which
//! OpenSubdiv itself would only print), `"C++ exception: ..."` otherwise.
//!
//! ## Example
//!
//! ```
//! use katachi_reference::{osd_catmark, Creases, OsdOptions, RefMesh};
//! let quad = RefMesh {
//!     positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
//!     face_sizes: vec![4],
//!     face_vertices: vec![0, 1, 2, 3],
//! };
//! let refined = osd_catmark(&quad, &Creases::default(), &OsdOptions::default(), 2).unwrap();
//! assert_eq!(refined.face_sizes.len(), 16);
//! ```

use std::collections::BTreeMap;
use std::ops::Range;
use std::time::Duration;

pub mod cut_setup;
pub mod flow_graphs;
pub mod gmsh;

#[allow(
    non_camel_case_types,
    non_upper_case_globals,
    non_snake_case,
    dead_code,
    unused_qualifications,
    clippy::all
)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/bindings.rs"));
}

/// The highest refinement level the shim accepts.
pub const MAX_LEVEL: u32 = sys::KR_MAX_LEVEL;

/// A polygon mesh in flat arrays, the form both reference libraries take and return.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RefMesh {
    /// Vertex positions, #V.
    pub positions: Vec<[f64; 3]>,
    /// Corner count of each face, #F (each >= 3).
    pub face_sizes: Vec<u32>,
    /// Vertex indices of all faces, concatenated in face order (sum of `face_sizes`).
    pub face_vertices: Vec<u32>,
}

impl RefMesh {
    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.positions.len()
    }

    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.face_sizes.len()
    }

    /// The faces as slices of vertex indices. Stops early if `face_sizes` claims more corners
    /// than `face_vertices` holds.
    pub fn faces(&self) -> impl Iterator<Item = &[u32]> + '_ {
        let mut start = 0usize;
        self.face_sizes.iter().map_while(move |&n| {
            let end = start + n as usize;
            let face = self.face_vertices.get(start..end)?;
            start = end;
            Some(face)
        })
    }

    /// The undirected edges, each as `[min, max]`, sorted and without duplicates.
    pub fn edges(&self) -> Vec<[u32; 2]> {
        let mut edges: Vec<[u32; 2]> = self
            .faces()
            .flat_map(|f| {
                (0..f.len()).map(move |i| {
                    let (a, b) = (f[i], f[(i + 1) % f.len()]);
                    [a.min(b), a.max(b)]
                })
            })
            .collect();
        edges.sort_unstable();
        edges.dedup();
        edges
    }
}

/// Boundary interpolation of vertex data (OpenSubdiv `Sdc::Options::VtxBoundaryInterpolation`).
///
/// Default value: `EdgeOnly` (katachi's default; OpenSubdiv's own `Sdc::Options` default is `None`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Boundary {
    /// `VTX_BOUNDARY_NONE`: boundary edges are not sharpened (for limit surfaces).
    None,
    /// `VTX_BOUNDARY_EDGE_ONLY`: boundary edges are infinitely sharp.
    #[default]
    EdgeOnly,
    /// `VTX_BOUNDARY_EDGE_AND_CORNER`: also vertices with a single face are corners.
    EdgeAndCorner,
}

/// How semi-sharp creases decay from level to level (OpenSubdiv `Sdc::Options::CreasingMethod`).
///
/// Default value: `Uniform` (OpenSubdiv's default).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CreaseMethod {
    /// `CREASE_UNIFORM`: a child edge gets `s - 1`.
    #[default]
    Uniform,
    /// `CREASE_CHAIKIN`: a child edge blends its parent's sharpness with its neighbours'.
    Chaikin,
}

/// Face-varying interpolation (OpenSubdiv `Sdc::Options::FVarLinearInterpolation`).
///
/// Default value: `All` (OpenSubdiv's default).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FVarLinear {
    /// `FVAR_LINEAR_NONE`: smooth everywhere.
    None,
    /// `FVAR_LINEAR_CORNERS_ONLY`: sharpen corners only.
    CornersOnly,
    /// `FVAR_LINEAR_CORNERS_PLUS1`.
    CornersPlus1,
    /// `FVAR_LINEAR_CORNERS_PLUS2`.
    CornersPlus2,
    /// `FVAR_LINEAR_BOUNDARIES`: sharpen all boundaries.
    Boundaries,
    /// `FVAR_LINEAR_ALL`: bilinear interpolation.
    #[default]
    All,
}

/// Options of an OpenSubdiv run. Default value: see each field's type.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct OsdOptions {
    /// Vertex boundary interpolation.
    pub boundary: Boundary,
    /// Crease decay.
    pub crease: CreaseMethod,
    /// Face-varying interpolation (used by [`osd_catmark_fvar`]).
    pub fvar: FVarLinear,
}

/// Edge and vertex (corner) sharpness, OpenSubdiv semantics: 0 smooth, >= 10 infinitely sharp.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Creases {
    /// Creased edges as vertex pairs; each must be an edge of the mesh.
    pub edges: Vec<[u32; 2]>,
    /// Sharpness of each creased edge (same length as `edges`).
    pub edge_sharpness: Vec<f64>,
    /// Sharp vertices.
    pub corners: Vec<u32>,
    /// Sharpness of each sharp vertex (same length as `corners`).
    pub corner_sharpness: Vec<f64>,
}

/// OpenSubdiv's vertex rule (`Sdc::Crease::Rule`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VertexRule {
    /// `RULE_UNKNOWN` (not yet assigned).
    Unknown,
    /// `RULE_SMOOTH`.
    Smooth,
    /// `RULE_DART`: one sharp edge.
    Dart,
    /// `RULE_CREASE`: two sharp edges.
    Crease,
    /// `RULE_CORNER`: three or more sharp edges, or a sharp vertex.
    Corner,
}

impl VertexRule {
    fn from_osd(rule: u32) -> Self {
        match rule {
            1 => VertexRule::Smooth,
            2 => VertexRule::Dart,
            4 => VertexRule::Crease,
            8 => VertexRule::Corner,
            _ => VertexRule::Unknown,
        }
    }
}

/// Tags OpenSubdiv keeps on an edge or a vertex.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Tags {
    /// On the boundary.
    pub boundary: bool,
    /// Non-manifold (an edge with more than two faces, or a vertex whose faces are not one fan).
    pub non_manifold: bool,
    /// Infinitely sharp.
    pub inf_sharp: bool,
    /// Semi-sharp (finite non-zero sharpness).
    pub semi_sharp: bool,
}

impl Tags {
    fn from_bits(bits: u32) -> Self {
        Tags {
            boundary: bits & 1 != 0,
            non_manifold: bits & 2 != 0,
            inf_sharp: bits & 4 != 0,
            semi_sharp: bits & 8 != 0,
        }
    }
}

/// One level of an OpenSubdiv refinement, as OpenSubdiv numbers it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OsdLevel {
    /// Positions (interpolated with `PrimvarRefinerReal<double>`) and faces of this level.
    pub mesh: RefMesh,
    /// Number of vertices.
    pub num_vertices: usize,
    /// Number of edges.
    pub num_edges: usize,
    /// Number of faces.
    pub num_faces: usize,
    /// The two vertices of each edge, in OpenSubdiv's edge order (not sorted).
    pub edges: Vec<[u32; 2]>,
    /// Sharpness of each edge (OpenSubdiv's `float`, widened).
    pub edge_sharpness: Vec<f64>,
    /// Tags of each edge.
    pub edge_tags: Vec<Tags>,
    /// Sharpness of each vertex.
    pub vertex_sharpness: Vec<f64>,
    /// Rule of each vertex.
    pub vertex_rule: Vec<VertexRule>,
    /// Tags of each vertex.
    pub vertex_tags: Vec<Tags>,
}

impl OsdLevel {
    /// Edge sharpness keyed by the edge's vertex pair `[min, max]`.
    pub fn sharpness_by_vertex_pair(&self) -> BTreeMap<[u32; 2], f64> {
        self.edges
            .iter()
            .zip(&self.edge_sharpness)
            .map(|(&[a, b], &s)| ([a.min(b), a.max(b)], s))
            .collect()
    }

    /// The sharpness of the edge between `a` and `b`, if they share an edge.
    pub fn edge_sharpness_between(&self, a: u32, b: u32) -> Option<f64> {
        self.edges
            .iter()
            .position(|&[x, y]| (x, y) == (a, b) || (x, y) == (b, a))
            .map(|e| self.edge_sharpness[e])
    }
}

/// Where the children of each kind of parent element sit among a level's vertices.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ChildVertexOrder {
    /// Child vertices of parent faces (face points).
    pub from_faces: Range<u32>,
    /// Child vertices of parent edges (edge points).
    pub from_edges: Range<u32>,
    /// Child vertices of parent vertices (vertex points).
    pub from_vertices: Range<u32>,
    /// Every map is `child = range.start + parent index` (children in parent order).
    pub sequential: bool,
}

/// How OpenSubdiv refined level `l` into level `l + 1`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OsdRefinement {
    /// Child vertex of each parent face.
    pub face_child_vertex: Vec<u32>,
    /// Child vertex of each parent edge.
    pub edge_child_vertex: Vec<u32>,
    /// Child vertex of each parent vertex.
    pub vertex_child_vertex: Vec<u32>,
    /// Child faces of each parent face (one per parent corner, in corner order).
    pub face_child_faces: Vec<Vec<u32>>,
    /// The two child edges of each parent edge.
    pub edge_child_edges: Vec<[u32; 2]>,
    /// Parent face of each child face.
    pub child_face_parent: Vec<u32>,
    /// The ranges of the three maps above.
    pub order: ChildVertexOrder,
}

/// Everything OpenSubdiv knows about every level of a uniform refinement, for diagnosis.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OsdLevelInfo {
    /// Levels `0..=level`.
    pub levels: Vec<OsdLevel>,
    /// Refinements `l -> l + 1` for `l` in `0..level`.
    pub refinements: Vec<OsdRefinement>,
}

/// OpenSubdiv uniform Catmull-Clark refinement to `level` (0..=[`MAX_LEVEL`]): a refiner from
/// `TopologyRefinerFactory<TopologyDescriptor>` (creases and corners as its crease and corner
/// arrays), `RefineUniform`, and positions interpolated with `Far::PrimvarRefinerReal<double>`
/// level by level. Returns the last level's mesh, vertices and faces in OpenSubdiv's order (see
/// the crate docs).
///
/// The last level is refined without `fullTopologyInLastLevel` (its faces are all this needs, and
/// full topology costs 2-3x the refinement time at level 3); [`osd_level_info`] refines with it.
/// Both give the same mesh.
///
/// Non-manifold input (an edge with three faces) is accepted, as OpenSubdiv accepts it.
pub fn osd_catmark(
    mesh: &RefMesh,
    creases: &Creases,
    opts: &OsdOptions,
    level: u32,
) -> Result<RefMesh, String> {
    let r = run_osd(mesh, creases, opts, level, None, false)?;
    r.mesh(level)
}

/// Time spent inside a reference library during one call, measured by the shim with a steady
/// clock around the library calls only (not the shim's argument checks and copying), for
/// benchmarks that compare katachi with the libraries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RefTimings {
    /// OpenSubdiv: `TopologyRefinerFactory::Create`. OpenMesh: building the `PolyMesh`.
    pub build: Duration,
    /// OpenSubdiv: `RefineUniform` (topology of all levels). OpenMesh: `CatmullClarkT` (topology
    /// and positions together).
    pub refine: Duration,
    /// OpenSubdiv: `PrimvarRefinerReal<double>::Interpolate` of the positions, all levels,
    /// with the allocation of each level's destination buffer.
    /// OpenMesh: zero (counted in `refine`).
    pub interpolate: Duration,
}

impl RefTimings {
    /// The sum of the three parts.
    pub fn total(&self) -> Duration {
        self.build + self.refine + self.interpolate
    }

    fn from_seconds(s: &[f64]) -> Self {
        let d = |i: usize| Duration::from_secs_f64(s.get(i).copied().unwrap_or(0.0).max(0.0));
        RefTimings {
            build: d(0),
            refine: d(1),
            interpolate: d(2),
        }
    }
}

/// As [`osd_catmark`], also returning the time spent inside OpenSubdiv.
pub fn osd_catmark_timed(
    mesh: &RefMesh,
    creases: &Creases,
    opts: &OsdOptions,
    level: u32,
) -> Result<(RefMesh, RefTimings), String> {
    let r = run_osd(mesh, creases, opts, level, None, false)?;
    let timings = RefTimings::from_seconds(&r.f64(sys::KR_F64_TIMINGS, 0));
    Ok((r.mesh(level)?, timings))
}

/// As [`osd_catmark`], also interpolating one face-varying channel: `uv` holds the values and
/// `uv_indices` gives, for every face corner of `mesh` (in `face_vertices` order), the index of its
/// value. Returns the refined mesh and one value per face corner of it (in its `face_vertices`
/// order), interpolated with `opts.fvar`.
pub fn osd_catmark_fvar(
    mesh: &RefMesh,
    creases: &Creases,
    opts: &OsdOptions,
    level: u32,
    uv: &[[f64; 2]],
    uv_indices: &[u32],
) -> Result<(RefMesh, Vec<[f64; 2]>), String> {
    let r = run_osd(mesh, creases, opts, level, Some((uv, uv_indices)), false)?;
    let refined = r.mesh(level)?;
    let values = pairs(r.f64_slice(sys::KR_F64_FVAR, level));
    if values.len() != refined.face_vertices.len() {
        return Err(format!(
            "internal: {} face-varying values for {} face corners",
            values.len(),
            refined.face_vertices.len()
        ));
    }
    Ok((refined, values))
}

/// Runs [`osd_catmark`] and returns, for every level, OpenSubdiv's counts, topology, edge and
/// vertex sharpness, rules and tags, and for every step its child maps.
pub fn osd_level_info(
    mesh: &RefMesh,
    creases: &Creases,
    opts: &OsdOptions,
    level: u32,
) -> Result<OsdLevelInfo, String> {
    let r = run_osd(mesh, creases, opts, level, None, true)?;
    let mut info = OsdLevelInfo::default();
    for l in 0..=level {
        let counts = r.u32(sys::KR_U32_COUNTS, l);
        let [nv, ne, nf] = match counts[..] {
            [v, e, f, _] => [v as usize, e as usize, f as usize],
            _ => return Err(format!("internal: no counts for level {l}")),
        };
        let lev = OsdLevel {
            mesh: r.mesh(l)?,
            num_vertices: nv,
            num_edges: ne,
            num_faces: nf,
            edges: r
                .u32(sys::KR_U32_EDGE_VERTICES, l)
                .chunks_exact(2)
                .map(|c| [c[0], c[1]])
                .collect(),
            edge_sharpness: r.f64(sys::KR_F64_EDGE_SHARPNESS, l),
            edge_tags: r
                .u32(sys::KR_U32_EDGE_FLAGS, l)
                .into_iter()
                .map(Tags::from_bits)
                .collect(),
            vertex_sharpness: r.f64(sys::KR_F64_VERTEX_SHARPNESS, l),
            vertex_rule: r
                .u32(sys::KR_U32_VERTEX_RULE, l)
                .into_iter()
                .map(VertexRule::from_osd)
                .collect(),
            vertex_tags: r
                .u32(sys::KR_U32_VERTEX_FLAGS, l)
                .into_iter()
                .map(Tags::from_bits)
                .collect(),
        };
        info.levels.push(lev);
    }
    for l in 0..level {
        let parent = &info.levels[l as usize];
        let flat = r.u32(sys::KR_U32_FACE_CHILD_FACES, l);
        let mut face_child_faces = Vec::with_capacity(parent.num_faces);
        let mut start = 0usize;
        for &n in &parent.mesh.face_sizes {
            let end = start + n as usize;
            let children = flat
                .get(start..end)
                .ok_or_else(|| format!("internal: short child-face map at level {l}"))?;
            face_child_faces.push(children.to_vec());
            start = end;
        }
        let face_child_vertex = r.u32(sys::KR_U32_FACE_CHILD_VERTEX, l);
        let edge_child_vertex = r.u32(sys::KR_U32_EDGE_CHILD_VERTEX, l);
        let vertex_child_vertex = r.u32(sys::KR_U32_VERTEX_CHILD_VERTEX, l);
        let order = ChildVertexOrder {
            from_faces: span(&face_child_vertex),
            from_edges: span(&edge_child_vertex),
            from_vertices: span(&vertex_child_vertex),
            sequential: [&face_child_vertex, &edge_child_vertex, &vertex_child_vertex]
                .iter()
                .all(|m| sequential(m)),
        };
        info.refinements.push(OsdRefinement {
            face_child_vertex,
            edge_child_vertex,
            vertex_child_vertex,
            face_child_faces,
            edge_child_edges: r
                .u32(sys::KR_U32_EDGE_CHILD_EDGES, l)
                .chunks_exact(2)
                .map(|c| [c[0], c[1]])
                .collect(),
            child_face_parent: r.u32(sys::KR_U32_FACE_PARENT_FACE, l + 1),
            order,
        });
    }
    Ok(info)
}

/// OpenMesh 9 `CatmullClarkT` (`level` steps, 0..=[`MAX_LEVEL`]) on a `PolyMesh_ArrayKernelT`
/// with `OpenMesh::Vec3d` points. Returns the refined mesh in OpenMesh's vertex and face order,
/// or OpenMesh's complaint (it rejects complex edges and vertices, e.g. three faces on an edge).
///
/// OpenMesh calls are serialised inside the shim, and OpenMesh's `omerr()` stream is redirected
/// for good into the shim (its messages come back in the error).
pub fn openmesh_catmull_clark(mesh: &RefMesh, level: u32) -> Result<RefMesh, String> {
    openmesh_catmull_clark_timed(mesh, level).map(|(m, _)| m)
}

/// As [`openmesh_catmull_clark`], also returning the time spent inside OpenMesh.
pub fn openmesh_catmull_clark_timed(
    mesh: &RefMesh,
    level: u32,
) -> Result<(RefMesh, RefTimings), String> {
    let input = MeshIn::new(mesh)?;
    let mut out: *mut sys::kr_result = std::ptr::null_mut();
    // SAFETY: `input.raw` points into `mesh`, which outlives the call; the shim reads the arrays
    // by the counts it is given, which MeshIn took from the slices.
    let status = unsafe { sys::kr_openmesh_catmull_clark(&input.raw, level, &mut out) };
    let r = Handle::new(status, out)?;
    let timings = RefTimings::from_seconds(&r.f64(sys::KR_F64_TIMINGS, 0));
    Ok((r.mesh(level)?, timings))
}

fn run_osd(
    mesh: &RefMesh,
    creases: &Creases,
    opts: &OsdOptions,
    level: u32,
    fvar: Option<(&[[f64; 2]], &[u32])>,
    level_info: bool,
) -> Result<Handle, String> {
    let input = MeshIn::new(mesh)?;
    if creases.edges.len() != creases.edge_sharpness.len() {
        return Err(format!(
            "{} crease edges but {} sharpness values",
            creases.edges.len(),
            creases.edge_sharpness.len()
        ));
    }
    if creases.corners.len() != creases.corner_sharpness.len() {
        return Err(format!(
            "{} corners but {} sharpness values",
            creases.corners.len(),
            creases.corner_sharpness.len()
        ));
    }
    let raw_creases = sys::kr_creases {
        num_edges: count(creases.edges.len(), "crease edges")?,
        edge_vertices: creases.edges.as_ptr().cast(),
        edge_sharpness: creases.edge_sharpness.as_ptr(),
        num_corners: count(creases.corners.len(), "corners")?,
        corner_vertices: creases.corners.as_ptr(),
        corner_sharpness: creases.corner_sharpness.as_ptr(),
    };
    let options = sys::kr_osd_options {
        boundary: match opts.boundary {
            Boundary::None => sys::KR_BOUNDARY_NONE,
            Boundary::EdgeOnly => sys::KR_BOUNDARY_EDGE_ONLY,
            Boundary::EdgeAndCorner => sys::KR_BOUNDARY_EDGE_AND_CORNER,
        },
        crease: match opts.crease {
            CreaseMethod::Uniform => sys::KR_CREASE_UNIFORM,
            CreaseMethod::Chaikin => sys::KR_CREASE_CHAIKIN,
        },
        fvar: match opts.fvar {
            FVarLinear::None => sys::KR_FVAR_NONE,
            FVarLinear::CornersOnly => sys::KR_FVAR_CORNERS_ONLY,
            FVarLinear::CornersPlus1 => sys::KR_FVAR_CORNERS_PLUS1,
            FVarLinear::CornersPlus2 => sys::KR_FVAR_CORNERS_PLUS2,
            FVarLinear::Boundaries => sys::KR_FVAR_BOUNDARIES,
            FVarLinear::All => sys::KR_FVAR_ALL,
        },
        level_info: u32::from(level_info),
    };
    let raw_fvar = match fvar {
        Some((values, indices)) => {
            if indices.len() != mesh.face_vertices.len() {
                return Err(format!(
                    "{} face-varying indices for {} face corners",
                    indices.len(),
                    mesh.face_vertices.len()
                ));
            }
            Some(sys::kr_fvar {
                num_values: count(values.len(), "face-varying values")?,
                values: values.as_ptr().cast(),
                indices: indices.as_ptr(),
            })
        }
        None => None,
    };
    let fvar_ptr = raw_fvar
        .as_ref()
        .map_or(std::ptr::null(), |f| f as *const sys::kr_fvar);
    let mut out: *mut sys::kr_result = std::ptr::null_mut();
    // SAFETY: every pointer points into a slice borrowed for the duration of the call, with the
    // count taken from that slice (`[f64; 2]` and `[u32; 2]` are laid out as 2 contiguous
    // scalars); `indices` has one entry per face corner, as checked above.
    let status = unsafe {
        sys::kr_osd_catmark(
            &input.raw,
            &raw_creases,
            &options,
            level,
            fvar_ptr,
            &mut out,
        )
    };
    Handle::new(status, out)
}

/// A view of the stroke cut: `clip = view_proj * [x, y, z, 1]` (column-major),
/// `ndc = clip.xyz / clip.w`, and pixels with a top-left origin, y down:
/// `(x0 + (ndc.x + 1) / 2 * width, y0 + (1 - ndc.y) / 2 * height)`. Perspective and orthographic
/// matrices alike; [`cut_setup::look_at_bounds`] builds one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutView {
    /// The 4x4 view-projection matrix, column-major (glam's `to_cols_array`).
    pub view_proj: [f64; 16],
    /// `[x0, y0, width, height]` in pixels.
    pub viewport: [f64; 4],
}

/// Which faces the exact cut cuts.
///
/// Default value: `ThroughAll` (the only mode the reference implements).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CutMode {
    /// Every face under the stroke, front- or back-facing, occluded or not.
    #[default]
    ThroughAll,
}

/// Where a vertex the exact cut created lies on the input mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum NewVertexSource {
    /// Inside input face `f` (a stroke point inside it, or where the stroke crosses itself there).
    Face(u32),
    /// On the input edge `(u, v)`, `u < v` (where the stroke crosses it), shared by its faces.
    Edge(u32, u32),
}

/// The result of [`cgal_stroke_cut`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ExactCut {
    /// The cut mesh, triangles only: the input vertices first (unchanged), then the new ones;
    /// faces in input order, each split face replaced in place by its pieces (same orientation).
    pub mesh: RefMesh,
    /// The input face of each output face.
    pub face_origin: Vec<u32>,
    /// The output faces that replace split input faces: every piece of every split face.
    pub new_faces: Vec<u32>,
    /// The minimum angle, in degrees and in 3D, of each face of `new_faces` (same order).
    pub new_face_min_angles: Vec<f64>,
    /// Where each new vertex (output vertex `num_input_vertices + i`) lies on the input.
    pub new_vertex_sources: Vec<NewVertexSource>,
    /// Faces whose screen image meets the stroke (corners in front of the eye, non-zero area).
    pub crossed_faces: usize,
    /// Input faces replaced by two or more pieces.
    pub split_faces: usize,
    /// New triangles: the pieces minus the faces they replace (`new_faces.len() - split_faces`).
    pub new_triangles: usize,
    /// Faces with a corner behind the eye (`w <= 0`), never cut on screen.
    pub faces_behind_eye: usize,
    /// Faces whose screen image has no area, never cut on screen.
    pub faces_without_area: usize,
    /// Faces of the two kinds above split only because a neighbour put points on their edges.
    pub faces_split_by_neighbours: usize,
    /// Time spent in the cut (projection excluded, copying out excluded).
    pub time: Duration,
}

impl ExactCut {
    /// The smallest minimum angle of the new triangles, in degrees; `None` if nothing was split.
    pub fn min_angle(&self) -> Option<f64> {
        self.new_face_min_angles.iter().copied().reduce(f64::min)
    }

    /// The number of vertices the cut created.
    pub fn num_new_vertices(&self) -> usize {
        self.new_vertex_sources.len()
    }

    /// The output triangles.
    pub fn triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.mesh
            .face_vertices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
    }
}

/// The exact stroke cut of a triangle mesh, through CGAL 5: for every face whose corners are in
/// front of the eye (`w > 0`) and whose screen image has an area and meets the stroke, the
/// stroke's pieces clipped to the face become constraints of a `Constrained_Delaunay_triangulation_2`
/// of its screen image (`Exact_predicates_exact_constructions_kernel`, `Exact_intersections_tag`:
/// constructed points lie exactly on their edges, so neighbours share them); new vertices are
/// lifted onto the face with perspective-correct barycentrics (interpolated with `1 / w`).
/// Crossings of an edge are made once per edge and shared by all faces of the edge, also by a
/// neighbour that cannot be cut on screen (it is split in its own parameter domain), so the
/// output has no cracks.
///
/// `stroke` is in pixels (see [`CutView`]); consecutive equal points are merged. Errors
/// (`"bad argument: ..."`): fewer than 2 points, a zero-length stroke, a non-finite value in the
/// mesh, the matrix, the viewport or the stroke, a non-positive viewport size, a face that is
/// not a triangle.
pub fn cgal_stroke_cut(
    mesh: &RefMesh,
    view: &CutView,
    stroke: &[[f64; 2]],
    mode: CutMode,
) -> Result<ExactCut, String> {
    let input = MeshIn::new(mesh)?;
    let raw_view = sys::kr_view {
        view_proj: view.view_proj,
        viewport: view.viewport,
    };
    let raw_mode = match mode {
        CutMode::ThroughAll => sys::KR_CUT_THROUGH_ALL,
    };
    let mut out: *mut sys::kr_result = std::ptr::null_mut();
    // SAFETY: `input.raw` points into `mesh` and `stroke.as_ptr()` into `stroke` (`[f64; 2]` is 2
    // contiguous doubles), both borrowed for the call, with counts taken from the slices.
    let status = unsafe {
        sys::kr_cgal_stroke_cut(
            &input.raw,
            &raw_view,
            stroke.as_ptr().cast(),
            count(stroke.len(), "stroke points")?,
            raw_mode,
            &mut out,
        )
    };
    let r = Handle::new(status, out)?;
    let cut_mesh = r.mesh(0)?;
    let counts = r.u32(sys::KR_U32_CUT_COUNTS, 0);
    let [crossed, split, new_tris, new_verts, behind, no_area, by_neighbours] = counts[..] else {
        return Err(format!("internal: {} cut counts", counts.len()));
    };
    let new_vertex_sources: Vec<NewVertexSource> = r
        .u32_slice(sys::KR_U32_CUT_VERTEX_SOURCE, 0)
        .chunks_exact(3)
        .map(|c| match c[0] {
            0 => NewVertexSource::Face(c[1]),
            _ => NewVertexSource::Edge(c[1], c[2]),
        })
        .collect();
    let new_faces = r.u32(sys::KR_U32_CUT_NEW_FACES, 0);
    let new_face_min_angles = r.f64(sys::KR_F64_CUT_MIN_ANGLES, 0);
    let face_origin = r.u32(sys::KR_U32_FACE_ORIGIN, 0);
    if new_vertex_sources.len() != new_verts as usize
        || new_face_min_angles.len() != new_faces.len()
        || face_origin.len() != cut_mesh.num_faces()
        || cut_mesh.num_vertices() != mesh.num_vertices() + new_verts as usize
    {
        return Err("internal: the cut's arrays do not agree in length".into());
    }
    let seconds = r.f64(sys::KR_F64_TIMINGS, 0);
    Ok(ExactCut {
        mesh: cut_mesh,
        face_origin,
        new_faces,
        new_face_min_angles,
        new_vertex_sources,
        crossed_faces: crossed as usize,
        split_faces: split as usize,
        new_triangles: new_tris as usize,
        faces_behind_eye: behind as usize,
        faces_without_area: no_area as usize,
        faces_split_by_neighbours: by_neighbours as usize,
        time: RefTimings::from_seconds(&seconds).build,
    })
}

/// A flow network for [`boost_bk_max_flow`]: nodes `0..n` with capacities from the source and
/// to the sink, and edges `(a, b)` with a capacity each way.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RefFlowNetwork {
    /// Capacity from the source to each node (≥ 0).
    pub source_caps: Vec<i64>,
    /// Capacity from each node to the sink (≥ 0).
    pub sink_caps: Vec<i64>,
    /// `(a, b, capacity a → b, capacity b → a)`.
    pub edges: Vec<(u32, u32, i64, i64)>,
}

/// What Boost.Graph's max-flow found.
#[derive(Clone, Debug, PartialEq)]
pub struct BoostFlow {
    /// The maximum flow.
    pub flow: i64,
    /// Per node: on the minimum cut's source side (Boost's source search tree).
    pub source_side: Vec<bool>,
    /// The time of each repeated call inside Boost (the graph's construction not counted).
    pub times: Vec<Duration>,
}

/// Boost.Graph 1.74's `boykov_kolmogorov_max_flow` on `network` (an `adjacency_list` with a
/// source and a sink vertex added), called `repeats` times on the graph built once.
pub fn boost_bk_max_flow(network: &RefFlowNetwork, repeats: u32) -> Result<BoostFlow, String> {
    let n = network.source_caps.len();
    if network.sink_caps.len() != n {
        return Err("bad argument: source and sink capacities differ in length".into());
    }
    let nodes: Vec<u32> = network.edges.iter().flat_map(|e| [e.0, e.1]).collect();
    let caps: Vec<i64> = network.edges.iter().flat_map(|e| [e.2, e.3]).collect();
    let raw = sys::kr_flow_network {
        num_nodes: count(n, "nodes")?,
        source_caps: network.source_caps.as_ptr(),
        sink_caps: network.sink_caps.as_ptr(),
        num_edges: count(network.edges.len(), "edges")?,
        edge_nodes: nodes.as_ptr(),
        edge_caps: caps.as_ptr(),
    };
    let mut out: *mut sys::kr_result = std::ptr::null_mut();
    // SAFETY: the arrays live for the call and their lengths are the counts given.
    let status = unsafe { sys::kr_boost_bk_max_flow(&raw, repeats, &mut out) };
    let r = Handle::new(status, out)?;
    let flow = r.f64(sys::KR_F64_FLOW, 0);
    let side = r.u32(sys::KR_U32_FLOW_SOURCE_SIDE, 0);
    if flow.len() != 1 || side.len() != n {
        return Err("internal: the max-flow result's arrays have the wrong length".into());
    }
    Ok(BoostFlow {
        flow: flow[0] as i64,
        source_side: side.iter().map(|&s| s != 0).collect(),
        times: r
            .f64(sys::KR_F64_TIMINGS, 0)
            .iter()
            .map(|&t| Duration::from_secs_f64(t.max(0.0)))
            .collect(),
    })
}

fn count(n: usize, what: &str) -> Result<u32, String> {
    u32::try_from(n).map_err(|_| format!("too many {what}: {n}"))
}

fn span(map: &[u32]) -> Range<u32> {
    match (map.iter().min(), map.iter().max()) {
        (Some(&lo), Some(&hi)) => lo..hi.saturating_add(1),
        _ => 0..0,
    }
}

fn sequential(map: &[u32]) -> bool {
    let Some(&start) = map.first() else {
        return true;
    };
    map.iter()
        .enumerate()
        .all(|(i, &c)| u64::from(c) == u64::from(start) + i as u64)
}

fn pairs(flat: &[f64]) -> Vec<[f64; 2]> {
    flat.chunks_exact(2).map(|c| [c[0], c[1]]).collect()
}

/// The base mesh as the shim reads it; borrows the arrays of a [`RefMesh`].
struct MeshIn {
    raw: sys::kr_mesh,
}

impl MeshIn {
    fn new(mesh: &RefMesh) -> Result<Self, String> {
        Ok(MeshIn {
            raw: sys::kr_mesh {
                num_vertices: count(mesh.positions.len(), "vertices")?,
                positions: mesh.positions.as_ptr().cast(),
                num_faces: count(mesh.face_sizes.len(), "faces")?,
                face_sizes: mesh.face_sizes.as_ptr(),
                num_face_vertices: count(mesh.face_vertices.len(), "face corners")?,
                face_vertices: mesh.face_vertices.as_ptr(),
            },
        })
    }
}

/// Owns a `kr_result` and frees it on drop.
struct Handle(*mut sys::kr_result);

impl Handle {
    /// Takes ownership of `out` and turns a failed status into its message.
    fn new(status: u32, out: *mut sys::kr_result) -> Result<Self, String> {
        if out.is_null() {
            return Err(format!(
                "the reference shim could not allocate a result (status {status})"
            ));
        }
        let handle = Handle(out);
        if status == sys::KR_STATUS_OK {
            return Ok(handle);
        }
        // SAFETY: `out` is a live result; the message is NUL-terminated and lives as long as it.
        let message = unsafe { std::ffi::CStr::from_ptr(sys::kr_result_message(handle.0)) }
            .to_string_lossy()
            .into_owned();
        let kind = match status {
            sys::KR_STATUS_REJECTED => "rejected",
            sys::KR_STATUS_BAD_ARGUMENT => "bad argument",
            _ => "C++ exception",
        };
        Err(format!("{kind}: {message}"))
    }

    /// The array as a slice borrowed from the handle (empty if the result has no such array).
    fn slice<T>(&self, p: *const T, len: usize) -> &[T] {
        if p.is_null() || len == 0 {
            &[]
        } else {
            // SAFETY: the shim returned `p` with `len` elements owned by the live result, which
            // is not modified until it is freed when `self` drops.
            unsafe { std::slice::from_raw_parts(p, len) }
        }
    }

    fn f64_slice(&self, array: u32, level: u32) -> &[f64] {
        let mut len = 0usize;
        // SAFETY: the handle is live; the shim writes `len` and returns null or a valid array.
        let p = unsafe { sys::kr_result_f64(self.0, array, level, &mut len) };
        self.slice(p, len)
    }

    fn u32_slice(&self, array: u32, level: u32) -> &[u32] {
        let mut len = 0usize;
        // SAFETY: as in `f64_slice`.
        let p = unsafe { sys::kr_result_u32(self.0, array, level, &mut len) };
        self.slice(p, len)
    }

    fn f64(&self, array: u32, level: u32) -> Vec<f64> {
        self.f64_slice(array, level).to_vec()
    }

    fn u32(&self, array: u32, level: u32) -> Vec<u32> {
        self.u32_slice(array, level).to_vec()
    }

    fn mesh(&self, level: u32) -> Result<RefMesh, String> {
        let coords = self.f64_slice(sys::KR_F64_POSITIONS, level);
        if coords.len() % 3 != 0 {
            return Err(format!("internal: {} coordinates", coords.len()));
        }
        Ok(RefMesh {
            positions: coords.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
            face_sizes: self.u32(sys::KR_U32_FACE_SIZES, level),
            face_vertices: self.u32(sys::KR_U32_FACE_VERTICES, level),
        })
    }
}

impl Drop for Handle {
    fn drop(&mut self) {
        // SAFETY: the handle owns the result and frees it once.
        unsafe { sys::kr_result_free(self.0) }
    }
}
