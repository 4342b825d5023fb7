//! PATCH (scasm-testbed): the mass matrix's factorisation kept from one step
//! to the next ([`MassLu`]: nalgebra's `LU::new` operation for operation on
//! raw storage, or the tree's `L^T D L` factors), and its solve
//! ([`lu_solve_mut`]). A new file of the patch; `multibody.rs` declares it.

use super::*;

/// PATCH (scasm-testbed): an LU factorisation with partial (row) pivoting of a
/// multibody's mass matrix that keeps its storage from one step to the next.
/// [`MassLu::factor`] is nalgebra's `LU::new`, operation for operation (the
/// same pivots, the same row swaps, the same eliminations in the same order,
/// so the same bits), on raw column-major storage instead of a view per column
/// and without the copy into a fresh matrix that `LU::new` takes by value.
///
/// With [`MultibodyDynamics::Tree`], the same type holds instead the
/// `L^T D L` factors of the mass matrix that follow the kinematic tree
/// (`tree_ldl.rs`), and [`MassLu::solve_mut`] solves with those.
#[cfg_attr(feature = "serde-serialize", derive(Serialize, Deserialize))]
#[derive(Clone, Debug)]
pub struct MassLu {
    /// `L` (below the diagonal, unit diagonal implied) and `U`, as nalgebra's `LU` stores them.
    pub(super) lu: DMatrix<Real>,
    /// The row transpositions, in the order nalgebra's permutation sequence applies them.
    pub(super) swaps: Vec<(usize, usize)>,
    /// The factors along the tree, when they are the ones in use.
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub(super) tree: Option<TreeLdl>,
}

impl MassLu {
    #[doc(hidden)] // Public for the benchmarks against nalgebra's `LU`.
    pub fn empty() -> Self {
        Self {
            lu: DMatrix::zeros(0, 0),
            swaps: Vec::new(),
            tree: None,
        }
    }

    /// The dimension of the factored matrix.
    pub fn dim(&self) -> usize {
        match &self.tree {
            Some(tree) => tree.dim(),
            None => self.lu.nrows(),
        }
    }

    /// Factors the top-left `dim x dim` block of the symmetric positive
    /// definite `m` as `L^T D L`, from the last coordinate to the first.
    /// Beyond [`tree_ldl::MAX_DIM`] coordinates, the dense LU of
    /// [`Self::factor`] (correct for any invertible matrix).
    #[doc(hidden)] // Public for the benchmarks against nalgebra's `LU`.
    pub fn factor_tree(&mut self, m: &DMatrix<Real>, dim: usize) {
        if dim > tree_ldl::MAX_DIM {
            self.factor(m, dim);
            return;
        }
        self.tree.get_or_insert_with(TreeLdl::default).factor(m, dim);
    }

    /// Factors the top-left `dim x dim` block of `m`.
    #[doc(hidden)] // Public for the benchmarks against nalgebra's `LU`.
    pub fn factor(&mut self, m: &DMatrix<Real>, dim: usize) {
        self.tree = None;
        if self.lu.nrows() != dim {
            self.lu = DMatrix::zeros(dim, dim);
        }
        let rows = m.nrows();
        let (src, n) = (m.as_slice(), dim);
        let a = self.lu.as_mut_slice();
        for j in 0..n {
            a[j * n..(j + 1) * n].copy_from_slice(&src[j * rows..j * rows + n]);
        }
        self.swaps.clear();
        for i in 0..n {
            // `icamax` on the column below the diagonal: the first largest |a|.
            let column = &a[i * n..(i + 1) * n];
            let (mut piv, mut max) = (i, column[i].abs());
            for (r, v) in column.iter().enumerate().skip(i + 1) {
                if v.abs() > max {
                    (piv, max) = (r, v.abs());
                }
            }
            let diag = column[piv];
            if diag == 0.0 {
                continue; // No non-zero entries on this column.
            }
            if piv != i {
                self.swaps.push((i, piv));
                for c in 0..=i {
                    a.swap(c * n + i, c * n + piv);
                }
            }
            let inv_diag = 1.0 / diag;
            for x in &mut a[i * n + i + 1..(i + 1) * n] {
                *x *= inv_diag;
            }
            for k in i + 1..n {
                if piv != i {
                    a.swap(k * n + i, k * n + piv);
                }
                let (left, right) = a.split_at_mut(k * n);
                let coeffs = &left[i * n + i + 1..(i + 1) * n];
                let pivot = -right[i];
                for (y, x) in right[i + 1..n].iter_mut().zip(coeffs) {
                    *y = pivot * *x + *y;
                }
            }
        }
    }

    /// Solves `A x = b` in place, as nalgebra's `LU::solve_mut`; `false` if `A` is singular.
    pub fn solve_mut<C: na::Dim, S: StorageMut<Real, Dyn, C>>(
        &self,
        b: &mut na::Matrix<Real, Dyn, C, S>,
    ) -> bool {
        lu_solve_mut(self, b)
    }
}

/// PATCH (scasm-testbed): `lu.solve_mut(b)`: the same operations in the same
/// order as nalgebra's `LU::solve_mut` (row swaps, then the unit lower and the
/// upper triangular solves column by column). For one right-hand side it works
/// on the factors' raw column-major storage and a copy of `b` on the stack,
/// without building a view per column, and skips a column whose coefficient is
/// zero: it would add `-0 * l`, which changes no value (at most the sign of a
/// zero). Systems larger than the stack copy use nalgebra's triangular solves.
pub(crate) fn lu_solve_mut<C: na::Dim, S: StorageMut<Real, Dyn, C>>(
    lu: &MassLu,
    b: &mut na::Matrix<Real, Dyn, C, S>,
) -> bool {
    const MAX_DIM: usize = 64;
    let n = lu.dim();
    assert_eq!(n, b.nrows(), "LU solve matrix dimension mismatch.");
    if let Some(tree) = &lu.tree {
        // n <= tree_ldl::MAX_DIM == MAX_DIM.
        let mut x = [0.0 as Real; MAX_DIM];
        let mut solved = true;
        for c in 0..b.ncols() {
            for (i, xi) in x[..n].iter_mut().enumerate() {
                *xi = b[(i, c)];
            }
            solved &= tree.solve(&mut x[..n]);
            for (i, xi) in x[..n].iter().enumerate() {
                b[(i, c)] = *xi;
            }
        }
        return solved;
    }
    for &(i, i2) in &lu.swaps {
        b.swap_rows(i, i2);
    }
    if n > MAX_DIM || b.ncols() != 1 {
        let _ = lu.lu.solve_lower_triangular_with_diag_mut(b, 1.0);
        return lu.lu.solve_upper_triangular_mut(b);
    }
    let mut x = [0.0 as Real; MAX_DIM];
    for (i, xi) in x[..n].iter_mut().enumerate() {
        *xi = b[i];
    }
    let x = &mut x[..n];
    let f = lu.lu.as_slice();
    // L y = P b, L with a unit diagonal.
    for i in 0..n.saturating_sub(1) {
        let coeff = x[i];
        if coeff != 0.0 {
            let below = &f[i * n + i + 1..(i + 1) * n];
            for (xr, l) in x[i + 1..].iter_mut().zip(below) {
                *xr = -coeff * *l + *xr;
            }
        }
    }
    // U x = y.
    let mut solved = true;
    for i in (0..n).rev() {
        let column = &f[i * n..i * n + i + 1];
        let diag = column[i];
        if diag == 0.0 {
            solved = false;
            break;
        }
        let coeff = x[i] / diag;
        x[i] = coeff;
        if coeff != 0.0 {
            for (xr, u) in x[..i].iter_mut().zip(&column[..i]) {
                *xr = -coeff * *u + *xr;
            }
        }
    }
    for (i, xi) in x.iter().enumerate() {
        b[i] = *xi;
    }
    solved
}
