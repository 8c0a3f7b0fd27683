//! [`Primvar`]: what can be interpolated through a subdivision hierarchy — positions,
//! colours, weights, UVs, and sparse rows (which make the stencil matrix).

use glam::{DVec2, DVec3};

/// A value that subdivision combines linearly. One rule implementation serves every type,
/// so positions, vertex data and stencils can never disagree.
pub trait Primvar: Clone + Send + Sync {
    /// The additive identity.
    fn zero() -> Self;
    /// `self += w · other`.
    fn add_scaled(&mut self, other: &Self, w: f64);
    /// `w · self`.
    fn scaled(&self, w: f64) -> Self {
        let mut z = Self::zero();
        z.add_scaled(self, w);
        z
    }
    /// `n` zeros, for outputs handed to the caller.
    fn zeros(n: usize) -> Vec<Self> {
        crate::mem::filled(n, Self::zero())
    }
}

impl Primvar for f64 {
    fn zero() -> Self {
        0.0
    }
    #[inline]
    fn add_scaled(&mut self, other: &Self, w: f64) {
        *self += w * other;
    }
}

impl Primvar for DVec2 {
    fn zero() -> Self {
        DVec2::ZERO
    }
    #[inline]
    fn add_scaled(&mut self, other: &Self, w: f64) {
        *self += w * *other;
    }
}

impl Primvar for DVec3 {
    fn zero() -> Self {
        DVec3::ZERO
    }
    /// Zeroed memory: positions are the largest output, and no pass need write its zeros.
    fn zeros(n: usize) -> Vec<Self> {
        crate::mem::zero_points(n)
    }
    #[inline]
    fn add_scaled(&mut self, other: &Self, w: f64) {
        *self += w * *other;
    }
}

impl<const N: usize> Primvar for [f64; N] {
    #[inline]
    fn zero() -> Self {
        [0.0; N]
    }
    #[inline]
    fn add_scaled(&mut self, other: &Self, w: f64) {
        for i in 0..N {
            self[i] += w * other[i];
        }
    }
    #[inline]
    fn scaled(&self, w: f64) -> Self {
        std::array::from_fn(|i| w * self[i])
    }
}

/// A sparse row: (input vertex, weight) pairs, sorted by vertex, no duplicates.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SparseRow(pub Vec<(u32, f64)>);

impl Primvar for SparseRow {
    fn zero() -> Self {
        SparseRow(Vec::new())
    }
    fn add_scaled(&mut self, other: &Self, w: f64) {
        if w == 0.0 || other.0.is_empty() {
            return;
        }
        let mut out = Vec::with_capacity(self.0.len() + other.0.len());
        let (mut i, mut j) = (0, 0);
        let (a, b) = (&self.0, &other.0);
        while i < a.len() || j < b.len() {
            if j == b.len() || (i < a.len() && a[i].0 < b[j].0) {
                out.push(a[i]);
                i += 1;
            } else if i == a.len() || b[j].0 < a[i].0 {
                out.push((b[j].0, w * b[j].1));
                j += 1;
            } else {
                out.push((a[i].0, a[i].1 + w * b[j].1));
                i += 1;
                j += 1;
            }
        }
        self.0 = out;
    }
}
