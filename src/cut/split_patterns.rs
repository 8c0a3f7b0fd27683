//! The split patterns (seed 002 §3.3-3.4, Figs. 7, 13; spec §4 step 7), as two local
//! operations on each face's small list of sub-triangles:
//! - a vertex on an edge splits each sub-triangle holding that edge in two, joining the new
//!   vertex to the opposite corner; the face across gets the same vertex (created once per
//!   edge), so no T-junction remains (spec's T-junction rule). With a path vertex at the
//!   opposite corner this is P1 (vertex + edge, 1 → 2); two edge vertices in one face give
//!   P2 (edge + edge, 1 → 3) with the new chord already an edge;
//! - a piece end strictly inside a face splits its sub-triangle in three (P3, Fig. 13(c)).
//!
//! P2's quadrilateral is then split along the diagonal that maximises the smallest angle
//! (gap-fill, spec §4 step 7) by flipping non-path diagonals. A chord that the insertions did
//! not make an edge (several pieces in one face) is recovered by flips inside the face.

use rustc_hash::FxHashMap;

use glam::{DVec2, DVec3};
use rayon::prelude::*;
use smallvec::SmallVec;

use super::first_normalization::{elem_depth, Elem, Occ};
use super::geom::{in_triangle, map3, max_cos_sides, orient};
use super::ids::{Le, Lf, Lv};
use super::path_and_opening::Path;
use super::region::Region;
use super::second_normalization::Normalized;

/// No item.
const NONE: u32 = u32::MAX;

/// A touched face's sub-triangles: at most four but where pieces meet in one face.
pub(crate) type Pieces = SmallVec<[[Lv; 3]; 4]>;

/// Items for a few of `n` keys, stored in order of first use: most of the region's faces
/// and edges are never touched.
struct Pool<T> {
    slot: Vec<u32>,
    items: Vec<T>,
}

impl<T> Pool<T> {
    fn new(n: usize) -> Self {
        Pool {
            slot: vec![NONE; n],
            // Room for a quarter of the keys, so the items are rarely reallocated.
            items: Vec::with_capacity(n / 4),
        }
    }

    fn get(&self, key: usize) -> Option<&T> {
        let k = self.slot[key];
        (k != NONE).then(|| &self.items[k as usize])
    }

    /// The item of `key`, made by `new` on first use (then `true`).
    fn get_or_insert(&mut self, key: usize, new: impl FnOnce() -> T) -> (&mut T, bool) {
        let first = self.slot[key] == NONE;
        if first {
            self.slot[key] = self.items.len() as u32;
            self.items.push(new());
        }
        (&mut self.items[self.slot[key] as usize], first)
    }
}

pub(crate) struct Splitter<'r> {
    pub r: &'r Region,
    /// New vertices (ids from the region's vertex count on).
    pub new_pos: Vec<DVec3>,
    pub new_screen: Vec<DVec2>,
    /// Sub-triangles of the touched faces (the pool's items are in `touched`'s order).
    pieces: Pool<Pieces>,
    /// Touched faces in order of first touch.
    pub touched: Vec<Lf>,
    /// Vertices on each split edge, by screen parameter from its first to its second end.
    on_edge: Pool<SmallVec<[(f64, Lv); 2]>>,
    /// The vertex of each E element already placed, by edge: (stroke index, on a stroke
    /// point, vertex); an edge has one or two.
    placed_e: Pool<SmallVec<[(u32, bool, Lv); 1]>>,
    /// The vertex of each P element already placed (a piece end inside a face: few).
    placed: FxHashMap<Elem, Lv>,
    /// Screen distance under which a constructed point is an existing vertex (1e-9·L).
    eps_px: f64,
}

impl<'r> Splitter<'r> {
    pub fn new(r: &'r Region, l_px: f64) -> Self {
        Splitter {
            r,
            // Sized for a usual cut (about one edge in eight split, half the faces touched).
            new_pos: Vec::with_capacity(r.edge_count() / 8),
            new_screen: Vec::with_capacity(r.edge_count() / 8),
            pieces: Pool::new(r.face_count()),
            touched: Vec::with_capacity(r.face_count() / 2),
            on_edge: Pool::new(r.edge_count()),
            placed_e: Pool::new(r.edge_count()),
            placed: FxHashMap::default(),
            eps_px: 1e-9 * l_px.max(1.0),
        }
    }

    fn n0(&self) -> u32 {
        self.r.vertex_count() as u32
    }

    /// Whether `v` is a vertex the cut added.
    pub fn is_new(&self, v: Lv) -> bool {
        v.0 >= self.n0()
    }

    pub fn screen(&self, v: Lv) -> DVec2 {
        if v.0 < self.n0() {
            self.r.screen(v)
        } else {
            self.new_screen[(v.0 - self.n0()) as usize]
        }
    }

    pub fn pos(&self, v: Lv) -> DVec3 {
        if v.0 < self.n0() {
            self.r.pos(v)
        } else {
            self.new_pos[(v.0 - self.n0()) as usize]
        }
    }

    fn add_vertex(&mut self, p: DVec3, s: DVec2) -> Lv {
        self.new_pos.push(p);
        self.new_screen.push(s);
        Lv(self.n0() + self.new_pos.len() as u32 - 1)
    }

    /// A new vertex at the same place as `v` (opening).
    pub fn copy_vertex(&mut self, v: Lv) -> Lv {
        let (p, s) = (self.pos(v), self.screen_or_zero(v));
        self.add_vertex(p, s)
    }

    fn screen_or_zero(&self, v: Lv) -> DVec2 {
        if v.0 < self.n0() {
            self.r.seen(v).map_or(DVec2::ZERO, |s| s.screen)
        } else {
            self.new_screen[(v.0 - self.n0()) as usize]
        }
    }

    /// Replaces corner `v` of sub-triangle `i` of face `lf` by `by`.
    pub fn replace_corner(&mut self, lf: Lf, i: usize, v: Lv, by: Lv) {
        let t = &mut self.subs_mut(lf)[i];
        for c in t.iter_mut() {
            if *c == v {
                *c = by;
            }
        }
    }

    fn subs_mut(&mut self, lf: Lf) -> &mut Pieces {
        let whole = self.r.corners(lf);
        let (subs, first) = self
            .pieces
            .get_or_insert(lf.idx(), || Pieces::from_slice(&[whole]));
        if first {
            self.touched.push(lf);
        }
        subs
    }

    /// The touched faces in ascending order with their sub-triangles.
    pub fn touched_in_order(&self) -> impl Iterator<Item = (Lf, &Pieces)> {
        let items = &self.pieces.items;
        self.pieces
            .slot
            .iter()
            .enumerate()
            .filter(|&(_, &k)| k != NONE)
            .map(move |(lf, &k)| (Lf(lf as u32), &items[k as usize]))
    }

    /// The sub-triangles of a touched face.
    pub fn pieces_of(&self, lf: Lf) -> Option<&Pieces> {
        self.pieces.get(lf.idx())
    }

    /// The current sub-triangles of a face (its triangle when untouched).
    pub fn face_subs(&self, lf: Lf) -> &[[Lv; 3]] {
        match self.pieces_of(lf) {
            Some(s) => s,
            None => std::slice::from_ref(&self.r.all_corners()[lf.idx()]),
        }
    }

    /// The path vertex of an element, creating and inserting it on first use. Crossings of
    /// one edge by different chains get their own vertices (a chain crosses an edge once
    /// after normalization); one crossing shared by chains gets one.
    pub fn vertex_for(&mut self, o: &Occ) -> Lv {
        if let Elem::V(v) = o.elem {
            return v;
        }
        let known = match o.elem {
            Elem::E { edge, at, on_point } => self
                .placed_e
                .get(edge.idx())
                .and_then(|l| l.iter().find(|x| (x.0, x.1) == (at, on_point)).map(|x| x.2)),
            _ => self.placed.get(&o.elem).copied(),
        };
        if let Some(m) = known {
            return m;
        }
        // Spec §4 step 5: the 3D point is the perspective-correct interpolation.
        let (_, x) = elem_depth(self.r, o);
        let near = |sp: &Self, v: Lv| (sp.screen(v) - o.screen).length() <= sp.eps_px;
        let m = match o.elem {
            Elem::E { edge, .. } => {
                // Spec §4 step 5: a crossing a rounding error from an end hits that vertex;
                // two crossings a rounding error apart are one.
                let [a, b] = self.r.ends(edge);
                let list = self.edge_vertices(edge);
                let existing = [a, b]
                    .into_iter()
                    .chain(list.iter().map(|x| x.1))
                    .find(|&v| near(self, v));
                match existing {
                    Some(m) => m,
                    None => {
                        let m = self.add_vertex(x, o.screen);
                        self.insert_on_edge(edge, m, o.edge_t);
                        m
                    }
                }
            }
            Elem::P { face, .. } => {
                let nearest = self.nearest_corner(face, o.screen);
                if near(self, nearest) {
                    nearest
                } else {
                    match self.locate(face, o.screen) {
                        Some(at) => {
                            let m = self.add_vertex(x, o.screen);
                            self.insert_in_face(face, m, at);
                            m
                        }
                        // Constructed split vertices can leave a point a rounding error away
                        // from every sub-triangle; it is then that close to a corner: use it.
                        None => nearest,
                    }
                }
            }
            Elem::V(_) => unreachable!("handled above"),
        };
        match o.elem {
            Elem::E { edge, at, on_point } => self
                .placed_e
                .get_or_insert(edge.idx(), SmallVec::new)
                .0
                .push((at, on_point, m)),
            _ => {
                self.placed.insert(o.elem, m);
            }
        }
        m
    }

    /// The vertices inserted on a local edge, from its first end to its second.
    pub fn edge_vertices(&self, e: Le) -> &[(f64, Lv)] {
        self.on_edge.get(e.idx()).map_or(&[], |l| l)
    }

    fn insert_on_edge(&mut self, e: Le, m: Lv, t: f64) {
        let [a, b] = self.r.ends(e);
        let (list, _) = self.on_edge.get_or_insert(e.idx(), SmallVec::new);
        let k = list.partition_point(|&(x, _)| x < t);
        let u = if k == 0 { a } else { list[k - 1].1 };
        let w = if k == list.len() { b } else { list[k].1 };
        list.insert(k, (t, m));
        for f in self.r.edge_faces(e) {
            if !f.is_some() {
                continue;
            }
            let subs = self.subs_mut(f);
            if let Some((i, rot)) = find_edge(subs, u, w).or_else(|| find_edge(subs, w, u)) {
                let t = rotated(subs[i], rot);
                subs[i] = [t[0], m, t[2]];
                subs.push([m, t[1], t[2]]);
            }
        }
    }

    /// Where `s` lies among face `lf`'s sub-triangles: strictly inside one, or on an inner
    /// sub-edge; `None` when no predicate places it (rounding of constructed vertices).
    fn locate(&self, lf: Lf, s: DVec2) -> Option<Location> {
        let sign = self.r.sign(lf);
        let subs = self.face_subs(lf);
        let mut on_edge = None;
        for (i, t) in subs.iter().enumerate() {
            let p = map3(*t, |v| self.screen(v));
            match in_triangle(p[0], p[1], p[2], sign, s) {
                Some(true) => return Some(Location::Inside(i)),
                Some(false) if on_edge.is_none() => {
                    for r in 0..3 {
                        let (u, w) = (t[r], t[(r + 1) % 3]);
                        // Only an inner edge (both sides in this face) may take the point.
                        let inner = subs
                            .iter()
                            .any(|x| find_edge(std::slice::from_ref(x), w, u).is_some());
                        if inner && orient(p[r], p[(r + 1) % 3], s) == 0.0 {
                            on_edge = Some(Location::OnEdge(u, w));
                        }
                    }
                }
                _ => {}
            }
        }
        on_edge
    }

    fn nearest_corner(&self, lf: Lf, s: DVec2) -> Lv {
        let mut best = (f64::INFINITY, Lv::NONE);
        for t in self.face_subs(lf) {
            for &v in t {
                let d = (self.screen(v) - s).length();
                if (d, v) < best {
                    best = (d, v);
                }
            }
        }
        best.1
    }

    fn insert_in_face(&mut self, lf: Lf, m: Lv, at: Location) {
        let subs = self.subs_mut(lf);
        match at {
            Location::Inside(i) => {
                let t = subs[i];
                subs[i] = [t[0], t[1], m];
                subs.push([t[1], t[2], m]);
                subs.push([t[2], t[0], m]);
            }
            Location::OnEdge(u, w) => {
                for (a, b) in [(u, w), (w, u)] {
                    if let Some((i, rot)) = find_edge(subs, a, b) {
                        let t = rotated(subs[i], rot);
                        subs[i] = [t[0], m, t[2]];
                        subs.push([m, t[1], t[2]]);
                    }
                }
            }
        }
    }

    /// Makes u-w an edge of face `lf`'s sub-triangles, flipping crossing diagonals if needed.
    pub fn ensure_chord(&mut self, lf: Lf, u: Lv, w: Lv, protected: &[(Lv, Lv)]) -> bool {
        let sign = self.r.sign(lf);
        for _ in 0..32 {
            if self
                .face_subs(lf)
                .iter()
                .any(|t| t.contains(&u) && t.contains(&w))
            {
                return true;
            }
            // A copy only to search for a flip (the chord is mostly there already).
            let subs = self.face_subs(lf).to_vec();
            let (su, sw) = (self.screen(u), self.screen(w));
            let mut flipped = false;
            'search: for (i, t) in subs.iter().enumerate() {
                for r in 0..3 {
                    let (x, y) = (t[r], t[(r + 1) % 3]);
                    if x == u
                        || x == w
                        || y == u
                        || y == w
                        || protected.contains(&(x.min(y), x.max(y)))
                    {
                        continue;
                    }
                    let (sx, sy) = (self.screen(x), self.screen(y));
                    let crosses = orient(su, sw, sx) * orient(su, sw, sy) < 0.0
                        && orient(sx, sy, su) * orient(sx, sy, sw) < 0.0;
                    if crosses && self.try_flip(lf, i, r, sign, false) {
                        flipped = true;
                        break 'search;
                    }
                }
            }
            if !flipped {
                return false;
            }
        }
        false
    }

    /// The shortest route (screen length) from u to w along the edges of face `lf`'s
    /// sub-triangles, inner vertices only; for a chord that crosses another piece's path in
    /// the same face (pieces are normalized apart, so their chords may cross).
    pub fn route(&self, lf: Lf, u: Lv, w: Lv) -> Option<Vec<Lv>> {
        let subs = self.face_subs(lf);
        let mut nodes: Vec<Lv> = subs.iter().flatten().copied().collect();
        nodes.sort_unstable();
        nodes.dedup();
        let idx = |v: Lv| nodes.binary_search(&v).ok();
        let (s, t) = (idx(u)?, idx(w)?);
        let n = nodes.len();
        let mut dist = vec![f64::INFINITY; n];
        let mut prev = vec![usize::MAX; n];
        let mut done = vec![false; n];
        dist[s] = 0.0;
        for _ in 0..n {
            let Some(a) = (0..n)
                .filter(|&i| !done[i])
                .min_by(|&i, &j| dist[i].total_cmp(&dist[j]))
            else {
                break;
            };
            if dist[a] == f64::INFINITY {
                break;
            }
            done[a] = true;
            for tri in subs {
                if let Some(r) = tri.iter().position(|&x| x == nodes[a]) {
                    for b in [tri[(r + 1) % 3], tri[(r + 2) % 3]] {
                        let bi = idx(b).expect("a node");
                        let d = dist[a] + (self.screen(nodes[a]) - self.screen(b)).length();
                        if d < dist[bi] {
                            dist[bi] = d;
                            prev[bi] = a;
                        }
                    }
                }
            }
        }
        if dist[t] == f64::INFINITY {
            return None;
        }
        let mut inner = Vec::new();
        let mut k = prev[t];
        while k != s {
            inner.push(nodes[k]);
            k = prev[k];
        }
        inner.reverse();
        Some(inner)
    }

    /// Flips the diagonal of sub-triangle `i`'s edge `r` if the quadrilateral is strictly
    /// convex (and, with `better`, only if the smallest angle grows).
    fn try_flip(&mut self, lf: Lf, i: usize, r: usize, sign: f64, better: bool) -> bool {
        let k = self.pieces.slot[lf.idx()];
        if k == NONE {
            // An untouched face has one sub-triangle: nothing to flip.
            return false;
        }
        let mut subs = std::mem::take(&mut self.pieces.items[k as usize]);
        let flipped = flip(&mut subs, i, r, sign, better, self);
        self.pieces.items[k as usize] = subs;
        flipped
    }

    /// Max-min-angle flips of the non-path diagonals inside each split face (P2's quad).
    /// Faces are independent (flips stay inside one face), so they run on rayon.
    pub fn improve(&mut self, is_path_edge: &(dyn Fn(Lv, Lv) -> bool + Sync)) {
        let mut pieces = std::mem::take(&mut self.pieces.items);
        let sp = &*self;
        pieces
            .par_iter_mut()
            .zip(&sp.touched)
            .with_min_len(64)
            .for_each(|(subs, &lf)| {
                let sign = sp.r.sign(lf);
                // Two pieces are a triangle cut from a corner to a point on the opposite side:
                // their diagonal is a path chord, or flipping it would make that side a
                // triangle with no area.
                if sign == 0.0 || !sp.r.cuttable(lf) || subs.len() <= 2 {
                    return;
                }
                for _ in 0..3 {
                    let (mut any, mut diagonals) = (false, 0);
                    for i in 0..subs.len() {
                        for r in 0..3 {
                            let t = subs[i];
                            let (x, y) = (t[r], t[(r + 1) % 3]);
                            // Sides of the face have no twin here: only inner diagonals
                            // are looked up among the path's edges.
                            if x > y || find_edge(subs, y, x).is_none() || is_path_edge(x, y) {
                                continue;
                            }
                            diagonals += 1;
                            if flip(subs, i, r, sign, true, sp) {
                                any = true;
                            }
                        }
                    }
                    // A lone flippable diagonal (P2's quad) just flipped would only flip
                    // back, which makes the smallest angle smaller: no second look.
                    if !any || diagonals == 1 {
                        break;
                    }
                }
            });
        self.pieces.items = pieces;
    }
}

/// Splits the faces along normalized array `nz` of piece `piece` (seed 002 Figs. 7, 13): each
/// element's vertex is placed, splitting the sub-triangles around it, and the path through
/// them is returned (`None` when it has a single vertex). Marks the occurrences placed in
/// `placed`.
pub(crate) fn split_along(
    sp: &mut Splitter,
    occ: &[Occ],
    nz: &Normalized,
    piece: u32,
    placed: &mut [bool],
) -> Option<Path> {
    let mut verts: Vec<Lv> = Vec::with_capacity(nz.occ.len());
    let mut faces = Vec::with_capacity(nz.faces.len());
    for (k, &o) in nz.occ.iter().enumerate() {
        placed[o as usize] = true;
        let v = sp.vertex_for(&occ[o as usize]);
        // A piece end merged into a neighbouring vertex adds no step.
        if verts.last() == Some(&v) {
            continue;
        }
        if k > 0 {
            faces.push(nz.faces[k - 1]);
        }
        verts.push(v);
    }
    (verts.len() >= 2).then_some(Path {
        piece,
        verts,
        faces,
    })
}

/// Flips the diagonal across edge `r` of sub-triangle `i` when the quad is strictly convex
/// and (with `better`) the smallest angle grows; `sp` gives positions (its `subs` unused).
fn flip(
    subs: &mut [[Lv; 3]],
    i: usize,
    r: usize,
    sign: f64,
    better: bool,
    sp: &Splitter<'_>,
) -> bool {
    let t1 = rotated(subs[i], r);
    let (x, y, p) = (t1[0], t1[1], t1[2]);
    let Some((j, rj)) = find_edge(subs, y, x) else {
        return false;
    };
    let q = rotated(subs[j], rj)[2];
    let s = [sp.screen(x), sp.screen(q), sp.screen(y), sp.screen(p)];
    let convex = (0..4).all(|k| orient(s[k], s[(k + 1) % 4], s[(k + 2) % 4]) * sign > 0.0);
    if !convex {
        return false;
    }
    if better {
        let (px, py, pp, pq) = (sp.pos(x), sp.pos(y), sp.pos(p), sp.pos(q));
        let (xy, xp, yp) = ((py - px).length(), (pp - px).length(), (pp - py).length());
        let (xq, yq, pq_) = ((pq - px).length(), (pq - py).length(), (pq - pp).length());
        let before =
            max_cos_sides(px, py, pp, [xy, yp, xp]).max(max_cos_sides(py, px, pq, [xy, xq, yq]));
        let after =
            max_cos_sides(pp, px, pq, [xp, xq, pq_]).max(max_cos_sides(pq, py, pp, [yq, yp, pq_]));
        // Arc cosine falls, so the smallest angle can only grow with a smaller cosine; the
        // angles (and the slack) only then.
        if after >= before || after.acos() <= before.acos() * (1.0 + 1e-9) {
            return false;
        }
    }
    subs[i] = [p, x, q];
    subs[j] = [q, y, p];
    true
}

#[derive(Debug, Clone, Copy)]
enum Location {
    Inside(usize),
    OnEdge(Lv, Lv),
}

fn rotated(t: [Lv; 3], r: usize) -> [Lv; 3] {
    [t[r], t[(r + 1) % 3], t[(r + 2) % 3]]
}

/// The sub-triangle with directed edge a → b, and the rotation putting a first.
fn find_edge(subs: &[[Lv; 3]], a: Lv, b: Lv) -> Option<(usize, usize)> {
    subs.iter().enumerate().find_map(|(i, t)| {
        (0..3)
            .find(|&r| t[r] == a && t[(r + 1) % 3] == b)
            .map(|r| (i, r))
    })
}
