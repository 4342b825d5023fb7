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
        self.add_weighted(v, y, 1.0);
    }

    /// Adds the point `(v, y)` with weight `w` (`add` is weight 1).
    pub(crate) fn add_weighted(&mut self, v: &[f64], y: f64, w: f64) {
        debug_assert_eq!(v.len(), self.regressors);
        let m = self.cols();
        let mut row = [0.0; MAX_COLS];
        row[0] = 1.0;
        row[1..=self.regressors].copy_from_slice(v);
        row[m - 1] = y;
        if w != 1.0 {
            let sw = libm::sqrt(w);
            for r in &mut row[..m] {
                *r *= sw;
            }
        }

        if self.sqrt_gamma != 1.0 {
            for (i, r_row) in self.r.iter_mut().enumerate().take(m) {
                for r in &mut r_row[i..m] {
                    *r *= self.sqrt_gamma;
                }
            }
        }
        rotate_in(&mut self.r, &mut row, m);
        self.points += 1;
    }

    /// The forgetting-weighted number of points, `sum_k gamma^k`.
    pub(crate) fn weight(&self) -> f64 {
        let g = self.sqrt_gamma * self.sqrt_gamma;
        if g == 1.0 {
            self.points as f64
        } else {
            (1.0 - libm::pow(g, self.points as f64)) / (1.0 - g)
        }
    }

    /// The weighted residual sum of squares of the fit.
    pub(crate) fn residual_ss(&self) -> f64 {
        let n = self.regressors + 1;
        self.r[n][n] * self.r[n][n]
    }

    /// The solution with pseudo-observations `beta_j = 0` of weight
    /// `ridge[j]` (index 0 is the intercept), or `None` as [`Self::solve`].
    pub(crate) fn solve_with_ridge(&self, ridge: &[f64]) -> Option<[f64; MAX_COLS]> {
        let mut with = self.clone();
        let m = self.cols();
        for (j, &w) in ridge.iter().enumerate().take(self.regressors + 1) {
            if w > 0.0 {
                let mut row = [0.0; MAX_COLS];
                row[j] = w;
                rotate_in(&mut with.r, &mut row, m);
            }
        }
        with.solve()
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

/// Rotates `row` (over the first `m` columns) into the triangular factor `r`.
fn rotate_in(r: &mut Square, row: &mut [f64; MAX_COLS], m: usize) {
    for j in 0..m {
        let (a, b) = (r[j][j], row[j]);
        if b == 0.0 {
            continue;
        }
        let h = libm::sqrt(a * a + b * b);
        let inv_h = 1.0 / h;
        let (c, s) = (a * inv_h, b * inv_h);
        r[j][j] = h;
        row[j] = 0.0;
        for (rk, zk) in r[j][j + 1..m].iter_mut().zip(&mut row[j + 1..m]) {
            let (a, b) = (*rk, *zk);
            *rk = c * a + s * b;
            *zk = c * b - s * a;
        }
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
    fn a_ridge_of_zero_is_the_plain_fit_and_a_heavy_one_removes_its_column() {
        let mut f = IncrementalWls::new(2, 0.99);
        for k in 0..30 {
            let x = f64::from(k) * 0.3;
            f.add(
                &[x, x * x],
                1.0 + 2.0 * x + 0.5 * x * x + libm::sin(x * 7.0),
            );
        }
        let plain = f.solve().expect("determined");
        let zero = f.solve_with_ridge(&[0.0, 0.0, 0.0]).expect("determined");
        assert_eq!(plain[..3], zero[..3]);
        // A heavy pseudo-observation beta_2 = 0 gives the fit without x^2.
        let heavy = f.solve_with_ridge(&[0.0, 0.0, 1e9]).expect("determined");
        let mut line = IncrementalWls::new(1, 0.99);
        for k in 0..30 {
            let x = f64::from(k) * 0.3;
            line.add(&[x], 1.0 + 2.0 * x + 0.5 * x * x + libm::sin(x * 7.0));
        }
        let line = line.solve().expect("determined");
        assert!(heavy[2].abs() < 1e-6, "{}", heavy[2]);
        assert!((heavy[0] - line[0]).abs() < 1e-6 && (heavy[1] - line[1]).abs() < 1e-6);
        // The weighted count and residual describe the same data.
        assert!((f.weight() - (1.0 - 0.99f64.powi(30)) / 0.01).abs() < 1e-9);
        assert!(f.residual_ss() > 0.0);
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
