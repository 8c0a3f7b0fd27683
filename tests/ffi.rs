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
    let mut out = 1usize as *mut KatachiMesh; // not NULL: must be reset
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
    let mut out = 1usize as *mut KatachiMesh;
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
