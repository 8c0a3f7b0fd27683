//! `katachi subdivide IN OUT [options]`.

use std::path::PathBuf;

use clap::ValueEnum;
use indicatif::{ProgressBar, ProgressStyle};
use katachi::mesh::holes::split_faces_with_holes;
use katachi::subdivide::{
    catmull_clark_with_progress, BoundaryInterpolation, CreaseMethod, HoleMethod, SubdivideOptions,
};
use katachi::{io, Error};

#[derive(Clone, Copy, ValueEnum)]
pub enum Holes {
    /// Method [a]: bridge the loops, subdivide smoothly.
    Smooth,
    /// Method [b]: loops stay sharp, the face stays planar.
    Sharp,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum Boundary {
    EdgeOnly,
    EdgeAndCorner,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum Crease {
    Uniform,
    Chaikin,
}

#[derive(clap::Args)]
pub struct Args {
    /// Input mesh (.obj, .ply, .off).
    input: PathBuf,
    /// Output mesh (.obj, .ply, .off).
    output: PathBuf,
    /// Subdivision levels.
    #[arg(long, default_value_t = 1)]
    levels: u32,
    /// Method for faces with holes.
    #[arg(long, value_enum, default_value_t = Holes::Smooth)]
    holes: Holes,
    /// Boundary rule.
    #[arg(long, value_enum, default_value_t = Boundary::EdgeOnly)]
    boundary: Boundary,
    /// Semi-sharp crease rule.
    #[arg(long, value_enum, default_value_t = Crease::Uniform)]
    crease_method: Crease,
    /// Recover faces with holes from coplanar regions first (a boolean's triangulated output).
    #[arg(long)]
    solid: bool,
    /// Tag edges whose dihedral angle exceeds DEG degrees as sharp creases (CAD meshes).
    #[arg(long, value_name = "DEG")]
    feature_angle: Option<f64>,
}

/// Inputs at least this large show a progress bar.
const PROGRESS_FACES: u32 = 100_000;

pub fn run(args: &Args) -> Result<(), Error> {
    let mesh = io::read(&args.input)?;
    let mut options = SubdivideOptions::with_levels(args.levels);
    options.holes = match args.holes {
        Holes::Smooth => HoleMethod::Smooth,
        Holes::Sharp => HoleMethod::Sharp,
    };
    options.boundary = match args.boundary {
        Boundary::EdgeOnly => BoundaryInterpolation::EdgeOnly,
        Boundary::EdgeAndCorner => BoundaryInterpolation::EdgeAndCorner,
    };
    options.crease_method = match args.crease_method {
        Crease::Uniform => CreaseMethod::Uniform,
        Crease::Chaikin => CreaseMethod::Chaikin,
    };
    options.recover_faces_with_holes = args.solid;
    options.feature_angle = args.feature_angle;
    let grows = (mesh.corner_count() as u64) << (2 * args.levels.saturating_sub(1).min(8));
    let bar = (grows >= PROGRESS_FACES as u64).then(|| {
        ProgressBar::new(args.levels as u64).with_style(
            ProgressStyle::with_template("subdividing {bar:30} level {pos}/{len}")
                .expect("a valid template"),
        )
    });
    let out = catmull_clark_with_progress(&mesh, &options, &mut |done, _| {
        if let Some(b) = &bar {
            b.set_position(done as u64);
        }
    })?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    for (f, why) in &out.report.fell_back_to_sharp {
        crate::out::note(format!(
            "note: face {f}: method [a] could not bridge it ({why}); method [b] was used"
        ));
    }
    let holes = out
        .mesh
        .faces()
        .filter(|&f| out.mesh.face_loop_count(f) > 1)
        .count();
    let mesh = if holes > 0 {
        // OBJ, PLY and OFF store no faces with holes: cut them along their bridges.
        crate::out::note(format!(
            "note: {holes} faces with holes written as simple polygons cut along bridge edges"
        ));
        split_faces_with_holes(&out.mesh)?.0
    } else {
        out.mesh
    };
    io::write(&args.output, &mesh)?;
    crate::out::line(format!(
        "wrote {} ({} vertices, {} faces, {} levels)",
        args.output.display(),
        mesh.vertex_count(),
        mesh.face_count(),
        args.levels
    ))?;
    Ok(())
}
