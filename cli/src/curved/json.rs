//! The JSON input of `katachi curved-mesh` (schema in `docs/curved.md`, examples in
//! `examples/curved_*.json`). The reader names the field at fault
//! ("regions[1].loops[0][3].curve: expected a curve index, found \"x\"").

use std::path::Path;

use glam::{DVec2, DVec3};
use serde_json::Value;

use katachi::curved::{
    BezierCurve, BezierPatch, CurveUse, CurvedOptions, Grid2, Grid3, Metric2, Metric3, MetricField,
    PatchId, Region, SizeField, TrimLoop, TrimmedPatches,
};
use katachi::{Error, Result};

/// Reads a curved-meshing input file: the patches, curves, regions and metric, and the
/// options it sets (the rest default).
pub fn read_input(path: &Path) -> Result<(TrimmedPatches, CurvedOptions)> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_input(&text).map_err(|e| match e {
        ReadError::Syntax { line, message } => Error::Parse {
            path: path.to_path_buf(),
            line,
            byte: None,
            message,
        },
        ReadError::Field { field, message } => Error::Parse {
            path: path.to_path_buf(),
            line: 0,
            byte: None,
            message: format!("{field}: {message}"),
        },
    })
}

/// A JSON syntax error (with its 1-based line) or a field that is missing or malformed.
#[derive(Debug, Clone, PartialEq)]
pub enum ReadError {
    Syntax { line: usize, message: String },
    Field { field: String, message: String },
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReadError::Syntax { line, message } => write!(f, "line {line}: {message}"),
            ReadError::Field { field, message } => write!(f, "{field}: {message}"),
        }
    }
}

type R<T> = std::result::Result<T, ReadError>;

fn field_err<T>(field: &str, message: impl Into<String>) -> R<T> {
    Err(ReadError::Field {
        field: field.to_string(),
        message: message.into(),
    })
}

fn describe(v: &Value) -> String {
    match v {
        Value::Null => "null".into(),
        Value::Bool(b) => b.to_string(),
        Value::Number(n) => n.to_string(),
        Value::String(s) => format!("{s:?}"),
        Value::Array(a) => format!("an array of {}", a.len()),
        Value::Object(_) => "an object".into(),
    }
}

fn get<'a>(obj: &'a Value, field: &str, key: &str) -> R<&'a Value> {
    match obj.get(key) {
        Some(v) => Ok(v),
        None => field_err(&format!("{field}.{key}"), "missing"),
    }
}

fn number(v: &Value, field: &str) -> R<f64> {
    match v.as_f64() {
        Some(x) if x.is_finite() => Ok(x),
        _ => field_err(
            field,
            format!("expected a finite number, found {}", describe(v)),
        ),
    }
}

fn positive(v: &Value, field: &str) -> R<f64> {
    let x = number(v, field)?;
    if x > 0.0 {
        Ok(x)
    } else {
        field_err(field, format!("expected a positive number, found {x}"))
    }
}

fn index(v: &Value, field: &str, what: &str) -> R<u32> {
    match v.as_u64() {
        Some(x) if x <= u32::MAX as u64 => Ok(x as u32),
        _ => field_err(field, format!("expected {what}, found {}", describe(v))),
    }
}

fn array<'a>(v: &'a Value, field: &str) -> R<&'a Vec<Value>> {
    v.as_array().ok_or_else(|| ReadError::Field {
        field: field.to_string(),
        message: format!("expected an array, found {}", describe(v)),
    })
}

fn numbers<const N: usize>(v: &Value, field: &str) -> R<[f64; N]> {
    let a = array(v, field)?;
    if a.len() != N {
        return field_err(field, format!("expected {N} numbers, found {}", a.len()));
    }
    let mut out = [0.0; N];
    for (k, x) in a.iter().enumerate() {
        out[k] = number(x, &format!("{field}[{k}]"))?;
    }
    Ok(out)
}

fn counts<const N: usize>(v: &Value, field: &str) -> R<[u32; N]> {
    let a = array(v, field)?;
    if a.len() != N {
        return field_err(field, format!("expected {N} counts, found {}", a.len()));
    }
    let mut out = [0; N];
    for (k, x) in a.iter().enumerate() {
        let c = index(x, &format!("{field}[{k}]"), "a sample count")?;
        if c == 0 {
            return field_err(&format!("{field}[{k}]"), "a count must be at least 1");
        }
        out[k] = c;
    }
    let total: u64 = out.iter().map(|&c| c as u64).product();
    if total > 100_000_000 {
        return field_err(field, format!("{total} samples is more than 10⁸"));
    }
    Ok(out)
}

/// Parses the text of an input file.
pub fn parse_input(text: &str) -> R<(TrimmedPatches, CurvedOptions)> {
    let root: Value = serde_json::from_str(text).map_err(|e| ReadError::Syntax {
        line: e.line(),
        message: e.to_string(),
    })?;
    if !root.is_object() {
        return field_err(
            "(top level)",
            format!("expected an object, found {}", describe(&root)),
        );
    }
    let mut patches = Vec::new();
    for (i, p) in array(get(&root, "(top level)", "patches")?, "patches")?
        .iter()
        .enumerate()
    {
        patches.push(patch(p, &format!("patches[{i}]"))?);
    }
    let mut curves = Vec::new();
    for (i, c) in array(get(&root, "(top level)", "curves")?, "curves")?
        .iter()
        .enumerate()
    {
        curves.push(curve(c, &format!("curves[{i}]"))?);
    }
    let mut regions = Vec::new();
    for (i, r) in array(get(&root, "(top level)", "regions")?, "regions")?
        .iter()
        .enumerate()
    {
        regions.push(region(
            r,
            &format!("regions[{i}]"),
            patches.len(),
            curves.len(),
        )?);
    }
    let metric = metric(get(&root, "(top level)", "metric")?, "metric")?;
    let options = match root.get("options") {
        Some(o) => options(o, "options")?,
        None => CurvedOptions::default(),
    };
    Ok((
        TrimmedPatches {
            patches,
            curves,
            regions,
            metric,
        },
        options,
    ))
}

fn patch(v: &Value, field: &str) -> R<BezierPatch> {
    let d = array(get(v, field, "degree")?, &format!("{field}.degree"))?;
    if d.len() != 2 {
        return field_err(
            &format!("{field}.degree"),
            format!("expected [m, n], found {} numbers", d.len()),
        );
    }
    let m = index(&d[0], &format!("{field}.degree[0]"), "a degree")? as usize;
    let n = index(&d[1], &format!("{field}.degree[1]"), "a degree")? as usize;
    if m == 0 || n == 0 || m > 30 || n > 30 {
        return field_err(
            &format!("{field}.degree"),
            format!("degrees must be in 1..=30, found [{m}, {n}]"),
        );
    }
    let pts = array(get(v, field, "points")?, &format!("{field}.points"))?;
    let expected = (m + 1) * (n + 1);
    if pts.len() != expected {
        return field_err(
            &format!("{field}.points"),
            format!(
                "bidegree [{m}, {n}] needs (m+1)(n+1) = {expected} points, found {}",
                pts.len()
            ),
        );
    }
    let mut points = Vec::with_capacity(expected);
    for (k, p) in pts.iter().enumerate() {
        points.push(DVec3::from_array(numbers::<3>(
            p,
            &format!("{field}.points[{k}]"),
        )?));
    }
    Ok(BezierPatch::new(m, n, points))
}

fn curve(v: &Value, field: &str) -> R<BezierCurve> {
    let (pts, pf) = match v {
        Value::Object(_) => (get(v, field, "points")?, format!("{field}.points")),
        _ => (v, field.to_string()),
    };
    let pts = array(pts, &pf)?;
    if pts.len() < 2 || pts.len() > 64 {
        return field_err(
            &pf,
            format!("a curve needs 2 to 64 control points, found {}", pts.len()),
        );
    }
    let mut points = Vec::with_capacity(pts.len());
    for (k, p) in pts.iter().enumerate() {
        points.push(DVec2::from_array(numbers::<2>(p, &format!("{pf}[{k}]"))?));
    }
    Ok(BezierCurve::new(points))
}

fn region(v: &Value, field: &str, patch_count: usize, curve_count: usize) -> R<Region> {
    let p = index(
        get(v, field, "patch")?,
        &format!("{field}.patch"),
        "a patch index",
    )?;
    if p as usize >= patch_count {
        return field_err(
            &format!("{field}.patch"),
            format!("patch {p} does not exist (the file has {patch_count})"),
        );
    }
    let loops_v = array(get(v, field, "loops")?, &format!("{field}.loops"))?;
    if loops_v.is_empty() {
        return field_err(
            &format!("{field}.loops"),
            "a region needs at least its outer loop",
        );
    }
    let mut loops = Vec::with_capacity(loops_v.len());
    for (l, lp) in loops_v.iter().enumerate() {
        let lf = format!("{field}.loops[{l}]");
        let items = array(lp, &lf)?;
        if items.is_empty() {
            return field_err(&lf, "a loop needs at least one curve");
        }
        let mut uses = Vec::with_capacity(items.len());
        for (k, it) in items.iter().enumerate() {
            let f = format!("{lf}[{k}]");
            let (c, reversed) = match it {
                Value::Object(_) => {
                    let c = index(
                        get(it, &f, "curve")?,
                        &format!("{f}.curve"),
                        "a curve index",
                    )?;
                    let r = match it.get("reversed") {
                        None => false,
                        Some(Value::Bool(b)) => *b,
                        Some(x) => {
                            return field_err(
                                &format!("{f}.reversed"),
                                format!("expected true or false, found {}", describe(x)),
                            )
                        }
                    };
                    (c, r)
                }
                _ => (
                    index(
                        it,
                        &f,
                        "a curve index or {\"curve\": i, \"reversed\": true}",
                    )?,
                    false,
                ),
            };
            if c as usize >= curve_count {
                return field_err(
                    &f,
                    format!("curve {c} does not exist (the file has {curve_count})"),
                );
            }
            uses.push(if reversed {
                CurveUse::backward(c)
            } else {
                CurveUse::forward(c)
            });
        }
        loops.push(TrimLoop::new(uses));
    }
    Ok(Region {
        patch: PatchId(p),
        loops,
    })
}

fn tensor3(v: &Value, field: &str) -> R<Metric3> {
    let a = array(v, field)?;
    let t = match a.len() {
        6 => {
            let x = numbers::<6>(v, field)?;
            Metric3::new(x[0], x[1], x[2], x[3], x[4], x[5])
        }
        3 if a[0].is_array() => {
            let mut m = [[0.0; 3]; 3];
            for (r, row) in a.iter().enumerate() {
                m[r] = numbers::<3>(row, &format!("{field}[{r}]"))?;
            }
            for (r, c) in [(0, 1), (0, 2), (1, 2)] {
                let (x, y) = (m[r][c], m[c][r]);
                if (x - y).abs() > 1e-12 * (x.abs() + y.abs()).max(1e-300) {
                    return field_err(
                        field,
                        format!(
                            "the tensor is not symmetric: [{r}][{c}] = {x} but [{c}][{r}] = {y}"
                        ),
                    );
                }
            }
            Metric3::new(m[0][0], m[0][1], m[0][2], m[1][1], m[1][2], m[2][2])
        }
        n => {
            return field_err(
                field,
                format!(
                    "expected 6 numbers (xx, xy, xz, yy, yz, zz) or a 3×3 array, found {n} items"
                ),
            )
        }
    };
    if !t.is_positive_definite() {
        return field_err(field, "the tensor is not positive definite");
    }
    Ok(t)
}

fn tensor2(v: &Value, field: &str) -> R<Metric2> {
    let x = numbers::<3>(v, field)?;
    let t = Metric2::new(x[0], x[1], x[2]);
    if !t.is_positive_definite() {
        return field_err(field, "the tensor [uu, uv, vv] is not positive definite");
    }
    Ok(t)
}

fn metric(v: &Value, field: &str) -> R<MetricField> {
    let kind = get(v, field, "type")?;
    let kind = kind.as_str().ok_or_else(|| ReadError::Field {
        field: format!("{field}.type"),
        message: format!("expected a string, found {}", describe(kind)),
    })?;
    let f = |k: &str| format!("{field}.{k}");
    match kind {
        "isotropic" => Ok(MetricField::isotropic(positive(get(v, field, "size")?, &f("size"))?)),
        "directional" => {
            let h = positive(get(v, field, "size")?, &f("size"))?;
            let a = positive(get(v, field, "anisotropy")?, &f("anisotropy"))?;
            let d = DVec3::from_array(numbers::<3>(get(v, field, "direction")?, &f("direction"))?);
            if d.length() <= 0.0 {
                return field_err(&f("direction"), "the direction is the zero vector");
            }
            Ok(MetricField::Constant(Metric3::from_direction(d, h * a, h)))
        }
        "tensor" => Ok(MetricField::Constant(tensor3(get(v, field, "tensor")?, &f("tensor"))?)),
        "uv_tensor" => {
            let t = tensor2(get(v, field, "tensor")?, &f("tensor"))?;
            Ok(MetricField::ParameterGrid(Grid2 {
                min: DVec2::ZERO,
                max: DVec2::ONE,
                counts: [1, 1],
                values: vec![t],
            }))
        }
        "size_grid" | "tensor_grid" => {
            let min = DVec3::from_array(numbers::<3>(get(v, field, "min")?, &f("min"))?);
            let max = DVec3::from_array(numbers::<3>(get(v, field, "max")?, &f("max"))?);
            let counts = counts::<3>(get(v, field, "counts")?, &f("counts"))?;
            let n: usize = counts.iter().map(|&c| c as usize).product();
            let key = if kind == "size_grid" { "sizes" } else { "tensors" };
            let items = array(get(v, field, key)?, &f(key))?;
            if items.len() != n {
                return field_err(&f(key), format!("counts {counts:?} need {n} samples, found {}", items.len()));
            }
            if kind == "size_grid" {
                let values = items
                    .iter()
                    .enumerate()
                    .map(|(k, x)| positive(x, &format!("{}[{k}]", f(key))))
                    .collect::<R<Vec<_>>>()?;
                Ok(MetricField::Isotropic(SizeField::Grid(Grid3 { min, max, counts, values })))
            } else {
                let values = items
                    .iter()
                    .enumerate()
                    .map(|(k, x)| tensor3(x, &format!("{}[{k}]", f(key))))
                    .collect::<R<Vec<_>>>()?;
                Ok(MetricField::Grid(Grid3 { min, max, counts, values }))
            }
        }
        "uv_tensor_grid" => {
            let min = match v.get("min") {
                Some(x) => DVec2::from_array(numbers::<2>(x, &f("min"))?),
                None => DVec2::ZERO,
            };
            let max = match v.get("max") {
                Some(x) => DVec2::from_array(numbers::<2>(x, &f("max"))?),
                None => DVec2::ONE,
            };
            let counts = counts::<2>(get(v, field, "counts")?, &f("counts"))?;
            let n: usize = counts.iter().map(|&c| c as usize).product();
            let items = array(get(v, field, "tensors")?, &f("tensors"))?;
            if items.len() != n {
                return field_err(&f("tensors"), format!("counts {counts:?} need {n} samples, found {}", items.len()));
            }
            let values = items
                .iter()
                .enumerate()
                .map(|(k, x)| tensor2(x, &format!("{}[{k}]", f("tensors"))))
                .collect::<R<Vec<_>>>()?;
            Ok(MetricField::ParameterGrid(Grid2 { min, max, counts, values }))
        }
        other => field_err(
            &f("type"),
            format!("unknown metric type {other:?} (isotropic, directional, tensor, uv_tensor, size_grid, tensor_grid, uv_tensor_grid)"),
        ),
    }
}

fn options(v: &Value, field: &str) -> R<CurvedOptions> {
    let obj = v.as_object().ok_or_else(|| ReadError::Field {
        field: field.to_string(),
        message: format!("expected an object, found {}", describe(v)),
    })?;
    let mut o = CurvedOptions::default();
    for (k, x) in obj {
        let f = format!("{field}.{k}");
        let int = |x: &Value| index(x, &f, "a non-negative integer");
        let big = |x: &Value| {
            x.as_u64().ok_or_else(|| ReadError::Field {
                field: f.clone(),
                message: format!("expected a non-negative integer, found {}", describe(x)),
            })
        };
        match k.as_str() {
            "order" => o.order = int(x)?,
            "mu" => o.mu = number(x, &f)?,
            "max_cone_deg" => o.max_cone_deg = number(x, &f)?,
            "max_split_depth" => o.max_split_depth = int(x)?,
            "radius_edge_bound" => o.radius_edge_bound = number(x, &f)?,
            "size_bound" => o.size_bound = number(x, &f)?,
            "small_angle_deg" => o.small_angle_deg = number(x, &f)?,
            "max_anisotropy" => o.max_anisotropy = number(x, &f)?,
            "min_uv_size" => o.min_uv_size = number(x, &f)?,
            "max_uv_size" => o.max_uv_size = number(x, &f)?,
            "max_sites" => o.max_sites = Some(big(x)?),
            "max_steps" => o.max_steps = Some(big(x)?),
            "max_curve_pieces" => o.max_curve_pieces = big(x)?,
            "angle_samples" => o.angle_samples = int(x)?,
            "sampled_quality" => {
                o.sampled_quality = x.as_bool().ok_or_else(|| ReadError::Field {
                    field: f.clone(),
                    message: format!("expected true or false, found {}", describe(x)),
                })?
            }
            _ => return field_err(&f, "unknown option"),
        }
    }
    if let Err(Error::InvalidOption { option, message }) = o.validate() {
        return field_err(&format!("{field}.{option}"), message);
    }
    Ok(o)
}
