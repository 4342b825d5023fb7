//! PATCH (scasm-testbed): the solver's two products on a multibody's
//! constraint rows, on plain slices, with the same bits as nalgebra's.
//!
//! The solver reads a row's `J v` and adds `impulse * M^-1 J^T` to the
//! velocities once per row per pass. nalgebra's `dot` and `axpy` on
//! dynamically sized views pay for the view and its strides on every call;
//! these run the same operations in the same order on contiguous slices.

use crate::math::Real;

/// `a . b` as nalgebra's `Matrix::dot` computes it for a dynamically sized
/// column: eight interleaved accumulators over whole blocks of eight, summed
/// pairwise as `(0 + 4), (1 + 5), (2 + 6), (3 + 7)`, then the tail in order.
/// Same bits.
#[inline]
pub(crate) fn dot_as_nalgebra(a: &[Real], b: &[Real]) -> Real {
    assert_eq!(a.len(), b.len(), "dot of slices of different lengths");
    let (a_blocks, a_tail) = a.as_chunks::<8>();
    let (b_blocks, b_tail) = b.as_chunks::<8>();
    let mut acc = [0.0; 8];
    for (x, y) in a_blocks.iter().zip(b_blocks) {
        for t in 0..8 {
            acc[t] += x[t] * y[t];
        }
    }
    let mut res: Real = 0.0;
    res += acc[0] + acc[4];
    res += acc[1] + acc[5];
    res += acc[2] + acc[6];
    res += acc[3] + acc[7];
    for (x, y) in a_tail.iter().zip(b_tail) {
        res += x * y;
    }
    res
}

/// `y += a * x`: nalgebra's `y.axpy(a, x, 1.0)`, which computes
/// `a * x_i * 1 + 1 * y_i`, both products by one exact. Same bits.
#[inline]
pub(crate) fn add_scaled(y: &mut [Real], a: Real, x: &[Real]) {
    assert_eq!(y.len(), x.len(), "axpy of slices of different lengths");
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += a * xi;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec::Vec;
    use na::DVector;

    /// Values whose sums round differently in different orders.
    fn awkward(n: usize, seed: u32) -> Vec<Real> {
        (0..n)
            .map(|i| {
                let k = (i as u32).wrapping_mul(2_654_435_761).wrapping_add(seed);
                let mantissa = (k % 10_007) as Real / 10_007.0 - 0.5;
                mantissa * (10.0 as Real).powi((k % 9) as i32 - 4)
            })
            .collect()
    }

    #[test]
    fn the_slices_products_are_nalgebras_bit_for_bit() {
        for n in 0..40 {
            let (a, b) = (awkward(n, 1), awkward(n, 77));
            let (va, vb) = (DVector::from_column_slice(&a), DVector::from_column_slice(&b));
            assert_eq!(dot_as_nalgebra(&a, &b).to_bits(), va.dot(&vb).to_bits(), "n = {n}");
            let mut y = b.to_vec();
            add_scaled(&mut y, -0.37, &a);
            let mut vy = vb.clone();
            vy.axpy(-0.37, &va, 1.0);
            let bits = |v: &[Real]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&y), bits(vy.as_slice()), "n = {n}");
        }
    }
}
