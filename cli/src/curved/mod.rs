//! `katachi curved-mesh INPUT.json OUT.msh [--order N] [--report REPORT.json]
//! [--space surface|parameter] [--also FILE]...`: curved anisotropic meshing of trimmed
//! Bézier patches (seed 000) from the command line.
//!
//! The input file holds the patches, the trim curves, the regions (loops of curves by
//! index) and the metric; `docs/curved.md` gives its schema and `examples/curved_*.json`
//! are samples. The output's format follows its extension: `.msh` (Gmsh 4.1, high-order
//! triangles), `.vtk` (legacy VTK, Lagrange triangles) or `.obj` (a linear preview).

mod json;

pub use json::read_input;

use std::path::PathBuf;

use clap::ValueEnum;
use indicatif::{ProgressBar, ProgressStyle};
use katachi::curved::{
    mesh_with_progress, AngleStats, CurvedMesh, CurvedOptions, ElementKind, Space,
};
use katachi::{io, Error};
use serde_json::{json, Value};

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SpaceArg {
    /// On the surface: the nodes' images P(u, v).
    Surface,
    /// In the parameter square, (u, v, 0).
    Parameter,
}

#[derive(clap::Args)]
pub struct Args {
    /// The input: patches, curves, regions and metric as JSON (docs/curved.md).
    input: PathBuf,
    /// The mesh: .msh (Gmsh 4.1), .vtk (legacy VTK) or .obj (linear preview).
    output: PathBuf,
    /// Element order, 1 to 10 (overrides the file's "options.order"; default 2).
    #[arg(long)]
    order: Option<u32>,
    /// Write a report as JSON: counts, metric-angle statistics, timings.
    #[arg(long, value_name = "REPORT.json")]
    report: Option<PathBuf>,
    /// Which coordinates the files get.
    #[arg(long, value_enum, default_value_t = SpaceArg::Surface)]
    space: SpaceArg,
    /// Another output file (.msh, .vtk, .obj), e.g. a preview beside the MSH file;
    /// repeatable.
    #[arg(long, value_name = "FILE")]
    also: Vec<PathBuf>,
}

/// Meshes whose estimate reaches this many vertices show a progress bar.
const PROGRESS_SITES: u64 = 50_000;

pub fn run(args: &Args) -> Result<(), Error> {
    let (input, mut options) = json::read_input(&args.input)?;
    if let Some(q) = args.order {
        options.order = q;
    }
    let space = match args.space {
        SpaceArg::Surface => Space::Surface,
        SpaceArg::Parameter => Space::Parameter,
    };
    let mut bar: Option<ProgressBar> = None;
    let mesh = mesh_with_progress(&input, &options, &mut |sites, estimate| {
        if bar.is_none() && estimate >= PROGRESS_SITES {
            bar = Some(
                ProgressBar::new(estimate).with_style(
                    ProgressStyle::with_template("meshing {bar:30} {pos}/~{len} vertices")
                        .expect("a valid template"),
                ),
            );
        }
        if let Some(b) = &bar {
            b.set_length(estimate.max(sites));
            b.set_position(sites);
        }
    })?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    mesh.write(&args.output, space)?;
    crate::out::line(format!("wrote {}", args.output.display()))?;
    for path in &args.also {
        mesh.write(path, space)?;
        crate::out::line(format!("wrote {}", path.display()))?;
    }
    for line in summary(&mesh) {
        crate::out::line(line)?;
    }
    if let Some(path) = &args.report {
        let text =
            serde_json::to_string_pretty(&report(&mesh, &options)).expect("JSON values print");
        io::write_bytes(path, text.as_bytes())?;
        crate::out::line(format!("wrote the report to {}", path.display()))?;
    }
    Ok(())
}

fn counts(m: &CurvedMesh) -> (usize, usize, usize) {
    let curved = m
        .info
        .iter()
        .filter(|i| i.kind == ElementKind::Curved)
        .count();
    let exempt = m.info.iter().filter(|i| i.exempt).count();
    (m.element_count() - curved, curved, exempt)
}

/// The short human report: one fact a line.
fn summary(m: &CurvedMesh) -> Vec<String> {
    let q = &m.quality;
    let (straight, curved, exempt) = counts(m);
    let s = &m.stats;
    vec![
        format!(
            "elements: {} of order {} ({straight} straight, {curved} curved, {exempt} exempt at small input angles); nodes: {}",
            m.element_count(),
            m.order,
            m.nodes_uv.len()
        ),
        format!(
            "smallest angle in the metric (straight, not exempt): {:.2}° (bound {:.2}°); below 14.48°: {:.2}%",
            q.straight_min_vertex.min,
            q.guaranteed_angle_deg,
            100.0 * q.straight_min_vertex.below_14_48
        ),
        format!(
            "all corner angles (straight elements): min {:.2}°, max {:.2}°, mean {:.2}°, median {:.2}°",
            q.straight_angles.min, q.straight_angles.max, q.straight_angles.mean, q.straight_angles.median
        ),
        format!(
            "smallest scaled Jacobian: {:.4} in parameter space, {:.4} on the surface",
            q.min_scaled_jacobian, q.min_scaled_jacobian_surface
        ),
        format!(
            "time: {:.3} s (validation {:.3}, guarding {:.3}, refinement {:.3}, output {:.3}); {} sites inserted, {} curve bisections",
            s.seconds_validate + s.seconds_guard + s.seconds_refine + s.seconds_output,
            s.seconds_validate,
            s.seconds_guard,
            s.seconds_refine,
            s.seconds_output,
            s.refine.insertions,
            s.refine.bisections
        ),
    ]
}

fn stats(a: &AngleStats) -> Value {
    json!({
        "count": a.count,
        "min": a.min,
        "max": a.max,
        "mean": a.mean,
        "median": a.median,
        "q01": a.q01,
        "share_below_14_48": a.below_14_48,
        "share_below_20": a.below_20,
        "share_below_20_7": a.below_20_7,
    })
}

/// The full report as JSON.
fn report(m: &CurvedMesh, o: &CurvedOptions) -> Value {
    let q = &m.quality;
    let s = &m.stats;
    let (straight, curved, exempt) = counts(m);
    json!({
        "order": m.order,
        "nodes": m.nodes_uv.len(),
        "elements": {"total": m.element_count(), "straight": straight, "curved": curved, "exempt": exempt},
        "angles_deg": {
            "guaranteed": q.guaranteed_angle_deg,
            "straight_min_in_vertex_metrics": stats(&q.straight_min_vertex),
            "straight_corner_angles": stats(&q.straight_angles),
            "curved_corner_angles": stats(&q.curved_angles),
            "all_corner_angles": stats(&q.all_angles),
            "straight_min_sampled": stats(&q.straight_min_sampled),
            "curved_min_sampled": stats(&q.curved_min_sampled),
            "straight_min_on_surface": stats(&q.straight_min_xyz),
            "all_corner_angles_on_surface": stats(&q.all_angles_xyz),
            "exempt_min_in_vertex_metrics": stats(&q.exempt),
        },
        "min_scaled_jacobian": q.min_scaled_jacobian,
        "min_scaled_jacobian_surface": q.min_scaled_jacobian_surface,
        "refinement": {
            "sites_inserted": s.refine.insertions,
            "curve_bisections": s.refine.bisections,
            "steps": s.refine.steps,
            "unresolved": s.refine.unresolved,
            "curve_pieces": s.curve_pieces,
            "inexact_voronoi_vertices": s.inexact_voronoi_vertices,
        },
        "seconds": {
            "validation": s.seconds_validate,
            "guarding": s.seconds_guard,
            "refinement": s.seconds_refine,
            "output": s.seconds_output,
        },
        "options": {
            "order": o.order,
            "mu": o.mu,
            "max_cone_deg": o.max_cone_deg,
            "max_split_depth": o.max_split_depth,
            "radius_edge_bound": o.radius_edge_bound,
            "size_bound": o.size_bound,
            "small_angle_deg": o.small_angle_deg,
            "max_anisotropy": o.max_anisotropy,
            "min_uv_size": o.min_uv_size,
            "max_uv_size": o.max_uv_size,
        },
    })
}
