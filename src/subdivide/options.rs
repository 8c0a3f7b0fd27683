//! Options of [`super::catmull_clark`].

use super::regions::MergeOptions;

/// How faces with holes (a P loop and C loops, seed 001 §1, §4) are subdivided.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum HoleMethod {
    /// Method `[a]`, seed 001 §4: bridge each C loop to the P loop and subdivide smoothly;
    /// loop vertices take valence n + 1 in eq. (2). Faces it cannot bridge fall back to
    /// [`HoleMethod::Sharp`] and are listed in the report.
    Smooth,
    /// Method `[b]`, seed 001 §4: P and C loop edges become sharp, the face stays one planar
    /// face with holes, and its loops become cubic B-spline crease curves.
    Sharp,
}

/// How boundary edges and corners are treated (OpenSubdiv `VtxBoundaryInterpolation`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BoundaryInterpolation {
    /// Boundary edges are infinitely sharp; a vertex with one face is smoothed along the
    /// boundary (crease rule, eq. (3)). Blender's "Boundary Smooth: All".
    EdgeOnly,
    /// As `EdgeOnly`, and a boundary vertex with one face is pinned (corner rule, eq. (4)).
    /// Blender's "Boundary Smooth: Keep Corners".
    EdgeAndCorner,
}

/// How semi-sharp creases relax from level to level (OpenSubdiv `CreasingMethod`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CreaseMethod {
    /// Each level subtracts 1 from the sharpness (DeRose et al. 1998).
    Uniform,
    /// Chaikin's rule: a child's sharpness is ¾ of its own plus ¼ of the average of the other
    /// semi-sharp edges at its end vertex, minus 1 (DeRose et al. 1998, appendix).
    Chaikin,
}

/// Options of [`super::catmull_clark`]. Defaults follow OpenSubdiv's and the paper's.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct SubdivideOptions {
    /// Number of subdivision levels, 1 or more. Default value: `1`.
    pub levels: u32,
    /// Method for faces with holes. Default value: [`HoleMethod::Smooth`] (method `[a]`).
    pub holes: HoleMethod,
    /// Boundary rule. Default value: [`BoundaryInterpolation::EdgeOnly`] (OpenSubdiv's default).
    pub boundary: BoundaryInterpolation,
    /// Semi-sharp crease rule. Default value: [`CreaseMethod::Uniform`] (OpenSubdiv's default).
    pub crease_method: CreaseMethod,
    /// First turn coplanar regions (a boolean's triangulated or fanned output) back into
    /// faces with holes ([`super::merge_coplanar_regions`]). Default value: `false`.
    pub recover_faces_with_holes: bool,
    /// Tolerances of that recovery. Default value: [`MergeOptions::default`].
    pub merge: MergeOptions,
    /// Tag edges whose dihedral angle exceeds this many degrees as infinitely sharp
    /// ([`super::tag_feature_edges`]), for CAD meshes. Default value: `None` (off).
    pub feature_angle: Option<f64>,
    /// Cut the result's faces with holes (method `[b]`'s, and faces method `[a]` could not
    /// bridge) into simple polygons along bridge edges, for formats and hosts that store no
    /// faces with holes (Blender, MeshLab, OBJ). Default value: `false`.
    pub split_faces_with_holes: bool,
}

impl Default for SubdivideOptions {
    fn default() -> Self {
        SubdivideOptions {
            levels: 1,
            holes: HoleMethod::Smooth,
            boundary: BoundaryInterpolation::EdgeOnly,
            crease_method: CreaseMethod::Uniform,
            recover_faces_with_holes: false,
            merge: MergeOptions::default(),
            feature_angle: None,
            split_faces_with_holes: false,
        }
    }
}

impl SubdivideOptions {
    /// Options with `levels` levels and every other field at its default.
    pub fn with_levels(levels: u32) -> Self {
        SubdivideOptions {
            levels,
            ..Default::default()
        }
    }
}
