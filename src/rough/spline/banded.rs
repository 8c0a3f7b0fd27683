//! A symmetric positive definite banded matrix and its Cholesky factorisation: the normal
//! equations of a tensor-product fit are banded (half-bandwidth p·n_v + q, spec §2), so the
//! factorisation costs O(n b²) and memory O(n b), with no sparse-matrix crate needed.

use glam::DVec3;

/// The lower band of an n × n symmetric matrix: entry (i, j), i − b ≤ j ≤ i, at
/// `i · (b + 1) + j + b − i`.
pub(crate) struct BandedSpd {
    n: usize,
    b: usize,
    a: Vec<f64>,
}

impl BandedSpd {
    pub fn new(n: usize, b: usize) -> Self {
        let b = b.min(n.saturating_sub(1));
        BandedSpd {
            n,
            b,
            a: vec![0.0; n * (b + 1)],
        }
    }

    #[inline]
    fn at(&self, i: usize, j: usize) -> usize {
        debug_assert!(j <= i && i - j <= self.b);
        i * (self.b + 1) + j + self.b - i
    }

    /// Adds `v` to entry (i, j), j ≤ i within the band.
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        let k = self.at(i, j);
        self.a[k] += v;
    }

    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.a[self.at(i, j)]
    }

    /// Replaces the matrix by its Cholesky factor L (A = L Lᵀ). Fails with the index of the
    /// first pivot that is not positive (the matrix is singular or not positive definite).
    pub fn factor(&mut self) -> Result<(), usize> {
        let (n, b) = (self.n, self.b);
        for i in 0..n {
            for j in i.saturating_sub(b)..=i {
                let lo = i.saturating_sub(b).max(j.saturating_sub(b));
                let mut s = self.get(i, j);
                for k in lo..j {
                    s -= self.get(i, k) * self.get(j, k);
                }
                if i == j {
                    // A pivot this small next to its diagonal entry: the unknown is not
                    // determined by the data.
                    let d = self.get(i, i);
                    if s.is_nan() || s <= 1e-13 * d.abs() {
                        return Err(i);
                    }
                    let k = self.at(i, i);
                    self.a[k] = s.sqrt();
                } else {
                    let k = self.at(i, j);
                    self.a[k] = s / self.get(j, j);
                }
            }
        }
        Ok(())
    }

    /// Solves L Lᵀ x = rhs with the factor, three right-hand sides at once.
    #[allow(clippy::needless_range_loop)] // index form: the substitutions as written
    pub fn solve(&self, mut x: Vec<DVec3>) -> Vec<DVec3> {
        let (n, b) = (self.n, self.b);
        for i in 0..n {
            let mut s = x[i];
            for k in i.saturating_sub(b)..i {
                s -= self.get(i, k) * x[k];
            }
            x[i] = s / self.get(i, i);
        }
        for i in (0..n).rev() {
            let mut s = x[i];
            for k in i + 1..(i + b + 1).min(n) {
                s -= self.get(k, i) * x[k];
            }
            x[i] = s / self.get(i, i);
        }
        x
    }
}
