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
use super::domain::{Domain, VertexKind};
use super::error::CurvedError;
use super::options::CurvedOptions;
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

const ENCROACHED: u8 = 0;
const BAD: u8 = 1;
const BIG: u8 = 2;

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
    heap: BinaryHeap<Task>,
    cav: Cavity,
    out: Vec<u32>,
    cos_min: f64,
    /// Per vertex: at a small input corner (triangles there are exempt).
    pub corner: Vec<bool>,
    /// Per triangle slot: left bad on purpose (see [`RefineStats::unresolved`]).
    pub unresolved: Vec<bool>,
    pub stats: RefineStats,
    max_sites: u64,
    max_steps: u64,
}

impl<'o> Refiner<'o> {
    pub fn new(d: &Domain, opts: &'o CurvedOptions, corner: Vec<bool>) -> Self {
        let boundary = d.tr.vertex_count() as u64;
        let max_sites = opts.max_sites.unwrap_or(10 * boundary + 1_000_000);
        Refiner {
            opts,
            heap: BinaryHeap::new(),
            cav: Cavity::default(),
            out: Vec::new(),
            cos_min: (1.0 / (2.0 * opts.radius_edge_bound)).asin().cos(),
            corner,
            unresolved: Vec::new(),
            stats: RefineStats::default(),
            max_sites,
            max_steps: opts.max_steps.unwrap_or(8 * max_sites),
        }
    }

    fn is_exempt(&self, d: &Domain, t: u32) -> bool {
        d.tr.tri(t).iter().any(|&v| self.corner.get(v as usize).copied().unwrap_or(false))
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
    pub fn run(&mut self, d: &mut Domain) -> Result<(), Error> {
        self.unresolved.resize(d.tr.triangle_slots(), false);
        for t in 0..d.tr.triangle_slots() as u32 {
            self.push_triangle(d, t);
        }
        while let Some(task) = self.heap.pop() {
            self.stats.steps += 1;
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
                    let apex = d.tr.pos[d.tr.apex(con.half) as usize];
                    if self.encroached(d, c, apex) {
                        if std::env::var_os("KATACHI_CURVED_TRACE").is_some() && self.stats.bisections < 30 {
                            eprintln!(
                                "encroached {c}: {:?} -> {:?} by apex {:?} (kind {:?}), piece {} depth {}",
                                d.tr.pos[con.a as usize],
                                d.tr.pos[con.b as usize],
                                apex,
                                d.kind[d.tr.apex(con.half) as usize],
                                con.piece,
                                d.guarded.piece(con.piece).depth
                            );
                        }
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
    fn split_piece(&mut self, d: &mut Domain, piece: u32, then: Option<u32>) -> Result<bool, Error> {
        self.budget_check(d)?;
        match bisect(d, piece)? {
            Bisected::AtDepthCap => Ok(false),
            Bisected::Split { touched, .. } => {
                self.stats.bisections += 1;
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

    /// Inserts the Voronoi vertex of bad or big triangle `t`, or splits the guard edge it
    /// lies beyond or encroaches.
    fn fix_triangle(&mut self, d: &mut Domain, t: u32) -> Result<(), Error> {
        if self.unresolved.get(t as usize).copied().unwrap_or(false) {
            return Ok(());
        }
        if self.assess(d, t).is_none() {
            return Ok(());
        }
        let c = d.tr.center[t as usize];
        let seeds = match d.tr.locate(c, t) {
            Located::Inside(u) => vec![u],
            Located::OnEdge(h) => {
                let g = d.tr.twin[h as usize];
                if d.tr.cons[h as usize] != NONE || g == NONE {
                    return self.split_or_give_up(d, d.tr.cons[h as usize], t);
                }
                vec![tri_of(h), tri_of(g)]
            }
            Located::Blocked(h) => {
                return self.split_or_give_up(d, d.tr.cons[h as usize], t);
            }
            Located::OnVertex(_) => {
                self.give_up(d, t);
                return Ok(());
            }
        };
        let m = match d.metric.at(c) {
            Ok(m) => m,
            Err(e) => return Err(e.into()),
        };
        let mut cav = std::mem::take(&mut self.cav);
        d.tr.cavity(c, &m, &seeds, NONE, &mut cav);
        // Ruppert: a new site that would encroach a guard edge splits that edge's piece.
        let enc = cav
            .boundary
            .iter()
            .map(|&h| d.tr.cons[h as usize])
            .find(|&k| k != NONE && self.encroached(d, k, c));
        if let Some(k) = enc {
            if std::env::var_os("KATACHI_CURVED_TRACE").is_some() && self.stats.bisections < 30 {
                let con = d.tr.constraints[k as usize];
                eprintln!(
                    "candidate {c:?} for {t} (r2 {}, tri {:?}) encroaches {:?} -> {:?}",
                    d.tr.radius2[t as usize],
                    d.tr.tri(t).map(|v| d.tr.pos[v as usize]),
                    d.tr.pos[con.a as usize],
                    d.tr.pos[con.b as usize]
                );
            }
            self.cav = cav;
            let piece = d.tr.constraints[k as usize].piece;
            if !self.split_piece(d, piece, Some(t))? {
                self.give_up(d, t);
            }
            return Ok(());
        }
        self.budget_check(d)?;
        let v = d.add_vertex_with(c, m, VertexKind::Steiner);
        let mut out = std::mem::take(&mut self.out);
        d.tr.fill(v, &cav, NONE, &mut out);
        self.stats.insertions += 1;
        if self.unresolved.len() < d.tr.triangle_slots() {
            self.unresolved.resize(d.tr.triangle_slots(), false);
        }
        for &u in &out {
            self.unresolved[u as usize] = false;
            self.push_triangle(d, u);
        }
        self.out = out;
        self.cav = cav;
        if d.tr.alive[t as usize] && !cav_contains(&self.cav, t) {
            // The new site did not take t over (possible only where neighbouring metrics
            // disagree); leave it for the report rather than loop.
            if self.assess(d, t).is_some() {
                self.give_up(d, t);
            }
        }
        Ok(())
    }

    fn split_or_give_up(&mut self, d: &mut Domain, c: u32, t: u32) -> Result<(), Error> {
        if std::env::var_os("KATACHI_CURVED_TRACE").is_some() && self.stats.bisections < 30 {
            eprintln!(
                "center {:?} of {t} {:?} is beyond constraint {c}",
                d.tr.center[t as usize],
                d.tr.tri(t).map(|v| d.tr.pos[v as usize])
            );
        }
        if c == NONE {
            self.give_up(d, t);
            return Ok(());
        }
        let piece = d.tr.constraints[c as usize].piece;
        if !self.split_piece(d, piece, Some(t))? {
            self.give_up(d, t);
        }
        Ok(())
    }
}

fn cav_contains(c: &Cavity, t: u32) -> bool {
    c.tris.contains(&t)
}
