//! The Blender add-on's ctypes bindings (`blender_addon/katachi/ffi.py`) against the C header
//! (`include/katachi.h`): every function the add-on declares exists in the header with the
//! same return and argument types, every struct it mirrors has the header's fields in the
//! header's order with the same types, every callback type (`CFUNCTYPE`) it declares is a
//! function-pointer typedef of the header with the same signature, a function-pointer
//! typedef is passed only as the callback type declared for it, and its constants have the
//! header's values.
//!
//! ctypes cannot say `const`, so `POINTER(T)` matches both `T *` and `const T *`; otherwise
//! types must be the same (`c_uint32` is `uint32_t`, `c_size_t` is `size_t`, `c_char_p` is a
//! `char *`, `c_void_p` is a `void *`, `None` is `void`, `KatachiStatus` is `KatachiStatus`).
//! The parsers are small and made for these two files; the tests below also prove that a
//! changed declaration is caught.

use std::collections::BTreeMap;
use std::path::Path;

/// A type as both sides can say it: a base name and a pointer depth (and an array length).
#[derive(Debug, Clone, PartialEq, Eq)]
struct Ty {
    base: String,
    pointers: u32,
    array: Option<u32>,
}

impl std::fmt::Display for Ty {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}{}", self.base, "*".repeat(self.pointers as usize))?;
        if let Some(n) = self.array {
            write!(f, "[{n}]")?;
        }
        Ok(())
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
struct Function {
    ret: Ty,
    args: Vec<Ty>,
}

fn read(rel: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

// ------------------------------------------------------------------------------ C header

fn strip_c_comments(src: &str) -> String {
    let mut out = String::with_capacity(src.len());
    let mut rest = src;
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix("/*") {
            rest = r.split_once("*/").map_or("", |(_, after)| after);
            out.push(' ');
        } else if let Some(r) = rest.strip_prefix("//") {
            rest = r.split_once('\n').map_or("", |(_, after)| after);
            out.push('\n');
        } else {
            let c = rest.chars().next().expect("not empty");
            out.push(c);
            rest = &rest[c.len_utf8()..];
        }
    }
    // Preprocessor lines (guards, `#if defined(__cplusplus)` around enum bases) go too.
    out.lines()
        .filter(|l| !l.trim_start().starts_with('#'))
        .collect::<Vec<_>>()
        .join("\n")
}

/// `const struct KatachiMesh *` → KatachiMesh, 1. With `named`, the last word is a name.
fn c_type(decl: &str, named: bool) -> (Ty, Option<String>) {
    let decl = decl.trim();
    let pointers = decl.matches('*').count() as u32;
    let mut words: Vec<&str> = decl
        .split(|c: char| c.is_whitespace() || c == '*')
        .filter(|w| !w.is_empty() && *w != "const" && *w != "struct")
        .collect();
    let mut array = None;
    let name = if named && words.len() > 1 {
        let mut n = words.pop().expect("a name").to_owned();
        if let Some((base, len)) = n.split_once('[') {
            array = Some(len.trim_end_matches(']').parse().expect("an array length"));
            n = base.to_owned();
        }
        Some(n)
    } else {
        None
    };
    let base = words.join(" ");
    (
        Ty {
            base,
            pointers,
            array,
        },
        name,
    )
}

fn header_functions(header: &str) -> BTreeMap<String, Function> {
    let code = strip_c_comments(header);
    let mut out = BTreeMap::new();
    for stmt in code.split(';') {
        // What follows `extern "C" {` or a closing brace is the declaration.
        let stmt = stmt.rsplit(['{', '}']).next().unwrap_or("").trim();
        let Some(open) = stmt.find('(') else { continue };
        if !stmt.ends_with(')') {
            continue;
        }
        let head = &stmt[..open];
        let (ret, name) = c_type(head, true);
        let Some(name) = name.filter(|n| n.starts_with("katachi_")) else {
            continue;
        };
        let inner = &stmt[open + 1..stmt.len() - 1];
        let args = if inner.trim() == "void" {
            Vec::new()
        } else {
            inner.split(',').map(|a| c_type(a, true).0).collect()
        };
        out.insert(name, Function { ret, args });
    }
    out
}

/// `typedef R (*Name)(args);` → Name: its signature (function-pointer typedefs).
fn header_callbacks(header: &str) -> BTreeMap<String, Function> {
    let code = strip_c_comments(header);
    let mut out = BTreeMap::new();
    for stmt in code.split(';') {
        let stmt = stmt.rsplit(['{', '}']).next().unwrap_or("").trim();
        let Some(rest) = stmt.strip_prefix("typedef ") else {
            continue;
        };
        let Some((ret, rest)) = rest.split_once("(*") else {
            continue;
        };
        let (name, rest) = rest
            .split_once(')')
            .unwrap_or_else(|| panic!("a function-pointer typedef without `)`: {stmt}"));
        let inner = rest
            .trim()
            .strip_prefix('(')
            .and_then(|r| r.strip_suffix(')'))
            .unwrap_or_else(|| panic!("a function-pointer typedef without arguments: {stmt}"));
        let args = if inner.trim() == "void" {
            Vec::new()
        } else {
            inner.split(',').map(|a| c_type(a, true).0).collect()
        };
        let f = Function {
            ret: c_type(ret, false).0,
            args,
        };
        assert!(
            out.insert(name.trim().to_owned(), f).is_none(),
            "{name} typedef'd twice"
        );
    }
    out
}

/// `typedef struct Name { fields } Name;` → Name: [(field, type)].
fn header_structs(header: &str) -> BTreeMap<String, Vec<(String, Ty)>> {
    let code = strip_c_comments(header);
    let mut out = BTreeMap::new();
    let mut rest = code.as_str();
    while let Some(at) = rest.find("typedef struct ") {
        rest = &rest[at + "typedef struct ".len()..];
        let Some(open) = rest.find(['{', ';']) else {
            break;
        };
        if rest.as_bytes()[open] == b';' {
            continue; // an opaque handle
        }
        let name = rest[..open].trim().to_owned();
        let close = rest.find('}').expect("a closing brace");
        let fields = rest[open + 1..close]
            .split(';')
            .filter(|f| !f.trim().is_empty())
            .map(|f| {
                let (ty, n) = c_type(f, true);
                (n.expect("a field name"), ty)
            })
            .collect();
        out.insert(name, fields);
        rest = &rest[close..];
    }
    out
}

/// `KATACHI_X = 3,` inside enums, and `#define KATACHI_ABI_VERSION 2`.
fn header_constants(header: &str) -> BTreeMap<String, i64> {
    let mut out = BTreeMap::new();
    for line in header.lines() {
        let l = line.trim();
        if let Some(rest) = l.strip_prefix("#define KATACHI_") {
            if let Some((name, value)) = rest.split_once(' ') {
                if let Ok(v) = value.trim().parse() {
                    out.insert(format!("KATACHI_{name}"), v);
                }
            }
        } else if l.starts_with("KATACHI_") && l.ends_with(',') {
            if let Some((name, value)) = l.trim_end_matches(',').split_once('=') {
                if let Ok(v) = value.trim().parse() {
                    out.insert(name.trim().to_owned(), v);
                }
            }
        }
    }
    out
}

// ------------------------------------------------------------------------------ Python

/// The lines between `# ---- NAME (…` and `# ---- end of NAME ----`.
fn block<'a>(py: &'a str, name: &str) -> &'a str {
    let start = py
        .find(&format!("# ---- {name} ("))
        .unwrap_or_else(|| panic!("ffi.py has no `# ---- {name} (` marker"));
    let end_marker = format!("# ---- end of {name} ----");
    let end = py[start..]
        .find(&end_marker)
        .unwrap_or_else(|| panic!("ffi.py has no `{end_marker}` marker"));
    &py[start..start + end]
}

/// A ctypes expression as a [`Ty`].
fn py_type(expr: &str) -> Ty {
    let e = expr.trim();
    if let Some(inner) = e.strip_prefix("POINTER(").and_then(|r| r.strip_suffix(')')) {
        let mut t = py_type(inner);
        t.pointers += 1;
        return t;
    }
    if let Some((base, n)) = e.split_once('*') {
        let mut t = py_type(base);
        t.array = Some(n.trim().parse().expect("an array length"));
        return t;
    }
    let (base, pointers) = match e {
        "None" => ("void", 0),
        "c_uint32" => ("uint32_t", 0),
        "c_int64" => ("int64_t", 0),
        "c_double" => ("double", 0),
        "c_float" => ("float", 0),
        "c_size_t" => ("size_t", 0),
        "c_bool" => ("bool", 0),
        "c_char" => ("char", 0),
        "c_char_p" => ("char", 1),
        "c_void_p" => ("void", 1),
        other if other.starts_with("Katachi") => (other, 0),
        other => panic!("ffi.py uses a ctypes type the test does not know: {other}"),
    };
    Ty {
        base: base.to_owned(),
        pointers,
        array: None,
    }
}

/// Splits at commas outside parentheses and brackets.
fn split_top(s: &str) -> Vec<&str> {
    let (mut depth, mut start, mut out) = (0i32, 0usize, Vec::new());
    for (i, c) in s.char_indices() {
        match c {
            '(' | '[' => depth += 1,
            ')' | ']' => depth -= 1,
            ',' if depth == 0 => {
                out.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out.into_iter().filter(|p| !p.trim().is_empty()).collect()
}

fn python_functions(py: &str) -> BTreeMap<String, Function> {
    let mut out = BTreeMap::new();
    for line in block(py, "functions").lines() {
        let l = line.trim();
        let Some(rest) = l.strip_prefix('"') else {
            continue;
        };
        let (name, rest) = rest.split_once('"').expect("a closing quote");
        let sig = rest
            .trim_start_matches(':')
            .trim()
            .trim_end_matches(',')
            .trim();
        let sig = sig
            .strip_prefix('(')
            .and_then(|s| s.strip_suffix(')'))
            .unwrap_or_else(|| panic!("{name}: not a (restype, [argtypes]) pair: {sig}"));
        let parts = split_top(sig);
        assert_eq!(
            parts.len(),
            2,
            "{name}: expected (restype, [argtypes]), got {sig}"
        );
        let args = parts[1]
            .trim()
            .strip_prefix('[')
            .and_then(|s| s.strip_suffix(']'))
            .unwrap_or_else(|| panic!("{name}: argtypes is not a list"));
        let f = Function {
            ret: py_type(parts[0]),
            args: split_top(args).into_iter().map(py_type).collect(),
        };
        assert!(
            out.insert(name.to_owned(), f).is_none(),
            "{name} declared twice"
        );
    }
    out
}

/// `Name = CFUNCTYPE(restype, argtypes…)` → Name: its signature.
fn python_callbacks(py: &str) -> BTreeMap<String, Function> {
    let mut out = BTreeMap::new();
    for line in block(py, "callbacks").lines() {
        let l = line.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let (name, expr) = l
            .split_once('=')
            .unwrap_or_else(|| panic!("not `Name = CFUNCTYPE(…)`: {l}"));
        let name = name.trim();
        let sig = expr
            .trim()
            .strip_prefix("CFUNCTYPE(")
            .and_then(|s| s.strip_suffix(')'))
            .unwrap_or_else(|| panic!("{name}: not CFUNCTYPE(restype, argtypes…): {expr}"));
        let mut parts = split_top(sig).into_iter().map(py_type);
        let ret = parts
            .next()
            .unwrap_or_else(|| panic!("{name}: CFUNCTYPE without a return type"));
        let f = Function {
            ret,
            args: parts.collect(),
        };
        assert!(
            out.insert(name.to_owned(), f).is_none(),
            "{name} declared twice"
        );
    }
    out
}

fn python_structs(py: &str) -> BTreeMap<String, Vec<(String, Ty)>> {
    let mut out = BTreeMap::new();
    let text = block(py, "structs");
    for chunk in text.split("class ").skip(1) {
        let name = chunk
            .split(['(', ':'])
            .next()
            .expect("a class name")
            .trim()
            .to_owned();
        let Some(fields_at) = chunk.find("_fields_") else {
            continue;
        };
        let body = &chunk[fields_at..];
        let open = body.find('[').expect("a field list");
        let close = body.rfind(']').expect("a field list's end");
        let fields = split_top(&body[open + 1..close])
            .into_iter()
            .map(|f| {
                let f = f.trim().trim_start_matches('(').trim_end_matches(')');
                let (n, t) = f.split_once(',').expect("(name, type)");
                (n.trim().trim_matches('"').to_owned(), py_type(t))
            })
            .collect();
        out.insert(name, fields);
    }
    out
}

fn python_constants(py: &str) -> BTreeMap<String, i64> {
    let mut out = BTreeMap::new();
    for line in block(py, "enums")
        .lines()
        .chain(py.lines().filter(|l| l.starts_with("KATACHI_ABI_VERSION")))
    {
        if let Some((name, value)) = line.split_once('=') {
            if let Ok(v) = value.trim().parse() {
                out.insert(name.trim().to_owned(), v);
            }
        }
    }
    out
}

// ------------------------------------------------------------------------------ comparison

/// Every difference between the bindings and the header, one line each.
fn differences(header: &str, py: &str) -> Vec<String> {
    let mut bad = Vec::new();
    let hf = header_functions(header);
    for (name, f) in python_functions(py) {
        match hf.get(&name) {
            None => bad.push(format!(
                "{name}: declared in ffi.py, missing from katachi.h"
            )),
            Some(h) if h.ret != f.ret => bad.push(format!(
                "{name}: returns {} in katachi.h, {} in ffi.py",
                h.ret, f.ret
            )),
            Some(h) if h.args.len() != f.args.len() => bad.push(format!(
                "{name}: {} arguments in katachi.h, {} in ffi.py",
                h.args.len(),
                f.args.len()
            )),
            Some(h) => {
                for (i, (a, b)) in h.args.iter().zip(&f.args).enumerate() {
                    if a != b {
                        bad.push(format!(
                            "{name}: argument {i} is {a} in katachi.h, {b} in ffi.py"
                        ));
                    }
                }
            }
        }
    }
    let hcb = header_callbacks(header);
    let pcb = python_callbacks(py);
    for (name, f) in &pcb {
        match hcb.get(name) {
            None => bad.push(format!(
                "callback {name}: in ffi.py, not a function-pointer typedef of katachi.h"
            )),
            Some(h) if h != f => {
                let show = |f: &Function| {
                    let args: Vec<String> = f.args.iter().map(|a| a.to_string()).collect();
                    format!("{} (*)({})", f.ret, args.join(", "))
                };
                bad.push(format!(
                    "callback {name}: {} in katachi.h, {} in ffi.py",
                    show(h),
                    show(f)
                ));
            }
            Some(_) => {}
        }
    }
    // A function-pointer argument matches by name only above: its CFUNCTYPE must be one
    // checked here, so that its signature is checked too.
    for (name, f) in python_functions(py) {
        for (i, a) in f.args.iter().chain([&f.ret]).enumerate() {
            if hcb.contains_key(&a.base) && !pcb.contains_key(&a.base) {
                bad.push(format!(
                    "{name}: {} (type {i}) is a callback not declared in ffi.py's callbacks block",
                    a.base
                ));
            }
        }
    }
    let hs = header_structs(header);
    for (name, fields) in python_structs(py) {
        match hs.get(&name) {
            None => bad.push(format!("struct {name}: in ffi.py, not in katachi.h")),
            Some(h) if *h != fields => {
                let show = |v: &[(String, Ty)]| {
                    v.iter()
                        .map(|(n, t)| format!("{t} {n}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                bad.push(format!(
                    "struct {name}: katachi.h has {{{}}}, ffi.py {{{}}}",
                    show(h),
                    show(&fields)
                ));
            }
            Some(_) => {}
        }
    }
    let hc = header_constants(header);
    for (name, v) in python_constants(py) {
        match hc.get(&name) {
            None => bad.push(format!("{name}: in ffi.py, not in katachi.h")),
            Some(h) if *h != v => bad.push(format!("{name} is {h} in katachi.h, {v} in ffi.py")),
            Some(_) => {}
        }
    }
    bad
}

const HEADER: &str = "include/katachi.h";
const FFI: &str = "blender_addon/katachi/ffi.py";

#[test]
fn bindings_match_the_header() {
    let (header, py) = (read(HEADER), read(FFI));
    let bad = differences(&header, &py);
    assert!(
        bad.is_empty(),
        "ffi.py disagrees with katachi.h:\n  {}",
        bad.join("\n  ")
    );
}

#[test]
fn the_parsers_see_everything() {
    let (header, py) = (read(HEADER), read(FFI));
    let hf = header_functions(&header);
    let pf = python_functions(&py);
    // Not vacuous: the add-on binds what it calls, and the parsers found it all.
    // Every declaration line of the header, counted independently of the parser.
    let declared = header
        .lines()
        .filter(|l| {
            !l.starts_with([' ', '*', '/', '#']) && l.contains("katachi_") && l.contains('(')
        })
        .count();
    assert!(declared >= 38, "only {declared} declarations in katachi.h");
    assert_eq!(
        hf.len(),
        declared,
        "the parser missed functions of katachi.h"
    );
    assert!(
        pf.len() >= 25,
        "only {} functions parsed from ffi.py",
        pf.len()
    );
    let create = &hf["katachi_mesh_create"];
    assert_eq!(create.args.len(), 9);
    assert_eq!(create.ret.base, "KatachiStatus");
    assert_eq!(create.args[8].to_string(), "KatachiMesh**");
    assert_eq!(hf["katachi_last_error_message"].ret.to_string(), "char*");
    assert_eq!(hf["katachi_mesh_free"].ret.to_string(), "void");
    let hs = header_structs(&header);
    let ps = python_structs(&py);
    assert_eq!(
        ps.keys().collect::<Vec<_>>(),
        [
            "KatachiCutInfo",
            "KatachiCutOptions",
            "KatachiCutPolygonsInfo",
            "KatachiMeshCounts",
            "KatachiMeshInfo",
            "KatachiSubdivideOptions",
            "KatachiSubdivisionInfo"
        ]
    );
    assert_eq!(hs["KatachiCutInfo"].len(), 27);
    assert_eq!(
        hs["KatachiCutOptions"]
            .iter()
            .map(|(n, t)| format!("{t} {n}"))
            .collect::<Vec<_>>(),
        [
            "uint32_t struct_size",
            "uint32_t mode",
            "uint32_t open",
            "uint32_t max_faces_split",
            "double snap_vertex_ratio",
            "double snap_segment_ratio",
            "double corner_angle_degrees",
            "double min_stroke_px",
            "double depth_eps_rel"
        ]
    );
    let cut = &hf["katachi_cut_by_stroke"];
    assert_eq!(
        cut.args.iter().map(|a| a.to_string()).collect::<Vec<_>>(),
        [
            "KatachiMesh*",
            "double*",
            "uint32_t",
            "double*",
            "double*",
            "KatachiCutOptions*",
            "KatachiCut**"
        ]
    );
    let info = &hs["KatachiMeshInfo"];
    assert_eq!(
        info.last().map(|f| f.1.to_string()).as_deref(),
        Some("double[3]")
    );
    // Function-pointer typedefs, counted independently of the parser.
    let typedefs = header
        .lines()
        .filter(|l| l.starts_with("typedef ") && l.contains("(*"))
        .count();
    let hcb = header_callbacks(&header);
    assert!(typedefs >= 1, "no function-pointer typedef in katachi.h");
    assert_eq!(hcb.len(), typedefs, "the parser missed typedefs: {hcb:?}");
    let progress = &hcb["KatachiProgressFn"];
    assert_eq!(progress.ret.to_string(), "void");
    assert_eq!(
        progress
            .args
            .iter()
            .map(|a| a.to_string())
            .collect::<Vec<_>>(),
        ["uint32_t", "uint32_t", "void*"]
    );
    let pcb = python_callbacks(&py);
    assert_eq!(
        pcb.keys().collect::<Vec<_>>(),
        ["KatachiCutProgressFn", "KatachiProgressFn"]
    );
    let cut_progress = &hcb["KatachiCutProgressFn"];
    assert_eq!(cut_progress.ret.to_string(), "uint32_t");
    assert_eq!(pcb["KatachiCutProgressFn"], *cut_progress);
    let with_progress = &hf["katachi_subdivide_with_progress"];
    assert_eq!(with_progress.args[2].to_string(), "KatachiProgressFn");
    assert_eq!(
        pf["katachi_subdivide_with_progress"].args[2].to_string(),
        "KatachiProgressFn"
    );
    let constants = python_constants(&py);
    assert_eq!(constants.get("KATACHI_ABI_VERSION"), Some(&2));
    assert_eq!(constants.len(), 28, "{constants:?}");
}

/// The stroke cut's part of the header is bound in full: every `katachi_cut_*` function,
/// both of its structs and every `KATACHI_CUT_*` constant (the Blender add-on's Cut by
/// Stroke calls them all, or could), so a function added to the header without the add-on
/// learning of it fails here.
#[test]
fn the_cut_api_is_bound_in_full() {
    let (header, py) = (read(HEADER), read(FFI));
    let hf = header_functions(&header);
    let pf = python_functions(&py);
    let cut: Vec<&String> = hf
        .keys()
        .filter(|n| n.starts_with("katachi_cut_"))
        .collect();
    assert!(
        cut.len() >= 13,
        "only {} katachi_cut_* functions in katachi.h",
        cut.len()
    );
    let missing: Vec<&&String> = cut.iter().filter(|n| !pf.contains_key(**n)).collect();
    assert!(missing.is_empty(), "ffi.py does not bind {missing:?}");
    let ps = python_structs(&py);
    let hs = header_structs(&header);
    for name in hs.keys().filter(|n| n.starts_with("KatachiCut")) {
        assert!(
            ps.contains_key(name),
            "ffi.py does not mirror struct {name}"
        );
    }
    let hc = header_constants(&header);
    let pc = python_constants(&py);
    let cut_constants: Vec<&String> = hc
        .keys()
        .filter(|n| n.starts_with("KATACHI_CUT_"))
        .collect();
    assert_eq!(cut_constants.len(), 6, "{cut_constants:?}");
    for name in cut_constants {
        assert_eq!(pc.get(name), hc.get(name), "{name}");
    }
    // The result handle is freed by the function the add-on's _Handle names.
    assert!(
        py.contains("FREE = \"katachi_cut_free\""),
        "ffi.Cut does not free with katachi_cut_free"
    );
}

#[test]
fn a_changed_declaration_is_caught() {
    let (header, py) = (read(HEADER), read(FFI));
    let mutate = |from: &str, to: &str| {
        assert!(py.contains(from), "ffi.py no longer has {from:?}");
        differences(&header, &py.replacen(from, to, 1))
    };
    // An argument's type.
    let bad = mutate(
        r#""katachi_mesh_copy_positions": (KatachiStatus, [POINTER(KatachiMesh), POINTER(c_double), c_size_t]),"#,
        r#""katachi_mesh_copy_positions": (KatachiStatus, [POINTER(KatachiMesh), POINTER(c_double), c_uint32]),"#,
    );
    assert!(
        bad.iter()
            .any(|b| b.contains("katachi_mesh_copy_positions: argument 2")),
        "{bad:?}"
    );
    // A missing argument, a pointer depth, a return type, a name.
    let bad = mutate(
        "c_uint32, POINTER(c_double), c_size_t]),\n    \"katachi_mesh_split_faces_with_holes\"",
        "c_uint32, POINTER(c_double)]),\n    \"katachi_mesh_split_faces_with_holes\"",
    );
    assert!(
        bad.iter().any(|b| b.contains("arguments in katachi.h")),
        "{bad:?}"
    );
    let bad = mutate(
        "[POINTER(KatachiSubdivision), POINTER(POINTER(KatachiMesh))]",
        "[POINTER(KatachiSubdivision), POINTER(KatachiMesh)]",
    );
    assert!(
        bad.iter().any(|b| b.contains("katachi_subdivision_mesh")),
        "{bad:?}"
    );
    let bad = mutate(
        r#""katachi_abi_version": (c_uint32, []),"#,
        r#""katachi_abi_version": (KatachiStatus, []),"#,
    );
    assert!(
        bad.iter()
            .any(|b| b.contains("katachi_abi_version: returns")),
        "{bad:?}"
    );
    let bad = mutate(r#""katachi_mesh_free": "#, r#""katachi_mesh_release": "#);
    assert!(
        bad.iter().any(|b| b.contains("missing from katachi.h")),
        "{bad:?}"
    );
    // A struct field's order, type and array length; a constant's value.
    let bad = mutate(
        "(\"levels\", c_uint32),\n        (\"holes\", c_uint32),",
        "(\"holes\", c_uint32),\n        (\"levels\", c_uint32),",
    );
    assert!(
        bad.iter()
            .any(|b| b.contains("struct KatachiSubdivideOptions")),
        "{bad:?}"
    );
    let bad = mutate("(\"genus\", c_int64)", "(\"genus\", c_uint32)");
    assert!(
        bad.iter().any(|b| b.contains("struct KatachiMeshInfo")),
        "{bad:?}"
    );
    let bad = mutate(
        "(\"bounding_box_max\", c_double * 3)",
        "(\"bounding_box_max\", c_double * 2)",
    );
    assert!(
        bad.iter().any(|b| b.contains("struct KatachiMeshInfo")),
        "{bad:?}"
    );
    let bad = mutate(
        "KATACHI_STATUS_BAD_TOPOLOGY = 5",
        "KATACHI_STATUS_BAD_TOPOLOGY = 6",
    );
    assert!(
        bad.iter()
            .any(|b| b.contains("KATACHI_STATUS_BAD_TOPOLOGY")),
        "{bad:?}"
    );
    // A callback's argument, argument count and return type; a function-pointer argument
    // declared as something else, or with a CFUNCTYPE the test does not check.
    let callback = "KatachiProgressFn = CFUNCTYPE(None, c_uint32, c_uint32, c_void_p)";
    for changed in [
        "KatachiProgressFn = CFUNCTYPE(None, c_uint32, c_size_t, c_void_p)",
        "KatachiProgressFn = CFUNCTYPE(None, c_uint32, c_uint32)",
        "KatachiProgressFn = CFUNCTYPE(c_uint32, c_uint32, c_uint32, c_void_p)",
    ] {
        let bad = mutate(callback, changed);
        assert!(
            bad.iter().any(|b| b.contains("callback KatachiProgressFn")),
            "{changed}: {bad:?}"
        );
    }
    let bad = mutate(
        "POINTER(KatachiSubdivideOptions), KatachiProgressFn, c_void_p,",
        "POINTER(KatachiSubdivideOptions), c_void_p, c_void_p,",
    );
    assert!(
        bad.iter()
            .any(|b| b.contains("katachi_subdivide_with_progress: argument 2")),
        "{bad:?}"
    );
    let bad = mutate(callback, "# moved out of the block");
    assert!(
        bad.iter()
            .any(|b| b.contains("KatachiProgressFn (type 2) is a callback not declared")),
        "{bad:?}"
    );
    let bad = mutate(
        callback,
        "KatachiProgressFn = CFUNCTYPE(None, c_uint32, c_uint32, c_void_p)\nKatachiDoneFn = CFUNCTYPE(None)",
    );
    assert!(
        bad.iter().any(|b| b.contains("callback KatachiDoneFn")),
        "{bad:?}"
    );
    // The stroke cut's declarations: an argument, a field, a constant.
    let bad = mutate(
        "POINTER(c_double), c_uint32, POINTER(c_double), POINTER(c_double), POINTER(KatachiCutOptions)",
        "POINTER(c_double), c_size_t, POINTER(c_double), POINTER(c_double), POINTER(KatachiCutOptions)",
    );
    assert!(
        bad.iter()
            .any(|b| b.contains("katachi_cut_by_stroke: argument 2")),
        "{bad:?}"
    );
    let bad = mutate(
        "(\"max_move_world\", c_double),\n        (\"max_move_px\", c_double),",
        "(\"max_move_px\", c_double),\n        (\"max_move_world\", c_double),",
    );
    assert!(
        bad.iter().any(|b| b.contains("struct KatachiCutInfo")),
        "{bad:?}"
    );
    let bad = mutate(
        "KATACHI_CUT_STAGE_OFF_MESH = 3",
        "KATACHI_CUT_STAGE_OFF_MESH = 4",
    );
    assert!(
        bad.iter().any(|b| b.contains("KATACHI_CUT_STAGE_OFF_MESH")),
        "{bad:?}"
    );
    let bad = mutate(
        "\"katachi_cut_copy_paths\": (KatachiStatus, [POINTER(KatachiCut), POINTER(c_uint32), c_size_t, POINTER(c_uint32), c_size_t]),",
        "\"katachi_cut_copy_paths\": (KatachiStatus, [POINTER(KatachiCut), POINTER(c_uint32), POINTER(c_uint32), c_size_t]),",
    );
    assert!(
        bad.iter()
            .any(|b| b.contains("katachi_cut_copy_paths: 5 arguments")),
        "{bad:?}"
    );
    let bad = mutate("KATACHI_ABI_VERSION = 2", "KATACHI_ABI_VERSION = 3");
    assert!(
        bad.iter().any(|b| b.contains("KATACHI_ABI_VERSION")),
        "{bad:?}"
    );
}
