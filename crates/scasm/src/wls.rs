//! Incremental exponentially weighted least squares with an intercept
//! (the paper's Eq. 2-7), kept in square-root information form.
//!
//! Instead of the sums of Eq. 6-7 (whose matrix has the *square* of the data's
//! condition number) this keeps the upper-triangular factor `R` of the weighted
//! data matrix `W^(1/2) [1 | V | y]`. Adding a point scales `R` by `sqrt(gamma)`
//! (older points weigh `gamma^(n-k)`) and rotates the new row in with Givens
//! rotations: O(m^2) work, constant memory, and the same solution as the batch
//! weighted least-squares problem. Solving is one back-substitution.
//!
//! Any invertible lower-triangular change of regressors `z' = T z` (shifting or
//! rescaling a polynomial's variable, say) maps the factor exactly to `R T^T`,
//! which is still upper triangular: [`IncrementalWls::reparametrise`].

use crate::MAX_REGRESSORS;

/// Columns of the factor: intercept, up to [`MAX_REGRESSORS`] regressors, target.
pub(crate) const MAX_COLS: usize = MAX_REGRESSORS + 2;

/// A column whose new information is below this fraction of its norm is taken as
/// a linear combination of the earlier ones: the system is under-determined.
const RANK_TOL: f64 = 1e-10;

/// `[[f64; MAX_COLS]; MAX_COLS]`, the triangular factor (row-major).
pub(crate) type Square = [[f64; MAX_COLS]; MAX_COLS];

/// Incremental weighted least-squares fit of `y ~ alpha + beta . v`.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct IncrementalWls {
    /// Upper-triangular factor over columns `[1, v_1..v_p, y]`.
    r: Square,
    /// Number of regressors `p` (the factor uses `p + 2` columns).
    regressors: usize,
    /// `sqrt(gamma)`, applied to the factor before each new row.
    sqrt_gamma: f64,
    /// Points added so far (unweighted), for the "enough data" test.
    points: u64,
}

impl IncrementalWls {
    /// An empty fit with `regressors` regressors (1..=MAX_REGRESSORS) and
    /// forgetting factor `gamma` in (0, 1]; both are checked by the caller.
    pub(crate) fn new(regressors: usize, gamma: f64) -> Self {
        debug_assert!((1..=MAX_REGRESSORS).contains(&regressors));
        debug_assert!(gamma > 0.0 && gamma <= 1.0);
        Self {
            r: [[0.0; MAX_COLS]; MAX_COLS],
            regressors,
            sqrt_gamma: libm::sqrt(gamma),
            points: 0,
        }
    }

    fn cols(&self) -> usize {
        self.regressors + 2
    }

    /// Points added so far.
    pub(crate) fn points(&self) -> u64 {
        self.points
    }

    /// Adds the point `(v, y)`; `v` has exactly `regressors` entries.
    pub(crate) fn add(&mut self, v: &[f64], y: f64) {
        debug_assert_eq!(v.len(), self.regressors);
        let m = self.cols();
        let mut row = [0.0; MAX_COLS];
        row[0] = 1.0;
        row[1..=self.regressors].copy_from_slice(v);
        row[m - 1] = y;

        if self.sqrt_gamma != 1.0 {
            for (i, r_row) in self.r.iter_mut().enumerate().take(m) {
                for r in &mut r_row[i..m] {
                    *r *= self.sqrt_gamma;
                }
            }
        }
        for j in 0..m {
            let (a, b) = (self.r[j][j], row[j]);
            if b == 0.0 {
                continue;
            }
            let h = libm::sqrt(a * a + b * b);
            let inv_h = 1.0 / h;
            let (c, s) = (a * inv_h, b * inv_h);
            self.r[j][j] = h;
            row[j] = 0.0;
            for (r, z) in self.r[j][j + 1..m].iter_mut().zip(&mut row[j + 1..m]) {
                let (rk, zk) = (*r, *z);
                *r = c * rk + s * zk;
                *z = c * zk - s * rk;
            }
        }
        self.points += 1;
    }

    /// Applies the change of regressors `z' = T z` to everything seen so far, where
    /// `z = [1, v_1..v_p]` and `t` is lower triangular with a non-zero diagonal
    /// (only its leading `(p+1) x (p+1)` block is read). The target is unchanged.
    pub(crate) fn reparametrise(&mut self, t: &Square) {
        let n = self.regressors + 1;
        let old = self.r;
        for i in 0..n {
            for k in i..n {
                // (R T^T)_ik = sum_j R_ij T_kj over i <= j <= k.
                self.r[i][k] = (i..=k).map(|j| old[i][j] * t[k][j]).sum();
            }
        }
    }

    /// The weighted least-squares solution `[alpha, beta_1..beta_p]` (first
    /// `p + 1` entries), or `None` while the data do not determine it.
    pub(crate) fn solve(&self) -> Option<[f64; MAX_COLS]> {
        let n = self.regressors + 1;
        if self.points < n as u64 {
            return None;
        }
        for j in 0..n {
            // |R_jj| > RANK_TOL * |column j|, compared in squares; written so that
            // a NaN also counts as "not determined".
            let col_norm_sq: f64 = (0..=j).map(|i| self.r[i][j] * self.r[i][j]).sum();
            let determined = self.r[j][j] * self.r[j][j] > RANK_TOL * RANK_TOL * col_norm_sq;
            if !determined {
                return None;
            }
        }
        let mut x = [0.0; MAX_COLS];
        for i in (0..n).rev() {
            let tail: f64 = (i + 1..n).map(|k| self.r[i][k] * x[k]).sum();
            x[i] = (self.r[i][n] - tail) / self.r[i][i];
        }
        x[..n].iter().all(|v| v.is_finite()).then_some(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_line_is_recovered() {
        let mut f = IncrementalWls::new(1, 1.0);
        for k in 0..10 {
            let x = f64::from(k);
            f.add(&[x], 3.0 - 2.0 * x);
        }
        let s = f.solve().expect("determined");
        assert!((s[0] - 3.0).abs() < 1e-12 && (s[1] + 2.0).abs() < 1e-12);
    }

    #[test]
    fn under_determined_says_so() {
        let mut f = IncrementalWls::new(2, 1.0);
        // Two points cannot determine three unknowns...
        f.add(&[1.0, 1.0], 1.0);
        f.add(&[2.0, 4.0], 2.0);
        assert!(f.solve().is_none());
        // ...nor can any number of points on two distinct inputs fit a quadratic.
        for _ in 0..20 {
            f.add(&[1.0, 1.0], 1.0);
            f.add(&[2.0, 4.0], 2.0);
        }
        assert!(f.solve().is_none());
        f.add(&[3.0, 9.0], 5.0);
        assert!(f.solve().is_some());
    }

    #[test]
    fn reparametrising_a_shift_keeps_the_fit() {
        // Fit y on v, then shift v by 5 (z' = [1, v - 5]) and keep going.
        let mut a = IncrementalWls::new(1, 0.9);
        let mut b = IncrementalWls::new(1, 0.9);
        let pts = [(1.0, 2.0), (2.0, 2.5), (4.0, 5.0), (5.0, 4.0)];
        for &(v, y) in &pts[..2] {
            a.add(&[v], y);
            b.add(&[v], y);
        }
        let mut t = [[0.0; MAX_COLS]; MAX_COLS];
        t[0][0] = 1.0;
        t[1][0] = -5.0;
        t[1][1] = 1.0;
        b.reparametrise(&t);
        for &(v, y) in &pts[2..] {
            a.add(&[v], y);
            b.add(&[v - 5.0], y);
        }
        let (sa, sb) = (a.solve().expect("a"), b.solve().expect("b"));
        for v in [0.0, 3.0, 7.0] {
            let (fa, fb) = (sa[0] + sa[1] * v, sb[0] + sb[1] * (v - 5.0));
            assert!((fa - fb).abs() < 1e-12, "{fa} vs {fb}");
        }
    }
}
