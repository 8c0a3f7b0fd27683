//! Vertices of the anisotropic Voronoi diagram (Labelle & Shewchuk 2003, via seed 000 §3.3
//! and spec §4.1).
//!
//! Every site `s` measures distance in its own frozen metric, `d_s(x) = |x − s|_{M_s}`; a
//! Voronoi vertex of sites `s, t, u` is a point `c` with `d_s(c) = d_t(c) = d_u(c) = r`. The
//! bisectors `d_s² = d_t²` are conics, so `c` is found by Newton's method on
//! `f₁ = d_s² − d_t²`, `f₂ = d_s² − d_u²`, started at the circumcentre in the mean metric
//! (exact when the three metrics agree) [DESIGN, spec §4.1].

use glam::DVec2;

use super::tensor::Metric2;

/// A triangle's Voronoi vertex `c` and its squared radius `r² = d_s(c)²`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct VoronoiVertex {
    pub center: DVec2,
    pub radius2: f64,
    /// Newton converged to a point equidistant in the three metrics. When it did not (metrics
    /// too different for the triangle's size, or the conics nearly tangent), `center` is the
    /// mean-metric circumcentre and `radius2` the largest of the three squared distances.
    pub exact: bool,
}

/// The circumcentre of `p` in the metric with Cholesky factor `f`, computed relative to
/// `p[0]`: map by `F`, take the Euclidean circumcentre, map back. `None` for collinear points.
fn circumcentre_in(p: &[DVec2; 3], m: &Metric2) -> Option<DVec2> {
    let f = m.cholesky()?;
    let b = f.apply(p[1] - p[0]);
    let c = f.apply(p[2] - p[0]);
    let d = 2.0 * b.perp_dot(c);
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    let (bb, cc) = (b.length_squared(), c.length_squared());
    let o = DVec2::new(c.y * bb - b.y * cc, b.x * cc - c.x * bb) / d;
    Some(p[0] + f.solve(o))
}

/// The anisotropic Voronoi vertex of the sites `p` with metrics `m` (spec §4.1 steps 1–3).
/// `None` only when the three sites are collinear in the mean metric.
pub(crate) fn voronoi_vertex(p: &[DVec2; 3], m: &[Metric2; 3]) -> Option<VoronoiVertex> {
    let same = m[0] == m[1] && m[1] == m[2];
    let mean = if same {
        m[0]
    } else {
        m[0].add(&m[1]).add(&m[2]).scale(1.0 / 3.0)
    };
    let start = circumcentre_in(p, &mean)?;
    if same {
        return Some(VoronoiVertex {
            center: start,
            radius2: m[0].norm_sq(start - p[0]),
            exact: true,
        });
    }
    // Newton on f₁ = d₀² − d₁², f₂ = d₀² − d₂², in coordinates relative to p₀.
    let q1 = p[1] - p[0];
    let q2 = p[2] - p[0];
    let mut x = start - p[0];
    let scale2 = mean.norm_sq(x).max(1e-300);
    let mut converged = false;
    for _ in 0..8 {
        let g0 = m[0].mul(x);
        let g1 = m[1].mul(x - q1);
        let g2 = m[2].mul(x - q2);
        let d0 = x.dot(g0);
        let f1 = d0 - (x - q1).dot(g1);
        let f2 = d0 - (x - q2).dot(g2);
        // Rows: ∇f₁ = 2(M₀ x − M₁ (x − q₁)), ∇f₂ = 2(M₀ x − M₂ (x − q₂)).
        let r1 = 2.0 * (g0 - g1);
        let r2 = 2.0 * (g0 - g2);
        let det = r1.perp_dot(r2);
        if det == 0.0 || !det.is_finite() {
            break;
        }
        // Solve [r1; r2] δ = [f1; f2].
        let delta = DVec2::new(f1 * r2.y - f2 * r1.y, r1.x * f2 - r2.x * f1) / det;
        x -= delta;
        if !x.is_finite() {
            break;
        }
        if mean.norm_sq(delta) <= 1e-26 * scale2 {
            converged = true;
            break;
        }
    }
    let d = [m[0].norm_sq(x), m[1].norm_sq(x - q1), m[2].norm_sq(x - q2)];
    // A root far from the mean-metric start is the wrong branch of the conics.
    let plausible = converged && mean.norm_sq(x - (start - p[0])) <= 4.0 * scale2;
    if plausible {
        return Some(VoronoiVertex {
            center: p[0] + x,
            radius2: d[0],
            exact: true,
        });
    }
    let x = start - p[0];
    let r2 = m[0]
        .norm_sq(x)
        .max(m[1].norm_sq(x - q1))
        .max(m[2].norm_sq(x - q2));
    Some(VoronoiVertex {
        center: start,
        radius2: r2,
        exact: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euclidean_circumcentre() {
        let p = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(0.0, 2.0),
        ];
        let m = [Metric2::IDENTITY; 3];
        let v = voronoi_vertex(&p, &m).unwrap();
        assert!((v.center - DVec2::new(1.0, 1.0)).length() < 1e-15);
        assert!((v.radius2 - 2.0).abs() < 1e-14);
    }

    #[test]
    fn equidistant_in_three_metrics() {
        let p = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.1),
            DVec2::new(0.2, 0.9),
        ];
        let m = [
            Metric2::new(4.0, 0.5, 1.0),
            Metric2::new(4.4, 0.3, 1.1),
            Metric2::new(3.8, 0.6, 0.9),
        ];
        let v = voronoi_vertex(&p, &m).unwrap();
        assert!(v.exact);
        let d: Vec<f64> = (0..3).map(|i| m[i].norm_sq(v.center - p[i])).collect();
        assert!(
            (d[0] - d[1]).abs() < 1e-12 && (d[0] - d[2]).abs() < 1e-12,
            "{d:?}"
        );
    }
}
