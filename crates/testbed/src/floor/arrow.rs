//! The floor's normal equations: a tridiagonal block in the path (each
//! location meets only its neighbours) bordered by dense columns for the
//! models, solved by block elimination: `q` tridiagonal solves and a `q x q`
//! Cholesky for `q` model coefficients, O(frames q^2) in all.

use nalgebra::{DMatrix, DVector};

/// The normal equations `F step = -gradient` of the floor's sum of squares
/// at a point, and the sum's parts there.
#[derive(Debug, Clone)]
pub(super) struct Normal {
    /// The path block's diagonal.
    pub diag: Vec<f64>,
    /// `off[i]` couples locations `i` and `i + 1`.
    pub off: Vec<f64>,
    /// Path rows by model columns.
    pub border: DMatrix<f64>,
    /// The model block.
    pub model: DMatrix<f64>,
    /// `J' W r`: the path's part, then the models'.
    pub gradient_path: Vec<f64>,
    pub gradient_model: DVector<f64>,
    /// `r' W r`.
    pub weighted_squares: f64,
    /// The sum of the residuals' log variances.
    pub log_variances: f64,
}

impl Normal {
    pub fn zeros(free: usize, q: usize) -> Self {
        Self {
            diag: vec![0.0; free],
            off: vec![0.0; free.saturating_sub(1)],
            border: DMatrix::zeros(free, q),
            model: DMatrix::zeros(q, q),
            gradient_path: vec![0.0; free],
            gradient_model: DVector::zeros(q),
            weighted_squares: 0.0,
            log_variances: 0.0,
        }
    }

    /// Adds a residual `r` of precision `w` whose derivatives are `entries`
    /// (free index, value; path indices below `free`, then the models');
    /// entries of model columns beyond this one's are left out.
    pub fn add(&mut self, w: f64, r: f64, entries: &[(usize, f64)]) {
        let free = self.diag.len();
        let end = free + self.model.nrows();
        self.weighted_squares += w * r * r;
        self.log_variances -= w.ln();
        let entries = entries.iter().filter(|e| e.0 < end);
        for &(a, va) in entries.clone() {
            if a < free {
                self.gradient_path[a] += w * va * r;
            } else {
                self.gradient_model[a - free] += w * va * r;
            }
            for &(b, vb) in entries.clone() {
                let v = w * va * vb;
                match (a < free, b < free) {
                    (true, true) if a == b => self.diag[a] += v,
                    (true, true) if b + 1 == a => self.off[b] += v,
                    (true, true) | (false, true) => {}
                    (true, false) => self.border[(a, b - free)] += v,
                    (false, false) => self.model[(a - free, b - free)] += v,
                }
            }
        }
    }

    /// The path block factored alone, the models held.
    pub fn path_factor(&self) -> Option<Tridiagonal> {
        Tridiagonal::factor(&self.diag, &self.off)
    }

    /// The whole system eliminated: `None` unless it is positive definite.
    pub fn eliminate(&self) -> Option<Eliminated> {
        let path = self.path_factor()?;
        let mut y = self.border.clone();
        for mut column in y.column_iter_mut() {
            let solved = path.solve(column.iter().copied().collect());
            column.iter_mut().zip(solved).for_each(|(c, s)| *c = s);
        }
        let schur = (&self.model - self.border.transpose() * &y).cholesky()?;
        Some(Eliminated { path, y, schur })
    }
}

/// A factored [`Normal`].
pub(super) struct Eliminated {
    path: Tridiagonal,
    /// The path block's inverse times the border.
    y: DMatrix<f64>,
    /// The models' Schur complement, the marginal information of the models.
    schur: nalgebra::Cholesky<f64, nalgebra::Dyn>,
}

impl Eliminated {
    /// The model block of the inverse: the models' covariance bound.
    pub fn model_covariance(&self) -> DMatrix<f64> {
        self.schur.inverse()
    }

    /// The Gauss-Newton step `-F^-1 gradient`: (path, models).
    pub fn step(&self, normal: &Normal) -> (Vec<f64>, DVector<f64>) {
        let minus = |v: &[f64]| v.iter().map(|g| -g).collect::<Vec<f64>>();
        let y0 = self.path.solve(minus(&normal.gradient_path));
        let rhs =
            -&normal.gradient_model - normal.border.transpose() * DVector::from_column_slice(&y0);
        let model = self.schur.solve(&rhs);
        let correction = &self.y * &model;
        let path = y0
            .iter()
            .zip(correction.iter())
            .map(|(a, b)| a - b)
            .collect();
        (path, model)
    }
}

/// `L D L'` of a symmetric positive definite tridiagonal matrix.
pub(super) struct Tridiagonal {
    d: Vec<f64>,
    l: Vec<f64>,
    /// `log det`, the sum of the pivots' logarithms.
    pub log_det: f64,
}

impl Tridiagonal {
    /// `None` unless every pivot is positive and finite.
    pub fn factor(diag: &[f64], off: &[f64]) -> Option<Self> {
        let mut d = Vec::with_capacity(diag.len());
        let mut l = Vec::with_capacity(off.len());
        for (i, &a) in diag.iter().enumerate() {
            let pivot = match i {
                0 => a,
                _ => a - l[i - 1] * off[i - 1],
            };
            if !(pivot > 0.0 && pivot.is_finite()) {
                return None;
            }
            d.push(pivot);
            if i < off.len() {
                l.push(off[i] / pivot);
            }
        }
        let log_det = d.iter().map(|p| p.ln()).sum();
        Some(Self { d, l, log_det })
    }

    pub fn solve(&self, mut b: Vec<f64>) -> Vec<f64> {
        for i in 1..b.len() {
            b[i] -= self.l[i - 1] * b[i - 1];
        }
        for (x, d) in b.iter_mut().zip(&self.d) {
            *x /= d;
        }
        for i in (0..b.len().saturating_sub(1)).rev() {
            b[i] -= self.l[i] * b[i + 1];
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tridiagonal_factor_solves_and_gives_the_log_determinant() {
        let (diag, off) = ([4.0, 5.0, 6.0], [1.0, 2.0]);
        let m = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.0, 1.0, 5.0, 2.0, 0.0, 2.0, 6.0]);
        let f = Tridiagonal::factor(&diag, &off).expect("positive definite");
        let x = f.solve(vec![1.0, 2.0, 3.0]);
        let back = &m * DVector::from_vec(x);
        assert!((back - DVector::from_vec(vec![1.0, 2.0, 3.0])).amax() < 1e-12);
        assert!((f.log_det - m.determinant().ln()).abs() < 1e-12);
        assert!(Tridiagonal::factor(&[1.0, 1.0], &[2.0]).is_none());
    }

    #[test]
    fn block_elimination_is_the_dense_solve_and_inverse() {
        // Three locations bordered by two model columns, from residuals.
        let mut normal = Normal::zeros(3, 2);
        type Row<'a> = (f64, f64, &'a [(usize, f64)]);
        let rows: [Row; 6] = [
            (2.0, 0.5, &[(0, 1.0), (3, 0.3)]),
            (1.0, -0.2, &[(1, 1.0), (0, -1.0), (3, 0.7)]),
            (3.0, 0.1, &[(2, 1.0), (1, -1.0), (4, 0.2)]),
            (1.5, 0.3, &[(0, 0.4), (4, 1.0)]),
            (0.5, -0.4, &[(2, 0.9), (3, 1.0), (4, 0.5)]),
            (1.0, 0.2, &[(1, 0.6), (4, 0.8)]),
        ];
        let mut dense = DMatrix::zeros(5, 5);
        let mut gradient = DVector::zeros(5);
        for (w, r, entries) in rows {
            normal.add(w, r, entries);
            for &(a, va) in entries {
                gradient[a] += w * va * r;
                for &(b, vb) in entries {
                    dense[(a, b)] += w * va * vb;
                }
            }
        }
        let eliminated = normal.eliminate().expect("positive definite");
        let (path, model) = eliminated.step(&normal);
        let want: DVector<f64> = -dense.clone().cholesky().expect("spd").solve(&gradient);
        let got: Vec<f64> = path.into_iter().chain(model.iter().copied()).collect();
        for (g, w) in got.iter().zip(want.iter()) {
            assert!((g - w).abs() < 1e-12, "{got:?} {want}");
        }
        let inverse = dense.try_inverse().expect("invertible");
        let block = inverse.view((3, 3), (2, 2)).into_owned();
        assert!((eliminated.model_covariance() - block).amax() < 1e-12);
    }
}
