//! Clamped knot vectors and B-spline basis functions with their derivatives (the Cox–de Boor
//! recurrence; the derivative scheme of Piegl and Tiller, "The NURBS Book", §2.3, eq. (2.10)).

use crate::error::{Error, Result};

/// A clamped knot vector on [0, 1]: `degree + 1` zeros, the interior knots ascending, and
/// `degree + 1` ones. It has `knots.len() - degree - 1` basis functions.
#[derive(Debug, Clone, PartialEq)]
pub struct Knots {
    degree: usize,
    knots: Vec<f64>,
}

/// The basis functions that are non-zero at one parameter, and their derivatives.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BasisAt {
    /// The first non-zero function's index; the others follow (`degree + 1` in all).
    pub first: usize,
    /// `values[d][r]`: the `d`-th derivative of function `first + r`, d = 0, 1, 2.
    pub values: [[f64; MAX_DEGREE + 1]; 3],
}

/// The highest degree supported (cubic is the paper's; quintic leaves room).
pub const MAX_DEGREE: usize = 5;

impl Knots {
    /// Clamped uniform knots of `degree` with `count` basis functions (`count > degree`).
    pub fn uniform(degree: usize, count: usize) -> Result<Knots> {
        if degree == 0 || degree > MAX_DEGREE {
            return Err(Error::InvalidArgument(format!(
                "B-spline degree {degree} is not in 1..={MAX_DEGREE}"
            )));
        }
        if count <= degree {
            return Err(Error::InvalidArgument(format!(
                "a B-spline of degree {degree} needs more than {degree} control points per direction, not {count}"
            )));
        }
        let spans = count - degree;
        let interior = (1..spans).map(|i| i as f64 / spans as f64);
        Knots::clamped(degree, interior.collect())
    }

    /// Clamped knots of `degree` with the given interior knots (strictly inside (0, 1),
    /// strictly ascending).
    pub fn clamped(degree: usize, interior: Vec<f64>) -> Result<Knots> {
        if degree == 0 || degree > MAX_DEGREE {
            return Err(Error::InvalidArgument(format!(
                "B-spline degree {degree} is not in 1..={MAX_DEGREE}"
            )));
        }
        let mut prev = 0.0;
        for (i, &k) in interior.iter().enumerate() {
            if !(k > prev && k < 1.0) {
                return Err(Error::InvalidArgument(format!(
                    "interior knot {i} is {k}: knots must ascend strictly inside (0, 1)"
                )));
            }
            prev = k;
        }
        let mut knots = vec![0.0; degree + 1];
        knots.extend(interior);
        knots.extend(std::iter::repeat_n(1.0, degree + 1));
        Ok(Knots { degree, knots })
    }

    /// The degree.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// All knots, the clamped ends included.
    pub fn as_slice(&self) -> &[f64] {
        &self.knots
    }

    /// The interior knots.
    pub fn interior(&self) -> &[f64] {
        &self.knots[self.degree + 1..self.knots.len() - self.degree - 1]
    }

    /// The number of basis functions (control points in this direction).
    pub fn count(&self) -> usize {
        self.knots.len() - self.degree - 1
    }

    /// The knot spans, as `(start, end)` parameter pairs.
    pub fn spans(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        let p = self.degree;
        (p..self.count()).map(move |i| (self.knots[i], self.knots[i + 1]))
    }

    /// The index `i` of the span `[t_i, t_{i+1})` holding `u` (the last span for `u = 1`);
    /// `u` is clamped to [0, 1].
    pub fn span(&self, u: f64) -> usize {
        let (p, n) = (self.degree, self.count());
        let u = u.clamp(0.0, 1.0);
        if u >= self.knots[n] {
            return n - 1;
        }
        // The last i in p..n with t_i <= u.
        let (mut lo, mut hi) = (p, n);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if self.knots[mid] <= u {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// The non-zero basis functions at `u` and their first and second derivatives.
    #[allow(clippy::needless_range_loop)] // index form: the recurrences as written
    pub(crate) fn basis(&self, u: f64) -> BasisAt {
        let p = self.degree;
        let t = &self.knots;
        let i = self.span(u);
        let u = u.clamp(0.0, 1.0);
        // ndu: the functions of each degree (upper triangle) and the knot differences (lower).
        let mut ndu = [[0.0f64; MAX_DEGREE + 1]; MAX_DEGREE + 1];
        let mut left = [0.0f64; MAX_DEGREE + 1];
        let mut right = [0.0f64; MAX_DEGREE + 1];
        ndu[0][0] = 1.0;
        for j in 1..=p {
            left[j] = u - t[i + 1 - j];
            right[j] = t[i + j] - u;
            let mut saved = 0.0;
            for r in 0..j {
                ndu[j][r] = right[r + 1] + left[j - r];
                let temp = ndu[r][j - 1] / ndu[j][r];
                ndu[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[j][j] = saved;
        }
        let mut values = [[0.0f64; MAX_DEGREE + 1]; 3];
        for r in 0..=p {
            values[0][r] = ndu[r][p];
        }
        // Derivatives: differences of the lower-degree functions (NURBS Book eq. (2.10)).
        let orders = 2.min(p);
        for r in 0..=p {
            let mut a = [[0.0f64; MAX_DEGREE + 1]; 2];
            let (mut s1, mut s2) = (0, 1);
            a[0][0] = 1.0;
            for k in 1..=orders {
                let mut d = 0.0;
                let rk = r as isize - k as isize;
                let pk = p - k;
                if rk >= 0 {
                    a[s2][0] = a[s1][0] / ndu[pk + 1][rk as usize];
                    d = a[s2][0] * ndu[rk as usize][pk];
                }
                let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
                let j2 = if r as isize - 1 <= pk as isize {
                    k - 1
                } else {
                    p - r
                };
                for j in j1..=j2 {
                    let idx = (rk + j as isize) as usize;
                    a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                    d += a[s2][j] * ndu[idx][pk];
                }
                if r <= pk {
                    a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                    d += a[s2][k] * ndu[r][pk];
                }
                values[k][r] = d;
                std::mem::swap(&mut s1, &mut s2);
            }
        }
        let mut factor = p as f64;
        for k in 1..=orders {
            for r in 0..=p {
                values[k][r] *= factor;
            }
            factor *= (p - k) as f64;
        }
        BasisAt {
            first: i - p,
            values,
        }
    }

    /// The knots with `u` inserted (strictly inside a span, not at a knot).
    pub fn with_knot(&self, u: f64) -> Result<Knots> {
        let mut interior = self.interior().to_vec();
        let at = interior.partition_point(|&k| k < u);
        interior.insert(at, u);
        Knots::clamped(self.degree, interior)
    }
}
