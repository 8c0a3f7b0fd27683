//! Stroke cut at the edges of the input space: stroke points, matrix entries, viewports and
//! mesh coordinates of huge but finite magnitude (1e300, `f64::MAX`) and tiny ones. Each is a
//! typed error naming what is wrong, or a cut whose every position is finite — never a panic,
//! a huge allocation or a read out of bounds (the C tests run the same through the C ABI
//! under valgrind, `tests/c/cut_api.c`, `tests/c/cut_fuzz.c`). Then a property test over
//! extreme numbers: `KATACHI_CUT_EXTREME_CASES` cases (default 256). All of them run again
//! in a child process under a 1 GiB address-space limit.

use glam::{DMat4, DVec2, DVec3};
use katachi::cut::{cut_by_stroke, CutMode, CutOptions, CutOutput, Stroke, View, SCREEN_RANGE_PX};
use katachi::{Error, ErrorKind, PolyMesh};
use proptest::prelude::*;

mod cut_meshes;
mod support;
use cut_meshes::{icosphere, tri_grid, view_for};
use support::property::counted_proptest;

/// Looking down at the 8 × 8 grid, 450 × 450 pixels.
fn top() -> View {
    View::new(
        DMat4::orthographic_rh_gl(-0.5, 8.5, -0.5, 8.5, -10.0, 10.0)
            * DMat4::look_at_rh(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, DVec3::Y),
        [0.0, 0.0, 450.0, 450.0],
    )
}

fn stroke(pts: &[(f64, f64)]) -> Stroke {
    Stroke::new(pts.iter().map(|&(x, y)| DVec2::new(x, y)).collect())
}

/// A short stroke across the middle of the top view.
const ACROSS: [(f64, f64); 3] = [(30.0, 200.0), (150.0, 210.0), (300.0, 230.0)];

/// The cut in both modes, opened or not: a result whose positions are all finite (and a valid
/// mesh), or a typed error (not an internal one), which is returned.
fn outcome(mesh: &PolyMesh, s: &Stroke, v: &View) -> Vec<Result<CutOutput, Error>> {
    let mut out = Vec::new();
    for mode in [CutMode::VisibleOnly, CutMode::ThroughAll] {
        for open in [false, true] {
            let mut o = CutOptions::with_mode(mode);
            o.open = open;
            let r = cut_by_stroke(mesh, s, v, &o);
            match &r {
                Ok(c) => {
                    let bad = c.mesh.positions().iter().position(|p| !p.is_finite());
                    assert_eq!(bad, None, "{mode:?}, open {open}: a non-finite vertex");
                    assert!(katachi::mesh::inspect(&c.mesh).is_ok());
                }
                Err(e) => assert_ne!(e.kind(), ErrorKind::Internal, "{e}"),
            }
            out.push(r);
        }
    }
    out
}

fn all_errors(rs: &[Result<CutOutput, Error>], what: impl Fn(&Error) -> bool) -> bool {
    rs.iter().all(|r| r.as_ref().is_err_and(&what))
}

#[test]
fn stroke_points_of_huge_magnitude_are_out_of_range() {
    limit_memory_in_a_child();
    let g = tri_grid(8, 8);
    for h in [1e300, f64::MAX, -f64::MAX, 1e13, 2.0 * SCREEN_RANGE_PX] {
        // Two points (no pair of segments to test), three in a line, and a point far off.
        for pts in [
            vec![(30.0, 200.0), (h, h)],
            vec![(30.0, 200.0), (150.0, 210.0), (h, 230.0)],
            vec![(-h, 200.0), (150.0, 210.0), (300.0, 230.0)],
            vec![(30.0, 200.0), (150.0, -h), (300.0, 230.0)],
        ] {
            let rs = outcome(&g, &stroke(&pts), &top());
            assert!(
                all_errors(&rs, |e| matches!(e, Error::StrokePointOutOfRange { .. })),
                "{pts:?}: {:?}",
                rs.iter()
                    .map(|r| r.as_ref().err().map(|e| e.to_string()))
                    .collect::<Vec<_>>()
            );
        }
    }
    // At the edge of the range: a stroke far off screen, nothing cut.
    let r = &outcome(
        &g,
        &stroke(&[(SCREEN_RANGE_PX, 0.0), (SCREEN_RANGE_PX, 100.0)]),
        &top(),
    )[0];
    assert!(r.as_ref().unwrap().report.nothing_cut());
}

#[test]
fn view_matrices_and_viewports_of_huge_magnitude_are_errors() {
    limit_memory_in_a_child();
    let g = tri_grid(8, 8);
    let s = stroke(&ACROSS);
    for h in [1e300, f64::MAX, 1e154, 1e100] {
        let mut v = top();
        v.view_proj *= h;
        let rs = outcome(&g, &s, &v);
        assert!(
            all_errors(&rs, |e| matches!(e, Error::ViewProjectionOutOfRange { .. })),
            "matrix × {h:e}: {:?}",
            rs[0].as_ref().err()
        );
        for (i, value) in [(0, h), (1, -h), (2, h), (3, h)] {
            let mut v = top();
            v.viewport[i] = value;
            let rs = outcome(&g, &s, &v);
            assert!(
                all_errors(&rs, |e| matches!(e, Error::InvalidViewport { .. })),
                "viewport[{i}] = {value:e}"
            );
        }
    }
    // A tiny scale is singular, a large translation is not out of range.
    let mut v = top();
    v.view_proj *= 1e-300;
    assert!(all_errors(&outcome(&g, &s, &v), |e| matches!(
        e,
        Error::SingularViewProjection { .. }
    )));
}

#[test]
fn mesh_coordinates_of_huge_magnitude_cut_or_overflow_typed() {
    limit_memory_in_a_child();
    let s = stroke(&ACROSS);
    for h in [1e300, f64::MAX, -f64::MAX, 1e154, 1e20] {
        // A grid vertex under the stroke moved far along the view (orthographic: it stays
        // under the stroke), and one moved far aside.
        for (k, d) in [(2, DVec3::Z), (0, DVec3::X)] {
            let g = tri_grid(8, 8);
            let mut p = g.positions().to_vec();
            p[40] += d * h;
            let faces: Vec<Vec<u32>> = g
                .faces()
                .map(|f| g.face_outer(f).iter().map(|v| v.0).collect())
                .collect();
            let m = PolyMesh::from_polygons(p, faces).unwrap();
            for r in outcome(&m, &s, &top()) {
                if let Err(e) = r {
                    assert!(
                        matches!(e, Error::CoordinateOverflow { .. }),
                        "axis {k}, {h:e}: {e}"
                    );
                }
            }
        }
        // A sphere vertex scaled far out, in perspective.
        let sphere = icosphere(2);
        let v = view_for(&sphere, false, 0.3, 0.5, 3.0);
        let mut p = sphere.positions().to_vec();
        p[3] *= h;
        let faces: Vec<Vec<u32>> = sphere
            .faces()
            .map(|f| sphere.face_outer(f).iter().map(|v| v.0).collect())
            .collect();
        let m = PolyMesh::from_polygons(p, faces).unwrap();
        let pts = [(300.0, 280.0), (400.0, 300.0), (520.0, 320.0)];
        for r in outcome(&m, &stroke(&pts), &v) {
            if let Err(e) = r {
                assert!(matches!(e, Error::CoordinateOverflow { .. }), "{h:e}: {e}");
            }
        }
    }
}

/// Property-test cases: 256, or `KATACHI_CUT_EXTREME_CASES`.
fn cases() -> u32 {
    std::env::var("KATACHI_CUT_EXTREME_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(256)
}

/// A number of any magnitude: ordinary, huge, tiny, the largest finite, zero.
fn magnitude() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => -1e3f64..1e3,
        1 => (-308i32..308, any::<bool>()).prop_map(|(e, neg)| {
            let x = 10f64.powi(e);
            if neg { -x } else { x }
        }),
        1 => prop_oneof![Just(f64::MAX), Just(-f64::MAX), Just(0.0), Just(f64::MIN_POSITIVE)],
    ]
}

counted_proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    #[test]
    fn extreme_numbers_give_a_finite_cut_or_a_typed_error(
        sphere in any::<bool>(),
        ortho in any::<bool>(),
        view_scale in magnitude(),
        entry in (0usize..4, 0usize..4, magnitude()),
        viewport in prop::collection::vec(magnitude(), 4),
        keep_viewport in any::<bool>(),
        vertex in (0usize..20, magnitude(), 0usize..3),
        pts in prop::collection::vec((magnitude(), magnitude()), 2..6),
        near in prop::collection::vec((0.0f64..600.0, 0.0f64..450.0), 2..6),
        use_near in 0usize..3,
    ) {
        limit_memory_in_a_child();
        let base = if sphere { icosphere(1) } else { tri_grid(4, 4) };
        let mut p = base.positions().to_vec();
        let (vi, value, axis) = vertex;
        let n = p.len();
        p[vi % n][axis] = value;
        let faces: Vec<Vec<u32>> = base
            .faces()
            .map(|f| base.face_outer(f).iter().map(|v| v.0).collect())
            .collect();
        let mesh = PolyMesh::from_polygons(p, faces).unwrap();
        let mut view = view_for(&base, ortho, 0.7, 0.4, 3.0);
        if view_scale.abs() > 1e-6 && view_scale.abs() < 1e6 {
            view.view_proj *= view_scale;
        }
        view.view_proj.col_mut(entry.0)[entry.1] = entry.2;
        if !keep_viewport {
            view.viewport = [viewport[0], viewport[1], viewport[2], viewport[3]];
        }
        // Ordinary strokes over the view, extreme ones, and a mix.
        let pts: Vec<(f64, f64)> = match use_near {
            0 => near,
            1 => pts,
            _ => near.iter().zip(&pts).enumerate().map(|(i, (a, b))| if i % 2 == 0 { *a } else { *b }).collect(),
        };
        outcome(&mesh, &stroke(&pts), &view);
    }
}

/// The environment variable that makes this binary a child run under an address-space limit.
const UNDER_LIMIT: &str = "KATACHI_CUT_EXTREME_UNDER_LIMIT";

/// In a child run ([`every_case_runs_under_a_1_gib_address_space_limit`]), caps this
/// process's address space at 1 GiB before a test cuts anything (every test calls it; the
/// limit is per process, so setting it again is harmless).
fn limit_memory_in_a_child() {
    if std::env::var_os(UNDER_LIMIT).is_none() {
        return;
    }
    let limit = libc::rlimit {
        rlim_cur: 1 << 30,
        rlim_max: 1 << 30,
    };
    // SAFETY: a plain system call on this process's own limit.
    assert_eq!(unsafe { libc::setrlimit(libc::RLIMIT_AS, &limit) }, 0);
}

/// Issue 34: an extreme number once made the cut allocate 2 GiB for a 26-face mesh (an abort
/// under a 4 GB limit). Every other test of this file runs again in a child process whose
/// address space is capped at 1 GiB (RLIMIT_AS): an allocation beyond it aborts the child and
/// fails this test.
#[test]
fn every_case_runs_under_a_1_gib_address_space_limit() {
    if std::env::var_os(UNDER_LIMIT).is_some() {
        return;
    }
    let out = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "--skip",
            "every_case_runs_under_a_1_gib_address_space_limit",
            "--test-threads=1",
        ])
        .env(UNDER_LIMIT, "1")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{:?}\n{text}\n{err}", out.status);
    assert!(text.contains("test result: ok. 4 passed"), "{text}");
}
