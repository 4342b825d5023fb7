//! The linear algebra the batch solve needs: a symmetric positive definite
//! tridiagonal factorisation, a small dense solve with pivoting, and a small
//! Cholesky factorisation.

use std::vec;
use std::vec::Vec;

/// A factored symmetric positive definite tridiagonal matrix (LDL^T).
pub(crate) struct Tridiagonal {
    /// D.
    pub(crate) d: Vec<f64>,
    /// L's subdiagonal.
    pub(crate) l: Vec<f64>,
}

impl Tridiagonal {
    pub(crate) fn factor(diag: &[f64], off: &[f64]) -> Option<Self> {
        let n = diag.len();
        let mut d = vec![0.0; n];
        let mut l = vec![0.0; n.saturating_sub(1)];
        for i in 0..n {
            d[i] = diag[i]
                - if i > 0 {
                    l[i - 1] * l[i - 1] * d[i - 1]
                } else {
                    0.0
                };
            if d[i].is_nan() || d[i] <= 0.0 {
                return None;
            }
            if i + 1 < n {
                l[i] = off[i] / d[i];
            }
        }
        Some(Self { d, l })
    }

    pub(crate) fn solve(&self, b: &mut [f64]) {
        let n = b.len();
        for i in 1..n {
            b[i] -= self.l[i - 1] * b[i - 1];
        }
        for i in 0..n {
            b[i] /= self.d[i];
        }
        for i in (0..n.saturating_sub(1)).rev() {
            b[i] -= self.l[i] * b[i + 1];
        }
    }
}

/// Solves the dense `q x q` system `a x = b` (row-major) by Gaussian
/// elimination with partial pivoting; `None` if it is singular.
pub(crate) fn solve_dense(a: &mut [f64], b: &mut [f64], q: usize) -> Option<Vec<f64>> {
    for c in 0..q {
        let pivot = (c..q).max_by(|&i, &j| a[i * q + c].abs().total_cmp(&a[j * q + c].abs()))?;
        if a[pivot * q + c].is_nan() || a[pivot * q + c].abs() <= 1e-300 {
            return None;
        }
        if pivot != c {
            for k in 0..q {
                a.swap(c * q + k, pivot * q + k);
            }
            b.swap(c, pivot);
        }
        for r in c + 1..q {
            let f = a[r * q + c] / a[c * q + c];
            if f == 0.0 {
                continue;
            }
            for k in c..q {
                a[r * q + k] -= f * a[c * q + k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = vec![0.0; q];
    for r in (0..q).rev() {
        let tail: f64 = (r + 1..q).map(|k| a[r * q + k] * x[k]).sum();
        x[r] = (b[r] - tail) / a[r * q + r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The lower Cholesky factor `L` of the symmetric positive definite `q x q`
/// matrix `a` (row-major; `L L' = a`); `None` if it is not positive definite.
pub(crate) fn cholesky(a: &[f64], q: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; q * q];
    for r in 0..q {
        for c in 0..=r {
            let dot: f64 = (0..c).map(|k| l[r * q + k] * l[c * q + k]).sum();
            let v = a[r * q + c] - dot;
            if r == c {
                if v.is_nan() || v <= 0.0 {
                    return None;
                }
                l[r * q + r] = v.sqrt();
            } else {
                l[r * q + c] = v / l[c * q + c];
            }
        }
    }
    Some(l)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tridiagonal_solve_matches_the_matrix() {
        let (diag, off) = (vec![4.0, 5.0, 6.0, 3.0], vec![1.0, -2.0, 0.5]);
        let t = Tridiagonal::factor(&diag, &off).expect("spd");
        let mut x = vec![1.0, 2.0, 3.0, 4.0];
        t.solve(&mut x);
        let mul = |i: usize| {
            diag[i] * x[i]
                + if i > 0 { off[i - 1] * x[i - 1] } else { 0.0 }
                + if i + 1 < 4 { off[i] * x[i + 1] } else { 0.0 }
        };
        for (i, want) in [1.0, 2.0, 3.0, 4.0].iter().enumerate() {
            assert!((mul(i) - want).abs() < 1e-12);
        }
    }

    #[test]
    fn cholesky_factors_back_to_the_matrix() {
        let a = [4.0, 2.0, 0.4, 2.0, 5.0, 1.0, 0.4, 1.0, 3.0];
        let l = cholesky(&a, 3).expect("positive definite");
        for r in 0..3 {
            for c in 0..3 {
                let v: f64 = (0..3).map(|k| l[r * 3 + k] * l[c * 3 + k]).sum();
                assert!((v - a[r * 3 + c]).abs() < 1e-12);
            }
        }
        assert!(cholesky(&[1.0, 2.0, 2.0, 1.0], 2).is_none());
    }

    #[test]
    fn dense_solve_pivots() {
        let mut a = vec![0.0, 2.0, 1.0, 1.0];
        let mut b = vec![4.0, 3.0];
        let x = solve_dense(&mut a, &mut b, 2).expect("regular");
        assert!((x[0] - 1.0).abs() < 1e-12 && (x[1] - 2.0).abs() < 1e-12);
    }
}
