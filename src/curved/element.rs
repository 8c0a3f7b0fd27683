//! Curved elements (seed 000 §4 Step 4; spec §5.1, §5.3): the Bézier triangle of a guarding
//! triangle, Lagrange node layouts in Gmsh's (and VTK's) order, and the Jacobian validity
//! test through the Bézier coefficients of `det DF`.
//!
//! For a piece `c` of degree `d` with control points `b₀ … b_d` and guard `o`, the element
//! `(v₀, v₁, v₂) = (p₀, p_d, o)` is the degree-d Bézier triangle whose edge row is the curve
//! (`b_{d−j, j, 0} = b_j`) and whose other control points are those of the flat triangle
//! elevated to degree d (`b_{ijk} = (i v₀ + j v₁ + k v₂)/d`): its edge `v₀v₁` is the curve
//! exactly, its other edges are the straight guard edges, so it conforms with its neighbours.

use glam::DVec2;

use super::bezier::binomial;

/// Multi-indices `(i, j, k)`, `i + j + k = n`, in a fixed order: `i` descending, then `j`
/// descending — barycentric weights of `(v₀, v₁, v₂)`.
pub(crate) fn multi_indices(n: u32) -> Vec<[u32; 3]> {
    let mut out = Vec::with_capacity(((n + 1) * (n + 2) / 2) as usize);
    for i in (0..=n).rev() {
        for j in (0..=n - i).rev() {
            out.push([i, j, n - i - j]);
        }
    }
    out
}

fn index_of(n: u32, a: [u32; 3]) -> usize {
    // Position of (i, j, k) in `multi_indices(n)`: rows of i from n down.
    let i = a[0];
    let before: u32 = (i + 1..=n).map(|ii| n - ii + 1).sum();
    (before + (n - i - a[1])) as usize
}

/// `n! / (i! j! k!)`.
fn trinomial(n: u32, a: [u32; 3]) -> f64 {
    binomial(n as usize, a[0] as usize) * binomial((n - a[0]) as usize, a[1] as usize)
}

/// A Bézier triangle of degree `n` with control points in [`multi_indices`] order.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct BezierTriangle {
    pub degree: u32,
    pub points: Vec<DVec2>,
}

impl BezierTriangle {
    /// The guarding triangle of a curve piece (spec §5.1): curve control points `ctrl` from
    /// `v₀` to `v₁`, apex `v₂`.
    #[cfg(test)]
    pub fn guarding(ctrl: &[DVec2], apex: DVec2) -> BezierTriangle {
        let d = (ctrl.len() - 1) as u32;
        let (v0, v1) = (ctrl[0], ctrl[d as usize]);
        let points = multi_indices(d)
            .into_iter()
            .map(|[i, j, k]| {
                if k == 0 {
                    ctrl[j as usize]
                } else {
                    (i as f64 * v0 + j as f64 * v1 + k as f64 * apex) / d as f64
                }
            })
            .collect();
        BezierTriangle { degree: d, points }
    }

    /// The point at reference coordinates `(ξ, η)` (barycentrics `(1 − ξ − η, ξ, η)`).
    pub fn eval(&self, xi: f64, eta: f64) -> DVec2 {
        let l = [1.0 - xi - eta, xi, eta];
        let n = self.degree;
        multi_indices(n)
            .iter()
            .zip(&self.points)
            .map(|(a, p)| {
                trinomial(n, *a)
                    * l[0].powi(a[0] as i32)
                    * l[1].powi(a[1] as i32)
                    * l[2].powi(a[2] as i32)
                    * *p
            })
            .fold(DVec2::ZERO, |s, x| s + x)
    }

    /// The Bézier coefficients of `det DF` (a Bézier triangle of degree `2(n − 1)`, spec
    /// §5.1): all positive means the element is valid everywhere.
    pub fn jacobian_coefficients(&self) -> Vec<f64> {
        let n = self.degree;
        if n == 0 {
            return vec![0.0];
        }
        let m = n - 1;
        let at = |a: [u32; 3]| self.points[index_of(n, a)];
        // ∂F/∂ξ = n Σ B_β (C_{β+e₁} − C_{β+e₀}), ∂F/∂η = n Σ B_β (C_{β+e₂} − C_{β+e₀}).
        let betas = multi_indices(m);
        let d1: Vec<DVec2> = betas
            .iter()
            .map(|b| n as f64 * (at([b[0], b[1] + 1, b[2]]) - at([b[0] + 1, b[1], b[2]])))
            .collect();
        let d2: Vec<DVec2> = betas
            .iter()
            .map(|b| n as f64 * (at([b[0], b[1], b[2] + 1]) - at([b[0] + 1, b[1], b[2]])))
            .collect();
        let top = 2 * m;
        let mut coef = vec![0.0; multi_indices(top).len()];
        for (bi, b) in betas.iter().enumerate() {
            for (gi, g) in betas.iter().enumerate() {
                let delta = [b[0] + g[0], b[1] + g[1], b[2] + g[2]];
                let w = trinomial(m, *b) * trinomial(m, *g) / trinomial(top, delta);
                coef[index_of(top, delta)] += w * d1[bi].perp_dot(d2[gi]);
            }
        }
        coef
    }
}

/// The value at `(ξ, η)` of the scalar Bézier triangle of degree `n` with coefficients
/// `coef` (in [`multi_indices`] order).
pub(crate) fn eval_scalar(n: u32, coef: &[f64], xi: f64, eta: f64) -> f64 {
    let l = [1.0 - xi - eta, xi, eta];
    multi_indices(n)
        .iter()
        .zip(coef)
        .map(|(a, c)| {
            trinomial(n, *a)
                * l[0].powi(a[0] as i32)
                * l[1].powi(a[1] as i32)
                * l[2].powi(a[2] as i32)
                * c
        })
        .sum()
}

/// Lagrange nodes of a triangle of order `q` as lattice points `(a, b)` (reference
/// coordinates `(a/q, b/q)`), in Gmsh's order (spec §5.3): corners `(0,0), (q,0), (0,q)`;
/// each edge `0→1, 1→2, 2→0` from its first corner; then the interior as a triangle of
/// order `q − 3`, recursively. VTK's Lagrange triangle uses the same order.
pub fn lagrange_layout(q: u32) -> Vec<[u32; 2]> {
    let mut out = Vec::new();
    layout_into(q, 0, &mut out);
    out
}

fn layout_into(q: u32, off: u32, out: &mut Vec<[u32; 2]>) {
    if q == 0 {
        out.push([off, off]);
        return;
    }
    out.extend([[off, off], [off + q, off], [off, off + q]]);
    for k in 1..q {
        out.push([off + k, off]);
    }
    for k in 1..q {
        out.push([off + q - k, off + k]);
    }
    for k in 1..q {
        out.push([off, off + q - k]);
    }
    if q >= 3 {
        layout_into(q - 3, off + 1, out);
    }
}

/// Converts Lagrange nodes of order `q` (in [`lagrange_layout`] order) to the control
/// points of the same polynomial triangle, by solving the Bernstein collocation system.
#[allow(clippy::needless_range_loop)]
pub(crate) fn lagrange_to_bezier(q: u32, nodes: &[DVec2]) -> BezierTriangle {
    let layout = lagrange_layout(q);
    let idx = multi_indices(q);
    let n = idx.len();
    // A[r][c] = B_c(node r).
    let mut a = vec![vec![0.0; n]; n];
    for (r, &[x, y]) in layout.iter().enumerate() {
        let (xi, eta) = (x as f64 / q.max(1) as f64, y as f64 / q.max(1) as f64);
        let l = [1.0 - xi - eta, xi, eta];
        for (c, m) in idx.iter().enumerate() {
            a[r][c] = trinomial(q, *m)
                * l[0].powi(m[0] as i32)
                * l[1].powi(m[1] as i32)
                * l[2].powi(m[2] as i32);
        }
    }
    let mut rhs: Vec<DVec2> = nodes.to_vec();
    // Gauss–Jordan with partial pivoting (n ≤ 66).
    for col in 0..n {
        let piv = (col..n)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .expect("non-empty");
        a.swap(col, piv);
        rhs.swap(col, piv);
        let p = a[col][col];
        for c in col..n {
            a[col][c] /= p;
        }
        rhs[col] /= p;
        for r in 0..n {
            if r != col {
                let f = a[r][col];
                if f != 0.0 {
                    for c in col..n {
                        a[r][c] -= f * a[col][c];
                    }
                    let v = rhs[col];
                    rhs[r] -= f * v;
                }
            }
        }
    }
    BezierTriangle {
        degree: q,
        points: rhs,
    }
}

/// The guarding triangle as a ray map from the apex (Coons-like, \[DESIGN\]):
/// `F(ξ, η) = η o + (1 − η) c(ξ / (1 − η))`, the segment from each curve point to the apex.
/// It is a valid parametrization whenever the apex sees the whole curve (a guard does), and
/// on the straight edges it is linear, so its values make good starting interior nodes.
pub(crate) fn ray_map(c: &super::bezier::BezierCurve, apex: DVec2, xi: f64, eta: f64) -> DVec2 {
    if eta >= 1.0 {
        return apex;
    }
    eta * apex + (1.0 - eta) * c.eval((xi / (1.0 - eta)).clamp(0.0, 1.0))
}

/// The inverse of the Bernstein collocation matrix of order `q` (row `α`, column = node in
/// [`lagrange_layout`] order): Bézier control points are `C_α = Σ inv[α][n] · node_n`.
pub(crate) fn collocation_inverse(q: u32) -> Vec<Vec<f64>> {
    let n = multi_indices(q).len();
    let mut inv = vec![vec![0.0; n]; n];
    for k in 0..n {
        let mut e = vec![DVec2::ZERO; n];
        e[k] = DVec2::X;
        let col = lagrange_to_bezier(q, &e);
        for (a, p) in col.points.iter().enumerate() {
            inv[a][k] = p.x;
        }
    }
    inv
}

/// Places the interior nodes of a curved element of order `q ≥ 3` (the boundary nodes in
/// `nodes` are fixed: the curve's points and the straight edges' equispaced points) to make
/// the smallest of `coefficients(nodes)` as large as possible, one interior node at a time.
/// `coefficients` gives the Bézier coefficients of `det DF` ([`BezierTriangle::jacobian_coefficients`]
/// of [`control_points`]); with one free node each is affine in it (`a × a = 0`), so the best
/// position is a linear program, solved by its vertices. Returns the smallest coefficient
/// (> 0: the element is valid everywhere) [DESIGN: the spec's elevated interior control
/// points fold the thin curved triangles on a curve's convex side; BG's own construction
/// moves them too].
pub(crate) fn optimize_interior(
    q: u32,
    nodes: &mut [DVec2],
    coefficients: &dyn Fn(&[DVec2]) -> Vec<f64>,
) -> f64 {
    let layout = lagrange_layout(q);
    let interior: Vec<usize> = (0..layout.len())
        .filter(|&k| {
            let [a, b] = layout[k];
            a > 0 && b > 0 && a + b < q
        })
        .collect();
    let min_coef = |nodes: &[DVec2]| -> f64 {
        coefficients(nodes)
            .into_iter()
            .fold(f64::INFINITY, f64::min)
    };
    if interior.is_empty() {
        return min_coef(nodes);
    }
    let (mut lo, mut hi) = (nodes[0], nodes[0]);
    for p in nodes.iter() {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let mut best = min_coef(nodes);
    for _sweep in 0..3 {
        for &k in &interior {
            // coef(X) = K + G·X: sample at X = 0, e_x, e_y relative to the current node.
            let x0 = nodes[k];
            let f = |x: DVec2, nodes: &mut [DVec2]| -> Vec<f64> {
                nodes[k] = x;
                coefficients(nodes)
            };
            let scale = (hi - lo).length().max(1e-300);
            let c0 = f(x0, nodes);
            let cx = f(x0 + DVec2::X * scale, nodes);
            let cy = f(x0 + DVec2::Y * scale, nodes);
            nodes[k] = x0;
            let grads: Vec<DVec2> = (0..c0.len())
                .map(|i| DVec2::new(cx[i] - c0[i], cy[i] - c0[i]) / scale)
                .collect();
            // Max over X (in the element's box) of min_i c0_i + G_i·(X − x0): try the
            // vertices of the LP (three active constraints), keep the best feasible one.
            let eval = |x: DVec2| -> f64 {
                (0..c0.len())
                    .map(|i| c0[i] + grads[i].dot(x - x0))
                    .fold(f64::INFINITY, f64::min)
            };
            let mut cand_best = (eval(x0), x0);
            let n = c0.len();
            for a in 0..n {
                for b in a + 1..n {
                    // Equalize a and b, and a and c: solve (G_a − G_b)·d = c0_b − c0_a,
                    // (G_a − G_c)·d = c0_c − c0_a for d = X − x0.
                    for c in b + 1..n {
                        let r1 = grads[a] - grads[b];
                        let r2 = grads[a] - grads[c];
                        let det = r1.perp_dot(r2);
                        if det.abs() < 1e-300 {
                            continue;
                        }
                        let (f1, f2) = (c0[b] - c0[a], c0[c] - c0[a]);
                        let dx = DVec2::new(f1 * r2.y - f2 * r1.y, r1.x * f2 - r2.x * f1) / det;
                        let x = x0 + dx;
                        if x.x < lo.x || x.y < lo.y || x.x > hi.x || x.y > hi.y {
                            continue;
                        }
                        let v = eval(x);
                        if v > cand_best.0 {
                            cand_best = (v, x);
                        }
                    }
                }
            }
            nodes[k] = cand_best.1;
            let now = min_coef(nodes);
            if now > best {
                best = now;
            } else {
                nodes[k] = x0;
            }
        }
    }
    best
}

/// The Bézier triangle, in the plane of its corners, of a surface element with Lagrange
/// nodes `xyz`: the control points projected onto the orthonormal frame of the corners'
/// plane. Its [`BezierTriangle::jacobian_coefficients`] are those of `(∂X/∂ξ × ∂X/∂η)·n`
/// with `n` the straight element's normal — the signed Jacobian Gmsh checks surface elements
/// by. `None` for degenerate corners.
pub(crate) fn projected_control_points(
    q: u32,
    xyz: &[glam::DVec3],
    inv: &[Vec<f64>],
) -> Option<BezierTriangle> {
    let (a, b, c) = (xyz[0], xyz[1], xyz[2]);
    let n = (b - a).cross(c - a);
    if n.length_squared().is_nan() || n.length_squared() <= 0.0 {
        return None;
    }
    let n = n.normalize();
    let e1 = (b - a).normalize();
    let e2 = n.cross(e1);
    let nodes: Vec<DVec2> = xyz
        .iter()
        .map(|p| DVec2::new((*p - a).dot(e1), (*p - a).dot(e2)))
        .collect();
    Some(control_points(q, &nodes, inv))
}

/// The Bézier triangle of Lagrange nodes (with a precomputed [`collocation_inverse`]).
pub(crate) fn control_points(q: u32, nodes: &[DVec2], inv: &[Vec<f64>]) -> BezierTriangle {
    let points = inv
        .iter()
        .map(|row| {
            row.iter()
                .zip(nodes)
                .fold(DVec2::ZERO, |s, (w, p)| s + *w * *p)
        })
        .collect();
    BezierTriangle { degree: q, points }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_match_gmsh() {
        assert_eq!(lagrange_layout(1), vec![[0, 0], [1, 0], [0, 1]]);
        assert_eq!(
            lagrange_layout(2),
            vec![[0, 0], [2, 0], [0, 2], [1, 0], [1, 1], [0, 1]]
        );
        assert_eq!(
            lagrange_layout(3),
            vec![
                [0, 0],
                [3, 0],
                [0, 3],
                [1, 0],
                [2, 0],
                [2, 1],
                [1, 2],
                [0, 2],
                [0, 1],
                [1, 1]
            ]
        );
        for q in 1..=10 {
            assert_eq!(lagrange_layout(q).len() as u32, (q + 1) * (q + 2) / 2);
        }
    }

    #[test]
    fn guarding_triangle_edge_is_the_curve() {
        let ctrl = [
            DVec2::new(0.0, 0.0),
            DVec2::new(0.3, -0.25),
            DVec2::new(0.7, -0.25),
            DVec2::new(1.0, 0.0),
        ];
        let tri = BezierTriangle::guarding(&ctrl, DVec2::new(0.5, 0.8));
        let c = crate::curved::BezierCurve::new(ctrl.to_vec());
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            assert!((tri.eval(t, 0.0) - c.eval(t)).length() < 1e-15);
        }
        // The spec's measured case (§5.1): valid.
        assert!(tri.jacobian_coefficients().iter().all(|&x| x > 0.0));
        // The interior node placement keeps it valid.
        let inv = collocation_inverse(3);
        let mut nodes: Vec<DVec2> = lagrange_layout(3)
            .iter()
            .map(|&[a, b]| tri.eval(a as f64 / 3.0, b as f64 / 3.0))
            .collect();
        assert!(
            optimize_interior(3, &mut nodes, &|n: &[DVec2]| control_points(3, n, &inv)
                .jacobian_coefficients())
                > 0.0
        );
        // Interpolating it at order 3 and converting back gives the same control points.
        let nodes: Vec<DVec2> = lagrange_layout(3)
            .iter()
            .map(|&[a, b]| tri.eval(a as f64 / 3.0, b as f64 / 3.0))
            .collect();
        let back = lagrange_to_bezier(3, &nodes);
        for (p, q) in back.points.iter().zip(&tri.points) {
            assert!((*p - *q).length() < 1e-12);
        }
    }

    #[test]
    fn inverted_element_has_a_negative_coefficient() {
        // The guard on the wrong side of the curve.
        let ctrl = [
            DVec2::new(0.0, 0.0),
            DVec2::new(0.5, 0.5),
            DVec2::new(1.0, 0.0),
        ];
        let bad = BezierTriangle::guarding(&ctrl, DVec2::new(0.5, 0.1));
        assert!(bad.jacobian_coefficients().iter().any(|&x| x <= 0.0));
        let good = BezierTriangle::guarding(&ctrl, DVec2::new(0.5, 0.6));
        assert!(good.jacobian_coefficients().iter().all(|&x| x > 0.0));
    }
}

#[cfg(test)]
mod lens {
    use super::*;
    use crate::curved::bezier::BezierCurve;
    use crate::curved::guard::Guards;

    /// The thin curved triangles on a curve's convex side (the guard against its tangent
    /// lines) fold with elevated interior control points; placed interior nodes unfold them.
    #[test]
    fn convex_side_guarding_triangles_become_valid() {
        let k = 0.552_284_749_830_793_4;
        let arc = BezierCurve::new(vec![
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, -k),
            DVec2::new(k, -1.0),
            DVec2::new(0.0, -1.0),
        ]);
        let mut pieces = vec![arc.clone()];
        let mut p = arc;
        for _ in 0..6 {
            p = p.split_half().0;
            pieces.push(p.clone());
        }
        for piece in pieces {
            let g = Guards::of(&piece, 1.414, 1e-2, 179.0).unwrap().left;
            let exact = BezierTriangle::guarding(piece.points(), g);
            for q in 3..=4u32 {
                let inv = collocation_inverse(q);
                let mut nodes: Vec<DVec2> = lagrange_layout(q)
                    .iter()
                    .map(|&[a, b]| ray_map(&piece, g, a as f64 / q as f64, b as f64 / q as f64))
                    .collect();
                let _ = &exact;
                let m = optimize_interior(q, &mut nodes, &|n: &[DVec2]| {
                    control_points(q, n, &inv).jacobian_coefficients()
                });
                assert!(
                    m > 0.0,
                    "order {q}, piece of width {}: {m}",
                    (piece.end() - piece.start()).length()
                );
            }
        }
    }
}
