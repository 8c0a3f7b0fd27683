//! Curved anisotropic meshing of trimmed Bézier patches (seed 000: Nakaniwa & Imai,
//! "Curved mesh generation on parametric surfaces"; spec `spec/curved_mesh.md`).
//!
//! A tensor-product Bézier patch, trimmed by loops of planar Bézier curves in its parameter
//! square, is meshed for a metric given in real space (seed 000 §4):
//!
//! 1. **Step 1** — the metric is pulled back to the parameter square, `M_uv = Jᵀ M₃ J`.
//! 2. **Step 2** — the trim curves are *guarded* (Bézier Guarding, Mandad & Campen 2020):
//!    split until guardable, a guard point on each side, envelopes split until disjoint.
//! 3. **Step 3** — the linear domain Ω_lin bounded by the guard edges is refined by
//!    anisotropic Voronoi refinement (Labelle & Shewchuk 2003, with Imai & Yokosuka's bound
//!    for curved domains): every straight triangle ends with all its angles at least
//!    `arcsin(1/(2B))` (14.48° for the default B = 2) in the metric of each of its vertices,
//!    except at small input angles, which are reported apart.
//! 4. **Step 4** — the guarding triangles become curved elements whose edge is the input
//!    curve, and every node is mapped to the surface.
//!
//! | paper section / step | file |
//! | --- | --- |
//! | §2.1 input and conditions (a)–(b); spec §1 | `input.rs`, `validate.rs` |
//! | §2.1 condition (c): curves meet only at end points | `separate.rs` (envelopes that cannot be separated) |
//! | §2.2 Def. 2.1 guardable, Prop. 2.2 splitting | `cone.rs`, `separate.rs` |
//! | §2.2 Defs. 2.3–2.5 guard points, guarding triangles, envelopes | `guard.rs` |
//! | §3.1 tensor field, metric lengths and angles | `tensor.rs`, `field.rs`, `angles.rs` |
//! | §3.2 parametric (Bézier) surface | `patch.rs`; trim curves `bezier.rs` |
//! | §4 Step 1: pull the metric back | `field.rs` (`PatchMetric::at`) |
//! | §4 Step 2: guard, separate envelopes | `separate.rs` |
//! | §4 Step 3: the polygon of inner guarding triangles | `domain.rs` |
//! | §4 Step 3 (LS): anisotropic Voronoi vertices, insertion kernel | `voronoi.rs`, `triangulation.rs` |
//! | §4 Step 3 (LS, IY): refinement rules, angle bound | `refine.rs`; small input angles `corners.rs` |
//! | §6 future work: split curves where the straight triangles are small | `bisect.rs` |
//! | §4 Step 4: curved elements, mapping to the surface | `element.rs`, `assemble.rs` |
//! | §5.1 angles measured in the metric, Tables 1–2 | `quality.rs` |
//!
//! Gap-fills (spec tags in the docs of each file): straight trim pieces are their own guard
//! edges; a bisected piece's old guard point leaves the triangulation; bad triangles get
//! off-centres, and a local Lawson pass in the metric follows each insertion; curved elements
//! get interior nodes placed to make them valid.
//!
//! Written by hand: no crate does Bézier guarding or anisotropic Voronoi refinement. The
//! triangulation is ours too: `spade` keeps a *Euclidean* constrained Delaunay triangulation
//! after every insertion, which would undo the anisotropic connectivity the refinement
//! builds (per-site metrics decide which triangles a new site takes over), and its
//! refinement is isotropic; the predicates are `robust`'s exact `orient2d` and `incircle`.

mod angles;
mod assemble;
mod bezier;
mod bisect;
mod cone;
mod corners;
mod domain;
mod element;
mod error;
mod field;
mod guard;
mod input;
mod options;
mod output;
mod patch;
mod predicates;
mod quality;
mod refine;
mod separate;
mod tensor;
mod triangulation;
mod validate;
mod voronoi;
mod write;

pub use bezier::BezierCurve;
pub use error::CurvedError;

pub use element::lagrange_layout;
pub use field::{Grid2, Grid3, MetricField, SizeField};
pub use input::{CurveId, CurveUse, PatchId, Region, RegionId, TrimLoop, TrimmedPatches};
pub use options::CurvedOptions;
pub use output::{CurvedEdge, CurvedMesh, ElementInfo, ElementKind, ElementQuality, MeshStats};
pub use patch::{BezierPatch, SurfacePoint};
pub use quality::{AngleStats, QualityReport};
pub use refine::RefineStats;
pub use tensor::{Frame2, Metric2, Metric3};
pub use write::{gmsh_triangle_type, Space};

/// Checks `input` as [`mesh`] would before meshing (spec §1): curves, loops, regions,
/// patches and metric, each failure naming the element at fault.
pub fn validate(input: &TrimmedPatches) -> crate::Result<()> {
    validate::validate(input)?;
    Ok(())
}

/// Meshes every region of `input` (seed 000 §4, Steps 1–4): pulls the metric back to each
/// patch's parameter square, guards the trim curves and separates their envelopes, refines
/// the linear domain by anisotropic Voronoi refinement, and builds curved elements of
/// `options.order`, mapped to the surface.
///
/// Regions that share a curve are meshed together: the curve is split once, and its
/// vertices and edge nodes are the same (bit for bit) on both sides.
///
/// ```
/// use glam::{DVec2, DVec3};
/// use katachi::curved::{mesh, BezierPatch, CurvedOptions, MetricField, TrimmedPatches};
///
/// let patch = BezierPatch::bilinear(
///     DVec3::new(0.0, 0.0, 0.0),
///     DVec3::new(1.0, 0.0, 0.0),
///     DVec3::new(0.0, 1.0, 0.0),
///     DVec3::new(1.0, 1.0, 0.2),
/// );
/// let mut input = TrimmedPatches {
///     patches: vec![patch],
///     curves: vec![],
///     regions: vec![],
///     metric: MetricField::isotropic(0.2),
/// };
/// input.add_polygon_region(
///     0,
///     &[DVec2::new(0.1, 0.1), DVec2::new(0.9, 0.1), DVec2::new(0.9, 0.9), DVec2::new(0.1, 0.9)],
/// );
/// let out = mesh(&input, &CurvedOptions::with_order(2)).unwrap();
/// assert!(out.element_count() > 10);
/// assert!(out.quality.straight_min_vertex.min >= out.quality.guaranteed_angle_deg);
/// ```
pub fn mesh(input: &TrimmedPatches, options: &CurvedOptions) -> crate::Result<CurvedMesh> {
    mesh_with_progress(input, options, &mut |_, _| {})
}

/// [`mesh`], calling `progress(sites, estimate)` now and then during refinement (sites made
/// so far and a rough estimate of the total), for front ends that show progress.
pub fn mesh_with_progress(
    input: &TrimmedPatches,
    options: &CurvedOptions,
    progress: &mut dyn FnMut(u64, u64),
) -> crate::Result<CurvedMesh> {
    use std::time::Instant;
    options.validate()?;
    let t0 = Instant::now();
    let used = validate::validate(input)?;
    let mut stats = MeshStats {
        seconds_validate: t0.elapsed().as_secs_f64(),
        ..Default::default()
    };
    let params = separate::GuardParams {
        mu: options.mu,
        max_cone_deg: options.max_cone_deg,
        max_depth: options.max_split_depth,
        max_pieces: options.max_curve_pieces,
    };
    let mut assembly = assemble::Assembly::new(options.order);
    let (mut done_sites, mut done_estimate) = (0u64, 0u64);
    for patch in 0..input.patches.len() as u32 {
        let regions: Vec<u32> = (0..input.regions.len() as u32)
            .filter(|&r| input.regions[r as usize].patch.0 == patch)
            .collect();
        if regions.is_empty() {
            continue;
        }
        let mut curves: Vec<u32> = regions
            .iter()
            .flat_map(|&r| input.regions[r as usize].loops.iter())
            .flat_map(|l| l.uses.iter().map(|u| u.curve.0))
            .collect();
        curves.sort_unstable();
        curves.dedup();
        debug_assert!(curves.iter().all(|c| used.binary_search(c).is_ok()));
        let t = Instant::now();
        let guarded = separate::guard_and_separate(&input.curves, &curves, params)?;
        stats.seconds_guard += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let metric = field::PatchMetric::new(
            &input.metric,
            &input.patches[patch as usize],
            patch,
            options.clamp(),
        );
        let mut d = domain::build(input, &regions, metric, guarded)?;
        let corners = corners::Corners::find(&d, &regions, options.small_angle_deg);
        let mut refiner = refine::Refiner::new(&d, options, corners);
        let (base_sites, base_estimate) = (done_sites, done_estimate);
        let mut report = |s: u64, e: u64| progress(base_sites + s, base_estimate + e.max(s));
        refiner.run(&mut d, &mut report)?;
        unfold_curved_elements(&mut d, &mut refiner, options.order, &mut report)?;
        done_sites += d.tr.vertex_count() as u64;
        done_estimate += refiner.estimate.max(d.tr.vertex_count() as u64);
        progress(done_sites, done_estimate);
        stats.seconds_refine += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let r = refiner.stats;
        stats.refine.insertions += r.insertions;
        stats.refine.bisections += r.bisections;
        stats.refine.steps += r.steps;
        stats.refine.unresolved += r.unresolved;
        stats.curve_pieces += d.guarded.pieces.iter().flatten().count() as u64;
        stats.inexact_voronoi_vertices += d.tr.inexact_centers;
        let measure = quality::Measure {
            metric: &d.metric,
            field: &input.metric,
            patch: &input.patches[patch as usize],
            samples: options.angle_samples,
            sampled: options.sampled_quality,
        };
        assembly.add_patch(&d, &refiner.corners, &measure);
        stats.seconds_output += t.elapsed().as_secs_f64();
    }
    let t = Instant::now();
    use rayon::prelude::*;
    let nodes_xyz: Vec<glam::DVec3> = assembly
        .nodes_uv
        .par_iter()
        .zip(assembly.node_patch.par_iter())
        .map(|(uv, p)| input.patches[p.idx()].eval(uv.x, uv.y))
        .collect();
    // On the surface, each element's signed Jacobian along its corners' normal (Gmsh's check).
    let order = options.order;
    let inv = element::collocation_inverse(order);
    let npe = ((order + 1) * (order + 2) / 2) as usize;
    let surface: Vec<f64> = assembly
        .elements
        .par_chunks(npe)
        .map(|nodes| {
            let xyz: Vec<glam::DVec3> = nodes.iter().map(|&n| nodes_xyz[n as usize]).collect();
            element::projected_control_points(order, &xyz, &inv)
                .map_or(-1.0, |t| quality::scaled_jacobian(&t))
        })
        .collect();
    for (info, s) in assembly.info.iter_mut().zip(surface) {
        info.quality.scaled_jacobian_surface = s;
    }
    let q: Vec<(ElementKind, bool, output::ElementQuality)> = assembly
        .info
        .iter()
        .map(|i| (i.kind, i.exempt, i.quality))
        .collect();
    let quality = quality::QualityReport::of(&q, options.guaranteed_angle_deg());
    stats.seconds_output += t.elapsed().as_secs_f64();
    Ok(CurvedMesh {
        order: options.order,
        nodes_uv: assembly.nodes_uv,
        nodes_xyz,
        node_patch: assembly.node_patch,
        elements: assembly.elements,
        info: assembly.info,
        quality,
        stats,
    })
}

/// Bisects the pieces whose curved elements fold at the output order (spec §5.1: "or
/// bisect the curve further"), refining again after each round.
fn unfold_curved_elements(
    d: &mut domain::Domain,
    refiner: &mut refine::Refiner,
    q: u32,
    progress: &mut dyn FnMut(u64, u64),
) -> crate::Result<()> {
    if q == 1 {
        return Ok(());
    }
    let inv = element::collocation_inverse(q);
    for round in 0..=8 {
        let mut folded: Vec<u32> = Vec::new();
        let mut tilted: Vec<u32> = Vec::new();
        for (id, piece) in d.guarded.pieces.iter().enumerate() {
            let Some(piece) = piece else { continue };
            if piece.is_linear() {
                continue;
            }
            let sides = d.curve_regions[piece.curve as usize];
            for (k, right) in [false, true].into_iter().enumerate() {
                if sides[k] == triangulation::NONE {
                    continue;
                }
                let (nodes, m) = assemble::curved_nodes(d, id as u32, right, q, &inv);
                if m <= 0.0 {
                    folded.push(id as u32);
                    break;
                }
                // Valid in parameter space but not by Gmsh's check on the surface (a thin
                // element whose corners' plane tilts away from the surface): bisecting makes
                // it flatter, for a few rounds; what remains is reported per element.
                if round < SURFACE_ROUNDS && !surface_valid(d, q, &nodes, &inv) {
                    tilted.push(id as u32);
                    break;
                }
            }
        }
        if folded.is_empty() && tilted.is_empty() {
            return Ok(());
        }
        if round == 8 {
            let p = d.guarded.piece(folded[0]);
            return Err(CurvedError::InvalidElement {
                curve: p.curve,
                t0: p.t0(),
                t1: p.t1(),
                order: q,
            }
            .into());
        }
        for id in tilted {
            if d.guarded.pieces[id as usize].is_some() {
                refiner.split_piece(d, id, None)?;
            }
        }
        for id in folded {
            if d.guarded.pieces[id as usize].is_some() && !refiner.split_piece(d, id, None)? {
                let p = d.guarded.piece(id);
                return Err(CurvedError::InvalidElement {
                    curve: p.curve,
                    t0: p.t0(),
                    t1: p.t1(),
                    order: q,
                }
                .into());
            }
        }
        refiner.drain(d, progress)?;
    }
    Ok(())
}

/// Rounds of bisection spent on curved elements Gmsh's surface check would flag.
const SURFACE_ROUNDS: u32 = 3;

/// Whether the curved element with uv nodes `uv` passes Gmsh's check on the surface: its
/// signed Jacobian along the corners' normal, with nodes `P(u, v)`, positive.
fn surface_valid(d: &domain::Domain, q: u32, uv: &[glam::DVec2], inv: &[Vec<f64>]) -> bool {
    let xyz: Vec<glam::DVec3> = uv.iter().map(|p| d.metric.patch.eval(p.x, p.y)).collect();
    element::projected_control_points(q, &xyz, inv)
        .is_some_and(|t| quality::scaled_jacobian(&t) > 0.0)
}

/// The parameter-space metric [`mesh`] follows at `uv` on `patch`: the real-space metric
/// pulled back (`Jᵀ M J`, seed 000 §4 Step 1) and clamped as `options` say, or the
/// parameter-space field's value. For front ends and comparisons that need the same metric.
pub fn metric_at(
    input: &TrimmedPatches,
    options: &CurvedOptions,
    patch: PatchId,
    uv: glam::DVec2,
) -> crate::Result<Metric2> {
    let p = input
        .patches
        .get(patch.idx())
        .ok_or_else(|| crate::Error::InvalidArgument(format!("patch {patch} does not exist")))?;
    let pm = field::PatchMetric::new(&input.metric, p, patch.0, options.clamp());
    Ok(pm.at(uv)?)
}

/// Measures any triangle mesh of `patch`'s parameter square (`uv` positions, counter-clockwise
/// `triangles`) the way [`mesh`] measures its own straight elements (spec §6): angles in each
/// vertex's metric, sampled over a lattice, and on the flat triangles in R³. For comparing
/// another mesher's output on the same input and metric (all triangles count as straight and
/// not exempt).
pub fn measure_triangles(
    input: &TrimmedPatches,
    options: &CurvedOptions,
    patch: PatchId,
    uv: &[glam::DVec2],
    triangles: &[[u32; 3]],
) -> crate::Result<(Vec<ElementQuality>, QualityReport)> {
    use rayon::prelude::*;
    let p = input
        .patches
        .get(patch.idx())
        .ok_or_else(|| crate::Error::InvalidArgument(format!("patch {patch} does not exist")))?;
    let pm = field::PatchMetric::new(&input.metric, p, patch.0, options.clamp());
    let metrics = uv
        .iter()
        .map(|&x| pm.at(x))
        .collect::<Result<Vec<_>, _>>()?;
    for (t, tri) in triangles.iter().enumerate() {
        if let Some(&v) = tri.iter().find(|&&v| v as usize >= uv.len()) {
            return Err(crate::Error::InvalidArgument(format!(
                "triangle {t} refers to vertex {v}, but there are {} vertices",
                uv.len()
            )));
        }
    }
    let measure = quality::Measure {
        metric: &pm,
        field: &input.metric,
        patch: p,
        samples: options.angle_samples,
        sampled: options.sampled_quality,
    };
    let q: Vec<ElementQuality> = triangles
        .par_iter()
        .map(|t| {
            let pts = t.map(|v| uv[v as usize]);
            let ms = t.map(|v| metrics[v as usize]);
            measure.straight(&pts, &ms)
        })
        .collect();
    let tagged: Vec<(ElementKind, bool, ElementQuality)> = q
        .iter()
        .map(|e| (ElementKind::Straight, false, *e))
        .collect();
    let report = quality::QualityReport::of(&tagged, options.guaranteed_angle_deg());
    Ok((q, report))
}
