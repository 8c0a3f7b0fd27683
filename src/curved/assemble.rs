//! From the refined Ω_lin and the guarded pieces to high-order elements in parameter space
//! and on the surface (seed 000 §4 Step 4: "project the mesh onto the surface"; spec §5).
//!
//! Nodes are shared by topological key, never by comparing coordinates (spec §5.3): a vertex
//! by its id, a straight edge's nodes by its two vertices (placed from the lower id to the
//! higher), a curved edge's nodes by its piece, so an edge has the same nodes — bit for bit —
//! in both elements that use it, including the two regions on either side of a shared curve.
//! Curved-edge nodes are `c(t)` evaluated on the piece by de Casteljau (spec §5.3 \[MEASURED\]:
//! Lagrange nodes are interpolation points, not control points). Every node is mapped to
//! the surface as `P(u, v)`, so elements of order ≥ 2 follow the surface and stay conforming.

use glam::DVec2;
use rayon::prelude::*;

use super::bisect::piece_constraints;
use super::corners::Corners;
use super::domain::Domain;
use super::element::{
    collocation_inverse, control_points, lagrange_layout, optimize_interior, ray_map,
    BezierTriangle,
};
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
    /// [`collocation_inverse`] of the order.
    inv: Vec<Vec<f64>>,
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
            inv: collocation_inverse(order),
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

    /// Appends the elements of one refined patch.
    pub fn add_patch(&mut self, d: &Domain, corners: &Corners, measure: &Measure) {
        let q = self.order;
        let patch = PatchId(d.metric.patch_id);
        let tr = &d.tr;
        let mut vnode = vec![NONE; tr.vertex_count()];
        // Per half-edge: the first of its edge's q − 1 nodes, placed from the lower vertex id.
        let mut edge_start = vec![NONE; 3 * tr.triangle_slots()];
        let mut pending: Vec<Pending> = Vec::new();
        let first_element = self.info.len();
        let layout = std::mem::take(&mut self.layout);

        // Straight elements: the live triangles, in slot order.
        for t in 0..tr.triangle_slots() as u32 {
            if !tr.alive[t as usize] {
                continue;
            }
            let v = tr.tri(t);
            let p = v.map(|i| tr.pos[i as usize]);
            let halves = [3 * t, 3 * t + 1, 3 * t + 2];
            for &[a, b] in &layout {
                let n =
                    self.lattice_node(d, &mut vnode, &mut edge_start, v, halves, [a, b], &p, patch);
                self.elements.push(n);
            }
            self.info.push(ElementInfo {
                patch,
                region: RegionId(tr.region[t as usize]),
                kind: ElementKind::Straight,
                edge: None,
                exempt: corners.exempts(d, t),
                quality: empty_quality(),
            });
            pending.push(Pending::Straight(p, v.map(|i| tr.metric[i as usize])));
        }

        // Curved elements: every live curved piece, on each side that bounds a region.
        for (id, piece) in d.guarded.pieces.iter().enumerate() {
            let Some(piece) = piece else { continue };
            if piece.is_linear() {
                continue;
            }
            let id = id as u32;
            let [p0, pd, gl, gr] = d.piece_verts[id as usize];
            let regions = d.curve_regions[piece.curve as usize];
            let cons = piece_constraints(d, id);
            let mut curve_start = NONE;
            for (side, (g, region)) in [(gl, regions[0]), (gr, regions[1])].into_iter().enumerate()
            {
                if region == NONE || g == NONE {
                    continue;
                }
                let reversed = side == 1;
                let v = if reversed { [pd, p0, g] } else { [p0, pd, g] };
                let (uv, _) = curved_nodes(d, id, side == 1, q, &self.inv);
                let p = v.map(|i| tr.pos[i as usize]);
                // Edge v₁ → v₂ lies on the chain's second guard edge, v₂ → v₀ on its first.
                let halves = [
                    NONE,
                    tr.constraints[cons[2 * side + 1] as usize].half,
                    tr.constraints[cons[2 * side] as usize].half,
                ];
                for (k, &[a, b]) in layout.iter().enumerate() {
                    let n = if b == 0 && a > 0 && a < q {
                        // The curved edge v₀ → v₁: the piece's own nodes, c(k/q) by de Casteljau.
                        if curve_start == NONE {
                            curve_start = self.nodes_uv.len() as u32;
                            for j in 1..q {
                                self.node(piece.ctrl.eval(j as f64 / q as f64), patch);
                            }
                        }
                        let j = if reversed { q - a } else { a };
                        curve_start + j - 1
                    } else if b == 0 || a + b == q || a == 0 {
                        self.lattice_node(
                            d,
                            &mut vnode,
                            &mut edge_start,
                            v,
                            halves,
                            [a, b],
                            &p,
                            patch,
                        )
                    } else {
                        self.node(uv[k], patch)
                    };
                    self.elements.push(n);
                }
                let out_tri = control_points(q, &uv, &self.inv);
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
                pending.push(Pending::Curved(
                    out_tri,
                    p,
                    v.map(|i| tr.metric[i as usize]),
                ));
            }
        }
        self.layout = layout;

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

    /// The node at lattice point `(a, b)` of an element with corners `v` whose edges
    /// `v₀v₁, v₁v₂, v₂v₀` lie on half-edges `halves`: a corner, a node on an edge (shared
    /// through the half-edge and its twin), or an interior node of the flat triangle.
    #[allow(clippy::too_many_arguments)]
    fn lattice_node(
        &mut self,
        d: &Domain,
        vnode: &mut [u32],
        edge_start: &mut [u32],
        v: [u32; 3],
        halves: [u32; 3],
        [a, b]: [u32; 2],
        p: &[DVec2; 3],
        patch: PatchId,
    ) -> u32 {
        let q = self.order;
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
        // Edge index, and position k along it from its first corner.
        let edge = if b == 0 {
            Some((0, a))
        } else if a + b == q {
            Some((1, b))
        } else if a == 0 {
            Some((2, q - b))
        } else {
            None
        };
        if let Some((e, k)) = edge {
            let (x, y) = (v[e], v[(e + 1) % 3]);
            let (lo, hi) = (x.min(y), x.max(y));
            let h = halves[e];
            let mut start = edge_start[h as usize];
            if start == NONE {
                let g = d.tr.twin[h as usize];
                if g != NONE && edge_start[g as usize] != NONE {
                    start = edge_start[g as usize];
                } else {
                    start = self.nodes_uv.len() as u32;
                    let (pl, ph) = (d.tr.pos[lo as usize], d.tr.pos[hi as usize]);
                    for j in 1..q {
                        let t = j as f64 / q as f64;
                        self.nodes_uv.push(pl + t * (ph - pl));
                        self.node_patch.push(patch);
                    }
                    if g != NONE {
                        edge_start[g as usize] = start;
                    }
                }
                edge_start[h as usize] = start;
            }
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
        scaled_jacobian_surface: f64::NAN,
    }
}

/// The uv nodes (in [`lagrange_layout`] order) of the curved element of piece `id` on one
/// side, and the smallest Bézier coefficient of its `det DF` (> 0: valid). Corner and edge
/// nodes are computed exactly as the shared nodes are (curve points by de Casteljau on the
/// piece, straight-edge points from the lower vertex id), so the values agree bit for bit;
/// interior nodes start on the ray map and are placed by [`optimize_interior`].
pub(crate) fn curved_nodes(
    d: &Domain,
    id: u32,
    right: bool,
    q: u32,
    inv: &[Vec<f64>],
) -> (Vec<DVec2>, f64) {
    let piece = d.guarded.piece(id);
    let [p0, pd, gl, gr] = d.piece_verts[id as usize];
    let g = if right { gr } else { gl };
    let v = if right { [pd, p0, g] } else { [p0, pd, g] };
    let pos = |i: u32| d.tr.pos[i as usize];
    let apex = pos(g);
    let oriented = if right {
        piece.ctrl.reversed()
    } else {
        piece.ctrl.clone()
    };
    let layout = lagrange_layout(q);
    let mut nodes: Vec<DVec2> = layout
        .iter()
        .map(|&[a, b]| {
            let (xi, eta) = (a as f64 / q as f64, b as f64 / q as f64);
            if a == 0 && b == 0 {
                pos(v[0])
            } else if b == 0 && a == q {
                pos(v[1])
            } else if a == 0 && b == q {
                pos(v[2])
            } else if b == 0 {
                let j = if right { q - a } else { a };
                piece.ctrl.eval(j as f64 / q as f64)
            } else if a + b == q || a == 0 {
                let (x, y, k) = if a == 0 {
                    (v[2], v[0], q - b)
                } else {
                    (v[1], v[2], b)
                };
                let (lo, hi) = (x.min(y), x.max(y));
                let j = if x == lo { k } else { q - k };
                let t = j as f64 / q as f64;
                pos(lo) + t * (pos(hi) - pos(lo))
            } else {
                ray_map(&oriented, apex, xi, eta)
            }
        })
        .collect();
    // Interior nodes: placed in parameter space, where det DF's coefficients are affine in
    // each one. On the surface the element is P ∘ F, valid where F is; Gmsh's own check of
    // surface elements (the signed Jacobian along the corners' normal) is measured apart, as
    // `scaled_jacobian_surface`.
    let coefficients = |uv: &[DVec2]| control_points(q, uv, inv).jacobian_coefficients();
    let m = if q >= 3 {
        optimize_interior(q, &mut nodes, &coefficients)
    } else {
        coefficients(&nodes)
            .into_iter()
            .fold(f64::INFINITY, f64::min)
    };
    (nodes, m)
}
