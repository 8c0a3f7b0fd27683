//! Metric tensors: symmetric positive-definite 2×2 (parameter space) and 3×3 (real space)
//! matrices, with the few operations the mesher needs (lengths, angles, eigen-clamping,
//! Cholesky frames, pull-back).
//!
//! A metric `M` measures a vector `w` as `|w|_M = sqrt(wᵀ M w)` and the angle between `a`
//! and `b` as `arccos(aᵀ M b / (|a|_M |b|_M))` (seed 000 §3.1). A size `h` in every direction
//! is the metric `I / h²`: a vector of Euclidean length `h` has metric length 1.

use glam::{DVec2, DVec3};

/// A symmetric 2×2 matrix `[[xx, xy], [xy, yy]]`, used as a metric on the patch's parameter
/// square (it must then be positive definite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metric2 {
    pub xx: f64,
    pub xy: f64,
    pub yy: f64,
}

/// The upper-triangular Cholesky factor `F = [[a, b], [0, c]]` of a [`Metric2`]
/// (`M = Fᵀ F`), so that `|w|_M = |F w|₂`: it maps the metric's unit ellipse to the unit
/// circle, which turns metric constructions (circumcentres) into Euclidean ones.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame2 {
    pub a: f64,
    pub b: f64,
    pub c: f64,
}

impl Frame2 {
    /// `F w`.
    #[inline]
    pub fn apply(&self, w: DVec2) -> DVec2 {
        DVec2::new(self.a * w.x + self.b * w.y, self.c * w.y)
    }

    /// `F⁻¹ w`.
    #[inline]
    pub fn solve(&self, w: DVec2) -> DVec2 {
        let y = w.y / self.c;
        DVec2::new((w.x - self.b * y) / self.a, y)
    }
}

impl Metric2 {
    /// The Euclidean metric.
    pub const IDENTITY: Metric2 = Metric2 {
        xx: 1.0,
        xy: 0.0,
        yy: 1.0,
    };

    pub const fn new(xx: f64, xy: f64, yy: f64) -> Metric2 {
        Metric2 { xx, xy, yy }
    }

    /// Size `h` in every direction: `I / h²`.
    pub fn isotropic(h: f64) -> Metric2 {
        let s = 1.0 / (h * h);
        Metric2::new(s, 0.0, s)
    }

    /// Size `h_along` along the unit direction `dir` and `h_across` across it.
    pub fn from_axes(dir: DVec2, h_along: f64, h_across: f64) -> Metric2 {
        let d = dir.normalize();
        Metric2::from_eigen(1.0 / (h_along * h_along), 1.0 / (h_across * h_across), d)
    }

    /// The matrix with eigenvalue `l1` along the unit vector `e1` and `l2` across it.
    pub fn from_eigen(l1: f64, l2: f64, e1: DVec2) -> Metric2 {
        let (x, y) = (e1.x, e1.y);
        Metric2::new(
            l1 * x * x + l2 * y * y,
            (l1 - l2) * x * y,
            l1 * y * y + l2 * x * x,
        )
    }

    #[inline]
    pub fn det(&self) -> f64 {
        self.xx * self.yy - self.xy * self.xy
    }

    /// Finite entries and both eigenvalues > 0.
    pub fn is_positive_definite(&self) -> bool {
        self.xx.is_finite()
            && self.xy.is_finite()
            && self.yy.is_finite()
            && self.xx > 0.0
            && self.det() > 0.0
    }

    /// `Mw`.
    #[inline]
    pub fn mul(&self, w: DVec2) -> DVec2 {
        DVec2::new(self.xx * w.x + self.xy * w.y, self.xy * w.x + self.yy * w.y)
    }

    /// `aᵀ M b`.
    #[inline]
    pub fn dot(&self, a: DVec2, b: DVec2) -> f64 {
        a.x * (self.xx * b.x + self.xy * b.y) + a.y * (self.xy * b.x + self.yy * b.y)
    }

    /// `wᵀ M w`, the squared metric length.
    #[inline]
    pub fn norm_sq(&self, w: DVec2) -> f64 {
        self.xx * w.x * w.x + 2.0 * self.xy * w.x * w.y + self.yy * w.y * w.y
    }

    /// `|w|_M`.
    #[inline]
    pub fn length(&self, w: DVec2) -> f64 {
        self.norm_sq(w).max(0.0).sqrt()
    }

    /// The angle between `a` and `b` in this metric, in radians (seed 000 §3.1).
    pub fn angle(&self, a: DVec2, b: DVec2) -> f64 {
        let d = self.norm_sq(a) * self.norm_sq(b);
        if d <= 0.0 {
            return 0.0;
        }
        (self.dot(a, b) / d.sqrt()).clamp(-1.0, 1.0).acos()
    }

    /// `s M`.
    #[inline]
    pub fn scale(&self, s: f64) -> Metric2 {
        Metric2::new(self.xx * s, self.xy * s, self.yy * s)
    }

    /// `self + other`.
    #[inline]
    pub fn add(&self, o: &Metric2) -> Metric2 {
        Metric2::new(self.xx + o.xx, self.xy + o.xy, self.yy + o.yy)
    }

    /// Eigenvalues `(l1, l2)` with `l1 ≤ l2`, and a unit eigenvector of `l1`.
    pub fn eigen(&self) -> (f64, f64, DVec2) {
        let half_tr = 0.5 * (self.xx + self.yy);
        let half_diff = 0.5 * (self.xx - self.yy);
        let r = (half_diff * half_diff + self.xy * self.xy).sqrt();
        let (l1, l2) = (half_tr - r, half_tr + r);
        // The eigenvector of the smaller eigenvalue, from whichever row is better conditioned.
        let e = if r == 0.0 {
            DVec2::X
        } else if half_diff <= 0.0 {
            // xx ≤ yy: the small eigenvalue is mostly along x.
            DVec2::new(self.yy - l1, -self.xy)
        } else {
            DVec2::new(-self.xy, self.xx - l1)
        };
        let n = e.length();
        (l1, l2, if n > 0.0 { e / n } else { DVec2::X })
    }

    /// The metric with its eigenvalues clamped to `[min_eig, max_eig]` and its anisotropy
    /// (ratio of the largest to the smallest edge length it asks for, `sqrt(l2 / l1)`) to at
    /// most `max_ratio`, by raising the smaller eigenvalue (spec §2, \[DESIGN\]).
    pub fn clamped(&self, min_eig: f64, max_eig: f64, max_ratio: f64) -> Metric2 {
        let (l1, l2, e1) = self.eigen();
        let l2c = l2.clamp(min_eig, max_eig);
        let l1c = l1
            .clamp(min_eig, max_eig)
            .max(l2c / (max_ratio * max_ratio));
        if l1c == l1 && l2c == l2 {
            return *self;
        }
        Metric2::from_eigen(l1c, l2c, e1)
    }

    /// The Cholesky factor, or `None` if the matrix is not positive definite.
    pub fn cholesky(&self) -> Option<Frame2> {
        if !self.is_positive_definite() {
            return None;
        }
        let a = self.xx.sqrt();
        let b = self.xy / a;
        let c2 = self.yy - b * b;
        if c2 <= 0.0 {
            return None;
        }
        Some(Frame2 { a, b, c: c2.sqrt() })
    }
}

/// A symmetric 3×3 matrix, used as a metric in real space (the seed's tensor field, §3.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metric3 {
    pub xx: f64,
    pub xy: f64,
    pub xz: f64,
    pub yy: f64,
    pub yz: f64,
    pub zz: f64,
}

impl Metric3 {
    /// The Euclidean metric.
    pub const IDENTITY: Metric3 = Metric3 {
        xx: 1.0,
        xy: 0.0,
        xz: 0.0,
        yy: 1.0,
        yz: 0.0,
        zz: 1.0,
    };

    /// From the upper triangle, row by row: `xx, xy, xz, yy, yz, zz`.
    pub const fn new(xx: f64, xy: f64, xz: f64, yy: f64, yz: f64, zz: f64) -> Metric3 {
        Metric3 {
            xx,
            xy,
            xz,
            yy,
            yz,
            zz,
        }
    }

    /// Size `h` in every direction: `I / h²`.
    pub fn isotropic(h: f64) -> Metric3 {
        let s = 1.0 / (h * h);
        Metric3::new(s, 0.0, 0.0, s, 0.0, s)
    }

    /// Size `h_along` along `dir` and `h_across` in every direction across it:
    /// `I / h_across² + (1/h_along² − 1/h_across²) d dᵀ` with `d = dir / |dir|`.
    pub fn from_direction(dir: DVec3, h_along: f64, h_across: f64) -> Metric3 {
        let d = dir.normalize();
        let a = 1.0 / (h_across * h_across);
        let k = 1.0 / (h_along * h_along) - a;
        Metric3::new(
            a + k * d.x * d.x,
            k * d.x * d.y,
            k * d.x * d.z,
            a + k * d.y * d.y,
            k * d.y * d.z,
            a + k * d.z * d.z,
        )
    }

    /// The six entries `xx, xy, xz, yy, yz, zz`.
    pub fn to_array(&self) -> [f64; 6] {
        [self.xx, self.xy, self.xz, self.yy, self.yz, self.zz]
    }

    /// `Mw`.
    #[inline]
    pub fn mul(&self, w: DVec3) -> DVec3 {
        DVec3::new(
            self.xx * w.x + self.xy * w.y + self.xz * w.z,
            self.xy * w.x + self.yy * w.y + self.yz * w.z,
            self.xz * w.x + self.yz * w.y + self.zz * w.z,
        )
    }

    /// `aᵀ M b`.
    #[inline]
    pub fn dot(&self, a: DVec3, b: DVec3) -> f64 {
        a.dot(self.mul(b))
    }

    /// `wᵀ M w`.
    #[inline]
    pub fn norm_sq(&self, w: DVec3) -> f64 {
        w.dot(self.mul(w))
    }

    /// The angle between `a` and `b` in this metric, in radians.
    pub fn angle(&self, a: DVec3, b: DVec3) -> f64 {
        let d = self.norm_sq(a) * self.norm_sq(b);
        if d <= 0.0 {
            return 0.0;
        }
        (self.dot(a, b) / d.sqrt()).clamp(-1.0, 1.0).acos()
    }

    /// Finite entries and positive definite (the leading minors are all > 0, Sylvester).
    pub fn is_positive_definite(&self) -> bool {
        let a = self.to_array();
        if a.iter().any(|x| !x.is_finite()) {
            return false;
        }
        let m2 = self.xx * self.yy - self.xy * self.xy;
        let m3 = self.xx * (self.yy * self.zz - self.yz * self.yz)
            - self.xy * (self.xy * self.zz - self.yz * self.xz)
            + self.xz * (self.xy * self.yz - self.yy * self.xz);
        self.xx > 0.0 && m2 > 0.0 && m3 > 0.0
    }

    /// `s M`.
    pub fn scale(&self, s: f64) -> Metric3 {
        let a = self.to_array().map(|x| x * s);
        Metric3::new(a[0], a[1], a[2], a[3], a[4], a[5])
    }

    /// `Σ wᵢ Mᵢ`: a convex combination of positive-definite matrices is positive definite,
    /// which is why grids interpolate their tensors entry by entry.
    pub fn weighted_sum(items: &[(f64, Metric3)]) -> Metric3 {
        let mut s = [0.0; 6];
        for (w, m) in items {
            for (acc, x) in s.iter_mut().zip(m.to_array()) {
                *acc += w * x;
            }
        }
        Metric3::new(s[0], s[1], s[2], s[3], s[4], s[5])
    }

    /// `Jᵀ M J` for `J = [pu | pv]`: the metric pulled back to parameter space (seed 000
    /// §3.3, Step 1; spec §2). With `M = I` this is the first fundamental form `[[E, F], [F, G]]`.
    pub fn pull_back(&self, pu: DVec3, pv: DVec3) -> Metric2 {
        let mu = self.mul(pu);
        let mv = self.mul(pv);
        Metric2::new(pu.dot(mu), pu.dot(mv), pv.dot(mv))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_and_back() {
        let m = Metric2::from_axes(DVec2::new(1.0, 2.0), 0.1, 0.01);
        let (l1, l2, e1) = m.eigen();
        assert!((l1 - 100.0).abs() < 1e-9 && (l2 - 1e4).abs() < 1e-7);
        assert!((e1.dot(DVec2::new(1.0, 2.0).normalize()).abs() - 1.0).abs() < 1e-12);
        let back = Metric2::from_eigen(l1, l2, e1);
        assert!((back.xx - m.xx).abs() < 1e-8 && (back.xy - m.xy).abs() < 1e-8);
    }

    #[test]
    fn clamp_limits_anisotropy() {
        let m = Metric2::new(1e6, 0.0, 1.0);
        let c = m.clamped(1e-3, 1e12, 10.0);
        let (l1, l2, _) = c.eigen();
        assert!((l2 / l1 - 100.0).abs() < 1e-9);
    }

    #[test]
    fn cholesky_maps_lengths() {
        let m = Metric2::new(4.0, 1.0, 3.0);
        let f = m.cholesky().unwrap();
        let w = DVec2::new(0.3, -0.7);
        assert!((f.apply(w).length_squared() - m.norm_sq(w)).abs() < 1e-14);
        assert!((f.solve(f.apply(w)) - w).length() < 1e-15);
    }

    #[test]
    fn pull_back_of_scaled_plane() {
        // P = (a u, b v, 0), M3 = I gives diag(a², b²) (spec §2 test).
        let (a, b) = (3.0, 0.5);
        let m = Metric3::IDENTITY.pull_back(DVec3::new(a, 0.0, 0.0), DVec3::new(0.0, b, 0.0));
        assert_eq!(m, Metric2::new(a * a, 0.0, b * b));
    }

    #[test]
    fn sylvester() {
        assert!(Metric3::IDENTITY.is_positive_definite());
        assert!(!Metric3::new(1.0, 2.0, 0.0, 1.0, 0.0, 1.0).is_positive_definite());
        let d = Metric3::from_direction(DVec3::new(1.0, 1.0, 0.0), 0.5, 0.1);
        assert!(d.is_positive_definite());
        let v = DVec3::new(1.0, 1.0, 0.0).normalize() * 0.5;
        assert!((d.norm_sq(v) - 1.0).abs() < 1e-12);
    }
}
