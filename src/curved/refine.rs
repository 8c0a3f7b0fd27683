//! Anisotropic Voronoi refinement of Ω_lin (seed 000 §4 Step 3 and §3.3, after Labelle &
//! Shewchuk 2003 and Imai & Yokosuka 2006; spec §4.3).
//!
//! One priority queue holds the violations, fixed in this order:
//!
//! 1. **Encroached guard edge** (spec §4.3 rule 1): a site inside the diametral ellipse of
//!    a guard edge `ab`, `(a − q)ᵀ M (b − q) ≤ 0` with `M` the metric at the edge's midpoint.
//!    The edge's curve piece is bisected ([`super::bisect`]); guard edges never get Steiner
//!    points.
//! 2. **Bad triangle** (rule 3, with rule 2's inconsistencies): circumradius over shortest
//!    edge `r/ℓ_min > B`, both measured in the sites' own metrics (`r` is the Voronoi vertex's
//!    distance, `ℓ_min` the least of `d_p(q), d_q(p)` over the edges); or a corner angle below
//!    `arcsin(1/(2B))` in the metric of any of the three sites; or no consistent Voronoi vertex.
//!    The Voronoi vertex is inserted — unless it lies beyond a guard edge or encroaches one
//!    (Ruppert's rule), which is then split instead.
//! 3. **Big triangle** (rule 4): `r > r_max`; the Voronoi vertex is inserted likewise.
//!
//! The refinement stops when the queue is empty, so every triangle that is not exempt meets
//! the angle bound *by construction*, in the metric of each of its vertices: the bound is
//! the stopping test itself, not a consequence of a proof whose constants we could not
//! check against Labelle & Shewchuk's text (spec's warning). The theory (LS, IY: B = 2 with
//! curved boundaries, seed 000 §5.2) is why it stops on smooth metrics; the site and step
//! budgets stop it on anything else, with a typed error.
//!
//! Exempt: triangles at a small input corner (an angle below `small_angle_deg` in the
//! metric between two guard chains), which no refinement can fix (spec §4.3, Ruppert's
//! practice).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::DVec2;

use super::angles::angles_at_least;
use super::bisect::{bisect, Bisected};
use super::corners::Corners;
use super::domain::{Domain, VertexKind};
use super::error::CurvedError;
use super::options::CurvedOptions;
use super::tensor::Metric2;
use super::triangulation::{tri_of, Cavity, Located, NONE};
use crate::error::Error;

#[derive(Debug, Clone, Copy, PartialEq)]
struct Task {
    class: u8,
    key: f64,
    item: u32,
    generation: u32,
}

impl Eq for Task {}

impl Ord for Task {
    fn cmp(&self, o: &Self) -> Ordering {
        // BinaryHeap pops the greatest: lower class first, then larger key, then lower item.
        o.class
            .cmp(&self.class)
            .then(self.key.total_cmp(&o.key))
            .then(o.item.cmp(&self.item))
    }
}

impl PartialOrd for Task {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Most flips after one insertion or bisection.
const LEGALIZE_LIMIT: usize = 256;

const ENCROACHED: u8 = 0;
const BAD: u8 = 1;
const BIG: u8 = 2;

/// The queue of violations: encroached guard edges first (a stack), then bad triangles
/// (worst first, exactly), then big ones, largest first by buckets of a quarter octave of
/// `r²` (last in, first out within a bucket), which keeps the order coarse to fine at O(1)
/// a step.
#[derive(Default)]
struct Queue {
    encroached: Vec<u32>,
    bad: BinaryHeap<Task>,
    big: Vec<Vec<(u32, u32)>>,
    big_top: usize,
}

impl Queue {
    fn push(&mut self, t: Task) {
        match t.class {
            ENCROACHED => self.encroached.push(t.item),
            BAD => self.bad.push(t),
            _ => {
                let b = if t.key <= 1.0 {
                    0
                } else {
                    ((t.key.log2() * 4.0) as usize + 1).min(4095)
                };
                if self.big.len() <= b {
                    self.big.resize_with(b + 1, Vec::new);
                }
                self.big[b].push((t.item, t.generation));
                self.big_top = self.big_top.max(b);
            }
        }
    }

    fn pop(&mut self) -> Option<Task> {
        if let Some(c) = self.encroached.pop() {
            return Some(Task {
                class: ENCROACHED,
                key: 0.0,
                item: c,
                generation: 0,
            });
        }
        if let Some(t) = self.bad.pop() {
            return Some(t);
        }
        loop {
            let bucket = self.big.get_mut(self.big_top)?;
            if let Some((item, generation)) = bucket.pop() {
                return Some(Task {
                    class: BIG,
                    key: 0.0,
                    item,
                    generation,
                });
            }
            if self.big_top == 0 {
                return None;
            }
            self.big_top -= 1;
        }
    }
}

/// Counters of one refinement.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RefineStats {
    /// Sites inserted at Voronoi vertices.
    pub insertions: u64,
    /// Curve pieces bisected because a guard edge was encroached or a site would have been.
    pub bisections: u64,
    /// Queue pops.
    pub steps: u64,
    /// Triangles left bad because nothing could be inserted for them (a Voronoi vertex on a
    /// site, a piece at the split depth cap). Reported; zero on every input we know.
    pub unresolved: u64,
}

pub(crate) struct Refiner<'o> {
    opts: &'o CurvedOptions,
    heap: Queue,
    cav: Cavity,
    out: Vec<u32>,
    cos_min: f64,
    /// The small input corners (triangles there are exempt).
    pub corners: Corners,
    /// Per triangle slot: left bad on purpose (see [`RefineStats::unresolved`]).
    pub unresolved: Vec<bool>,
    pub stats: RefineStats,
    max_sites: u64,
    max_steps: u64,
    /// A rough count of the sites the mesh will need (the first triangulation's area in the
    /// metric over a unit triangle's, halved), for progress reports.
    pub estimate: u64,
}

impl<'o> Refiner<'o> {
    pub fn new(d: &Domain, opts: &'o CurvedOptions, corners: Corners) -> Self {
        let boundary = d.tr.vertex_count() as u64;
        let max_sites = opts.max_sites.unwrap_or(10 * boundary + 1_000_000);
        Refiner {
            opts,
            heap: Queue::default(),
            cav: Cavity::default(),
            out: Vec::new(),
            cos_min: (1.0 / (2.0 * opts.radius_edge_bound)).asin().cos(),
            corners,
            unresolved: Vec::new(),
            stats: RefineStats::default(),
            max_sites,
            max_steps: opts.max_steps.unwrap_or(8 * max_sites),
            estimate: estimate_sites(d, opts.size_bound),
        }
    }

    fn is_exempt(&self, d: &Domain, t: u32) -> bool {
        self.corners.exempts(d, t)
    }

    /// The violation of triangle `t`, if any: `(class, key)`.
    pub fn assess(&self, d: &Domain, t: u32) -> Option<(u8, f64)> {
        let tr = &d.tr;
        let v = tr.tri(t);
        let p = v.map(|i| tr.pos[i as usize]);
        let m = v.map(|i| tr.metric[i as usize]);
        let r2 = tr.radius2[t as usize];
        // ℓ_min² over the edges, each measured from both ends.
        let mut l2 = f64::INFINITY;
        for i in 0..3 {
            let j = (i + 1) % 3;
            let e = p[j] - p[i];
            l2 = l2.min(m[i].norm_sq(e)).min(m[j].norm_sq(e));
        }
        let b = self.opts.radius_edge_bound;
        let exempt = self.is_exempt(d, t);
        if !exempt {
            let ratio2 = r2 / l2;
            if ratio2 > b * b || !tr.exact_center[t as usize] {
                return Some((BAD, ratio2.min(1e300)));
            }
            if m.iter().any(|mk| !angles_at_least(&p, mk, self.cos_min)) {
                return Some((BAD, ratio2));
            }
        }
        let s = self.opts.size_bound;
        if r2 > s * s {
            return Some((BIG, r2));
        }
        None
    }

    fn push_triangle(&mut self, d: &Domain, t: u32) {
        if !d.tr.alive[t as usize] {
            return;
        }
        if let Some((class, key)) = self.assess(d, t) {
            self.heap.push(Task {
                class,
                key,
                item: t,
                generation: d.tr.generation[t as usize],
            });
        }
        // Guard edges of t encroached by its apex.
        for k in 0..3 {
            let h = 3 * t + k;
            let c = d.tr.cons[h as usize];
            if c != NONE && self.encroached(d, c, d.tr.pos[d.tr.apex(h) as usize]) {
                self.heap.push(Task {
                    class: ENCROACHED,
                    key: 0.0,
                    item: c,
                    generation: 0,
                });
            }
        }
    }

    /// Whether `q` is in the diametral ellipse of constraint `c` (spec §4.3 rule 1).
    fn encroached(&self, d: &Domain, c: u32, q: DVec2) -> bool {
        let con = &d.tr.constraints[c as usize];
        let a = d.tr.pos[con.a as usize];
        let b = d.tr.pos[con.b as usize];
        con.metric.dot(a - q, b - q) <= 0.0
    }

    /// Runs the refinement to the end (or a budget).
    pub fn run(&mut self, d: &mut Domain, progress: &mut dyn FnMut(u64, u64)) -> Result<(), Error> {
        // The first triangulation came from insertions into an enclosing triangle and edge
        // flips for the constraints: make it locally Delaunay in the metric first.
        let mut stack: Vec<(u32, u32)> = (0..d.tr.triangle_slots() as u32)
            .filter(|&t| d.tr.alive[t as usize])
            .flat_map(|t| (0..3).map(move |k| (3 * t + k, 0)))
            .map(|(h, _)| (h, d.tr.generation[tri_of(h) as usize]))
            .collect();
        let mut touched = Vec::new();
        let limit = 8 * d.tr.triangle_slots() + 64;
        d.tr.legalize(&mut stack, &mut touched, limit);
        self.unresolved.resize(d.tr.triangle_slots(), false);
        for t in 0..d.tr.triangle_slots() as u32 {
            self.push_triangle(d, t);
        }
        self.drain(d, progress)
    }

    /// Fixes violations until the queue is empty (or a budget runs out), calling
    /// `progress(sites, estimate)` every few thousand steps.
    pub fn drain(
        &mut self,
        d: &mut Domain,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<(), Error> {
        while let Some(task) = self.heap.pop() {
            self.stats.steps += 1;
            if self.stats.steps.is_multiple_of(4096) {
                progress(d.tr.vertex_count() as u64, self.estimate);
            }
            if self.stats.steps > self.max_steps {
                return Err(CurvedError::Budget {
                    what: "refinement steps",
                    option: "max_steps",
                    limit: self.max_steps,
                    detail: format!(
                        "{} sites so far, {} insertions, {} bisections",
                        d.tr.vertex_count(),
                        self.stats.insertions,
                        self.stats.bisections
                    ),
                }
                .into());
            }
            match task.class {
                ENCROACHED => {
                    let c = task.item;
                    let con = d.tr.constraints[c as usize];
                    if !con.alive {
                        continue;
                    }
                    let w = d.tr.apex(con.half);
                    let apex = d.tr.pos[w as usize];
                    if self
                        .corners
                        .protects(d, d.guarded.piece(con.piece).curve, w)
                    {
                        continue;
                    }
                    if self.encroached(d, c, apex) {
                        self.split_piece(d, con.piece, None)?;
                    }
                }
                _ => {
                    let t = task.item;
                    if !d.tr.alive[t as usize] || d.tr.generation[t as usize] != task.generation {
                        continue;
                    }
                    self.fix_triangle(d, t)?;
                }
            }
        }
        Ok(())
    }

    fn budget_check(&self, d: &Domain) -> Result<(), Error> {
        if d.tr.vertex_count() as u64 >= self.max_sites {
            return Err(CurvedError::Budget {
                what: "mesh vertices",
                option: "max_sites",
                limit: self.max_sites,
                detail: format!("{} triangles so far", d.tr.alive_count),
            }
            .into());
        }
        Ok(())
    }

    /// Bisects `piece` and queues what changed; `then` is re-queued if it survives.
    pub fn split_piece(
        &mut self,
        d: &mut Domain,
        piece: u32,
        then: Option<u32>,
    ) -> Result<bool, Error> {
        self.budget_check(d)?;
        match bisect(d, piece)? {
            Bisected::AtDepthCap => Ok(false),
            Bisected::Split { mut touched, .. } => {
                self.stats.bisections += 1;
                let mut stack: Vec<(u32, u32)> = touched
                    .iter()
                    .filter(|&&t| d.tr.alive[t as usize])
                    .flat_map(|&t| (0..3).map(move |k| 3 * t + k))
                    .map(|h| (h, d.tr.generation[tri_of(h) as usize]))
                    .collect();
                let mut more = Vec::new();
                d.tr.legalize(&mut stack, &mut more, LEGALIZE_LIMIT);
                touched.extend(more);
                for t in touched {
                    self.push_triangle(d, t);
                }
                if let Some(t) = then {
                    self.push_triangle(d, t);
                }
                Ok(true)
            }
        }
    }

    fn give_up(&mut self, d: &Domain, t: u32) {
        if self.unresolved.len() < d.tr.triangle_slots() {
            self.unresolved.resize(d.tr.triangle_slots(), false);
        }
        self.unresolved[t as usize] = true;
        self.stats.unresolved += 1;
    }

    /// The off-centre of triangle `t` (Üngör 2004; \[DESIGN\]): on the bisector of its
    /// shortest edge, at the point where a triangle on that edge would just meet the bound
    /// (with a 5% margin), or the circumcentre if nearer; all in the mean of the vertex
    /// metrics. For a skinny triangle it lies near the short edge, where the Voronoi vertex
    /// can be far away across the domain.
    fn off_center(&self, d: &Domain, t: u32) -> Option<DVec2> {
        let v = d.tr.tri(t);
        let p = v.map(|i| d.tr.pos[i as usize]);
        let m = v.map(|i| d.tr.metric[i as usize]);
        let mean = m[0].add(&m[1]).add(&m[2]).scale(1.0 / 3.0);
        let f = mean.cholesky()?;
        let q = p.map(|x| f.apply(x - p[0]));
        let (mut k, mut best) = (0, f64::INFINITY);
        for i in 0..3 {
            let l = (q[(i + 1) % 3] - q[i]).length_squared();
            if l < best {
                best = l;
                k = i;
            }
        }
        let (a, b) = (q[k], q[(k + 1) % 3]);
        let (bb, cc) = (q[1], q[2]);
        let den = 2.0 * bb.perp_dot(cc);
        if den == 0.0 {
            return None;
        }
        let (lb, lc) = (bb.length_squared(), cc.length_squared());
        let center = DVec2::new(cc.y * lb - bb.y * lc, bb.x * lc - cc.x * lb) / den;
        let mid = 0.5 * (a + b);
        let to_center = center - mid;
        let dist = to_center.length();
        let alpha = (1.0 / (2.0 * 0.95 * self.opts.radius_edge_bound)).asin();
        let h = 0.5 * best.sqrt() / (0.5 * alpha).tan();
        let off = if dist <= h || dist == 0.0 {
            center
        } else {
            mid + to_center * (h / dist)
        };
        let x = p[0] + f.solve(off);
        x.is_finite().then_some(x)
    }

    /// Inserts a point for bad or big triangle `t` — its off-centre (bad) or Voronoi vertex
    /// (big), else its centroid — or splits the guard edge the point encroaches.
    fn fix_triangle(&mut self, d: &mut Domain, t: u32) -> Result<(), Error> {
        if self.unresolved.get(t as usize).copied().unwrap_or(false) {
            return Ok(());
        }
        let Some((class, _)) = self.assess(d, t) else {
            return Ok(());
        };
        let first = if class == BAD {
            self.off_center(d, t)
        } else {
            Some(d.tr.center[t as usize])
        };
        let [a, b, c] = d.tr.tri(t).map(|i| d.tr.pos[i as usize]);
        let centroid = (a + b + c) / 3.0;
        for cand in [first, Some(centroid)].into_iter().flatten() {
            let seeds = match d.tr.locate(cand, t) {
                Located::Inside(u) => vec![u],
                Located::OnEdge(h)
                    if d.tr.cons[h as usize] == NONE && d.tr.twin[h as usize] != NONE =>
                {
                    vec![tri_of(h), tri_of(d.tr.twin[h as usize])]
                }
                Located::OnEdge(h) | Located::Blocked(h) => {
                    // Beyond a guard edge: split it if the point encroaches it (Ruppert).
                    let k = d.tr.cons[h as usize];
                    if k != NONE && self.encroached(d, k, cand) {
                        let piece = d.tr.constraints[k as usize].piece;
                        if !self.split_piece(d, piece, Some(t))? {
                            self.give_up(d, t);
                        }
                        return Ok(());
                    }
                    continue;
                }
                Located::OnVertex(_) => continue,
            };
            let m = d.metric.at(cand)?;
            let mut cav = std::mem::take(&mut self.cav);
            d.tr.cavity(cand, &m, &seeds, NONE, &mut cav);
            // Ruppert: a new site that would encroach a guard edge splits that edge's piece.
            let enc = cav
                .boundary
                .iter()
                .map(|&h| d.tr.cons[h as usize])
                .find(|&k| k != NONE && self.encroached(d, k, cand));
            if let Some(k) = enc {
                self.cav = cav;
                let piece = d.tr.constraints[k as usize].piece;
                if !self.split_piece(d, piece, Some(t))? {
                    self.give_up(d, t);
                }
                return Ok(());
            }
            self.budget_check(d)?;
            let v = d.add_vertex_with(cand, m, VertexKind::Steiner);
            let mut out = std::mem::take(&mut self.out);
            d.tr.fill(v, &cav, NONE, &mut out);
            self.stats.insertions += 1;
            if self.unresolved.len() < d.tr.triangle_slots() {
                self.unresolved.resize(d.tr.triangle_slots(), false);
            }
            let mut stack: Vec<(u32, u32)> = out
                .iter()
                .map(|&u| (3 * u, d.tr.generation[u as usize]))
                .collect();
            let mut flipped = Vec::new();
            d.tr.legalize(&mut stack, &mut flipped, LEGALIZE_LIMIT);
            if self.unresolved.len() < d.tr.triangle_slots() {
                self.unresolved.resize(d.tr.triangle_slots(), false);
            }
            for &u in out.iter().chain(&flipped) {
                self.unresolved[u as usize] = false;
                self.push_triangle(d, u);
            }
            self.out = out;
            let survived = d.tr.alive[t as usize] && !cav_contains(&cav, t);
            self.cav = cav;
            if survived && self.assess(d, t).is_some() {
                // The new site did not take t over (neighbouring metrics disagree): push it
                // again, its centroid comes next.
                self.push_triangle(d, t);
            }
            return Ok(());
        }
        self.give_up(d, t);
        Ok(())
    }
}

fn cav_contains(c: &Cavity, t: u32) -> bool {
    c.tris.contains(&t)
}

/// Sites a mesh of Ω_lin will need, roughly: its area in the metric (mean metric of each
/// first triangle) over that of a triangle with circumradius `size_bound`, halved (a
/// triangulation has about twice as many triangles as vertices).
fn estimate_sites(d: &Domain, size_bound: f64) -> u64 {
    let unit = 3.0 * 3f64.sqrt() / 4.0 * size_bound * size_bound;
    let mut area = 0.0;
    for t in 0..d.tr.triangle_slots() as u32 {
        if !d.tr.alive[t as usize] {
            continue;
        }
        let v = d.tr.tri(t);
        let p = v.map(|i| d.tr.pos[i as usize]);
        let m = v
            .iter()
            .fold(Metric2::new(0.0, 0.0, 0.0), |a, &i| {
                a.add(&d.tr.metric[i as usize])
            })
            .scale(1.0 / 3.0);
        area += 0.5 * (p[1] - p[0]).perp_dot(p[2] - p[0]).abs() * m.det().max(0.0).sqrt();
    }
    (area / unit / 2.0).ceil() as u64 + d.tr.vertex_count() as u64
}
