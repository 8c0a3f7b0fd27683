//! Boykov–Kolmogorov max-flow / min-cut over integer capacities: the solver of seed 003 §3
//! ("maximum flow, minimum cut"; Boykov and Kolmogorov, "An experimental comparison of
//! min-cut/max-flow algorithms for energy minimization in vision", PAMI 2004).
//!
//! Written here: no maintained Rust crate implements Boykov–Kolmogorov (the crates that
//! exist offer Edmonds–Karp or Dinic, which are far slower on the short, wide graphs a band
//! gives). The algorithm keeps two search trees, one grown from the source and one from the
//! sink, over the residual graph: *growth* extends them until they touch (an augmenting
//! path), *augmentation* pushes the path's bottleneck and cuts the saturated arcs, which
//! leaves orphans, and *adoption* finds orphans new parents in their own tree or frees them.
//! The trees are kept between paths, which is what makes it fast.
//!
//! Capacities are `i64`: the result is exact and the labels are the same bits on every run
//! and machine. Nodes and arcs are visited in index order, so nothing depends on the thread
//! count. The labels are the nodes reachable from the source in the final residual graph,
//! the minimal source side of a minimum cut: the same for every maximum flow, so any correct
//! solver (Boost.Graph's `boykov_kolmogorov_max_flow` in `tests/reference`) gives the same.

use std::collections::VecDeque;

use crate::error::{Error, Result};

/// "Joined to its terminal directly" (a tree root).
const TERMINAL: u32 = u32::MAX - 1;
/// "Lost its parent arc; waiting for adoption".
const ORPHAN: u32 = u32::MAX - 2;
/// "In no tree" (free).
const FREE: u32 = u32::MAX;

/// A flow network under construction: nodes `0..n`, terminal capacities per node and
/// undirected edges with a capacity in each direction. Build it, then [`FlowNetwork::solve`].
///
/// ```
/// use katachi::rough::FlowNetwork;
/// // source → 0 → 1 → sink, the middle edge the bottleneck.
/// let mut g = FlowNetwork::new(2);
/// g.add_terminal(0, 5, 0).unwrap();
/// g.add_terminal(1, 0, 4).unwrap();
/// g.add_edge(0, 1, 3, 0).unwrap();
/// let cut = g.solve();
/// assert_eq!(cut.flow, 3);
/// assert_eq!(cut.source_side, vec![true, false]);
/// ```
#[derive(Debug, Clone, Default)]
pub struct FlowNetwork {
    /// Per node: source capacity minus sink capacity once the common part is pushed.
    terminal: Vec<i64>,
    /// Flow pushed straight from source to sink through a node with both links.
    direct_flow: i64,
    /// `(a, b, cap a→b, cap b→a)`.
    edges: Vec<(u32, u32, i64, i64)>,
    /// All source and all sink capacity added so far: the flow and every residual terminal
    /// capacity stay below these, so bounding them bounds every sum the solver makes.
    total_source: i64,
    total_sink: i64,
}

/// The result of [`FlowNetwork::solve`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MinCut {
    /// The maximum flow, equal to the capacity of the minimum cut.
    pub flow: i64,
    /// Per node: reachable from the source in the final residual graph (the minimal source
    /// side of a minimum cut).
    pub source_side: Vec<bool>,
}

impl FlowNetwork {
    /// A network of `node_count` nodes with no capacities yet.
    pub fn new(node_count: u32) -> Self {
        FlowNetwork {
            terminal: vec![0; node_count as usize],
            direct_flow: 0,
            edges: Vec::new(),
            total_source: 0,
            total_sink: 0,
        }
    }

    /// The number of nodes.
    pub fn node_count(&self) -> u32 {
        self.terminal.len() as u32
    }

    /// The number of edges added.
    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// Each node's capacity from the source and to the sink, once the part both share has
    /// been pushed (at most one of the two is non-zero).
    pub fn terminal_capacities(&self) -> impl ExactSizeIterator<Item = (i64, i64)> + '_ {
        self.terminal.iter().map(|&t| (t.max(0), (-t).max(0)))
    }

    /// The flow pushed straight through nodes linked to both terminals (part of
    /// [`MinCut::flow`]).
    pub fn direct_flow(&self) -> i64 {
        self.direct_flow
    }

    /// The edges: `(a, b, capacity a → b, capacity b → a)`.
    pub fn edges(&self) -> &[(u32, u32, i64, i64)] {
        &self.edges
    }

    fn check_node(&self, node: u32) -> Result<()> {
        if node >= self.node_count() {
            return Err(Error::InvalidArgument(format!(
                "flow network: node {node} is out of range (the network has {} nodes)",
                self.node_count()
            )));
        }
        Ok(())
    }

    fn check_capacity(what: &str, c: i64) -> Result<()> {
        if !(0..=MAX_CAPACITY).contains(&c) {
            return Err(Error::InvalidArgument(format!(
                "flow network: {what} capacity {c} is not in [0, {MAX_CAPACITY}]"
            )));
        }
        Ok(())
    }

    /// Adds capacity from the source to `node` and from `node` to the sink (both ≥ 0; a
    /// second call adds to the first). The part both links share is pushed at once, as
    /// Boykov and Kolmogorov do, so only the difference takes part in the search.
    pub fn add_terminal(&mut self, node: u32, source: i64, sink: i64) -> Result<()> {
        self.check_node(node)?;
        Self::check_capacity("source", source)?;
        Self::check_capacity("sink", sink)?;
        let total_source = self.total_source + source;
        let total_sink = self.total_sink + sink;
        if total_source > MAX_TOTAL_CAPACITY || total_sink > MAX_TOTAL_CAPACITY {
            return Err(Error::InvalidArgument(format!(
                "flow network: node {node}'s terminal capacities bring the total from the source or to the sink above {MAX_TOTAL_CAPACITY}"
            )));
        }
        self.total_source = total_source;
        self.total_sink = total_sink;
        let t = &mut self.terminal[node as usize];
        let (mut s, mut k) = (source, sink);
        if *t > 0 {
            s += *t;
        } else {
            k -= *t;
        }
        let common = s.min(k);
        self.direct_flow += common;
        *t = s - k;
        Ok(())
    }

    /// Adds an edge between `a` and `b` with capacity `ab` from a to b and `ba` back.
    pub fn add_edge(&mut self, a: u32, b: u32, ab: i64, ba: i64) -> Result<()> {
        self.check_node(a)?;
        self.check_node(b)?;
        if a == b {
            return Err(Error::InvalidArgument(format!(
                "flow network: an edge from node {a} to itself"
            )));
        }
        Self::check_capacity("edge", ab)?;
        Self::check_capacity("edge", ba)?;
        self.edges.push((a, b, ab, ba));
        Ok(())
    }

    /// Computes the maximum flow and the minimum cut's source side.
    pub fn solve(self) -> MinCut {
        let mut solver = Solver::new(self);
        solver.run();
        let source_side = solver.nodes[..solver.n]
            .iter()
            .map(|v| v.parent != FREE && !v.in_sink)
            .collect();
        MinCut {
            flow: solver.flow,
            source_side,
        }
    }
}

/// The largest capacity of one link or one direction of an edge: an arc's residual capacity
/// is at most the sum of its edge's two directions.
pub const MAX_CAPACITY: i64 = 1 << 52;

/// The largest total of all source (or all sink) capacities: the flow, and every node's
/// residual terminal capacity, are at most this, far from `i64` overflow.
pub const MAX_TOTAL_CAPACITY: i64 = 1 << 60;

/// One arc of the residual graph.
#[derive(Debug, Clone, Copy)]
struct Arc {
    head: u32,
    /// The reverse arc.
    sister: u32,
    /// Residual capacity.
    rcap: i64,
}

/// One node: its arcs, its place in a search tree and its residual terminal capacity, side
/// by side because the search reads them together.
#[derive(Debug, Clone, Copy)]
struct Node {
    /// Arcs `first..` up to the next node's `first`.
    first: u32,
    /// The arc from this node to its parent, or [`TERMINAL`], [`ORPHAN`], [`FREE`].
    parent: u32,
    /// The parent itself (the head of `parent`), so walks up a tree read nodes only.
    up: u32,
    /// When `dist` was last known right (the distance heuristic of the paper's §3.3).
    ts: u32,
    dist: u32,
    /// Residual terminal capacity: > 0 from the source, < 0 to the sink.
    tr: i64,
    in_sink: bool,
    is_active: bool,
}

/// The residual graph and the two search trees (seed 003 §3's solver).
struct Solver {
    n: usize,
    /// `n + 1` nodes: the last one only closes the arc ranges.
    nodes: Vec<Node>,
    arcs: Vec<Arc>,
    active: VecDeque<u32>,
    orphans: VecDeque<u32>,
    time: u32,
    flow: i64,
}

impl Solver {
    fn new(net: FlowNetwork) -> Self {
        let n = net.terminal.len();
        // Arcs by tail node (counting sort), each edge's two arcs cross-linked.
        let mut first = vec![0u32; n + 1];
        for &(a, b, _, _) in &net.edges {
            first[a as usize + 1] += 1;
            first[b as usize + 1] += 1;
        }
        for i in 0..n {
            first[i + 1] += first[i];
        }
        let m = first[n] as usize;
        let mut fill = first.clone();
        let mut arcs = vec![
            Arc {
                head: 0,
                sister: 0,
                rcap: 0
            };
            m
        ];
        for &(a, b, ab, ba) in &net.edges {
            let (ia, ib) = (fill[a as usize], fill[b as usize]);
            fill[a as usize] += 1;
            fill[b as usize] += 1;
            arcs[ia as usize] = Arc {
                head: b,
                sister: ib,
                rcap: ab,
            };
            arcs[ib as usize] = Arc {
                head: a,
                sister: ia,
                rcap: ba,
            };
        }
        let nodes = (0..=n)
            .map(|i| Node {
                first: first[i],
                parent: FREE,
                up: FREE,
                ts: 0,
                dist: 0,
                tr: net.terminal.get(i).copied().unwrap_or(0),
                in_sink: false,
                is_active: false,
            })
            .collect();
        let mut s = Solver {
            n,
            nodes,
            arcs,
            active: VecDeque::new(),
            orphans: VecDeque::new(),
            time: 0,
            flow: net.direct_flow,
        };
        for i in 0..n {
            let node = &mut s.nodes[i];
            if node.tr != 0 {
                node.parent = TERMINAL;
                node.in_sink = node.tr < 0;
                node.dist = 1;
                s.set_active(i as u32);
            }
        }
        s
    }

    #[inline]
    fn arc_range(&self, i: usize) -> std::ops::Range<usize> {
        self.nodes[i].first as usize..self.nodes[i + 1].first as usize
    }

    #[inline]
    fn set_active(&mut self, i: u32) {
        let node = &mut self.nodes[i as usize];
        if !node.is_active {
            node.is_active = true;
            self.active.push_back(i);
        }
    }

    /// The next active node still in a tree.
    fn next_active(&mut self) -> Option<u32> {
        while let Some(i) = self.active.pop_front() {
            let node = &mut self.nodes[i as usize];
            node.is_active = false;
            if node.parent != FREE {
                return Some(i);
            }
        }
        None
    }

    fn run(&mut self) {
        let mut current: Option<u32> = None;
        loop {
            let i = match current.take() {
                Some(i) if self.nodes[i as usize].parent != FREE => i,
                _ => match self.next_active() {
                    Some(i) => i,
                    None => break,
                },
            };
            // Growth (paper §3.2 "growth stage").
            let Some(bridge) = self.grow(i as usize) else {
                continue;
            };
            // The node may have more paths: look at it again first.
            current = Some(i);
            self.time += 1;
            self.augment(bridge as usize);
            self.adopt();
        }
    }

    /// The residual capacity of arc `a` in the direction a tree grows: away from the source in
    /// the source tree, toward the sink (so the reverse arc) in the sink tree.
    #[inline]
    fn tree_rcap(&self, a: usize, sink: bool) -> i64 {
        if sink {
            self.arcs[self.arcs[a].sister as usize].rcap
        } else {
            self.arcs[a].rcap
        }
    }

    /// Grows node `i`'s tree over its residual arcs; returns an arc from the source tree to
    /// the sink tree when the trees touch.
    #[inline(never)]
    fn grow(&mut self, i: usize) -> Option<u32> {
        let (sink, ts_i, dist_i) = {
            let n = &self.nodes[i];
            (n.in_sink, n.ts, n.dist)
        };
        for a in self.arc_range(i) {
            if self.tree_rcap(a, sink) == 0 {
                continue;
            }
            let Arc { head, sister, .. } = self.arcs[a];
            let j = &mut self.nodes[head as usize];
            if j.parent == FREE {
                j.in_sink = sink;
                j.parent = sister;
                j.up = i as u32;
                j.ts = ts_i;
                j.dist = dist_i + 1;
                self.set_active(head);
            } else if j.in_sink != sink {
                return Some(if sink { sister } else { a as u32 });
            } else if j.ts <= ts_i && j.dist > dist_i {
                // A shorter way to the terminal (the paper's heuristic).
                j.parent = sister;
                j.up = i as u32;
                j.ts = ts_i;
                j.dist = dist_i + 1;
            }
        }
        None
    }

    /// Pushes the bottleneck of the path through arc `b` (source tree → sink tree) and makes
    /// orphans of the nodes whose parent arcs it saturates (paper §3.2 "augmentation").
    #[inline(never)]
    fn augment(&mut self, b: usize) {
        let mut bottleneck = self.arcs[b].rcap;
        let source_end = self.arcs[self.arcs[b].sister as usize].head as usize;
        let sink_end = self.arcs[b].head as usize;
        // Source side: arcs parent → child carry the flow.
        let mut x = source_end;
        loop {
            let a = self.nodes[x].parent;
            if a == TERMINAL {
                bottleneck = bottleneck.min(self.nodes[x].tr);
                break;
            }
            let arc = self.arcs[a as usize];
            bottleneck = bottleneck.min(self.arcs[arc.sister as usize].rcap);
            x = arc.head as usize;
        }
        // Sink side: arcs child → parent carry it.
        let mut x = sink_end;
        loop {
            let a = self.nodes[x].parent;
            if a == TERMINAL {
                bottleneck = bottleneck.min(-self.nodes[x].tr);
                break;
            }
            let arc = self.arcs[a as usize];
            bottleneck = bottleneck.min(arc.rcap);
            x = arc.head as usize;
        }

        let sb = self.arcs[b].sister as usize;
        self.arcs[sb].rcap += bottleneck;
        self.arcs[b].rcap -= bottleneck;
        let mut x = source_end;
        loop {
            let a = self.nodes[x].parent;
            if a == TERMINAL {
                self.nodes[x].tr -= bottleneck;
                if self.nodes[x].tr == 0 {
                    self.make_orphan_front(x);
                }
                break;
            }
            let (au, su) = (a as usize, self.arcs[a as usize].sister as usize);
            self.arcs[au].rcap += bottleneck;
            self.arcs[su].rcap -= bottleneck;
            let next = self.arcs[au].head as usize;
            if self.arcs[su].rcap == 0 {
                self.make_orphan_front(x);
            }
            x = next;
        }
        let mut x = sink_end;
        loop {
            let a = self.nodes[x].parent;
            if a == TERMINAL {
                self.nodes[x].tr += bottleneck;
                if self.nodes[x].tr == 0 {
                    self.make_orphan_front(x);
                }
                break;
            }
            let (au, su) = (a as usize, self.arcs[a as usize].sister as usize);
            self.arcs[su].rcap += bottleneck;
            self.arcs[au].rcap -= bottleneck;
            let next = self.arcs[au].head as usize;
            if self.arcs[au].rcap == 0 {
                self.make_orphan_front(x);
            }
            x = next;
        }
        self.flow += bottleneck;
    }

    fn make_orphan_front(&mut self, x: usize) {
        self.nodes[x].parent = ORPHAN;
        self.orphans.push_front(x as u32);
    }

    /// Adoption (paper §3.2): each orphan looks for a parent in its own tree whose path
    /// still reaches the terminal; one without becomes free, and its children orphans.
    fn adopt(&mut self) {
        while let Some(x) = self.orphans.pop_front() {
            self.process_orphan(x as usize);
        }
    }

    #[inline(never)]
    fn process_orphan(&mut self, x: usize) {
        let sink = self.nodes[x].in_sink;
        let time = self.time;
        let mut best: Option<(u32, u32)> = None; // (arc, distance)
        for a in self.arc_range(x) {
            // A residual arc from the candidate toward x (source tree) or from x toward it:
            // the tree direction seen from the candidate's side.
            if self.tree_rcap(self.arcs[a].sister as usize, sink) == 0 {
                continue;
            }
            let j = self.arcs[a].head as usize;
            if self.nodes[j].parent == FREE || self.nodes[j].in_sink != sink {
                continue;
            }
            // Does j's path still reach the terminal, and how far is it?
            let mut d = 0u32;
            let mut k = j;
            let reaches = loop {
                let node = &mut self.nodes[k];
                if node.ts == time {
                    d += node.dist;
                    break true;
                }
                let p = node.parent;
                d += 1;
                if p == TERMINAL {
                    node.ts = time;
                    node.dist = 1;
                    break true;
                }
                if p == ORPHAN {
                    break false;
                }
                k = node.up as usize;
            };
            if !reaches {
                continue;
            }
            if best.is_none_or(|(_, bd)| d < bd) {
                best = Some((a as u32, d));
            }
            // Remember the distances found along the path.
            let mut k = j;
            while self.nodes[k].ts != time {
                let node = &mut self.nodes[k];
                node.ts = time;
                node.dist = d;
                d -= 1;
                k = node.up as usize;
            }
        }
        if let Some((a, d)) = best {
            let up = self.arcs[a as usize].head;
            let node = &mut self.nodes[x];
            node.parent = a;
            node.up = up;
            node.ts = time;
            node.dist = d + 1;
            return;
        }
        // No parent: x leaves its tree; neighbours that could reach it again become active,
        // and its children become orphans.
        self.nodes[x].parent = FREE;
        for a in self.arc_range(x) {
            let j = self.arcs[a].head as usize;
            let p = self.nodes[j].parent;
            if p == FREE || self.nodes[j].in_sink != sink {
                continue;
            }
            if self.tree_rcap(self.arcs[a].sister as usize, sink) > 0 {
                self.set_active(j as u32);
            }
            if p != TERMINAL && p != ORPHAN && self.nodes[j].up as usize == x {
                self.nodes[j].parent = ORPHAN;
                self.orphans.push_back(j as u32);
            }
        }
    }
}
