//! `katachi cut IN OUT --stroke FILE.json [--mode M] [--open] [--report REPORT.json]
//! [--snap-vertex R] [--snap-segment R] [--corner-angle D]`: the
//! stroke cut (seed 002) from the command line.
//!
//! The stroke file holds what a front end has when the user draws:
//!
//! ```json
//! {
//!   "stroke": [[120.5, 300], [180, 290.25], ...],
//!   "view_proj": [16 numbers, column-major],
//!   "viewport": [0, 0, 800, 600],
//!   "mode": "visible-only",
//!   "open": false
//! }
//! ```
//!
//! `stroke` in pixels with the origin at the viewport's top-left corner and y down;
//! `view_proj` the view-projection matrix (`clip = view_proj · [x, y, z, 1]`, OpenGL NDC);
//! `viewport` as `[x0, y0, width, height]`; `mode` and `open` are optional, and the
//! command-line flags override them. `katachi demo` writes such a file beside its cut.

use std::path::{Path, PathBuf};

use clap::ValueEnum;
use glam::{DMat4, DVec2};
use katachi::cut::{cut_by_stroke, CutMode, CutOptions, CutOutput, Stroke, View};
use katachi::{io, Error, PolyMesh};
use serde_json::{json, Value};

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Mode {
    /// Only the faces seen from the eye (front-facing, not hidden).
    VisibleOnly,
    /// Every face under the stroke, front and back sheets alike.
    ThroughAll,
}

impl Mode {
    fn name(self) -> &'static str {
        match self {
            Mode::VisibleOnly => "visible-only",
            Mode::ThroughAll => "through-all",
        }
    }

    fn kernel(self) -> CutMode {
        match self {
            Mode::VisibleOnly => CutMode::VisibleOnly,
            Mode::ThroughAll => CutMode::ThroughAll,
        }
    }
}

#[derive(clap::Args)]
pub struct Args {
    /// Input mesh (.obj, .ply, .off).
    input: PathBuf,
    /// Output mesh (.obj, .ply, .off): the cut mesh, all triangles.
    output: PathBuf,
    /// The stroke and the camera, as JSON: {"stroke": [[x, y], ...] (pixels, top-left origin,
    /// y down), "view_proj": [16 numbers, column-major], "viewport": [x0, y0, w, h],
    /// optional "mode", optional "open"}.
    #[arg(long, value_name = "FILE.json")]
    stroke: PathBuf,
    /// Which faces are cut (overrides the file's "mode"; default visible-only).
    #[arg(long, value_enum)]
    mode: Option<Mode>,
    /// Open the cut: duplicate the path's vertices, so the mesh gets a slit or falls apart
    /// (overrides the file's "open").
    #[arg(long)]
    open: bool,
    /// Also write the full report (moves, dropped points, paths, ...) as JSON.
    #[arg(long, value_name = "REPORT.json")]
    report: Option<PathBuf>,
    /// Snap a vertex to a stroke point closer than this × L, the mean screen edge length
    /// (seed 002 §3.2), in [0, 0.5]; 0 turns it off.
    #[arg(long, value_name = "RATIO", default_value_t = CutOptions::default().snap_vertex_ratio)]
    snap_vertex: f64,
    /// Snap a vertex onto a stroke segment closer than this × L (seed 002 §3.2, Fig. 4), in
    /// [0, 0.5]; 0 turns it off.
    #[arg(long, value_name = "RATIO", default_value_t = CutOptions::default().snap_segment_ratio)]
    snap_segment: f64,
    /// Split the stroke where it turns by more than this many degrees (seed 002 §3.4), in
    /// [0, 180].
    #[arg(long, value_name = "DEGREES", default_value_t = CutOptions::default().corner_angle_deg)]
    corner_angle: f64,
}

/// What a stroke file holds.
#[derive(Debug, Clone, PartialEq)]
pub struct StrokeFile {
    pub stroke: Vec<DVec2>,
    pub view_proj: DMat4,
    pub viewport: [f64; 4],
    pub mode: Option<Mode>,
    pub open: Option<bool>,
}

const FIELDS: &str = "\"stroke\", \"view_proj\", \"viewport\", \"mode\", \"open\"";

impl StrokeFile {
    /// Parses a stroke file's text; errors name `path` and the field at fault.
    pub fn parse(text: &str, path: &Path) -> Result<StrokeFile, Error> {
        let bad =
            |message: String| Error::InvalidArgument(format!("{}: {message}", path.display()));
        let value: Value =
            serde_json::from_str(text).map_err(|e| bad(format!("not valid JSON: {e}")))?;
        let Value::Object(map) = value else {
            return Err(bad(format!(
                "expected a JSON object with the fields {FIELDS}, found {}",
                kind(&value)
            )));
        };
        if let Some(k) = map.keys().find(|k| !FIELDS.contains(&format!("\"{k}\""))) {
            return Err(bad(format!(
                "unknown field \"{k}\" (the fields are {FIELDS})"
            )));
        }
        let field = |name: &str, what: &str| {
            map.get(name)
                .ok_or_else(|| bad(format!("missing field \"{name}\" ({what})")))
        };
        let numbers = |name: &str, v: &Value, n: usize, what: &str| -> Result<Vec<f64>, Error> {
            let items = v
                .as_array()
                .ok_or_else(|| bad(format!("\"{name}\" must be {what}, but it is {}", kind(v))))?;
            if items.len() != n {
                return Err(bad(format!(
                    "\"{name}\" must be {what}, but it has {} elements",
                    items.len()
                )));
            }
            items
                .iter()
                .enumerate()
                .map(|(i, x)| {
                    x.as_f64()
                        .ok_or_else(|| bad(format!("\"{name}\"[{i}] is {}, not a number", kind(x))))
                })
                .collect()
        };

        const STROKE: &str = "an array of [x, y] points in pixels, top-left origin, y down";
        let stroke_value = field("stroke", STROKE)?;
        let points = stroke_value.as_array().ok_or_else(|| {
            bad(format!(
                "\"stroke\" must be {STROKE}, but it is {}",
                kind(stroke_value)
            ))
        })?;
        let stroke = points
            .iter()
            .enumerate()
            .map(|(i, p)| {
                numbers(&format!("stroke[{i}]"), p, 2, "[x, y] (two numbers)")
                    .map(|xy| DVec2::new(xy[0], xy[1]))
            })
            .collect::<Result<Vec<_>, _>>()?;

        const VIEW_PROJ: &str =
            "an array of 16 numbers, the view-projection matrix column by column";
        let m = numbers("view_proj", field("view_proj", VIEW_PROJ)?, 16, VIEW_PROJ)?;
        const VIEWPORT: &str = "[x0, y0, width, height] in pixels";
        let vp = numbers("viewport", field("viewport", VIEWPORT)?, 4, VIEWPORT)?;

        let mode = match map.get("mode") {
            None => None,
            Some(Value::String(s)) if s == "visible-only" => Some(Mode::VisibleOnly),
            Some(Value::String(s)) if s == "through-all" => Some(Mode::ThroughAll),
            Some(other) => {
                return Err(bad(format!(
                    "\"mode\" is {other}, which is not \"visible-only\" or \"through-all\""
                )))
            }
        };
        let open = match map.get("open") {
            None => None,
            Some(Value::Bool(b)) => Some(*b),
            Some(other) => {
                return Err(bad(format!(
                    "\"open\" must be true or false, but it is {}",
                    kind(other)
                )))
            }
        };
        Ok(StrokeFile {
            stroke,
            view_proj: DMat4::from_cols_slice(&m),
            viewport: [vp[0], vp[1], vp[2], vp[3]],
            mode,
            open,
        })
    }

    /// The file's JSON text (what `parse` reads back): one stroke point a line.
    pub fn to_json(&self) -> String {
        let num = |x: f64| Value::from(x).to_string();
        let list = |xs: &[f64]| xs.iter().map(|&x| num(x)).collect::<Vec<_>>().join(", ");
        let points: Vec<String> = self
            .stroke
            .iter()
            .map(|p| format!("    [{}, {}]", num(p.x), num(p.y)))
            .collect();
        let mut fields = vec![
            format!("  \"stroke\": [\n{}\n  ]", points.join(",\n")),
            format!(
                "  \"view_proj\": [{}]",
                list(&self.view_proj.to_cols_array())
            ),
            format!("  \"viewport\": [{}]", list(&self.viewport)),
        ];
        if let Some(m) = self.mode {
            fields.push(format!("  \"mode\": \"{}\"", m.name()));
        }
        if let Some(o) = self.open {
            fields.push(format!("  \"open\": {o}"));
        }
        format!("{{\n{}\n}}\n", fields.join(",\n"))
    }
}

/// A JSON value's kind, for messages ("a string \"x\"", "an object").
fn kind(v: &Value) -> String {
    match v {
        Value::Null => "null".into(),
        Value::Bool(b) => format!("{b}"),
        Value::Number(n) => format!("the number {n}"),
        Value::String(s) => format!("the string {s:?}"),
        Value::Array(a) => format!("an array of {} elements", a.len()),
        Value::Object(_) => "an object".into(),
    }
}

fn read_text(path: &Path) -> Result<String, Error> {
    std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Written as meshes are: a failed write leaves a file already there as it was.
fn write_text(path: &Path, text: &str) -> Result<(), Error> {
    io::write_bytes(path, text.as_bytes())
}

/// The kernel's options for `mode` and `open`, the rest at their defaults.
pub fn options(mode: Mode, open: bool) -> CutOptions {
    let mut o = CutOptions::with_mode(mode.kernel());
    o.open = open;
    o
}

/// Cuts `mesh` as the stroke file says, with the options already decided.
pub fn cut(mesh: &PolyMesh, file: &StrokeFile, options: &CutOptions) -> Result<CutOutput, Error> {
    cut_by_stroke(
        mesh,
        &Stroke::new(file.stroke.clone()),
        &View::new(file.view_proj, file.viewport),
        options,
    )
}

/// The short human report: one fact a line.
pub fn summary(out: &CutOutput, input_faces: u32) -> Vec<String> {
    let r = &out.report;
    let d = &r.dropped;
    let path_vertices: usize = r.paths.iter().map(|p| p.vertices.len()).sum();
    let closed = r.paths.iter().filter(|p| p.closed).count();
    let mut lines = vec![
        {
            let triangles = out.mesh.face_count() - r.new_faces;
            format!(
                "faces: {input_faces} -> {} triangles ({}{} triangles split, {} new faces, {} new \
                 vertices)",
                out.mesh.face_count(),
                if triangles != input_faces {
                    format!("{triangles} after triangulation; ")
                } else {
                    String::new()
                },
                r.split_faces,
                r.new_faces,
                r.new_vertices
            )
        },
        format!(
            "paths: {} ({path_vertices} vertices{}) in {} stroke piece{}",
            r.paths.len(),
            if closed > 0 {
                format!(", {closed} closed")
            } else {
                String::new()
            },
            r.pieces,
            if r.pieces == 1 { "" } else { "s" }
        ),
        format!(
            "moved vertices: {} onto the stroke, largest move {:.3} px ({:.4} world units); \
             mean edge length L = {:.3} px",
            r.moved.len(),
            r.max_move_px,
            r.max_move_world,
            r.mean_edge_length_px
        ),
        format!(
            "dropped stroke points: {} in preprocessing, {} by the first normalization, {} by \
             the second, {} off the mesh",
            d.preprocessing.len(),
            d.first_normalization.len(),
            d.second_normalization.len(),
            d.off_mesh.len()
        ),
    ];
    if r.paths.is_empty() {
        lines.push("note: the stroke meets no face the cut may touch; nothing was cut".into());
    }
    for (n, what) in [
        (
            r.snaps_refused.len(),
            "vertices near the stroke kept in place (moving them would flip a face)",
        ),
        (
            r.ends_moved_to_edges.len(),
            "piece ends moved onto a nearby edge",
        ),
        (r.clipped_faces.len(), "faces behind the eye left uncut"),
        (r.degenerate_faces.len(), "zero-area faces left unsplit"),
        (r.rerouted.len(), "path stretches routed along edges"),
        (
            r.unjoined.len(),
            "path stretches that could not be made edges",
        ),
    ] {
        if n > 0 {
            lines.push(format!("note: {n} {what}"));
        }
    }
    lines
}

/// The full report as JSON.
pub fn report_json(out: &CutOutput, input: &Path, output: &Path, mode: Mode, open: bool) -> Value {
    let r = &out.report;
    let ids = |v: &[katachi::mesh::VertexId]| v.iter().map(|x| x.0).collect::<Vec<_>>();
    let faces = |v: &[katachi::mesh::FaceId]| v.iter().map(|x| x.0).collect::<Vec<_>>();
    let triples = |v: &[(u32, katachi::mesh::VertexId, katachi::mesh::VertexId)]| {
        v.iter()
            .map(|&(p, a, b)| json!({"piece": p, "from": a.0, "to": b.0}))
            .collect::<Vec<_>>()
    };
    json!({
        "input": input.display().to_string(),
        "output": output.display().to_string(),
        "mode": mode.name(),
        "open": open,
        "vertex_count": out.mesh.vertex_count(),
        "face_count": out.mesh.face_count(),
        "new_vertices": r.new_vertices,
        "new_faces": r.new_faces,
        "split_faces": r.split_faces,
        "pieces": r.pieces,
        "mean_edge_length_px": r.mean_edge_length_px,
        "mean_edge_length_world": r.mean_edge_length_world,
        "max_move_px": r.max_move_px,
        "max_move_world": r.max_move_world,
        "moved": r.moved.iter().map(|m| json!({
            "vertex": m.vertex.0,
            "from": m.from.to_array(),
            "to": m.to.to_array(),
            "pixels": m.pixels,
        })).collect::<Vec<_>>(),
        "dropped": {
            "preprocessing": r.dropped.preprocessing,
            "first_normalization": r.dropped.first_normalization,
            "second_normalization": r.dropped.second_normalization,
            "off_mesh": r.dropped.off_mesh,
        },
        "paths": r.paths.iter().map(|p| json!({
            "piece": p.piece,
            "closed": p.closed,
            "vertices": ids(&p.vertices),
        })).collect::<Vec<_>>(),
        "snaps_refused": ids(&r.snaps_refused),
        "ends_moved_to_edges": r.ends_moved_to_edges,
        "clipped_faces": faces(&r.clipped_faces),
        "degenerate_faces": faces(&r.degenerate_faces),
        "rerouted": triples(&r.rerouted),
        "unjoined": triples(&r.unjoined),
    })
}

pub fn run(args: &Args) -> Result<(), Error> {
    // The stroke file first: a typo there should not wait for a large mesh to load.
    let file = StrokeFile::parse(&read_text(&args.stroke)?, &args.stroke)?;
    let mode = args.mode.or(file.mode).unwrap_or(Mode::VisibleOnly);
    let open = args.open || file.open.unwrap_or(false);
    let mut options = options(mode, open);
    options.snap_vertex_ratio = args.snap_vertex;
    options.snap_segment_ratio = args.snap_segment;
    options.corner_angle_deg = args.corner_angle;
    let mesh = io::read(&args.input)?;
    let out = cut(&mesh, &file, &options)?;
    io::write(&args.output, &out.mesh)?;
    crate::out::line(format!(
        "cut {} along {} stroke points ({}{})",
        args.input.display(),
        file.stroke.len(),
        mode.name(),
        if open { ", opened" } else { "" }
    ))?;
    for line in summary(&out, mesh.face_count()) {
        crate::out::line(line)?;
    }
    if let Some(path) = &args.report {
        let mut text =
            serde_json::to_string_pretty(&report_json(&out, &args.input, &args.output, mode, open))
                .expect("a JSON value always serializes");
        text.push('\n');
        write_text(path, &text)?;
        crate::out::line(format!("wrote the report to {}", path.display()))?;
    }
    crate::out::line(format!(
        "wrote {} ({} vertices, {} faces)",
        args.output.display(),
        out.mesh.vertex_count(),
        out.mesh.face_count()
    ))?;
    Ok(())
}
