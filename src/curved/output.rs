//! The result of [`super::mesh`]: high-order triangles in parameter space and on the
//! surface, with per-element provenance and metric angles (spec §5.2, §6).

use glam::{DVec2, DVec3};

use super::input::{CurveId, PatchId, RegionId};
use super::quality::QualityReport;
use super::refine::RefineStats;

/// A straight element of Ω_lin, or a curved guarding triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ElementKind {
    /// A triangle of the refined linear domain (its angles carry the guarantee).
    Straight,
    /// A guarding triangle: its local edge 0→1 is a piece of an input curve.
    Curved,
}

/// The piece of an input curve a curved element's edge 0→1 follows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvedEdge {
    pub curve: CurveId,
    /// The piece covers `[t0, t1]` of the curve (dyadic numbers, exact).
    pub t0: f64,
    pub t1: f64,
    /// The element's edge 0→1 runs from `c(t1)` to `c(t0)` (the region is on the curve's right).
    pub reversed: bool,
}

/// Metric angles of one element, in degrees (spec §6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementQuality {
    /// Smallest corner angle measured in the metric of each of its three vertices (the
    /// refinement's bound applies to this on straight, non-exempt elements).
    pub min_angle_vertex: f64,
    /// The three corner angles in the metric at the centroid (they sum to 180° for a straight
    /// element); curved corners use the curve's tangent.
    pub angles: [f64; 3],
    /// Smallest and largest corner angle over the sampling lattice, each in the parameter-space
    /// metric at the sample (spec §6 variant (A)); NaN when not measured.
    pub min_angle_sampled: f64,
    pub max_angle_sampled: f64,
    /// The same on the flat triangle through the corners' images in R³, in the real-space
    /// metric at the samples' images (variant (B)); NaN for parameter-space metrics or when not
    /// measured.
    pub min_angle_xyz: f64,
    pub max_angle_xyz: f64,
    /// The three corner angles in R³, in the real-space metric at the centroid's image (NaN
    /// for parameter-space metrics).
    pub xyz_angles: [f64; 3],
    /// Smallest over largest Jacobian determinant of the element in parameter space (1 for
    /// a straight one); > 0 means valid.
    pub scaled_jacobian: f64,
    /// The same for the element on the surface (nodes `P(u, v)`), with the determinant taken
    /// along its corners' normal as Gmsh checks surface elements.
    pub scaled_jacobian_surface: f64,
}

/// Where an element comes from and how good it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementInfo {
    pub patch: PatchId,
    pub region: RegionId,
    pub kind: ElementKind,
    /// For curved elements, the curve piece on edge 0→1.
    pub edge: Option<CurvedEdge>,
    /// At a small input angle (no angle bound).
    pub exempt: bool,
    pub quality: ElementQuality,
}

/// Counts and timings of one run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshStats {
    pub refine: RefineStats,
    /// Curve pieces after guarding and refinement.
    pub curve_pieces: u64,
    /// Voronoi vertices that fell back to the mean-metric circumcentre.
    pub inexact_voronoi_vertices: u64,
    /// Seconds spent in each stage: validation, guarding, refinement (with the first
    /// triangulation), output.
    pub seconds_validate: f64,
    pub seconds_guard: f64,
    pub seconds_refine: f64,
    pub seconds_output: f64,
}

/// A curved triangle mesh of trimmed patches.
#[derive(Debug, Clone)]
pub struct CurvedMesh {
    /// Element order q: every element has `(q+1)(q+2)/2` nodes.
    pub order: u32,
    /// Node positions in their patch's parameter square.
    pub nodes_uv: Vec<DVec2>,
    /// Node positions on the surface: `P(u, v)` of each node.
    pub nodes_xyz: Vec<DVec3>,
    /// The patch of each node.
    pub node_patch: Vec<PatchId>,
    /// Element node indices, `(q+1)(q+2)/2` per element, in Gmsh's (and VTK's) Lagrange
    /// order ([`super::lagrange_layout`]); the first three are the corners, counter-clockwise
    /// in parameter space.
    pub elements: Vec<u32>,
    pub info: Vec<ElementInfo>,
    pub quality: QualityReport,
    pub stats: MeshStats,
}

impl CurvedMesh {
    /// Nodes per element.
    pub fn nodes_per_element(&self) -> usize {
        ((self.order + 1) * (self.order + 2) / 2) as usize
    }

    pub fn element_count(&self) -> usize {
        self.info.len()
    }

    /// The nodes of element `e`.
    pub fn element(&self, e: usize) -> &[u32] {
        let n = self.nodes_per_element();
        &self.elements[e * n..(e + 1) * n]
    }
}

impl CurvedMesh {
    /// The area of element `e` in parameter space: `∫ det DF`, exact for the element's
    /// polynomial map (half the mean of `det DF`'s Bézier coefficients).
    pub fn element_area_uv(&self, e: usize) -> f64 {
        let uv: Vec<DVec2> = self
            .element(e)
            .iter()
            .map(|&n| self.nodes_uv[n as usize])
            .collect();
        let tri = super::element::lagrange_to_bezier(self.order, &uv);
        let c = tri.jacobian_coefficients();
        0.5 * c.iter().sum::<f64>() / c.len() as f64
    }
}
