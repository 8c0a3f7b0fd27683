//! From the refined Ω_lin and the guarded pieces to high-order elements in parameter space
//! and on the surface (seed 000 §4 Step 4: "project the mesh onto the surface"; spec §5).
//!
//! Nodes are shared by topological key, never by comparing coordinates (spec §5.3): a vertex
//! by its id, a straight edge's nodes by its two vertices (placed from the lower id to the
//! higher), a curved edge's nodes by its piece, so an edge has the same nodes — bit for bit —
//! in both elements that use it, including the two regions on either side of a shared curve.
//! Curved-edge nodes are `c(t)` evaluated on the piece by de Casteljau (spec §5.3 [MEASURED]:
//! Lagrange nodes are interpolation points, not control points). Every node is mapped to
//! the surface as `P(u, v)`, so elements of order ≥ 2 follow the surface and stay conforming.

use std::collections::HashMap;

use glam::DVec2;
use rayon::prelude::*;

use super::domain::{Domain, VertexKind};
use super::element::{lagrange_layout, lagrange_to_bezier, BezierTriangle};
use super::input::{CurveId, PatchId, RegionId};
use super::output::{CurvedEdge, ElementInfo, ElementKind, ElementQuality};
use super::quality::{scaled_jacobian, Measure};
use super::tensor::Metric2;
use super::triangulation::NONE;

/// The output being built, across patches.
pub(crate) struct Assembly {
    pub order: u32,
    layout: Vec<[u32; 2]>,
    pub nodes_uv: Vec<DVec2>,
    pub node_patch: Vec<PatchId>,
    pub elements: Vec<u32>,
    pub info: Vec<ElementInfo>,
}

/// What one element needs measured, gathered before the parallel measuring pass.
enum Pending {
    Straight([DVec2; 3], [Metric2; 3]),
    Curved(BezierTriangle, [DVec2; 3], [Metric2; 3]),
}

impl Assembly {
    pub fn new(order: u32) -> Self {
        Assembly {
            order,
            layout: lagrange_layout(order),
            nodes_uv: Vec::new(),
            node_patch: Vec::new(),
            elements: Vec::new(),
            info: Vec::new(),
        }
    }

    fn node(&mut self, uv: DVec2, patch: PatchId) -> u32 {
        self.nodes_uv.push(uv);
        self.node_patch.push(patch);
        self.nodes_uv.len() as u32 - 1
    }

    /// Appends the elements of one refined patch. `exempt` flags vertices at small corners.
    pub fn add_patch(&mut self, d: &Domain, exempt: &[bool], measure: &Measure) {
        let q = self.order;
        let patch = PatchId(d.metric.patch_id);
        let tr = &d.tr;
        let mut vnode = vec![NONE; tr.vertex_count()];
        let mut edge_nodes: HashMap<(u32, u32), u32> = HashMap::new();
        let mut piece_nodes: HashMap<u32, u32> = HashMap::new();
        let mut pending: Vec<Pending> = Vec::new();
        let first_element = self.info.len();

        // Straight elements: the live triangles, in slot order.
        for t in 0..tr.triangle_slots() as u32 {
            if !tr.alive[t as usize] {
                continue;
            }
            let v = tr.tri(t);
            let p = v.map(|i| tr.pos[i as usize]);
            let mut nodes = Vec::with_capacity(self.layout.len());
            for &[a, b] in &self.layout.clone() {
                nodes.push(self.lattice_node(d, &mut vnode, &mut edge_nodes, v, [a, b], &p, patch));
            }
            self.elements.extend(nodes);
            self.info.push(ElementInfo {
                patch,
                region: RegionId(tr.region[t as usize]),
                kind: ElementKind::Straight,
                edge: None,
                exempt: v.iter().any(|&i| exempt.get(i as usize).copied().unwrap_or(false)),
                quality: empty_quality(),
            });
            pending.push(Pending::Straight(p, v.map(|i| tr.metric[i as usize])));
        }

        // Curved elements: every live piece, on each side that bounds a region.
        for (id, piece) in d.guarded.pieces.iter().enumerate() {
            let Some(piece) = piece else { continue };
            if piece.is_linear() {
                continue;
            }
            let id = id as u32;
            let [p0, pd, gl, gr] = d.piece_verts[id as usize];
            let regions = d.curve_regions[piece.curve as usize];
            for (side, (g, region)) in [(gl, regions[0]), (gr, regions[1])].into_iter().enumerate() {
                if region == NONE || g == NONE {
                    continue;
                }
                let reversed = side == 1;
                let v = if reversed { [pd, p0, g] } else { [p0, pd, g] };
                let ctrl: Vec<DVec2> = if reversed {
                    piece.ctrl.points().iter().rev().copied().collect()
                } else {
                    piece.ctrl.points().to_vec()
                };
                let tri = BezierTriangle::guarding(&ctrl, tr.pos[g as usize]);
                let p = v.map(|i| tr.pos[i as usize]);
                let mut nodes = Vec::with_capacity(self.layout.len());
                for &[a, b] in &self.layout.clone() {
                    let n = if b == 0 && a > 0 && a < q {
                        // The curved edge v₀ → v₁: the piece's own nodes.
                        let start = *piece_nodes.entry(id).or_insert_with(|| {
                            let s = self.nodes_uv.len() as u32;
                            for k in 1..q {
                                self.node(piece.ctrl.eval(k as f64 / q as f64), patch);
                            }
                            s
                        });
                        let k = if reversed { q - a } else { a };
                        start + k - 1
                    } else if b == 0 || a + b == q || a == 0 {
                        self.lattice_node(d, &mut vnode, &mut edge_nodes, v, [a, b], &p, patch)
                    } else {
                        let uv = tri.eval(a as f64 / q as f64, b as f64 / q as f64);
                        self.node(uv, patch)
                    };
                    nodes.push(n);
                }
                // The output element is the order-q interpolant of the Bézier triangle.
                let uv: Vec<DVec2> = nodes.iter().map(|&n| self.nodes_uv[n as usize]).collect();
                let out_tri = if q >= tri.degree {
                    tri.clone()
                } else {
                    lagrange_to_bezier(q, &uv)
                };
                self.elements.extend(nodes);
                self.info.push(ElementInfo {
                    patch,
                    region: RegionId(region),
                    kind: ElementKind::Curved,
                    edge: Some(CurvedEdge {
                        curve: CurveId(piece.curve),
                        t0: piece.t0(),
                        t1: piece.t1(),
                        reversed,
                    }),
                    exempt: false,
                    quality: empty_quality(),
                });
                pending.push(Pending::Curved(out_tri, p, v.map(|i| tr.metric[i as usize])));
            }
        }

        let measured: Vec<ElementQuality> = pending
            .par_iter()
            .map(|e| match e {
                Pending::Straight(p, m) => measure.straight(p, m),
                Pending::Curved(tri, p, m) => {
                    let mut qy = measure.curved(tri, p, m);
                    qy.scaled_jacobian = scaled_jacobian(tri);
                    qy
                }
            })
            .collect();
        for (info, qy) in self.info[first_element..].iter_mut().zip(measured) {
            info.quality = qy;
        }
    }

    /// The node at lattice point `(a, b)` of a straight-edged position: a corner, a node on
    /// an edge (shared by key), or an interior node of the flat triangle.
    #[allow(clippy::too_many_arguments)]
    fn lattice_node(
        &mut self,
        d: &Domain,
        vnode: &mut [u32],
        edge_nodes: &mut HashMap<(u32, u32), u32>,
        v: [u32; 3],
        [a, b]: [u32; 2],
        p: &[DVec2; 3],
        patch: PatchId,
    ) -> u32 {
        let q = self.order;
        // Which corner or edge the lattice point lies on.
        let corner = match (a, b) {
            (0, 0) => Some(0),
            (x, 0) if x == q => Some(1),
            (0, y) if y == q => Some(2),
            _ => None,
        };
        if let Some(k) = corner {
            let vid = v[k];
            if vnode[vid as usize] == NONE {
                vnode[vid as usize] = self.node(d.tr.pos[vid as usize], patch);
            }
            return vnode[vid as usize];
        }
        // Edge (from, to, position k along from → to).
        let edge = if b == 0 {
            Some((v[0], v[1], a))
        } else if a + b == q {
            Some((v[1], v[2], b))
        } else if a == 0 {
            Some((v[2], v[0], q - b))
        } else {
            None
        };
        if let Some((x, y, k)) = edge {
            let (lo, hi) = (x.min(y), x.max(y));
            let start = *edge_nodes.entry((lo, hi)).or_insert_with(|| {
                let s = self.nodes_uv.len() as u32;
                let (pl, ph) = (d.tr.pos[lo as usize], d.tr.pos[hi as usize]);
                for j in 1..q {
                    let t = j as f64 / q as f64;
                    self.nodes_uv.push(pl + t * (ph - pl));
                    self.node_patch.push(patch);
                }
                s
            });
            let j = if x == lo { k } else { q - k };
            return start + j - 1;
        }
        let (xi, eta) = (a as f64 / q as f64, b as f64 / q as f64);
        self.node((1.0 - xi - eta) * p[0] + xi * p[1] + eta * p[2], patch)
    }
}

fn empty_quality() -> ElementQuality {
    ElementQuality {
        min_angle_vertex: f64::NAN,
        angles: [f64::NAN; 3],
        min_angle_sampled: f64::NAN,
        max_angle_sampled: f64::NAN,
        min_angle_xyz: f64::NAN,
        max_angle_xyz: f64::NAN,
        xyz_angles: [f64::NAN; 3],
        scaled_jacobian: f64::NAN,
    }
}

/// Whether vertex kind `k` is output (every kind but the enclosing triangle's corners).
#[allow(dead_code)]
pub(crate) fn is_output(k: VertexKind) -> bool {
    k != VertexKind::Outer
}
