//! Incremental weighted polynomial regression of one variable, `y ~ p(x)`, that
//! keeps its input normalised: it regresses on `u = (x - centre) / half_width`
//! with `|u| <= 1` for every input seen, and widens that interval (re-expressing
//! everything seen so far, exactly) when an input falls outside it.

use crate::polynomial::Polynomial;
use crate::wls::{IncrementalWls, MAX_COLS, Square};

/// How far past a new extreme the interval is widened, as a fraction of its
/// half-width, so that a slowly growing range renormalises only now and then.
const WIDEN: f64 = 0.25;

/// Smallest half-width, relative to the centre's magnitude (the first input
/// alone defines no interval).
const MIN_HALF_WIDTH: f64 = 1e-3;

/// `y ~ c_0 + c_1 x + ... + c_d x^d`, fitted incrementally with forgetting.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct PolynomialFit {
    wls: IncrementalWls,
    degree: usize,
    /// `(centre, half_width)` of the normalising interval, once an input is seen.
    interval: Option<(f64, f64)>,
}

impl PolynomialFit {
    /// An empty fit of the given degree (1..=MAX_REGRESSORS) and forgetting factor.
    pub(crate) fn new(degree: usize, gamma: f64) -> Self {
        Self {
            wls: IncrementalWls::new(degree, gamma),
            degree,
            interval: None,
        }
    }

    /// Adds the finite point `(x, y)`.
    pub(crate) fn add(&mut self, x: f64, y: f64) {
        let (centre, half_width) = match self.interval {
            None => {
                let hw = MIN_HALF_WIDTH * x.abs().max(f64::MIN_POSITIVE);
                self.interval = Some((x, hw));
                (x, hw)
            }
            Some((c, h)) if (x - c).abs() <= h => (c, h),
            Some((c, h)) => {
                let (lo, hi) = ((c - h).min(x), (c + h).max(x));
                let centre = 0.5 * (lo + hi);
                let half_width = 0.5 * (hi - lo) * (1.0 + WIDEN);
                self.renormalise((c, h), (centre, half_width));
                (centre, half_width)
            }
        };
        let u = (x - centre) / half_width;
        let mut powers = [0.0; MAX_COLS];
        let mut p = 1.0;
        for v in &mut powers[..self.degree] {
            p *= u;
            *v = p;
        }
        self.wls.add(&powers[..self.degree], y);
    }

    /// Re-expresses the fit in a new interval that contains the old one:
    /// `u_new = a u_old + b`, so `u_new^k = sum_j binom(k, j) a^j b^(k-j) u_old^j`.
    fn renormalise(&mut self, old: (f64, f64), new: (f64, f64)) {
        let a = old.1 / new.1;
        let b = (old.0 - new.0) / new.1;
        let mut t: Square = [[0.0; MAX_COLS]; MAX_COLS];
        for k in 0..=self.degree {
            let mut binom = 1.0;
            for j in 0..=k {
                t[k][j] = binom * libm::pow(a, j as f64) * libm::pow(b, (k - j) as f64);
                binom = binom * (k - j) as f64 / (j + 1) as f64;
            }
        }
        self.wls.reparametrise(&t);
        self.interval = Some(new);
    }

    /// The fitted polynomial in raw units of `x`, or `None` while under-determined.
    pub(crate) fn polynomial(&self) -> Option<Polynomial> {
        let (centre, half_width) = self.interval?;
        let q = self.wls.solve()?;
        Polynomial::from_normalised(&q[..=self.degree], centre, half_width)
            .filter(Polynomial::is_finite)
    }

    /// Points added so far.
    pub(crate) fn points(&self) -> u64 {
        self.wls.points()
    }
}
