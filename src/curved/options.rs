//! Options of [`super::mesh`]. Each default says where it comes from: the seed, Bézier
//! Guarding (Mandad & Campen 2020, \[BG\]), Labelle–Shewchuk 2003 / Imai–Yokosuka 2006
//! (\[LS\], \[IY\], through the seed), or a choice of this implementation (\[DESIGN\]).

use crate::error::{Error, Result};

use super::field::MetricClamp;

/// Options of [`super::mesh`].
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct CurvedOptions {
    /// Order of the output elements, 1 to 10 (Gmsh's triangles stop at 10). Curved edges are
    /// reproduced exactly in parameter space when the order is at least the curve's degree.
    /// Default value: `2`.
    pub order: u32,
    /// Guard offset μ: guard points move μ·w²/ŵ away from the curve (seed 000 §2.2, taken
    /// from \[BG\]'s experiments). Default value: `1e-2`.
    pub mu: f64,
    /// A guardable piece is split again while its control vectors spread over more than this
    /// many degrees (\[BG\] `GUARDING_MAX_CURVATURE_DEGREES`; spec §3.1). Default value: `179`.
    pub max_cone_deg: f64,
    /// Most bisections of one input curve (spec §3.3 \[DESIGN\]; \[BG\] allows 200 in rationals,
    /// f64 dyadics stay exact to about 50). Default value: `50`.
    pub max_split_depth: u32,
    /// Refinement bound B on a triangle's circumradius over its shortest edge, both in the
    /// metric: B = 2 gives angles ≥ arcsin(1/4) ≈ 14.48° for domains from curves (\[IY\] via
    /// seed 000 §5.2); B = √2 gives 20.7° for polygons (\[LS\] via seed 000 §1). Default value: `2`.
    pub radius_edge_bound: f64,
    /// Largest circumradius, in metric units (spec §4.3 rule 4 \[DESIGN\]): `1/√3` makes unit
    /// edges the target. Default value: `1/√3`.
    pub size_bound: f64,
    /// An input corner whose angle in the metric is below this is protected: its triangles
    /// are exempt from the angle bound and reported apart (spec §4.3, Ruppert's practice
    /// \[DESIGN\]). Default value: `60`.
    pub small_angle_deg: f64,
    /// Largest ratio of the longest to the shortest edge a metric may ask for (spec §2
    /// \[DESIGN\]). Default value: `1000`.
    pub max_anisotropy: f64,
    /// Smallest and largest edge length in parameter units a metric may ask for (spec §2
    /// \[DESIGN\]). Default values: `1e-7` and `1`.
    pub min_uv_size: f64,
    pub max_uv_size: f64,
    /// Most vertices of the mesh; `None` is `10·(boundary vertices) + 10⁶` (spec §4.3
    /// \[DESIGN\]). Exceeding it is [`super::CurvedError::Budget`]. Default value: `None`.
    pub max_sites: Option<u64>,
    /// Most refinement steps (queue pops); `None` is `8 × max_sites`. Default value: `None`.
    pub max_steps: Option<u64>,
    /// Most curve pieces after guarding and separation. Default value: `1_000_000`.
    pub max_curve_pieces: u64,
    /// Lattice density N of the points where angles are measured inside a triangle (spec §6
    /// \[DESIGN\]: `(i, j, k)/N`, 15 points for N = 4). Default value: `4`.
    pub angle_samples: u32,
    /// Measure every element's angles over the sampling lattice and in R³ (spec §6 variants
    /// (A) and (B)); off, only the vertex-metric angles are measured (what the bound is on).
    /// Default value: `true`.
    pub sampled_quality: bool,
}

impl Default for CurvedOptions {
    fn default() -> Self {
        CurvedOptions {
            order: 2,
            mu: 1e-2,
            max_cone_deg: 179.0,
            max_split_depth: 50,
            radius_edge_bound: 2.0,
            size_bound: 1.0 / 3f64.sqrt(),
            small_angle_deg: 60.0,
            max_anisotropy: 1e3,
            min_uv_size: 1e-7,
            max_uv_size: 1.0,
            max_sites: None,
            max_steps: None,
            max_curve_pieces: 1_000_000,
            angle_samples: 4,
            sampled_quality: true,
        }
    }
}

impl CurvedOptions {
    /// Default options with this element order.
    pub fn with_order(order: u32) -> Self {
        CurvedOptions {
            order,
            ..Default::default()
        }
    }

    /// The smallest angle the refinement guarantees on non-exempt straight triangles:
    /// `arcsin(1 / (2B))` in degrees (law of sines: the smallest angle θ of a triangle with
    /// circumradius R and shortest edge ℓ has sin θ = ℓ / 2R).
    pub fn guaranteed_angle_deg(&self) -> f64 {
        (1.0 / (2.0 * self.radius_edge_bound)).asin().to_degrees()
    }

    pub(crate) fn clamp(&self) -> MetricClamp {
        MetricClamp {
            min_size: self.min_uv_size,
            max_size: self.max_uv_size,
            max_anisotropy: self.max_anisotropy,
        }
    }

    /// Checks every field's domain.
    pub fn validate(&self) -> Result<()> {
        let bad =
            |option: &'static str, message: String| Err(Error::InvalidOption { option, message });
        if !(1..=10).contains(&self.order) {
            return bad("order", format!("{} is not in 1..=10", self.order));
        }
        if !(self.mu.is_finite() && self.mu > 0.0 && self.mu < 1.0) {
            return bad("mu", format!("{} is not in (0, 1)", self.mu));
        }
        if !(self.max_cone_deg > 0.0 && self.max_cone_deg < 180.0) {
            return bad(
                "max_cone_deg",
                format!("{} is not in (0, 180)", self.max_cone_deg),
            );
        }
        if !(1..=52).contains(&self.max_split_depth) {
            return bad(
                "max_split_depth",
                format!(
                    "{} is not in 1..=52 (t stays an exact dyadic number)",
                    self.max_split_depth
                ),
            );
        }
        if !(self.radius_edge_bound.is_finite()
            && self.radius_edge_bound >= 2f64.sqrt() * 0.999_999)
        {
            return bad(
                "radius_edge_bound",
                format!(
                    "{} is below √2 (the refinement would not terminate)",
                    self.radius_edge_bound
                ),
            );
        }
        if !(self.size_bound.is_finite() && self.size_bound > 0.0) {
            return bad("size_bound", format!("{} is not positive", self.size_bound));
        }
        if !(self.small_angle_deg >= 0.0 && self.small_angle_deg < 180.0) {
            return bad(
                "small_angle_deg",
                format!("{} is not in [0, 180)", self.small_angle_deg),
            );
        }
        if !(self.max_anisotropy.is_finite() && self.max_anisotropy >= 1.0) {
            return bad(
                "max_anisotropy",
                format!("{} is below 1", self.max_anisotropy),
            );
        }
        if !(self.min_uv_size > 0.0
            && self.max_uv_size.is_finite()
            && self.min_uv_size < self.max_uv_size)
        {
            return bad(
                "min_uv_size",
                format!(
                    "min_uv_size {} and max_uv_size {} must satisfy 0 < min < max",
                    self.min_uv_size, self.max_uv_size
                ),
            );
        }
        if self.max_sites == Some(0) {
            return bad("max_sites", "0 allows no vertex".into());
        }
        if self.max_steps == Some(0) {
            return bad("max_steps", "0 allows no step".into());
        }
        if self.max_curve_pieces == 0 {
            return bad("max_curve_pieces", "0 allows no curve".into());
        }
        if !(1..=64).contains(&self.angle_samples) {
            return bad(
                "angle_samples",
                format!("{} is not in 1..=64", self.angle_samples),
            );
        }
        Ok(())
    }
}
