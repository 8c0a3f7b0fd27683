//! Rough-model editing (seed 003: Masuda, Yoshioka, Furukawa; spec `rough_model.md`): pick a
//! feature from a rough band by a minimum cut ([`segment_band`], seed §3) over the
//! Boykov–Kolmogorov max-flow written here ([`FlowNetwork`]), and the B-spline base surface
//! fitted to the region around a feature ([`fit_surface`], seed §4).

mod max_flow;
mod segment;
mod spline;

pub use max_flow::{FlowNetwork, MinCut, MAX_CAPACITY, MAX_TOTAL_CAPACITY};
pub use segment::{
    band_graph, segment_band, Band, BandGraph, BoundaryLoop, SegmentOptions, Segmentation,
};
pub use spline::{
    fit_points, fit_surface, BSplineSurface, FitOptions, Knots, SurfaceFit, SurfacePoint,
};
