//! A polynomial with raw-unit coefficients, stored inline so that it is `Copy`
//! and needs no allocation.

use crate::MAX_REGRESSORS;

/// Most coefficients a [`Polynomial`] can hold (degree [`MAX_REGRESSORS`]).
pub const MAX_COEFFS: usize = MAX_REGRESSORS + 1;

/// `p(x) = c[0] + c[1] x + ... + c[d] x^d`, coefficients lowest power first, in the
/// raw units of its input and output (pixels to millimetres, command to mm/s, ...).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Polynomial {
    coeffs: [f64; MAX_COEFFS],
    len: u8,
}

impl Polynomial {
    /// The polynomial with these coefficients (lowest power first), or `None` if
    /// there are none or more than [`MAX_COEFFS`].
    pub fn new(coeffs: &[f64]) -> Option<Self> {
        if coeffs.is_empty() || coeffs.len() > MAX_COEFFS {
            return None;
        }
        let mut c = [0.0; MAX_COEFFS];
        c[..coeffs.len()].copy_from_slice(coeffs);
        Some(Self {
            coeffs: c,
            len: coeffs.len() as u8,
        })
    }

    /// `p(x) = value`.
    pub fn constant(value: f64) -> Self {
        let mut coeffs = [0.0; MAX_COEFFS];
        coeffs[0] = value;
        Self { coeffs, len: 1 }
    }

    /// `p(x) = x`: the paper's initial action model A0.
    pub fn identity() -> Self {
        Self {
            coeffs: {
                let mut c = [0.0; MAX_COEFFS];
                c[1] = 1.0;
                c
            },
            len: 2,
        }
    }

    /// The coefficients, lowest power first.
    pub fn coeffs(&self) -> &[f64] {
        &self.coeffs[..usize::from(self.len)]
    }

    /// `scale p(x) + offset`: the same model with its output in other units.
    pub fn rescaled(&self, scale: f64, offset: f64) -> Self {
        let mut out = *self;
        for c in out.coeffs.iter_mut().take(usize::from(self.len)) {
            *c *= scale;
        }
        out.coeffs[0] += offset;
        out
    }

    /// The degree (number of coefficients minus one).
    pub fn degree(&self) -> usize {
        usize::from(self.len) - 1
    }

    /// `p(x)` by Horner's rule.
    #[inline]
    pub fn eval(&self, x: f64) -> f64 {
        self.coeffs().iter().rev().fold(0.0, |acc, &c| acc * x + c)
    }

    /// `p'(x)` (the zero polynomial for a constant).
    pub fn derivative(&self) -> Self {
        let c = self.coeffs();
        if c.len() == 1 {
            return Self::constant(0.0);
        }
        let mut d = [0.0; MAX_COEFFS];
        for (k, dk) in d.iter_mut().enumerate().take(c.len() - 1) {
            *dk = (k + 1) as f64 * c[k + 1];
        }
        Self {
            coeffs: d,
            len: self.len - 1,
        }
    }

    /// Whether every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        self.coeffs().iter().all(|c| c.is_finite())
    }

    /// Expands `q(u)` with `u = (x - centre) / half_width` into raw powers of `x`:
    /// the result `p` has `p(x) = q((x - centre) / half_width)`. `None` if `q` is
    /// empty or too long.
    ///
    /// Raw coefficients lose about `d log10(|centre| / half_width)` digits
    /// to cancellation when a degree-`d` polynomial is used far from zero
    /// relative to the span of its inputs.
    pub fn from_normalised(q: &[f64], centre: f64, half_width: f64) -> Option<Self> {
        let n = q.len();
        if n == 0 || n > MAX_COEFFS {
            return None;
        }
        // Horner in polynomial arithmetic: p <- p * (x - centre) / half_width + q_k.
        let mut p = [0.0; MAX_COEFFS];
        let (a, b) = (1.0 / half_width, -centre / half_width); // u = a x + b
        for k in (0..n).rev() {
            let mut next = [0.0; MAX_COEFFS];
            for j in 0..n {
                if j + 1 < MAX_COEFFS {
                    next[j + 1] += a * p[j];
                }
                next[j] += b * p[j];
            }
            next[0] += q[k];
            p = next;
        }
        Self::new(&p[..n])
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn rescaled_maps_the_output() {
        let p = Polynomial::new(&[1.0, -2.0, 0.5]).expect("poly");
        let q = p.rescaled(3.0, 10.0);
        for x in [-2.0, 0.0, 1.5, 7.0] {
            assert!((q.eval(x) - (3.0 * p.eval(x) + 10.0)).abs() < 1e-12);
        }
        assert_eq!(q.degree(), p.degree());
    }

    use super::*;

    #[test]
    fn the_derivative_of_a_cubic_and_of_a_constant() {
        let p = Polynomial::new(&[1.0, -2.0, 0.5, 3.0]).expect("cubic");
        let d = p.derivative();
        assert_eq!(d.coeffs(), &[-2.0, 1.0, 9.0]);
        assert_eq!(Polynomial::constant(4.0).derivative().coeffs(), &[0.0]);
    }

    #[test]
    fn horner_matches_powers() {
        let p = Polynomial::new(&[1.0, -2.0, 0.5, 3.0]).expect("valid");
        let x: f64 = 1.7;
        let direct = 1.0 - 2.0 * x + 0.5 * x * x + 3.0 * x.powi(3);
        assert!((p.eval(x) - direct).abs() < 1e-12);
        assert_eq!(p.degree(), 3);
    }

    #[test]
    fn rejects_empty_and_too_long() {
        assert!(Polynomial::new(&[]).is_none());
        assert!(Polynomial::new(&[0.0; MAX_COEFFS + 1]).is_none());
    }

    #[test]
    fn normalised_expansion_is_exact_reparametrisation() {
        let q = [0.3, -1.2, 2.0, 0.7];
        let (centre, half) = (45.0, 12.5);
        let p = Polynomial::from_normalised(&q, centre, half).expect("valid");
        for &x in &[20.0, 33.3, 45.0, 57.5, 80.0] {
            let u = (x - centre) / half;
            let expected = q[0] + q[1] * u + q[2] * u * u + q[3] * u * u * u;
            assert!((p.eval(x) - expected).abs() < 1e-10 * (1.0 + expected.abs()));
        }
    }
}
