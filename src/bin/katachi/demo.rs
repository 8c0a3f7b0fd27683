//! `katachi demo`: every operation that exists, run on the bundled example models.
//! The models are compiled into the binary, so the demo runs from any directory.

use std::path::Path;

use indicatif::{ProgressBar, ProgressStyle};
use katachi::mesh::{inspect, shapes};
use katachi::{io, Error, PolyMesh};

/// Bundled models (see `examples/models/README.md` for sources and licenses).
const MODELS: &[(&str, &[u8])] = &[
    (
        "chamfer-cube.off",
        include_bytes!("../../../examples/models/chamfer-cube.off"),
    ),
    (
        "fandisk_quads.off",
        include_bytes!("../../../examples/models/fandisk_quads.off"),
    ),
    (
        "hole_capsule.off",
        include_bytes!("../../../examples/models/hole_capsule.off"),
    ),
    (
        "rhombicosidodecahedron.obj",
        include_bytes!("../../../examples/models/rhombicosidodecahedron.obj"),
    ),
];

fn write_file(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    std::fs::write(path, bytes).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })
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
    let mut creased = shapes::cube(2.0);
    let ids: Vec<_> = creased.vertices().collect();
    creased.set_edge_sharpnesses([(ids[0], ids[1], 2.5), (ids[1], ids[3], 10.0)])?;
    let generated: Vec<(&str, PolyMesh)> = vec![
        ("cube_creased", creased),
        ("hexagonal_prism", shapes::ngon_prism(6, 1.0, 2.0)),
        ("torus_24x12", shapes::torus(24, 12, 2.0, 0.6)),
        ("open_grid_8x5", shapes::grid(8, 5)),
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
    for l in &lines {
        println!("{l}");
    }
    println!("results in {}", out.display());
    Ok(())
}
