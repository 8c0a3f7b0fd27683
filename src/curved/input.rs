//! What the mesher is given: patches, trim curves with stable ids, regions made of loops of
//! curve uses, and a metric field (seed 000 §4 Step 1; spec §1).

use glam::DVec2;

use super::bezier::BezierCurve;
use super::field::MetricField;
use super::patch::BezierPatch;
use crate::mesh::id_type;

id_type!(
    /// A trim curve: its index in [`TrimmedPatches::curves`]. A curve that bounds two regions
    /// is one curve, used by both (spec §1.3).
    CurveId
);
id_type!(
    /// A patch: its index in [`TrimmedPatches::patches`].
    PatchId
);
id_type!(
    /// A region: its index in [`TrimmedPatches::regions`].
    RegionId
);

/// One curve of a loop, traversed forwards (`c(0) → c(1)`) or backwards.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CurveUse {
    pub curve: CurveId,
    pub reversed: bool,
}

impl CurveUse {
    pub fn forward(curve: u32) -> CurveUse {
        CurveUse {
            curve: CurveId(curve),
            reversed: false,
        }
    }

    pub fn backward(curve: u32) -> CurveUse {
        CurveUse {
            curve: CurveId(curve),
            reversed: true,
        }
    }
}

/// A closed loop: consecutive uses share their end points bit for bit, and the last use ends
/// where the first begins.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TrimLoop {
    pub uses: Vec<CurveUse>,
}

impl TrimLoop {
    pub fn new(uses: Vec<CurveUse>) -> TrimLoop {
        TrimLoop { uses }
    }
}

/// A trimmed region of one patch: the first loop is the outer boundary (counter-clockwise in
/// the parameter square), any further loops are holes (clockwise), so the region is always on
/// the left of its loops (spec §0).
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    pub patch: PatchId,
    pub loops: Vec<TrimLoop>,
}

/// The whole input of [`super::mesh`]: every region is meshed in one call, so curves shared
/// between regions are split once and their vertices are the same on both sides.
#[derive(Debug, Clone)]
pub struct TrimmedPatches {
    pub patches: Vec<BezierPatch>,
    pub curves: Vec<BezierCurve>,
    pub regions: Vec<Region>,
    pub metric: MetricField,
}

impl TrimmedPatches {
    /// The curve of a use, as traversed (reversed if the use is).
    pub fn curve_of(&self, u: CurveUse) -> BezierCurve {
        let c = &self.curves[u.curve.idx()];
        if u.reversed {
            c.reversed()
        } else {
            c.clone()
        }
    }

    /// Where a use begins.
    pub fn use_start(&self, u: CurveUse) -> DVec2 {
        let c = &self.curves[u.curve.idx()];
        if u.reversed {
            c.end()
        } else {
            c.start()
        }
    }

    /// Where a use ends.
    pub fn use_end(&self, u: CurveUse) -> DVec2 {
        let c = &self.curves[u.curve.idx()];
        if u.reversed {
            c.start()
        } else {
            c.end()
        }
    }

    /// The signed area of region `r` in parameter space, by Green's theorem on its loops
    /// (closed form from the control points, spec §3.4).
    pub fn region_area(&self, r: RegionId) -> f64 {
        self.regions[r.idx()]
            .loops
            .iter()
            .flat_map(|l| l.uses.iter())
            .map(|u| {
                let a = self.curves[u.curve.idx()].area_term();
                if u.reversed {
                    -a
                } else {
                    a
                }
            })
            .sum()
    }

    /// A region bounded by straight segments through `points` (counter-clockwise), on one
    /// patch: a convenience for tests and examples. Curves are appended to `self.curves`.
    pub fn add_polygon_region(&mut self, patch: u32, points: &[DVec2]) -> RegionId {
        let first = self.curves.len() as u32;
        let n = points.len();
        for i in 0..n {
            self.curves
                .push(BezierCurve::line(points[i], points[(i + 1) % n]));
        }
        let uses = (0..n as u32)
            .map(|i| CurveUse::forward(first + i))
            .collect();
        self.regions.push(Region {
            patch: PatchId(patch),
            loops: vec![TrimLoop::new(uses)],
        });
        RegionId(self.regions.len() as u32 - 1)
    }
}
