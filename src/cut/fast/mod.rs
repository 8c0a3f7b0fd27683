//! The cut's speed machinery, behind one narrow interface. The paper's steps ask it what
//! may be near what — the stroke segments near a point or a box ([`SegmentIndex`]), the
//! faces of the mesh that may lie near the stroke (its whole-mesh passes), the region's faces
//! that may hold a point ([`FaceIndex`], [`locate::Locator`]), the polyline segments that may
//! meet an edge ([`polyline::PolylineIndex`]) — and sort and number with it ([`Machinery::sort_pairs`],
//! [`Machinery::local_ids`], [`Machinery::edge_table`]). Every answer is a superset that the
//! steps filter with their exact tests, so how tight it is changes no result.
//!
//! [`Machinery::Fast`] answers from a grid over the stroke (`grid`, with the whole-mesh
//! passes in AVX2/AVX-512 where the CPU has them: `codes_simd`, `faces_simd`), face buckets
//! (`buckets`), windows along the polyline (`polyline`) and radix sorts (`radix`).
//! [`Machinery::Plain`] answers "everything" and sorts with the standard library: the same
//! edits bit for bit, in O(faces × stroke) time, so the tests run both and compare
//! ([`super::cut_edits_plain`]). Step timings for tuning are in `trace` (`KATACHI_CUT_TRACE`).
//!
//! The whole-mesh passes and a few per-vertex and per-face maps run on rayon in fixed chunks
//! (the result does not depend on the thread count). The cut keeps no scheduling tricks (a
//! worker kept awake, joins that spin instead of sleeping): measured in Blender, at the
//! user's end, they did not pay (`docs/benchmarks.md`).
//!
//! Written here because no crate indexes a polyline and a triangle soup in screen space the
//! way the cut asks (a BVH from `parry3d` or `rstar` per cut would cost more than the cut).

pub(crate) mod buckets;
#[cfg(target_arch = "x86_64")]
pub(crate) mod codes_simd;
pub(crate) mod edges;
#[cfg(target_arch = "x86_64")]
pub(crate) mod faces_simd;
pub(crate) mod grid;
pub(crate) mod locate;
pub(crate) mod polyline;
pub(crate) mod radix;
pub(crate) mod trace;

use glam::DVec2;

use super::geom::point_segment_distance;
use super::ids::{Lf, Lv};
use super::region::Region;
use super::view::Projector;
use crate::error::Result;
use crate::mesh::PolyMesh;
use buckets::FaceBuckets;
use edges::EdgeTable;
use grid::{CellGrid, Kept};

/// Which machinery a cut runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Machinery {
    /// The grid, SIMD passes, buckets, windows and radix sorts.
    Fast,
    /// Linear scans and the standard library's sorts.
    Plain,
}

impl Machinery {
    /// Sorts `(key, value)` pairs by key, keeping the order of equal keys.
    pub fn sort_pairs(self, pairs: &mut Vec<(u32, u32)>) {
        match self {
            Machinery::Fast => radix::sort_by_key(pairs),
            Machinery::Plain => pairs.sort_by_key(|p| p.0),
        }
    }

    /// Sorts `items` stably by `(index(item), key(item))`.
    pub fn sort_by_index_then_key<T, K>(
        self,
        items: &mut Vec<T>,
        index: impl Fn(&T) -> u32 + Sync,
        key: impl Fn(&T) -> K + Sync,
    ) where
        T: Copy + Send + Sync,
        K: Ord + Copy,
    {
        match self {
            Machinery::Fast => radix::sort_by_index_then_key(items, index, key),
            Machinery::Plain => items.sort_by_key(|a| (index(a), key(a))),
        }
    }

    /// The distinct vertices of faces with `corners` (global ids, ascending) and each face's
    /// corners as indices into them (`nv`: the mesh's vertex count).
    pub fn local_ids(self, corners: Vec<[u32; 3]>, nv: usize) -> (Vec<u32>, Vec<[Lv; 3]>) {
        let (verts, tri) = match self {
            Machinery::Fast => edges::local_ids(corners, nv),
            Machinery::Plain => {
                let mut verts: Vec<u32> = corners.iter().flatten().copied().collect();
                verts.sort_unstable();
                verts.dedup();
                let rank = |v: u32| verts.binary_search(&v).expect("a corner") as u32;
                let tri = corners.iter().map(|t| t.map(rank)).collect();
                (verts, tri)
            }
        };
        (
            verts,
            tri.into_iter().map(|t: [u32; 3]| t.map(Lv)).collect(),
        )
    }

    /// The region's edge table ([`edges::edge_table_plain`] defines it); the fast form reads
    /// the vertex → face lists (`vf_start`, and beside each face its corner at the vertex,
    /// `vf_corner`).
    pub fn edge_table(
        self,
        tri: &[[Lv; 3]],
        verts: &[u32],
        vf_start: &[u32],
        vf_corner: &[u32],
    ) -> Result<EdgeTable> {
        match self {
            Machinery::Fast => edges::edge_table(tri, verts, vf_start, vf_corner),
            Machinery::Plain => edges::edge_table_plain(tri, verts),
        }
    }

    /// The margin (pixels) within which to look for the region's candidates first, and the
    /// guess of L it came from (the grid's cells are about that wide): the snap distance
    /// `max_ratio` · L with some room, from a sample of the mesh's faces. The plain path
    /// looks at every face, so its margin is infinite.
    pub fn first_margin(self, max_ratio: f64, mesh: &PolyMesh, proj: &Projector) -> (f64, f64) {
        match self {
            Machinery::Fast => {
                let l_guess = grid::sample_edge_length(mesh.positions(), mesh.corners(), proj);
                (1.5 * max_ratio * l_guess, l_guess)
            }
            Machinery::Plain => (f64::INFINITY, 0.0),
        }
    }
}

/// The stroke's segments near screen points and boxes: a superset of those within the
/// margin it was built for.
pub(crate) enum SegmentIndex {
    /// A grid over the stroke.
    Grid(Box<CellGrid>),
    /// Every segment, `0..n`.
    All(Vec<u32>),
}

impl SegmentIndex {
    /// The index of `segments` for distances up to `margin`; with a grid, cells about
    /// `cell_hint` wide.
    pub fn new(
        machinery: Machinery,
        segments: &[(DVec2, DVec2)],
        margin: f64,
        cell_hint: f64,
    ) -> Self {
        match machinery {
            Machinery::Fast => {
                SegmentIndex::Grid(Box::new(CellGrid::new(segments, margin, cell_hint)))
            }
            Machinery::Plain => SegmentIndex::All((0..segments.len() as u32).collect()),
        }
    }

    /// The grid, for the indexes built over it.
    pub fn grid(&self) -> Option<&CellGrid> {
        match self {
            SegmentIndex::Grid(g) => Some(g),
            SegmentIndex::All(_) => None,
        }
    }

    /// The faces of `mesh` that may lie within the margin of the stroke on screen, ascending,
    /// with their corners (a superset: the region measures them), including every face with
    /// a corner behind the eye and one in front; and, ascending, those straddling faces.
    pub fn candidate_faces(&self, mesh: &PolyMesh, proj: &Projector) -> (Kept, Vec<u32>) {
        match self {
            SegmentIndex::Grid(grid) => {
                let codes = grid::vertex_codes(mesh.positions(), proj, grid);
                grid::candidate_faces(mesh.corners(), &codes, grid)
            }
            SegmentIndex::All(_) => {
                let front: Vec<bool> = mesh
                    .positions()
                    .iter()
                    .map(|&p| proj.see(p).is_some())
                    .collect();
                let (mut kept, mut clipped) = (Kept::default(), Vec::new());
                for (f, t) in mesh.corners().chunks_exact(3).enumerate() {
                    let t = [t[0].0, t[1].0, t[2].0];
                    let n = t.iter().filter(|&&v| front[v as usize]).count();
                    if n == 0 {
                        continue;
                    }
                    kept.faces.push(f as u32);
                    kept.corners.push(t);
                    if n < 3 {
                        clipped.push(f as u32);
                    }
                }
                (kept, clipped)
            }
        }
    }

    /// Segments that may lie within the margin of point `s`.
    #[inline]
    pub fn near_point(&self, s: DVec2) -> &[u32] {
        match self {
            SegmentIndex::Grid(grid) => grid.segments_near(s),
            SegmentIndex::All(all) => all,
        }
    }

    /// Segments that may lie within the margin of a point of the box `lo..=hi`, each once
    /// (`scratch` holds them when they are gathered from several cells).
    #[inline]
    pub fn near_box<'a>(&'a self, lo: DVec2, hi: DVec2, scratch: &'a mut Vec<u32>) -> &'a [u32] {
        match self {
            SegmentIndex::Grid(grid) => grid.segments_in_box(lo, hi, scratch),
            SegmentIndex::All(all) => all,
        }
    }

    /// The distance from `s` to the nearest segment, exact whenever it is within the margin
    /// (infinite when no segment may be).
    #[inline]
    pub fn distance_to(&self, s: DVec2, segments: &[(DVec2, DVec2)]) -> f64 {
        self.near_point(s)
            .iter()
            .map(|&k| point_segment_distance(s, segments[k as usize].0, segments[k as usize].1))
            .fold(f64::INFINITY, f64::min)
    }
}

/// The region's faces that may hold a screen point, for visible-only mode's visibility
/// tests (and its point location).
pub(crate) enum FaceIndex {
    /// Bucketed over the stroke grid's area ([`FaceBuckets`]).
    Buckets(FaceBuckets),
    /// Every face with an orientation on screen.
    All(Vec<Lf>),
}

impl FaceIndex {
    /// The index of the region's faces with an orientation on screen, valid while vertices
    /// move up to `slack` pixels (snapping).
    pub fn new(segments: &SegmentIndex, region: &Region, slack: f64) -> Self {
        match segments.grid() {
            Some(grid) => FaceIndex::Buckets(FaceBuckets::new(region, grid, slack)),
            None => FaceIndex::All(region.faces().filter(|&f| region.sign(f) != 0.0).collect()),
        }
    }

    /// Whether `f` holds for a face that may hold screen point `s` at an NDC depth nearer
    /// than `z` (each such face given at most once).
    #[inline]
    pub fn any_in_front(&self, s: DVec2, z: f64, mut f: impl FnMut(Lf) -> bool) -> bool {
        match self {
            FaceIndex::Buckets(b) => b.any_in_front(s, z, f),
            FaceIndex::All(faces) => faces.iter().any(|&x| f(x)),
        }
    }
}
