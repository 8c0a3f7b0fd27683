//! The C ABI called from Rust, through the same `extern "C"` functions C programs link to:
//! statuses, messages, NULL handling, struct sizes, and that failing calls leave the input
//! mesh untouched. Also two source checks: every function in `include/katachi.h` is
//! exercised by some program in `tests/c`, and every exported function runs inside the
//! panic boundary. (The boundary itself is unit-tested in `src/ffi/boundary.rs`, since a
//! panicking test hook must not be exported.)

use std::ffi::{c_char, CStr, CString};
use std::path::Path;
use std::ptr::{null, null_mut};

use katachi::ffi::*;

const CUBE_POSITIONS: [f64; 24] = [
    -0.5, -0.5, -0.5, 0.5, -0.5, -0.5, -0.5, 0.5, -0.5, 0.5, 0.5, -0.5, //
    -0.5, -0.5, 0.5, 0.5, -0.5, 0.5, -0.5, 0.5, 0.5, 0.5, 0.5, 0.5,
];
const CUBE_LOOP_SIZES: [u32; 6] = [4; 6];
const CUBE_FACE_LOOP_COUNTS: [u32; 6] = [1; 6];
const CUBE_CORNERS: [u32; 24] = [
    0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5,
];

fn message() -> String {
    // SAFETY: never NULL, valid until the next status-returning call; copied at once.
    unsafe { CStr::from_ptr(katachi_last_error_message()) }
        .to_str()
        .expect("messages are UTF-8")
        .to_owned()
}

/// Owns a mesh handle for the test's duration.
struct Mesh(*mut KatachiMesh);

impl Drop for Mesh {
    fn drop(&mut self) {
        unsafe { katachi_mesh_free(self.0) }
    }
}

fn create(positions: &[f64], loop_sizes: &[u32], flc: &[u32], corners: &[u32]) -> Mesh {
    let mut out = null_mut();
    let s = unsafe {
        katachi_mesh_create(
            positions.as_ptr(),
            (positions.len() / 3) as u32,
            loop_sizes.as_ptr(),
            loop_sizes.len() as u32,
            flc.as_ptr(),
            flc.len() as u32,
            corners.as_ptr(),
            corners.len() as u32,
            &mut out,
        )
    };
    assert_eq!(s, KatachiStatus::Ok, "{}", message());
    assert!(!out.is_null());
    Mesh(out)
}

fn cube() -> Mesh {
    create(
        &CUBE_POSITIONS,
        &CUBE_LOOP_SIZES,
        &CUBE_FACE_LOOP_COUNTS,
        &CUBE_CORNERS,
    )
}

/// Everything readable through the ABI, to compare before and after failing calls.
#[derive(Debug, PartialEq)]
struct Snapshot {
    counts: KatachiMeshCounts,
    positions: Vec<f64>,
    faces: (Vec<u32>, Vec<u32>, Vec<u32>),
    sharp: (Vec<u32>, Vec<f64>),
    vertex_sharpness: Vec<f64>,
}

fn snapshot(m: &Mesh) -> Snapshot {
    unsafe {
        let mut c = katachi_mesh_counts_default();
        assert_eq!(katachi_mesh_counts(m.0, &mut c), KatachiStatus::Ok);
        let mut positions = vec![0.0; 3 * c.vertex_count as usize];
        let mut ls = vec![0; c.loop_count as usize];
        let mut flc = vec![0; c.face_count as usize];
        let mut cs = vec![0; c.corner_count as usize];
        let mut e = vec![0; 2 * c.sharp_edge_count as usize];
        let mut v = vec![0.0; c.sharp_edge_count as usize];
        let mut vs = vec![0.0; c.vertex_count as usize];
        let ok = KatachiStatus::Ok;
        assert_eq!(
            katachi_mesh_copy_positions(m.0, positions.as_mut_ptr(), positions.len()),
            ok
        );
        assert_eq!(
            katachi_mesh_copy_faces(
                m.0,
                ls.as_mut_ptr(),
                ls.len(),
                flc.as_mut_ptr(),
                flc.len(),
                cs.as_mut_ptr(),
                cs.len()
            ),
            ok
        );
        assert_eq!(
            katachi_mesh_copy_sharp_edges(m.0, e.as_mut_ptr(), v.as_mut_ptr(), v.len()),
            ok
        );
        assert_eq!(
            katachi_mesh_copy_vertex_sharpness(m.0, vs.as_mut_ptr(), vs.len()),
            ok
        );
        Snapshot {
            counts: c,
            positions,
            faces: (ls, flc, cs),
            sharp: (e, v),
            vertex_sharpness: vs,
        }
    }
}

#[test]
fn versions_agree() {
    assert_eq!(katachi_abi_version(), KATACHI_ABI_VERSION);
    let v = unsafe { CStr::from_ptr(katachi_version_string()) };
    assert_eq!(
        v.to_str().unwrap(),
        format!("{KATACHI_VERSION_MAJOR}.{KATACHI_VERSION_MINOR}.{KATACHI_VERSION_PATCH}")
    );
    assert_eq!(v.to_str().unwrap(), env!("CARGO_PKG_VERSION"));
}

#[test]
fn status_values_and_names_are_stable() {
    let expected = [
        (KatachiStatus::Ok, 0, "KATACHI_STATUS_OK"),
        (KatachiStatus::NullPointer, 1, "KATACHI_STATUS_NULL_POINTER"),
        (
            KatachiStatus::InvalidArgument,
            2,
            "KATACHI_STATUS_INVALID_ARGUMENT",
        ),
        (
            KatachiStatus::BufferTooSmall,
            3,
            "KATACHI_STATUS_BUFFER_TOO_SMALL",
        ),
        (KatachiStatus::BadInput, 4, "KATACHI_STATUS_BAD_INPUT"),
        (KatachiStatus::BadTopology, 5, "KATACHI_STATUS_BAD_TOPOLOGY"),
        (KatachiStatus::IoError, 6, "KATACHI_STATUS_IO_ERROR"),
        (
            KatachiStatus::InternalError,
            7,
            "KATACHI_STATUS_INTERNAL_ERROR",
        ),
        (KatachiStatus::Cancelled, 8, "KATACHI_STATUS_CANCELLED"),
    ];
    for (status, value, name) in expected {
        assert_eq!(status as u32, value);
        assert_eq!(status.name(), name);
        let c = unsafe { CStr::from_ptr(katachi_status_name(value)) };
        assert_eq!(c.to_str().unwrap(), name);
    }
    assert_eq!(std::mem::size_of::<KatachiStatus>(), 4);
}

#[test]
fn null_pointers_are_named() {
    let mut out = std::ptr::dangling_mut::<KatachiMesh>(); // not NULL: must be reset
    let s = unsafe {
        katachi_mesh_create(
            null(),
            8,
            CUBE_LOOP_SIZES.as_ptr(),
            6,
            CUBE_FACE_LOOP_COUNTS.as_ptr(),
            6,
            CUBE_CORNERS.as_ptr(),
            24,
            &mut out,
        )
    };
    assert_eq!(s, KatachiStatus::NullPointer);
    assert_eq!(
        message(),
        "katachi_mesh_create: positions is NULL but vertex_count is 8"
    );
    assert!(out.is_null());

    let m = cube();
    let mut c = katachi_mesh_counts_default();
    assert_eq!(
        unsafe { katachi_mesh_counts(null(), &mut c) },
        KatachiStatus::NullPointer
    );
    assert_eq!(message(), "katachi_mesh_counts: mesh is NULL");
    assert_eq!(
        unsafe { katachi_mesh_counts(m.0, null_mut()) },
        KatachiStatus::NullPointer
    );
    assert_eq!(message(), "katachi_mesh_counts: counts is NULL");
    assert_eq!(
        unsafe { katachi_mesh_inspect(m.0, null_mut()) },
        KatachiStatus::NullPointer
    );
    assert_eq!(message(), "katachi_mesh_inspect: info is NULL");
    assert_eq!(
        unsafe { katachi_mesh_read(null(), &mut out) },
        KatachiStatus::NullPointer
    );
    assert_eq!(message(), "katachi_mesh_read: path is NULL");
    unsafe { katachi_mesh_free(null_mut()) };
}

#[test]
fn a_successful_call_clears_the_message_and_infallible_ones_keep_it() {
    let m = cube();
    assert_eq!(
        unsafe { katachi_mesh_set_vertex_sharpness(m.0, 99, 1.0) },
        KatachiStatus::InvalidArgument
    );
    let failed = message();
    assert_eq!(
        failed,
        "katachi_mesh_set_vertex_sharpness: vertex = 99 is out of range (the mesh has 8 vertices)"
    );
    let _ = katachi_status_name(2);
    let _ = katachi_abi_version();
    let _ = katachi_mesh_info_default();
    assert_eq!(message(), failed);
    let mut c = katachi_mesh_counts_default();
    assert_eq!(
        unsafe { katachi_mesh_counts(m.0, &mut c) },
        KatachiStatus::Ok
    );
    assert_eq!(message(), "");
}

#[test]
fn messages_belong_to_their_thread() {
    let m = cube();
    let shared = m.0 as usize; // read-only use from other threads
    assert_eq!(
        unsafe { katachi_mesh_clone(null(), null_mut()) },
        KatachiStatus::NullPointer
    );
    let main_message = message();
    let handles: Vec<_> = (0..4u32)
        .map(|t| {
            std::thread::spawn(move || {
                let mesh = shared as *const KatachiMesh;
                let mut s = 0.0;
                for _ in 0..100 {
                    let st = unsafe { katachi_mesh_vertex_sharpness(mesh, 50 + t, &mut s) };
                    assert_eq!(st, KatachiStatus::InvalidArgument);
                    assert!(message().contains(&format!("vertex = {} is out of range", 50 + t)));
                }
            })
        })
        .collect();
    for h in handles {
        h.join().unwrap();
    }
    assert_eq!(message(), main_message);
}

#[test]
fn bad_mesh_data_maps_to_bad_input() {
    let mut pos = CUBE_POSITIONS;
    pos[4] = f64::NAN;
    let mut out = null_mut();
    let s = unsafe {
        katachi_mesh_create(
            pos.as_ptr(),
            8,
            CUBE_LOOP_SIZES.as_ptr(),
            6,
            CUBE_FACE_LOOP_COUNTS.as_ptr(),
            6,
            CUBE_CORNERS.as_ptr(),
            24,
            &mut out,
        )
    };
    assert_eq!(s, KatachiStatus::BadInput);
    assert_eq!(
        message(),
        "katachi_mesh_create: vertex 1: coordinate y is NaN, not a finite number"
    );
    assert!(out.is_null());

    // Loop counts that do not add up.
    let s = unsafe {
        katachi_mesh_create(
            CUBE_POSITIONS.as_ptr(),
            8,
            CUBE_LOOP_SIZES.as_ptr(),
            5,
            CUBE_FACE_LOOP_COUNTS.as_ptr(),
            6,
            CUBE_CORNERS.as_ptr(),
            24,
            &mut out,
        )
    };
    assert_eq!(s, KatachiStatus::BadInput);
    assert!(
        message().contains("add up to 6, but 5 loop sizes"),
        "{}",
        message()
    );
}

#[test]
fn failing_calls_leave_the_mesh_unchanged() {
    let m = cube();
    unsafe {
        assert_eq!(
            katachi_mesh_set_edge_sharpness(m.0, 0, 1, 3.0),
            KatachiStatus::Ok
        );
        assert_eq!(
            katachi_mesh_set_vertex_sharpness(m.0, 2, 1.0),
            KatachiStatus::Ok
        );
    }
    let before = snapshot(&m);
    unsafe {
        // Second pair is no edge: nothing of the batch may land.
        let pairs = [1u32, 3, 0, 7];
        let values = [5.0, 5.0];
        assert_eq!(
            katachi_mesh_set_edge_sharpnesses(m.0, pairs.as_ptr(), values.as_ptr(), 2),
            KatachiStatus::BadInput
        );
        assert_eq!(
            katachi_mesh_set_edge_sharpness(m.0, 0, 1, f64::NAN),
            KatachiStatus::BadInput
        );
        assert_eq!(
            katachi_mesh_set_edge_sharpness(m.0, 0, 1, -0.5),
            KatachiStatus::BadInput
        );
        let vs = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, f64::INFINITY];
        assert_eq!(
            katachi_mesh_set_all_vertex_sharpness(m.0, vs.as_ptr(), 8),
            KatachiStatus::BadInput
        );
        assert!(message().contains("vertex 7"), "{}", message());
        assert_eq!(
            katachi_mesh_set_vertex_sharpness(m.0, 8, 1.0),
            KatachiStatus::InvalidArgument
        );
        let dir = std::env::temp_dir().join(format!("katachi-ffi-{}", std::process::id()));
        let path = CString::new(dir.join("x.unknown").to_str().unwrap()).unwrap();
        assert_eq!(
            katachi_mesh_write(m.0, path.as_ptr()),
            KatachiStatus::IoError
        );
    }
    assert_eq!(snapshot(&m), before);
}

#[test]
fn short_buffers_are_untouched_and_say_what_is_needed() {
    let m = cube();
    let mut buf = [7.0f64; 23];
    let s = unsafe { katachi_mesh_copy_positions(m.0, buf.as_mut_ptr(), buf.len()) };
    assert_eq!(s, KatachiStatus::BufferTooSmall);
    assert!(message().contains("24 are needed"), "{}", message());
    assert!(buf.iter().all(|&x| x == 7.0));
    // Size query: (NULL, 0).
    let s = unsafe { katachi_mesh_copy_positions(m.0, null_mut(), 0) };
    assert_eq!(s, KatachiStatus::BufferTooSmall);
}

#[test]
fn misaligned_pointers_are_rejected() {
    let m = cube();
    let mut raw = [0u64; 4];
    let odd = (raw.as_mut_ptr() as *mut u8).wrapping_add(1) as *mut f64;
    let s = unsafe { katachi_mesh_vertex_sharpness(m.0, 0, odd) };
    assert_eq!(s, KatachiStatus::InvalidArgument);
    assert!(message().contains("sharpness"), "{}", message());
    assert!(message().contains("not aligned"), "{}", message());
}

#[test]
fn struct_size_is_honoured() {
    let m = cube();
    // Too small: rejected, untouched.
    let mut info = katachi_mesh_info_default();
    info.struct_size = 8;
    info.edge_count = 99;
    assert_eq!(
        unsafe { katachi_mesh_inspect(m.0, &mut info) },
        KatachiStatus::InvalidArgument
    );
    assert_eq!(info.edge_count, 99);
    // Larger than this library's struct (a caller built against a newer header): only the
    // fields katachi knows are written; the rest of the caller's struct is left alone.
    #[repr(C)]
    struct Newer {
        info: KatachiMeshInfo,
        future: [u64; 2],
    }
    let mut newer = Newer {
        info: katachi_mesh_info_default(),
        future: [0xAAAA; 2],
    };
    newer.info.struct_size = std::mem::size_of::<Newer>() as u32;
    assert_eq!(
        unsafe { katachi_mesh_inspect(m.0, &mut newer.info) },
        KatachiStatus::Ok
    );
    assert_eq!(newer.info.struct_size, std::mem::size_of::<Newer>() as u32);
    assert_eq!(newer.info.edge_count, 12);
    assert_eq!(newer.info.euler_characteristic, 2);
    assert_eq!(newer.future, [0xAAAA; 2]);
}

#[test]
fn read_and_write_map_errors() {
    let dir = std::env::temp_dir().join(format!("katachi-ffi-rw-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let m = cube();
    let mut out = std::ptr::dangling_mut::<KatachiMesh>();
    let missing = CString::new(dir.join("missing.off").to_str().unwrap()).unwrap();
    assert_eq!(
        unsafe { katachi_mesh_read(missing.as_ptr(), &mut out) },
        KatachiStatus::IoError
    );
    assert!(message().contains("missing.off"), "{}", message());
    assert!(out.is_null());
    let bad_utf8: &[u8] = b"/tmp/\xff.obj\0";
    assert_eq!(
        unsafe { katachi_mesh_write(m.0, bad_utf8.as_ptr() as *const c_char) },
        KatachiStatus::InvalidArgument
    );
    assert!(message().contains("not valid UTF-8"), "{}", message());
    // A round trip.
    let path = CString::new(dir.join("cube.obj").to_str().unwrap()).unwrap();
    assert_eq!(
        unsafe { katachi_mesh_write(m.0, path.as_ptr()) },
        KatachiStatus::Ok,
        "{}",
        message()
    );
    let mut back = null_mut();
    assert_eq!(
        unsafe { katachi_mesh_read(path.as_ptr(), &mut back) },
        KatachiStatus::Ok,
        "{}",
        message()
    );
    let back = Mesh(back);
    assert_eq!(snapshot(&back), snapshot(&m));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn messages_escape_control_characters_from_the_input() {
    // A file name carrying a terminal escape code and a line break, as a host may pass on
    // (Blender and MeshLab show these messages; `blender -b` prints them to a terminal).
    let mut out = null_mut();
    let path = CString::new("/nonexistent/no\x1b[31msuch\n.off").unwrap();
    assert_eq!(
        unsafe { katachi_mesh_read(path.as_ptr(), &mut out) },
        KatachiStatus::IoError
    );
    let m = message();
    assert!(m.contains(r"no\u{1b}[31msuch\n.off"), "{m}");
    assert!(!m.chars().any(char::is_control), "{m:?}");
}

/// The exported functions' names, from the committed header.
fn header_functions() -> Vec<String> {
    let header =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("include/katachi.h"))
            .expect("include/katachi.h exists (cargo xtask header)");
    let mut names = Vec::new();
    let mut rest = header.as_str();
    while let Some(i) = rest.find("katachi_") {
        let tail = &rest[i..];
        let end = tail
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(tail.len());
        let name = &tail[..end];
        // A declaration: the name directly followed by '(' and preceded by a return type,
        // not inside a comment (comments in the header quote names in backticks).
        let before = &rest[..i];
        let line_start = before.rfind('\n').map_or(0, |p| p + 1);
        let line = &rest[line_start..i];
        if tail[end..].starts_with('(')
            && !line.trim_start().starts_with('*')
            && !line.contains('`')
        {
            names.push(name.to_owned());
        }
        rest = &tail[end..];
    }
    names.sort();
    names.dedup();
    names
}

#[test]
fn every_header_function_is_exercised_by_the_c_tests() {
    let functions = header_functions();
    assert!(
        functions.len() >= 20,
        "found only {functions:?} in the header"
    );
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/c");
    let mut sources = String::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let p = entry.unwrap().path();
        if matches!(
            p.extension().and_then(|e| e.to_str()),
            Some("c" | "cpp" | "h")
        ) {
            sources += &std::fs::read_to_string(&p).unwrap();
        }
    }
    let missing: Vec<&String> = functions
        .iter()
        .filter(|f| !sources.contains(&format!("{f}(")))
        .collect();
    assert!(
        missing.is_empty(),
        "these functions of include/katachi.h are called by no program in tests/c: {missing:?}"
    );
}

/// The index of the bracket closing the one at `open` (`(` or `{`), skipping string literals.
fn closing(text: &str, open: usize) -> usize {
    let bytes = text.as_bytes();
    let (o, c) = match bytes[open] {
        b'(' => (b'(', b')'),
        b'{' => (b'{', b'}'),
        other => panic!("not an opening bracket: {}", other as char),
    };
    let mut depth = 0usize;
    let mut i = open;
    while i < bytes.len() {
        match bytes[i] {
            b'"' => {
                i += 1;
                while bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
            }
            b if b == o => depth += 1,
            b if b == c => {
                depth -= 1;
                if depth == 0 {
                    return i;
                }
            }
            _ => {}
        }
        i += 1;
    }
    panic!("unbalanced brackets");
}

#[test]
fn every_exported_function_runs_inside_the_panic_boundary() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/ffi");
    let mut exported = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let p = entry.unwrap().path();
        let text = std::fs::read_to_string(&p).unwrap();
        let mut from = 0;
        while let Some(at) = text[from..].find("#[no_mangle]") {
            let start = from + at;
            let open = start + text[start..].find('{').expect("a function body");
            let sig = &text[start..open];
            let name = sig
                .split("fn ")
                .nth(1)
                .and_then(|s| s.split('(').next())
                .unwrap_or_else(|| panic!("{}: an export that is not a function", p.display()))
                .trim()
                .to_owned();
            assert!(
                sig.contains("extern \"C\""),
                "{name} in {} is not extern \"C\"",
                p.display()
            );
            // The whole body must be one call of guard(...) or guard_value(...).
            let close = closing(&text, open);
            let body = text[open + 1..close].trim();
            let call_open = ["guard(", "guard_value("]
                .iter()
                .find(|g| body.starts_with(*g))
                .map(|g| g.len() - 1)
                .unwrap_or_else(|| {
                    panic!(
                        "{name} in {} does not start with guard( or guard_value(",
                        p.display()
                    )
                });
            let call_close = closing(body, call_open);
            assert!(
                body[call_close + 1..].trim().is_empty(),
                "{name} in {} does something outside its guard call",
                p.display()
            );
            exported.push(name);
            from = close;
        }
    }
    exported.sort();
    assert_eq!(
        exported,
        header_functions(),
        "the functions exported by src/ffi and those in include/katachi.h differ \
         (run `cargo xtask header`)"
    );
}

/// A 4 × 4 grid of unit squares in z = 0 (two counter-clockwise triangles each) and an
/// orthographic view from above: world (x, y) is pixel (50 + 100 x, 450 − 100 y).
fn cut_grid() -> Mesh {
    let mut positions = Vec::new();
    for j in 0..5 {
        for i in 0..5 {
            positions.extend([i as f64, j as f64, 0.0]);
        }
    }
    let mut corners = Vec::new();
    for j in 0..4u32 {
        for i in 0..4u32 {
            let v = j * 5 + i;
            corners.extend([v, v + 1, v + 6, v, v + 6, v + 5]);
        }
    }
    create(&positions, &[3; 32], &[1; 32], &corners)
}

const CUT_VIEW_PROJ: [f64; 16] = [
    0.4, 0.0, 0.0, 0.0, 0.0, 0.4, 0.0, 0.0, 0.0, 0.0, -0.1, 0.0, -0.8, -0.8, 0.0, 1.0,
];
const CUT_VIEWPORT: [f64; 4] = [0.0, 0.0, 500.0, 500.0];
const CUT_STROKE: [f64; 6] = [20.0, 330.0, 250.0, 235.0, 480.0, 140.0];

/// Owns a cut handle for the test's duration.
struct Cut(*mut KatachiCut);

impl Drop for Cut {
    fn drop(&mut self) {
        unsafe { katachi_cut_free(self.0) }
    }
}

fn cut(m: &Mesh, stroke: &[f64], options: &KatachiCutOptions) -> (KatachiStatus, Cut) {
    let mut out = std::ptr::dangling_mut::<KatachiCut>(); // not NULL: must be reset on failure
    let s = unsafe {
        katachi_cut_by_stroke(
            m.0,
            stroke.as_ptr(),
            (stroke.len() / 2) as u32,
            CUT_VIEW_PROJ.as_ptr(),
            CUT_VIEWPORT.as_ptr(),
            options,
            &mut out,
        )
    };
    if s != KatachiStatus::Ok {
        assert!(out.is_null(), "out must be NULL after a failure");
    }
    (s, Cut(out))
}

#[test]
fn cut_by_stroke_through_the_abi() {
    let m = cut_grid();
    let before = snapshot(&m);
    let o = katachi_cut_options_default();
    assert_eq!(
        o.struct_size as usize,
        std::mem::size_of::<KatachiCutOptions>()
    );
    assert_eq!(o.mode, KatachiCutMode::VisibleOnly as u32);
    assert_eq!(o.max_faces_split, u32::MAX);
    let (s, c) = cut(&m, &CUT_STROKE, &o);
    assert_eq!(s, KatachiStatus::Ok, "{}", message());
    assert_eq!(snapshot(&m), before, "the input mesh is untouched");
    let mut info = katachi_cut_info_default();
    assert_eq!(
        unsafe { katachi_cut_info(c.0, &mut info) },
        KatachiStatus::Ok
    );
    assert_eq!((info.input_vertex_count, info.input_corner_count), (25, 96));
    assert_eq!(info.vertex_count, 25 + info.new_vertex_count);
    assert_eq!(info.face_count, 32 + info.new_face_count);
    assert_eq!(info.corner_count, 3 * info.face_count);
    assert_eq!((info.piece_count, info.path_count), (1, 1));
    assert_eq!(info.unjoined_count, 0);

    // The same cut through the kernel gives the same result.
    let grid = {
        let mut out = null_mut();
        assert_eq!(
            unsafe { katachi_cut_mesh(c.0, &mut out) },
            KatachiStatus::Ok
        );
        Mesh(out)
    };
    let kernel = {
        use glam::{DMat4, DVec2};
        use katachi::cut::{cut_by_stroke, CutOptions, Stroke, View};
        let mut positions = Vec::new();
        for j in 0..5 {
            for i in 0..5 {
                positions.push(glam::DVec3::new(i as f64, j as f64, 0.0));
            }
        }
        let mut faces = Vec::new();
        for j in 0..4u32 {
            for i in 0..4u32 {
                let v = j * 5 + i;
                faces.push(vec![v, v + 1, v + 6]);
                faces.push(vec![v, v + 6, v + 5]);
            }
        }
        let mesh = katachi::PolyMesh::from_polygons(positions, &faces).unwrap();
        let stroke = Stroke::new(
            CUT_STROKE
                .chunks(2)
                .map(|p| DVec2::new(p[0], p[1]))
                .collect(),
        );
        let view = View::new(DMat4::from_cols_array(&CUT_VIEW_PROJ), CUT_VIEWPORT);
        cut_by_stroke(&mesh, &stroke, &view, &CutOptions::default()).unwrap()
    };
    let got = snapshot(&grid);
    let want: Vec<f64> = kernel
        .mesh
        .positions()
        .iter()
        .flat_map(|p| p.to_array())
        .collect();
    assert_eq!(got.positions, want);
    assert_eq!(
        got.faces.2,
        kernel
            .mesh
            .corners()
            .iter()
            .map(|v| v.0)
            .collect::<Vec<_>>()
    );

    // Copy-out calls: sizes from info, short buffers refused untouched.
    let mut origin = vec![7u32; info.face_count as usize];
    let short = origin.len() - 1;
    assert_eq!(
        unsafe { katachi_cut_copy_face_origin(c.0, origin.as_mut_ptr(), short) },
        KatachiStatus::BufferTooSmall
    );
    assert!(origin.iter().all(|&f| f == 7));
    assert_eq!(
        unsafe { katachi_cut_copy_face_origin(c.0, origin.as_mut_ptr(), origin.len()) },
        KatachiStatus::Ok
    );
    let want: Vec<u32> = kernel.face_origin.iter().map(|f| f.0).collect();
    assert_eq!(origin, want);
    let mut offsets = vec![0u32; info.path_count as usize + 1];
    let mut path = vec![0u32; info.path_vertex_count as usize];
    assert_eq!(
        unsafe {
            katachi_cut_copy_paths(
                c.0,
                offsets.as_mut_ptr(),
                offsets.len(),
                path.as_mut_ptr(),
                path.len(),
            )
        },
        KatachiStatus::Ok
    );
    let want: Vec<u32> = kernel.report.paths[0]
        .vertices
        .iter()
        .map(|v| v.0)
        .collect();
    assert_eq!(path, want);
    assert_eq!(offsets, [0, want.len() as u32]);
    let (mut pieces, mut closed) = ([9u32], [9u32]);
    assert_eq!(
        unsafe { katachi_cut_copy_path_pieces(c.0, pieces.as_mut_ptr(), closed.as_mut_ptr(), 1) },
        KatachiStatus::Ok
    );
    assert_eq!((pieces, closed), ([0], [0]));
    let n = info.moved_vertex_count as usize;
    let (mut v, mut from, mut to, mut px) = (
        vec![0u32; n],
        vec![0.0; 3 * n],
        vec![0.0; 3 * n],
        vec![0.0; n],
    );
    assert_eq!(
        unsafe {
            katachi_cut_copy_moved_vertices(
                c.0,
                v.as_mut_ptr(),
                from.as_mut_ptr(),
                to.as_mut_ptr(),
                px.as_mut_ptr(),
                n,
            )
        },
        KatachiStatus::Ok
    );
    for (i, mv) in kernel.report.moved.iter().enumerate() {
        assert_eq!(v[i], mv.vertex.0);
        assert_eq!(&from[3 * i..3 * i + 3], &mv.from.to_array());
        assert_eq!(&to[3 * i..3 * i + 3], &mv.to.to_array());
        assert_eq!(px[i], mv.pixels);
    }
    for (stage, list, count) in [
        (
            KatachiCutStage::Preprocessing,
            &kernel.report.dropped.preprocessing,
            info.dropped_preprocessing_count,
        ),
        (
            KatachiCutStage::FirstNormalization,
            &kernel.report.dropped.first_normalization,
            info.dropped_first_normalization_count,
        ),
        (
            KatachiCutStage::SecondNormalization,
            &kernel.report.dropped.second_normalization,
            info.dropped_second_normalization_count,
        ),
        (
            KatachiCutStage::OffMesh,
            &kernel.report.dropped.off_mesh,
            info.dropped_off_mesh_count,
        ),
    ] {
        let mut buf = vec![0u32; count as usize];
        assert_eq!(
            unsafe {
                katachi_cut_copy_dropped_points(c.0, stage as u32, buf.as_mut_ptr(), buf.len())
            },
            KatachiStatus::Ok
        );
        assert_eq!(&buf, list, "{stage:?}");
    }
    assert_eq!(
        unsafe { katachi_cut_copy_dropped_points(c.0, 4, null_mut(), 0) },
        KatachiStatus::InvalidArgument
    );
    assert!(
        message().starts_with("katachi_cut_copy_dropped_points: stage is 4, which is not one of"),
        "{}",
        message()
    );
}

#[test]
fn cut_options_and_bad_strokes_are_named() {
    let m = cut_grid();
    let before = snapshot(&m);
    let d = katachi_cut_options_default();
    let cases: Vec<(KatachiCutOptions, Vec<f64>, KatachiStatus, &str)> = vec![
        (
            KatachiCutOptions { mode: 7, ..d },
            CUT_STROKE.to_vec(),
            KatachiStatus::InvalidArgument,
            "katachi_cut_by_stroke: options->mode is 7, which is not one of \
             KATACHI_CUT_MODE_VISIBLE_ONLY (0), KATACHI_CUT_MODE_THROUGH_ALL (1)",
        ),
        (
            KatachiCutOptions {
                struct_size: 4,
                ..d
            },
            CUT_STROKE.to_vec(),
            KatachiStatus::InvalidArgument,
            "options->struct_size is 4",
        ),
        (
            KatachiCutOptions { open: 3, ..d },
            CUT_STROKE.to_vec(),
            KatachiStatus::InvalidArgument,
            "options->open is 3, which is not one of 0, 1",
        ),
        (
            KatachiCutOptions {
                snap_segment_ratio: f64::NAN,
                ..d
            },
            CUT_STROKE.to_vec(),
            KatachiStatus::InvalidArgument,
            "options->snap_segment_ratio: NaN",
        ),
        (
            KatachiCutOptions {
                corner_angle_degrees: -1.0,
                ..d
            },
            CUT_STROKE.to_vec(),
            KatachiStatus::InvalidArgument,
            "options->corner_angle_degrees: -1",
        ),
        (
            KatachiCutOptions {
                depth_eps_rel: -1.0,
                ..d
            },
            CUT_STROKE.to_vec(),
            KatachiStatus::InvalidArgument,
            "options->depth_eps_rel",
        ),
        (
            KatachiCutOptions {
                max_faces_split: 1,
                ..d
            },
            CUT_STROKE.to_vec(),
            KatachiStatus::BadInput,
            "more than the limit of 1 (max_faces_split)",
        ),
        (
            d,
            vec![20.0, 330.0],
            KatachiStatus::BadInput,
            "a cut needs at least 2",
        ),
        (
            d,
            vec![20.0, 330.0, f64::NAN, 1.0],
            KatachiStatus::BadInput,
            "stroke point 1: coordinate x is NaN",
        ),
        (
            d,
            vec![100.0, 100.0, 400.0, 400.0, 400.0, 100.0, 100.0, 400.0],
            KatachiStatus::BadInput,
            "the stroke crosses itself",
        ),
    ];
    for (o, stroke, status, expect) in cases {
        let (s, _c) = cut(&m, &stroke, &o);
        assert_eq!(s, status, "{expect}: {}", message());
        assert!(
            message().contains(expect),
            "{} should contain {expect}",
            message()
        );
    }
    // A singular matrix.
    let mut out = null_mut();
    let s = unsafe {
        katachi_cut_by_stroke(
            m.0,
            CUT_STROKE.as_ptr(),
            3,
            [0.0; 16].as_ptr(),
            CUT_VIEWPORT.as_ptr(),
            &d,
            &mut out,
        )
    };
    assert_eq!(s, KatachiStatus::BadInput);
    assert!(message().contains("singular"), "{}", message());
    assert!(out.is_null());
    // NULLs are named.
    let s = unsafe {
        katachi_cut_by_stroke(
            m.0,
            null(),
            3,
            CUT_VIEW_PROJ.as_ptr(),
            CUT_VIEWPORT.as_ptr(),
            &d,
            &mut out,
        )
    };
    assert_eq!(s, KatachiStatus::NullPointer);
    assert_eq!(
        message(),
        "katachi_cut_by_stroke: stroke_px is NULL but point_count is 3"
    );
    assert_eq!(
        snapshot(&m),
        before,
        "failing cuts leave the mesh untouched"
    );
}

#[test]
fn cut_data_interpolation_checks_its_counts() {
    let m = cut_grid();
    let (s, c) = cut(&m, &CUT_STROKE, &katachi_cut_options_default());
    assert_eq!(s, KatachiStatus::Ok, "{}", message());
    let mut info = katachi_cut_info_default();
    assert_eq!(
        unsafe { katachi_cut_info(c.0, &mut info) },
        KatachiStatus::Ok
    );
    let values = vec![1.5; 96 * 2];
    let mut out = vec![0.0; 2 * info.corner_count as usize];
    let s = unsafe {
        katachi_cut_interpolate_corner_data(
            c.0,
            values.as_ptr(),
            95 * 2,
            2,
            out.as_mut_ptr(),
            out.len(),
        )
    };
    assert_eq!(s, KatachiStatus::InvalidArgument);
    assert_eq!(
        message(),
        "katachi_cut_interpolate_corner_data: value_count is 190, but the input mesh has 96 \
         corners × dim 2 = 192"
    );
    assert!(out.iter().all(|&x| x == 0.0));
    // A constant stays constant.
    let s = unsafe {
        katachi_cut_interpolate_corner_data(
            c.0,
            values.as_ptr(),
            values.len(),
            2,
            out.as_mut_ptr(),
            out.len(),
        )
    };
    assert_eq!(s, KatachiStatus::Ok, "{}", message());
    assert!(out.iter().all(|&x| (x - 1.5).abs() < 1e-15));
    let values = [2.0; 25];
    let mut out = vec![0.0; info.vertex_count as usize];
    let s = unsafe {
        katachi_cut_interpolate_vertex_data(
            c.0,
            values.as_ptr(),
            25,
            0,
            out.as_mut_ptr(),
            out.len(),
        )
    };
    assert_eq!(s, KatachiStatus::InvalidArgument);
    assert!(message().contains("dim is 0"), "{}", message());
    let s = unsafe {
        katachi_cut_interpolate_vertex_data(
            c.0,
            values.as_ptr(),
            25,
            1,
            out.as_mut_ptr(),
            out.len(),
        )
    };
    assert_eq!(s, KatachiStatus::Ok, "{}", message());
    assert!(out.iter().all(|&x| (x - 2.0).abs() < 1e-15));
}

#[test]
fn the_header_states_the_cut_conventions() {
    let header =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("include/katachi.h"))
            .unwrap();
    for needle in [
        "column-major",
        "clip.w > 0",
        "OpenGL-style NDC",
        "D3D-style",
        "Vulkan-style",
        "reversed-Z",
        "TOP-LEFT corner, y DOWN",
        "KATACHI_CUT_MODE_THROUGH_ALL = 1",
        "KATACHI_CUT_STAGE_OFF_MESH = 3",
    ] {
        assert!(
            header.contains(needle),
            "include/katachi.h should say {needle:?}"
        );
    }
}
