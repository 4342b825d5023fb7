//! PATCH (scasm-testbed): the `L^T D L` factorisation of a multibody's mass
//! matrix that follows its kinematic tree (Featherstone, *Rigid Body Dynamics
//! Algorithms*, 2008, section 6.5; MuJoCo's `mj_factorM`), and the inverse
//! it gives.
//!
//! The mass matrix of a tree has a non-zero `(i, j)` only where coordinate `j`
//! is an ancestor of coordinate `i` or the other way round: a leg's
//! coordinates couple with the floating base's and with one another, never
//! with another leg's. A multibody numbers its coordinates parents first, so
//! eliminating them from the last to the first (leaves first) creates no
//! fill-in, needs no pivoting (the matrix is symmetric positive definite), and
//! leaves `L` with the same pattern; `L^-1` has it too. The elimination skips
//! every zero, so its work is the tree's (coordinate, ancestor) pairs, not
//! `n^3`; it is the plain `L^T D L` elimination of any symmetric positive
//! definite matrix, so a matrix without that pattern is factored right, only
//! with fill-in.
//!
//! The inverse `A^-1 = L^-1 D^-1 L^-T` is formed once per factorisation, row
//! by row from the factors (Takahashi's equations, again only over the
//! (coordinate, ancestor) pairs):
//! every constraint row of a step (a joint motor, a limit, each contact row)
//! needs `A^-1 J^T`, and a product with the inverse costs one contiguous
//! multiply-add per non-zero of `J` (a unit motor row: one column; a contact
//! on a foot: the root's and that leg's columns).
//!
//! Rows are stored padded to a multiple of 8 entries, and every row operation
//! runs over the chunks of `LANES` entries (one SSE register) that can be
//! non-zero, so that it vectorises;
//! entries right of the diagonal of `L`'s rows are scratch and never read.

use crate::math::Real;
use alloc::vec::Vec;
use core::ops::Range;
use na::DMatrix;

/// The entries a row operation handles at a time (one SSE register).
const LANES: usize = 4;

/// A row's padded length is a multiple of this: the widths `eliminate` and
/// `solve_w` are compiled for.
const ROW_PAD: usize = 8;

/// The largest dimension factored here; [`TreeLdl::factor`] refuses larger.
pub(crate) const MAX_DIM: usize = 64;

/// `y -= f * x` on the lanes of chunks `chunks` of a row (each chunk
/// unrolled and vectorised).
#[inline(always)]
fn row_sub<const W: usize>(y: &mut [Real; W], f: Real, x: &[Real; W], chunks: Range<usize>) {
    let (y, x) = (y.as_chunks_mut::<LANES>().0, x.as_chunks::<LANES>().0);
    for c in chunks {
        for t in 0..LANES {
            y[c][t] -= f * x[c][t];
        }
    }
}

/// `y += f * x` on the lanes of chunks `chunks` of a row.
#[inline(always)]
fn row_add<const W: usize>(y: &mut [Real; W], f: Real, x: &[Real; W], chunks: Range<usize>) {
    let (y, x) = (y.as_chunks_mut::<LANES>().0, x.as_chunks::<LANES>().0);
    for c in chunks {
        for t in 0..LANES {
            y[c][t] += f * x[c][t];
        }
    }
}

/// The chunks holding entries `0..=last`.
#[inline(always)]
fn through(last: usize) -> Range<usize> {
    0..last / LANES + 1
}

/// The `L^T D L` factors and the inverse of a symmetric positive definite
/// matrix, eliminated from its last coordinate to its first.
#[derive(Clone, Debug, Default)]
pub(crate) struct TreeLdl {
    n: usize,
    /// The padded row length, a multiple of [`ROW_PAD`], at most [`MAX_DIM`].
    w: usize,
    /// Row-major, padded: below the diagonal `L` (unit diagonal implied), on
    /// it `D`; right of it scratch.
    a: Vec<Real>,
    /// Row-major, padded: the inverse (symmetric, so its rows are its columns).
    inv: Vec<Real>,
    /// A pivot of `D` was not positive: the matrix is not positive definite.
    singular: bool,
}

impl TreeLdl {
    /// The dimension of the factored matrix.
    pub(crate) fn dim(&self) -> usize {
        self.n
    }

    /// Factors the top-left `n x n` block of `m` (`n <= MAX_DIM`) and forms
    /// its inverse.
    pub(crate) fn factor(&mut self, m: &DMatrix<Real>, n: usize) {
        assert!(n <= MAX_DIM, "TreeLdl factors at most {MAX_DIM} coordinates");
        let w = n.div_ceil(ROW_PAD).max(1) * ROW_PAD;
        (self.n, self.w) = (n, w);
        for buffer in [&mut self.a, &mut self.inv] {
            buffer.clear();
            buffer.resize(n * w, 0.0);
        }
        let rows = m.nrows();
        let src = m.as_slice();
        // Row i's lower triangle is column i's upper one (m is symmetric).
        for i in 0..n {
            self.a[i * w..i * w + i + 1].copy_from_slice(&src[i * rows..i * rows + i + 1]);
        }
        match w {
            8 => self.eliminate::<8>(),
            16 => self.eliminate::<16>(),
            24 => self.eliminate::<24>(),
            32 => self.eliminate::<32>(),
            40 => self.eliminate::<40>(),
            48 => self.eliminate::<48>(),
            56 => self.eliminate::<56>(),
            _ => self.eliminate::<64>(),
        }
    }

    /// The factorisation and the inverse, on rows of `W` entries.
    fn eliminate<const W: usize>(&mut self) {
        let n = self.n;
        let a = self.a.as_chunks_mut::<W>().0;
        self.singular = false;
        for k in (0..n).rev() {
            let (head, tail) = a.split_at_mut(k);
            let row_k = &mut tail[0];
            let dk = row_k[k];
            if !(dk > 0.0) {
                self.singular = true;
                return;
            }
            // Row k's entries left of i are still A's when row i is updated;
            // row i's entries right of i are scratch.
            for i in (0..k).rev() {
                let aki = row_k[i];
                if aki != 0.0 {
                    let f = aki / dk;
                    row_sub(&mut head[i], f, row_k, through(i));
                    row_k[i] = f;
                }
            }
        }
        // The inverse Z, row by row from the first coordinate (the root's):
        // A = L^T D L gives Z = D^-1 L^-T + (I - L) Z, and L^-T is upper
        // triangular, so Z_ij = [i = j] / d_i - sum_{k < i} L_ik Z_kj for
        // j <= i (Takahashi's equations), with L_ik non-zero only for k an
        // ancestor of i. Row k's entries right of k are mirrored in from the
        // later rows as each is finished; until row i is, row k's entries
        // from i on are still zero, and so are row i's own.
        let inv = self.inv.as_chunks_mut::<W>().0;
        for i in 0..n {
            let (done, rest) = inv.split_at_mut(i);
            let row = &mut rest[0];
            let ancestors = || (0..i).filter(|&k| a[i][k] != 0.0);
            for k in ancestors() {
                row_sub(row, a[i][k], &done[k], through(i));
            }
            row[i] = 1.0 / a[i][i];
            for k in ancestors() {
                row[i] -= a[i][k] * row[k];
            }
            for (j, done_j) in done.iter_mut().enumerate() {
                done_j[i] = row[j];
            }
        }
    }

    /// Whether the factored matrix was positive definite (else nothing solves).
    pub(crate) fn is_positive_definite(&self) -> bool {
        !self.singular
    }

    /// Row (and column) `i` of the inverse, `A^-1 e_i`; meaningless unless
    /// [`Self::is_positive_definite`].
    pub(crate) fn inverse_row(&self, i: usize) -> &[Real] {
        &self.inv[i * self.w..i * self.w + self.n]
    }

    /// Solves `A x = b` in place (as `A^-1 b`); `false`, leaving `x` as it
    /// was, if `A` was not positive definite.
    pub(crate) fn solve(&self, x: &mut [Real]) -> bool {
        debug_assert_eq!(x.len(), self.n);
        if self.singular {
            return false;
        }
        match self.w {
            8 => self.solve_w::<8>(x),
            16 => self.solve_w::<16>(x),
            24 => self.solve_w::<24>(x),
            32 => self.solve_w::<32>(x),
            40 => self.solve_w::<40>(x),
            48 => self.solve_w::<48>(x),
            56 => self.solve_w::<56>(x),
            _ => self.solve_w::<64>(x),
        }
        true
    }

    /// `out = A^-1 x` for an `x` that is zero outside `cols` (ascending):
    /// the products [`Self::solve`] forms, in its order, over `cols` only.
    /// `false`, leaving `out` as it was, if `A` was not positive definite.
    pub(crate) fn solve_sparse_into(&self, x: &[Real], cols: &[usize], out: &mut [Real]) -> bool {
        debug_assert_eq!((x.len(), out.len()), (self.n, self.n));
        debug_assert!(cols.windows(2).all(|p| p[0] < p[1]));
        if self.singular {
            return false;
        }
        match self.w {
            8 => self.solve_sparse_w::<8>(x, cols, out),
            16 => self.solve_sparse_w::<16>(x, cols, out),
            24 => self.solve_sparse_w::<24>(x, cols, out),
            32 => self.solve_sparse_w::<32>(x, cols, out),
            40 => self.solve_sparse_w::<40>(x, cols, out),
            48 => self.solve_sparse_w::<48>(x, cols, out),
            56 => self.solve_sparse_w::<56>(x, cols, out),
            _ => self.solve_sparse_w::<64>(x, cols, out),
        }
        true
    }

    fn solve_sparse_w<const W: usize>(&self, x: &[Real], cols: &[usize], out: &mut [Real]) {
        let inv = self.inv.as_chunks::<W>().0;
        let mut y = [0.0 as Real; W];
        for &c in cols {
            let xc = x[c];
            if xc != 0.0 {
                row_add(&mut y, xc, &inv[c], 0..W / LANES);
            }
        }
        out.copy_from_slice(&y[..self.n]);
    }

    fn solve_w<const W: usize>(&self, x: &mut [Real]) {
        let inv = self.inv.as_chunks::<W>().0;
        let mut y = [0.0 as Real; W];
        for (c, &xc) in x.iter().enumerate() {
            if xc != 0.0 {
                row_add(&mut y, xc, &inv[c], 0..W / LANES);
            }
        }
        x.copy_from_slice(&y[..self.n]);
    }
}

#[cfg(test)]
mod test {
    use super::TreeLdl;
    use alloc::{vec, vec::Vec};
    use na::{DMatrix, DVector};

    /// A random symmetric positive definite matrix with a tree's pattern.
    fn tree_matrix(parent: &[usize], seed: u32) -> DMatrix<f32> {
        let n = parent.len();
        let mut state = seed;
        let mut next = || {
            state = state.wrapping_mul(1664525).wrapping_add(1013904223);
            (state >> 8) as f32 / (1u32 << 24) as f32 - 0.5
        };
        // J^T J over "links" of the tree: each coordinate's column reaches its ancestors.
        let mut m = DMatrix::<f32>::zeros(n, n);
        for i in 0..n {
            let mut path = vec![i];
            let mut p = parent[i];
            while p != usize::MAX {
                path.push(p);
                p = parent[p];
            }
            let v: Vec<f32> = path.iter().map(|_| next()).collect();
            for (a, &ia) in path.iter().enumerate() {
                for (b, &ib) in path.iter().enumerate() {
                    m[(ia, ib)] += v[a] * v[b];
                }
            }
            m[(i, i)] += 0.5;
        }
        m
    }

    fn check_against_lu(m: &DMatrix<f32>) {
        let n = m.nrows();
        let mut ldl = TreeLdl::default();
        ldl.factor(m, n);
        let lu = m.clone().lu();
        for k in 0..n {
            let mut b = DVector::<f32>::zeros(n);
            b[k] = 1.0;
            b[0] = 0.25;
            let want = lu.solve(&b).expect("invertible");
            let mut got = b.clone();
            assert!(ldl.solve(got.as_mut_slice()));
            assert!((got - want).amax() < 1e-4, "column {k}");
        }
    }

    #[test]
    fn solves_as_a_dense_factorisation_on_a_tree() {
        // A floating base (a chain of six) with three legs of three.
        let mut parent = vec![usize::MAX, 0, 1, 2, 3, 4];
        for _ in 0..3 {
            let base = parent.len();
            parent.extend([5, base, base + 1]);
        }
        check_against_lu(&tree_matrix(&parent, 7));
    }

    #[test]
    fn a_sparse_right_hand_side_solves_to_the_same_bits() {
        let mut parent = vec![usize::MAX, 0, 1, 2, 3, 4];
        for _ in 0..4 {
            let base = parent.len();
            parent.extend([5, base, base + 1]);
        }
        let m = tree_matrix(&parent, 11);
        let n = m.nrows();
        let mut ldl = TreeLdl::default();
        ldl.factor(&m, n);
        // A contact on the second leg: the base's and that leg's columns.
        let cols: Vec<usize> = (0..6).chain(9..12).collect();
        let mut x = vec![0.0f32; n];
        for (k, &c) in cols.iter().enumerate() {
            x[c] = if k == 4 { 0.0 } else { 0.3 - 0.07 * k as f32 };
        }
        let mut want = x.clone();
        assert!(ldl.solve(&mut want));
        let mut got = vec![f32::NAN; n];
        assert!(ldl.solve_sparse_into(&x, &cols, &mut got));
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&got), bits(&want));
    }

    #[test]
    fn a_matrix_without_the_pattern_is_factored_too() {
        let n: usize = 11;
        let mut m = tree_matrix(&(0..n).map(|i| i.wrapping_sub(1)).collect::<Vec<_>>(), 5);
        // Couple two coordinates that are not ancestor and descendant.
        m[(3, 9)] += 0.1;
        m[(9, 3)] += 0.1;
        check_against_lu(&m);
    }

    #[test]
    fn a_matrix_that_is_not_positive_definite_is_refused() {
        let parent = [usize::MAX, 0, 1];
        let mut m = tree_matrix(&parent, 3);
        m[(1, 1)] = -1.0;
        let mut ldl = TreeLdl::default();
        ldl.factor(&m, 3);
        let mut b = [1.0, 0.0, 0.0];
        assert!(!ldl.solve(&mut b));
        assert_eq!(b, [1.0, 0.0, 0.0]);
    }
}
