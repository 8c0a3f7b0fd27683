//! Segmentation from a rough band (`katachi::rough::segment_band`, seed 003 §3, spec
//! `rough_model.md` §1 and §6 S1–S3): the boss's crease found from random bands, with and
//! without noise; the shortest cut on a flat band; several boundary loops; typed errors; and
//! properties of every result (closed loops that bound the feature, determinism).

mod support;

use katachi::error::RoughError;
use katachi::mesh::{shapes, FaceId, HalfedgeId, Topology};
use katachi::rough::{band_graph, segment_band, Band, SegmentOptions, Segmentation};
use katachi::{Error, PolyMesh};
use proptest::prelude::*;
use support::boss::{boss_plate, random_band, with_noise, BossPlate, BossSizes, Rng};
use support::property::counted_proptest;

/// Checks what every segmentation must satisfy, whatever the band: the boundary's half-edges
/// are exactly the feature's edges to faces outside it, each once, chained head to tail, and
/// closed where the feature does not reach the mesh boundary.
fn check_invariants(mesh: &PolyMesh, topo: &Topology, s: &Segmentation) {
    assert_eq!(s.is_feature.len(), mesh.face_count() as usize);
    let listed: Vec<FaceId> = (0..mesh.face_count())
        .filter(|&f| s.is_feature[f as usize])
        .map(FaceId)
        .collect();
    assert_eq!(s.feature, listed);
    let is_cut = |h: HalfedgeId| {
        let (f, g) = (topo.face(h), topo.face(topo.twin(h)));
        f.is_valid() && g.is_valid() && s.is_feature[f.idx()] && !s.is_feature[g.idx()]
    };
    let mut seen = vec![0u32; topo.halfedge_count() as usize];
    for lp in &s.boundary {
        assert!(!lp.halfedges.is_empty());
        for w in lp.halfedges.windows(2) {
            assert_eq!(topo.to(w[0]), topo.from(w[1]), "loop not head to tail");
        }
        let (first, last) = (lp.halfedges[0], *lp.halfedges.last().unwrap());
        if lp.closed {
            assert_eq!(
                topo.to(last),
                topo.from(first),
                "closed loop does not close"
            );
        } else {
            assert!(
                topo.is_boundary_vertex(topo.to(last)) && topo.is_boundary_vertex(topo.from(first))
            );
        }
        for &h in &lp.halfedges {
            assert!(
                is_cut(h),
                "half-edge {} is not between the feature and the rest",
                h.0
            );
            seen[h.idx()] += 1;
        }
    }
    for h in 0..topo.halfedge_count() {
        let want = u32::from(is_cut(HalfedgeId(h)));
        assert_eq!(
            seen[h as usize], want,
            "half-edge {h} listed {} times",
            seen[h as usize]
        );
    }
}

fn segment(mesh: &PolyMesh, band: &[FaceId], options: &SegmentOptions) -> Segmentation {
    segment_band(mesh, &Band::new(band.iter().copied()), options)
        .unwrap_or_else(|e| panic!("segment_band: {e}"))
}

fn hamming(a: &[bool], b: &[bool]) -> usize {
    a.iter().zip(b).filter(|(x, y)| x != y).count()
}

/// S1: random bands 3–10 faces wide around the boss's foot; the feature is the boss exactly.
fn boss_found(noise: f64, bands: u32, seed: u64) -> (u32, Vec<String>) {
    let plate = boss_plate(BossSizes::default(), false);
    let mut rng = Rng(seed);
    let mesh = if noise > 0.0 {
        // σ = `noise` × the mean edge length (about 0.13 here).
        with_noise(&plate.mesh, noise * 0.13, &mut rng)
    } else {
        plate.mesh.clone()
    };
    let topo = mesh.connectivity().unwrap();
    let want = plate.boss_faces();
    let mut exact = 0;
    let mut misses = Vec::new();
    for case in 0..bands {
        let width = 3 + rng.below(8) as u32;
        let band = random_band(&plate, plate.foot, width, &mut rng);
        let s = segment(&mesh, &band, &SegmentOptions::default());
        check_invariants(&mesh, &topo, &s);
        let d = hamming(&s.is_feature, &want);
        if d == 0 {
            exact += 1;
            assert_eq!(s.boundary.len(), 1);
            assert_eq!(s.boundary[0].halfedges.len() as u32, plate.sectors);
        } else {
            misses.push(format!("band {case} (width {width}): {d} faces differ"));
        }
    }
    (exact, misses)
}

#[test]
fn random_bands_around_a_boss_find_its_foot() {
    let (exact, misses) = boss_found(0.0, 200, 0x5eed_0001);
    assert!(
        exact >= 190,
        "{exact} of 200 bands exact (spec S1: ≥ 95 %): {misses:?}"
    );
}

#[test]
fn random_bands_around_a_noisy_boss_find_its_foot() {
    let (exact, misses) = boss_found(0.01, 200, 0x5eed_0002);
    assert!(
        exact >= 180,
        "{exact} of 200 bands exact with 1 % noise (spec S1: ≥ 90 %): {misses:?}"
    );
}

#[test]
fn the_active_side_can_be_the_larger_one() {
    // Seeded on the plate, the feature is the plate.
    let plate = boss_plate(BossSizes::default(), false);
    let mut rng = Rng(3);
    let band = random_band(&plate, plate.foot, 5, &mut rng);
    let mut options = SegmentOptions::default();
    options.seed = Some(FaceId(0));
    let s = segment(&plate.mesh, &band, &options);
    let boss = plate.boss_faces();
    assert_eq!(
        hamming(&s.is_feature, &boss),
        boss.len(),
        "the complement of the boss"
    );
}

/// A random band on the flat disc and the innermost ring every sector's part of it reaches.
fn flat_band(plate: &BossPlate, rng: &mut Rng) -> (Vec<FaceId>, u32) {
    // Bands in the plate's outer part, 4–9 rows wide, zigzagging; the innermost ring every
    // sector's part of the band touches is the shortest closed cycle inside the band.
    let width = 4 + rng.below(6) as u32;
    let ring = 11;
    let mut band = Vec::new();
    let mut innermost = 0;
    for j in 0..plate.sectors {
        let below = 1 + rng.below(width as u64 - 1) as u32;
        innermost = innermost.max(ring - below);
        for k in ring - below..ring - below + width {
            band.extend(plate.faces_at(k, j));
        }
    }
    (band, innermost)
}

#[test]
fn a_flat_band_is_cut_along_the_fewest_edges() {
    // S2, unweighted: with every capacity equal the cut crosses the fewest dual edges; no
    // closed cycle around the centre has fewer edges than the sectors.
    let plate = boss_plate(BossSizes::default(), true);
    let topo = plate.mesh.connectivity().unwrap();
    let mut rng = Rng(11);
    for _ in 0..40 {
        let (band, _) = flat_band(&plate, &mut rng);
        let s = segment(&plate.mesh, &band, &SegmentOptions::default());
        check_invariants(&plate.mesh, &topo, &s);
        assert_eq!(s.boundary.len(), 1);
        assert_eq!(s.boundary[0].halfedges.len() as u32, plate.sectors);
        assert!(
            (s.flow - plate.sectors as f64).abs() < 1e-9,
            "flow {}",
            s.flow
        );
    }
}

#[test]
fn a_flat_band_weighted_by_length_is_cut_short() {
    // S2: cut length ≤ 1.1 × the shortest cycle in the band (here the innermost ring all of
    // the band's sectors reach, a cycle the cut may take).
    let plate = boss_plate(BossSizes::default(), true);
    let topo = plate.mesh.connectivity().unwrap();
    let mut options = SegmentOptions::default();
    options.weight_by_edge_length = true;
    let mut rng = Rng(12);
    for case in 0..40 {
        let (band, innermost) = flat_band(&plate, &mut rng);
        let s = segment(&plate.mesh, &band, &options);
        check_invariants(&plate.mesh, &topo, &s);
        let length: f64 = s.boundary[0]
            .halfedges
            .iter()
            .map(|&h| {
                let p = plate.mesh.positions();
                p[topo.to(h).idx()].distance(p[topo.from(h).idx()])
            })
            .sum();
        let k = innermost as usize * plate.sectors as usize;
        let p = plate.mesh.positions();
        let ring: f64 = (0..plate.sectors as usize)
            .map(|j| p[k + j].distance(p[k + (j + 1) % plate.sectors as usize]))
            .sum();
        assert!(
            length <= 1.1 * ring,
            "case {case}: cut {length}, shortest cycle {ring}"
        );
    }
}

#[test]
fn two_bands_on_a_torus_give_a_feature_with_two_loops() {
    // Seed 003 Fig. 7: a feature bounded by several loops. Two meridian bands cut a torus into
    // two tubes; the shorter is the feature, bounded by one loop at each band.
    let (m, n) = (40u32, 12u32);
    let torus = shapes::torus(m, n, 3.0, 1.0).unwrap();
    let topo = torus.connectivity().unwrap();
    // Face (i, j) = i * n + j (i around the main circle); bands at i ∈ 4..6 and 14..17.
    let band: Vec<FaceId> = (0..m * n)
        .filter(|f| matches!(f / n, 4..=5 | 14..=16))
        .map(FaceId)
        .collect();
    let s = segment(&torus, &band, &SegmentOptions::default());
    check_invariants(&torus, &topo, &s);
    assert_eq!(s.boundary.len(), 2);
    assert!(s
        .boundary
        .iter()
        .all(|l| l.closed && l.halfedges.len() == n as usize));
    for f in 0..m * n {
        let i = f / n;
        if (6..14).contains(&i) {
            assert!(s.is_feature[f as usize], "face {f} between the bands");
        }
        if !(4..=16).contains(&i) {
            assert!(!s.is_feature[f as usize], "face {f} outside");
        }
    }
}

#[test]
fn a_band_across_an_open_grid_gives_an_open_boundary() {
    // A band from one side of a grid to the other separates it; the cut runs boundary to
    // boundary, one open piece.
    let grid = shapes::grid(10, 10).unwrap();
    let topo = grid.connectivity().unwrap();
    let band: Vec<FaceId> = (0..100)
        .filter(|f| matches!(f % 10, 2..=4))
        .map(FaceId)
        .collect();
    let s = segment(&grid, &band, &SegmentOptions::default());
    check_invariants(&grid, &topo, &s);
    assert_eq!(s.boundary.len(), 1);
    assert!(!s.boundary[0].closed);
    assert_eq!(s.boundary[0].halfedges.len(), 10);
    assert!(s.is_feature[0] && !s.is_feature[9]);
}

fn rough_error(r: katachi::Result<Segmentation>) -> RoughError {
    match r {
        Err(Error::Rough(e)) => e,
        other => panic!("expected a rough-model error, got {other:?}"),
    }
}

#[test]
fn bad_bands_and_seeds_are_typed_errors() {
    let plate = boss_plate(BossSizes::default(), false);
    let mesh = &plate.mesh;
    let nf = mesh.face_count();
    let run = |band: Vec<FaceId>, seed: Option<FaceId>| {
        let mut options = SegmentOptions::default();
        options.seed = seed;
        segment_band(mesh, &Band::new(band), &options)
    };
    assert_eq!(rough_error(run(vec![], None)), RoughError::EmptyBand);
    assert_eq!(
        rough_error(run(vec![FaceId(0), FaceId(nf)], None)),
        RoughError::FaceOutOfRange {
            what: "band",
            face: nf,
            face_count: nf
        }
    );
    let ring: Vec<FaceId> = (0..plate.sectors)
        .flat_map(|j| plate.faces_at(plate.foot, j))
        .collect();
    let in_ring = ring[3];
    assert_eq!(
        rough_error(run(ring.clone(), Some(in_ring))),
        RoughError::SeedInBand { face: in_ring.0 }
    );
    // An open band: the ring without sectors 10..14. Its ends are at sectors 9 and 14.
    let open: Vec<FaceId> = (0..plate.sectors)
        .filter(|j| !(10..14).contains(j))
        .flat_map(|j| plate.faces_at(plate.foot, j))
        .collect();
    match rough_error(run(open.clone(), None)) {
        RoughError::BandNotClosed { face } => {
            let sector = (face / 2) % plate.sectors;
            assert!(
                sector == 9 || sector == 14,
                "face {face} (sector {sector}) is not an end"
            );
        }
        e => panic!("expected BandNotClosed, got {e:?}"),
    }
    // A band from the plate's rim inward that stops: it reaches the boundary, cannot close.
    let spoke: Vec<FaceId> = (0..6).flat_map(|k| plate.faces_at(k, 0)).collect();
    match rough_error(run(spoke, None)) {
        RoughError::BandOpenAtBoundary { face } => assert!(plate.row_of(FaceId(face)) == 0),
        e => panic!("expected BandOpenAtBoundary, got {e:?}"),
    }
    // The options are checked.
    let mut bad = SegmentOptions::default();
    bad.eta_concave = f64::NAN;
    assert!(matches!(
        segment_band(mesh, &Band::new(ring), &bad),
        Err(Error::InvalidOption {
            option: "eta_concave",
            ..
        })
    ));
}

#[test]
fn non_manifold_input_is_refused() {
    // Three triangles on one edge.
    let p = vec![
        katachi::DVec3::new(0.0, 0.0, 0.0),
        katachi::DVec3::new(1.0, 0.0, 0.0),
        katachi::DVec3::new(0.0, 1.0, 0.0),
        katachi::DVec3::new(0.0, -1.0, 0.0),
        katachi::DVec3::new(0.0, 0.0, 1.0),
    ];
    let mesh =
        PolyMesh::from_polygons(p, vec![vec![0, 1, 2], vec![1, 0, 3], vec![0, 1, 4]]).unwrap();
    let r = segment_band(&mesh, &Band::new([FaceId(0)]), &SegmentOptions::default());
    assert!(matches!(r, Err(Error::NonManifoldEdge { .. })), "{r:?}");
}

#[test]
fn the_band_graph_holds_the_band_and_its_two_rings() {
    let plate = boss_plate(BossSizes::default(), false);
    let mut band = Vec::new();
    for k in plate.foot - 2..plate.foot + 2 {
        for j in 0..plate.sectors {
            band.extend(plate.faces_at(k, j));
        }
    }
    let g = band_graph(
        &plate.mesh,
        &Band::new(band.clone()),
        &SegmentOptions::default(),
    )
    .unwrap();
    // The band's 4 rows and the faces sharing an edge with it: in each row beside it, the
    // triangle of each quad that touches the band's ring edge.
    let rows: Vec<u32> = g.faces.iter().map(|&f| plate.row_of(f)).collect();
    assert_eq!(g.faces.len(), (4 * 2 + 2) * plate.sectors as usize);
    assert_eq!(g.network.node_count() as usize, g.faces.len());
    assert_eq!(*rows.iter().min().unwrap(), plate.foot - 3);
    assert_eq!(*rows.iter().max().unwrap(), plate.foot + 2);
}

/// A band for the property tests: random seed, width, ring, feature side (by area, the
/// plate's, the top's) and noise.
fn band_strategy() -> impl Strategy<Value = (u64, u32, u32, u8, bool)> {
    (any::<u64>(), 3u32..10, 3u32..33, 0u8..3, any::<bool>())
}

counted_proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn every_segmentation_is_deterministic_and_bounded_by_closed_loops(
        (seed, width, ring, side, noisy) in band_strategy()
    ) {
        let plate = boss_plate(BossSizes::default(), false);
        let mut rng = Rng(seed | 1);
        prop_assume!(ring >= width && ring + width < plate.rows);
        let mesh = if noisy { with_noise(&plate.mesh, 0.02, &mut rng) } else { plate.mesh.clone() };
        let band = random_band(&plate, ring, width, &mut rng);
        let mut options = SegmentOptions::default();
        options.seed = match side {
            0 => None,
            1 => Some(FaceId(0)),
            _ => Some(plate.faces_at(plate.rows - 1, 0)[0]),
        };
        let topo = mesh.connectivity().unwrap();
        let a = segment(&mesh, &band, &options);
        check_invariants(&mesh, &topo, &a);
        prop_assert!(a.boundary.iter().all(|l| l.closed));
        prop_assert!(!a.boundary.is_empty());
        // Seeded faces are in the feature; the other side's are not.
        if let Some(s) = options.seed {
            prop_assert!(a.is_feature[s.idx()]);
        }
        // Deterministic: the same bits again, and with the band's faces in another order.
        let mut shuffled = band.clone();
        shuffled.reverse();
        let b = segment(&mesh, &shuffled, &options);
        prop_assert_eq!(&a, &b);
        // The rows outside the band keep their side: the seed's, or one whole side.
        let lowest = band.iter().map(|&f| plate.row_of(f)).min().unwrap();
        let highest = band.iter().map(|&f| plate.row_of(f)).max().unwrap();
        let outer = a.is_feature[0];
        prop_assert_eq!(outer, side == 1 || (side == 0 && outer));
        for f in 0..mesh.face_count() {
            let r = plate.row_of(FaceId(f));
            if r < lowest {
                prop_assert_eq!(a.is_feature[f as usize], outer);
            }
            if r > highest {
                prop_assert_eq!(a.is_feature[f as usize], !outer);
            }
        }
    }
}
