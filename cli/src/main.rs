//! `katachi`: the command-line front end. Reads and writes OBJ/PLY/OFF by extension.
//! Bad input prints one line `error: …` and exits with status 2; no panic reaches the user.
//! The exit status is 0 or 2, nothing else: a usage error, an I/O error on stdout (a closed
//! pipe, a full disk) and a bug caught at the top are all 2.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use katachi::mesh::{inspect, MeshReport};
use katachi::{io, Error};

mod curved;
mod cut;
mod demo;
mod out;
mod subdivide;

#[derive(Parser)]
#[command(name = "katachi", version, about = "katachi: a mesh-modelling kernel", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Print what a mesh file holds: counts, boundaries, components, manifoldness, defects.
    Info {
        /// An .obj, .ply or .off file.
        file: PathBuf,
    },
    /// Convert a mesh between OBJ, PLY and OFF (formats by extension).
    Convert {
        /// Input file (.obj, .ply, .off).
        input: PathBuf,
        /// Output file (.obj, .ply, .off).
        output: PathBuf,
    },
    /// Catmull-Clark subdivision, solid-aware (creases, faces with holes; seed 001).
    Subdivide(subdivide::Args),
    /// Cut a mesh along a stroke drawn over a view of it (seed 002); the stroke and camera
    /// come from a JSON file.
    Cut(cut::Args),
    /// Mesh trimmed Bézier patches with curved anisotropic triangles (seed 000); the
    /// patches, curves, regions and metric come from a JSON file.
    CurvedMesh(curved::Args),
    /// Run every operation on the bundled example models and write the results.
    Demo {
        /// Directory for the results (created if missing).
        #[arg(long, default_value = "katachi-demo")]
        out: PathBuf,
    },
}

fn main() -> ExitCode {
    ignore_file_size_signal();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage(e),
    };
    // A panic is a bug; report it in one line rather than with a backtrace.
    std::panic::set_hook(Box::new(|_| {}));
    let result = std::panic::catch_unwind(|| run(cli.command).and_then(|()| out::flush()));
    match result {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(e)) => {
            out::note(format!("error: {e}"));
            ExitCode::from(2)
        }
        Err(panic) => {
            let msg = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            out::note(format!("error: {}", Error::Internal(msg)));
            ExitCode::from(2)
        }
    }
}

/// `--help` and `--version` on stdout (status 0, or 2 when stdout fails); a usage error on
/// stderr with status 2.
fn usage(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
        let text = e.to_string();
        let printed = std::io::Write::write_all(&mut std::io::stdout().lock(), text.as_bytes())
            .and_then(|()| std::io::Write::flush(&mut std::io::stdout()));
        return match printed {
            Ok(()) => ExitCode::SUCCESS,
            Err(source) => {
                out::note(format!("error: <stdout>: {source}"));
                ExitCode::from(2)
            }
        };
    }
    let _ = e.print();
    ExitCode::from(2)
}

/// Writing past a file-size limit (`ulimit -f`) then fails with an error katachi reports,
/// instead of the SIGXFSZ signal killing the process with a status other than 0 or 2.
fn ignore_file_size_signal() {
    #[cfg(unix)]
    // SAFETY: setting a signal's disposition to SIG_IGN touches no memory of ours.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

fn run(command: Command) -> Result<(), Error> {
    match command {
        Command::Info { file } => {
            let mesh = io::read(&file)?;
            let report = inspect(&mesh)?;
            for l in format_report(&file, &report).lines() {
                out::line(l)?;
            }
            Ok(())
        }
        Command::Convert { input, output } => {
            let mesh = io::read(&input)?;
            io::write(&output, &mesh)?;
            out::line(format!(
                "wrote {} ({} vertices, {} faces)",
                output.display(),
                mesh.vertex_count(),
                mesh.face_count()
            ))
        }
        Command::Subdivide(args) => subdivide::run(&args),
        Command::Cut(args) => cut::run(&args),
        Command::CurvedMesh(args) => curved::run(&args),
        Command::Demo { out } => demo::run(&out),
    }
}

/// The `info` text: one fact a line, `name: value`, so scripts can grep it.
pub(crate) fn format_report(file: &Path, r: &MeshReport) -> String {
    let mut s = String::new();
    let mut line = |k: &str, v: String| s.push_str(&format!("{k:<22}{v}\n"));
    line("file:", file.display().to_string());
    line(
        "vertices:",
        if r.unreferenced_vertices > 0 {
            format!("{} ({} unreferenced)", r.vertices, r.unreferenced_vertices)
        } else {
            r.vertices.to_string()
        },
    );
    let kinds: Vec<String> = r
        .faces_by_size
        .iter()
        .map(|(n, c)| match n {
            3 => format!("{c} triangles"),
            4 => format!("{c} quads"),
            _ => format!("{c} {n}-gons"),
        })
        .collect();
    line("faces:", format!("{} ({})", r.faces, kinds.join(", ")));
    if r.faces_with_holes > 0 {
        line("faces with holes:", r.faces_with_holes.to_string());
    }
    line("edges:", r.edges.to_string());
    line(
        "boundary:",
        format!("{} loops, {} edges", r.boundary_loops, r.boundary_edges),
    );
    line("components:", r.components.to_string());
    line(
        "closed:",
        if r.is_closed() { "yes" } else { "no" }.to_string(),
    );
    line(
        "manifold:",
        if r.is_manifold() {
            "yes".to_string()
        } else {
            format!(
                "no ({} non-manifold edges, {} non-manifold vertices, {} inconsistently oriented edges)",
                r.defects.non_manifold_edges.len(),
                r.defects.non_manifold_vertices.len(),
                r.defects.inconsistent_edges.len()
            )
        },
    );
    line("euler characteristic:", r.euler_characteristic.to_string());
    if let Some(g) = r.genus {
        line("genus:", g.to_string());
    }
    if let Some((lo, hi)) = r.bounding_box {
        line(
            "bounding box:",
            format!(
                "[{}, {}, {}] .. [{}, {}, {}]",
                lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
            ),
        );
    }
    line("sharp edges:", r.sharp_edges.to_string());
    line("sharp vertices:", r.sharp_vertices.to_string());
    if r.coincident_vertices > 0 {
        line("coincident vertices:", r.coincident_vertices.to_string());
    }
    if !r.zero_area_faces.is_empty() {
        line("zero-area faces:", r.zero_area_faces.len().to_string());
    }
    s
}
