//! A sensor fit without the errors-in-variables bias: fit the *forward* model,
//! the reading as a polynomial of the location (`obs ~ g(x)`), where the
//! reading's noise sits in the target and biases nothing, then invert it into
//! the sensor model S (location from reading) by the least-squares polynomial
//! through `(g(x), x)` on an even grid over the locations seen.
//!
//! The paper's fit regresses location on the reading. The reading's noise is
//! then in the regressor, which flattens the fit by a factor that grows with the
//! noise's variance and does not shrink with more data. Averaging readings
//! shrinks the noise but not the principle. Here the regressor is the learner's
//! own location estimate, whose error is small and smooth (dead reckoning,
//! pulled gently towards the readings), so the fit barely depends on the
//! camera's noise.

use crate::poly_fit::PolynomialFit;
use crate::polynomial::Polynomial;

/// Grid points of the inversion.
const GRID: usize = 41;

/// `sqrt(3)`: a uniform distribution's half-range in standard deviations. The
/// training behaviour sweeps its range back and forth, so the locations seen
/// are spread about evenly over it.
const HALF_RANGE_IN_STD: f64 = 1.732_050_807_568_877_2;

/// The forward fit `obs ~ g(x)` and the weighted spread of the locations seen.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct ForwardFit {
    forward: PolynomialFit,
    gamma: f64,
    /// Exponentially weighted sums of 1, x and x^2 (for the locations' mean and
    /// spread), with the same forgetting as the fit.
    moments: [f64; 3],
}

impl ForwardFit {
    /// An empty fit of a forward model of `degree` with forgetting `gamma`.
    pub(crate) fn new(degree: usize, gamma: f64) -> Self {
        Self {
            forward: PolynomialFit::new(degree, gamma),
            gamma,
            moments: [0.0; 3],
        }
    }

    /// Adds a reading `obs` taken at location `x`.
    pub(crate) fn add(&mut self, obs: f64, x: f64) {
        self.forward.add(x, obs);
        let m = &mut self.moments;
        for (k, v) in [1.0, x, x * x].into_iter().enumerate() {
            m[k] = self.gamma * m[k] + v;
        }
    }

    /// Points added so far.
    pub(crate) fn points(&self) -> u64 {
        self.forward.points()
    }

    /// The sensor model of `degree`: the least-squares polynomial of location on
    /// reading through `(g(x), x)` at evenly spaced locations over the mean plus
    /// or minus `sqrt(3)` standard deviations of the locations seen. `None`
    /// while `g` is not determined or is flat over that range.
    pub(crate) fn sensor_model(&self, degree: usize) -> Option<Polynomial> {
        let g = self.forward.polynomial()?;
        let [w, sx, sxx] = self.moments;
        let mean = sx / w;
        let std = libm::sqrt((sxx / w - mean * mean).max(0.0));
        let (lo, hi) = spread_range(mean, std)?;
        invert(|x| g.eval(x), lo, hi, degree)
    }
}

/// The range of locations an inversion covers: the mean plus or minus
/// `sqrt(3)` standard deviations (`None` if they do not make a range).
pub(crate) fn spread_range(mean: f64, std: f64) -> Option<(f64, f64)> {
    (std > 0.0 && std.is_finite() && mean.is_finite()).then_some((
        mean - HALF_RANGE_IN_STD * std,
        mean + HALF_RANGE_IN_STD * std,
    ))
}

/// The least-squares polynomial of `degree` of location on reading through
/// `(g(x), x)` at evenly spaced `x` over `[lo, hi]`: the inverse of the forward
/// model `g` as a sensor model. `None` if `g` does not change over the range
/// (it says nothing of location there). Where `g` wiggles (noise at the ends of
/// the range), the least-squares fit smooths it over.
pub(crate) fn invert(
    g: impl Fn(f64) -> f64,
    lo: f64,
    hi: f64,
    degree: usize,
) -> Option<Polynomial> {
    let mut inverse = PolynomialFit::new(degree, 1.0);
    for i in 0..GRID {
        let x = lo + (hi - lo) * i as f64 / (GRID - 1) as f64;
        inverse.add(g(x), x);
    }
    let span = (g(hi) - g(lo)).abs();
    if !(span > 0.0 && span.is_finite()) {
        return None;
    }
    inverse.polynomial()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Readings `k / x` with noise far larger than the errors-in-variables
    /// bias would allow an inverse fit to ignore: the forward fit's inverse is
    /// the same as with no noise at all.
    #[test]
    fn noise_in_the_reading_does_not_bias_the_inverse() {
        let fit = |noise: f64| {
            let mut f = ForwardFit::new(5, 1.0);
            let mut lcg: u64 = 7;
            for k in 0..4000 {
                let x = 1200.0 + 2400.0 * (0.5 + 0.5 * (f64::from(k) * 0.013).sin());
                lcg = lcg
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let u = (lcg >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                f.add(40_000.0 / x + noise * 3.46 * u, x);
            }
            f.sensor_model(3).expect("model")
        };
        let (clean, noisy) = (fit(0.0), fit(1.6));
        for obs in [12.0, 16.0, 20.0, 26.0, 32.0] {
            let (a, b) = (clean.eval(obs), noisy.eval(obs));
            assert!((a - b).abs() < 15.0, "at {obs} px: {a:.0} vs {b:.0} mm");
        }
    }

    #[test]
    fn a_flat_forward_model_has_no_inverse() {
        let mut f = ForwardFit::new(2, 1.0);
        for k in 0..50 {
            f.add(20.0, f64::from(k));
        }
        assert!(f.sensor_model(3).is_none());
    }
}
