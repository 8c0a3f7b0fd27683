//! `katachi demo`: every operation that exists, run on the bundled example models.
//! The models are compiled into the binary, so the demo runs from any directory.

use std::path::Path;

use glam::{DMat4, DVec2, DVec3};
use indicatif::{ProgressBar, ProgressStyle};
use katachi::mesh::holes::split_faces_with_holes;
use katachi::mesh::{inspect, shapes};
use katachi::subdivide::{catmull_clark, HoleMethod, SubdivideOptions};
use katachi::{io, Error, PolyMesh};

/// Bundled models (see `examples/models/README.md` for sources and licenses).
const MODELS: &[(&str, &[u8])] = &[
    (
        "chamfer-cube.off",
        include_bytes!("../../examples/models/chamfer-cube.off"),
    ),
    (
        "fandisk_quads.off",
        include_bytes!("../../examples/models/fandisk_quads.off"),
    ),
    (
        "hole_capsule.off",
        include_bytes!("../../examples/models/hole_capsule.off"),
    ),
    (
        "rhombicosidodecahedron.obj",
        include_bytes!("../../examples/models/rhombicosidodecahedron.obj"),
    ),
];

/// Written as meshes are: a failed write leaves a file already there as it was.
fn write_file(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    io::write_bytes(path, bytes)
}

fn create_dir(path: &Path) -> Result<(), Error> {
    std::fs::create_dir_all(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Inspects `mesh`, writes the report beside it, and converts it to the other formats.
fn process(out: &Path, stem: &str, source: &Path, mesh: &PolyMesh) -> Result<String, Error> {
    let report = inspect(mesh)?;
    write_file(
        &out.join(format!("{stem}.info.txt")),
        crate::format_report(source, &report).as_bytes(),
    )?;
    for ext in ["obj", "ply", "off"] {
        let path = out.join(format!("{stem}.{ext}"));
        if path != source {
            io::write(&path, mesh)?;
        }
    }
    Ok(format!(
        "{stem}: {} vertices, {} faces, {} edges, genus {}",
        report.vertices,
        report.faces,
        report.edges,
        report
            .genus
            .map_or("- (open or non-manifold)".to_string(), |g| g.to_string())
    ))
}

pub fn run(out: &Path) -> Result<(), Error> {
    let inputs = out.join("input");
    create_dir(&inputs)?;
    let mut creased = shapes::cube(2.0)?;
    let ids: Vec<_> = creased.vertices().collect();
    creased.set_edge_sharpnesses([(ids[0], ids[1], 2.5), (ids[1], ids[3], 10.0)])?;
    let generated: Vec<(&str, PolyMesh)> = vec![
        ("cube_creased", creased),
        ("hexagonal_prism", shapes::ngon_prism(6, 1.0, 2.0)?),
        ("torus_24x12", shapes::torus(24, 12, 2.0, 0.6)?),
        ("open_grid_8x5", shapes::grid(8, 5)?),
    ];
    let bar = ProgressBar::new((MODELS.len() + generated.len()) as u64).with_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}").expect("a valid template"),
    );
    let mut lines = Vec::new();
    for (name, bytes) in MODELS {
        bar.set_message(*name);
        let source = inputs.join(name);
        write_file(&source, bytes)?;
        let mesh = io::read(&source)?;
        let stem = name.rsplit_once('.').map_or(*name, |(s, _)| s);
        lines.push(process(out, stem, &source, &mesh)?);
        bar.inc(1);
    }
    for (stem, mesh) in &generated {
        bar.set_message(*stem);
        lines.push(process(out, stem, Path::new(stem), mesh)?);
        bar.inc(1);
    }
    bar.finish_and_clear();
    lines.extend(subdivision(out)?);
    lines.extend(stroke_cut(out)?);
    lines.extend(curved_meshing(out)?);
    for l in &lines {
        crate::out::line(l)?;
    }
    crate::out::line(format!("results in {}", out.display()))?;
    Ok(())
}

/// Subdivision (seed 001): a boolean's plate with a hole recovered as faces with holes and
/// refined with methods [a] and [b]; a creased cube; a CAD part creased by feature angle;
/// and beast.obj when the shared models are beside the project.
fn subdivision(out: &Path) -> Result<Vec<String>, Error> {
    let mut cases: Vec<(String, PolyMesh, SubdivideOptions)> = Vec::new();
    let plate = shapes::boolean_plate(4.0, 2.0, 1.0)?;
    for (name, method) in [
        ("smooth_a", HoleMethod::Smooth),
        ("sharp_b", HoleMethod::Sharp),
    ] {
        let mut o = SubdivideOptions::with_levels(3);
        o.recover_faces_with_holes = true;
        o.holes = method;
        cases.push((format!("plate_with_hole_{name}"), plate.clone(), o));
    }
    let mut cube = shapes::cube(2.0)?;
    let v: Vec<_> = cube.vertices().collect();
    cube.set_edge_sharpnesses([
        (v[0], v[1], 10.0),
        (v[1], v[3], 10.0),
        (v[3], v[2], 10.0),
        (v[2], v[0], 10.0),
        (v[4], v[5], 1.5),
    ])?;
    cases.push((
        "cube_creased".into(),
        cube,
        SubdivideOptions::with_levels(3),
    ));
    let fandisk = io::read_bytes(
        include_bytes!("../../examples/models/fandisk_quads.off"),
        io::Format::Off,
        Path::new("fandisk_quads.off"),
    )?;
    let mut o = SubdivideOptions::with_levels(2);
    o.feature_angle = Some(30.0);
    cases.push(("fandisk_quads_feature30".into(), fandisk, o));
    let mut lines = Vec::new();
    for (name, mesh, o) in cases {
        let r = catmull_clark(&mesh, &o)?;
        let holes = r
            .mesh
            .faces()
            .filter(|&f| r.mesh.face_loop_count(f) > 1)
            .count();
        let written = split_faces_with_holes(&r.mesh)?.0;
        let path = out.join(format!("{name}.subdivided.obj"));
        io::write(&path, &written)?;
        lines.push(format!(
            "{name}: subdivided {} levels: {} -> {} faces ({holes} faces with holes kept){}",
            o.levels,
            mesh.face_count(),
            r.mesh.face_count(),
            if r.report.fell_back_to_sharp.is_empty() {
                String::new()
            } else {
                format!(
                    ", {} fell back to method [b]",
                    r.report.fell_back_to_sharp.len()
                )
            }
        ));
    }
    Ok(lines)
}

/// Stroke cut (seed 002): a wavy stroke drawn over a perspective view of the fandisk, cut
/// visible-only (the faces seen) and again opened. The stroke and camera are written beside
/// the results as `fandisk_quads.stroke.json`, which `katachi cut` reads back:
/// `katachi cut input/fandisk_quads.off again.obj --stroke fandisk_quads.stroke.json`.
fn stroke_cut(out: &Path) -> Result<Vec<String>, Error> {
    let name = "fandisk_quads";
    let mesh = io::read_bytes(
        include_bytes!("../../examples/models/fandisk_quads.off"),
        io::Format::Off,
        Path::new("fandisk_quads.off"),
    )?;
    let (lo, hi) = mesh
        .positions()
        .iter()
        .fold((DVec3::MAX, DVec3::MIN), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let (centre, radius) = ((lo + hi) / 2.0, (hi - lo).length() / 2.0);
    let (width, height) = (800.0, 600.0);
    let eye = centre + DVec3::new(0.45, 0.35, 1.0).normalize() * 3.0 * radius;
    let view_proj = DMat4::perspective_rh_gl(
        40f64.to_radians(),
        width / height,
        0.1 * radius,
        10.0 * radius,
    ) * DMat4::look_at_rh(eye, centre, DVec3::Y);
    // Left to right across the middle of the picture, one and a half waves.
    let stroke: Vec<DVec2> = (0..48)
        .map(|i| {
            let t = i as f64 / 47.0;
            DVec2::new(
                width * (0.2 + 0.6 * t),
                height * (0.5 + 0.08 * (3.0 * std::f64::consts::PI * t).sin()),
            )
        })
        .collect();
    let file = crate::cut::StrokeFile {
        stroke,
        view_proj,
        viewport: [0.0, 0.0, width, height],
        mode: Some(crate::cut::Mode::VisibleOnly),
        open: Some(false),
    };
    let stroke_path = out.join(format!("{name}.stroke.json"));
    write_file(&stroke_path, file.to_json().as_bytes())?;
    let mut lines = Vec::new();
    let r = crate::cut::cut(
        &mesh,
        &file,
        &crate::cut::options(crate::cut::Mode::VisibleOnly, false),
    )?;
    io::write(&out.join(format!("{name}.cut.obj")), &r.mesh)?;
    lines.push(format!(
        "{name}: stroke cut (visible-only) along {} points from {}: {} -> {} faces, {} path(s) \
         of {} vertices, {} vertices snapped onto the stroke (largest move {:.2} px)",
        file.stroke.len(),
        stroke_path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default(),
        mesh.face_count(),
        r.mesh.face_count(),
        r.report.paths.len(),
        r.report
            .paths
            .iter()
            .map(|p| p.vertices.len())
            .sum::<usize>(),
        r.report.moved.len(),
        r.report.max_move_px,
    ));
    let r = crate::cut::cut(
        &mesh,
        &file,
        &crate::cut::options(crate::cut::Mode::VisibleOnly, true),
    )?;
    io::write(&out.join(format!("{name}.cut_open.obj")), &r.mesh)?;
    let report = inspect(&r.mesh)?;
    lines.push(format!(
        "{name}: the same cut opened: {} -> {} vertices, {} boundary loop(s) (a slit)",
        mesh.vertex_count(),
        r.mesh.vertex_count(),
        report.boundary_loops,
    ));
    Ok(lines)
}

/// Curved meshing (seed 000): the bundled trimmed bicubic patch with a circular hole, and
/// the two regions glued along a wavy cubic, as Gmsh MSH (cubic elements) and OBJ previews.
/// The input files are written beside the results, for `katachi curved-mesh`.
fn curved_meshing(out: &Path) -> Result<Vec<String>, Error> {
    let mut lines = Vec::new();
    for (name, text) in [
        (
            "curved_square_hole",
            include_str!("../../examples/curved_square_hole.json"),
        ),
        (
            "curved_two_regions",
            include_str!("../../examples/curved_two_regions.json"),
        ),
    ] {
        let source = out.join("input").join(format!("{name}.json"));
        write_file(&source, text.as_bytes())?;
        let (input, options) = crate::curved::read_input(&source)?;
        let mesh = katachi::curved::mesh(&input, &options)?;
        let space = katachi::curved::Space::Surface;
        mesh.write(&out.join(format!("{name}.msh")), space)?;
        mesh.write(&out.join(format!("{name}.preview.obj")), space)?;
        let q = &mesh.quality;
        lines.push(format!(
            "{name}: curved mesh of order {}: {} elements ({} curved), smallest angle in the metric {:.2}° (bound {:.2}°), median corner angle {:.2}°",
            mesh.order,
            mesh.element_count(),
            mesh.info.iter().filter(|i| i.kind == katachi::curved::ElementKind::Curved).count(),
            q.straight_min_vertex.min,
            q.guaranteed_angle_deg,
            q.all_angles.median
        ));
    }
    Ok(lines)
}
