//! A sensor fit without the errors-in-variables bias: the paper's regression of
//! location on the reading, with the reading's noise corrected for instead of
//! averaged down.
//!
//! Regressing `x` on a noisy reading `obs = o + e` biases a least-squares fit:
//! its normal equations hold sums of `obs^n`, whose expectations are not those
//! of the true `o^n` (`E[obs^2] = o^2 + sigma^2`, and so on), and more data does
//! not help. For Gaussian noise of variance `sigma^2` the Hermite polynomials
//! `He_n(obs; sigma^2)` are unbiased for `o^n`, so normal equations built from
//! them instead (the "corrected score" of Nakamura 1990; Cheng & Schneeweiss
//! 1998 for polynomials) give a consistent fit. `sigma^2` comes from the
//! readings themselves: over three consecutive frames the beacon's size hardly
//! curves, so the second difference of consecutive readings is noise, of
//! variance `6 sigma^2`. The scenario's noise setting is never used.
//!
//! The fit keeps exponentially weighted sums of the powers of the normalised
//! reading (to twice the degree) and of the location times them: O(1) time and
//! memory per point. The reading's normalising interval widens as readings
//! arrive, the sums re-expressed exactly by the binomial theorem.

use crate::polynomial::Polynomial;

/// Most degrees the corrected fit supports (its sums go to twice this).
pub(crate) const MAX_EIV_DEGREE: usize = 5;

const MOMENTS: usize = 2 * MAX_EIV_DEGREE + 1;

/// How far past a new extreme the interval widens, as a fraction of its
/// half-width (as in [`crate::poly_fit`]).
const WIDEN: f64 = 0.25;

/// The readings' noise variance from second differences of consecutive ones.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct NoiseEstimate {
    /// The last two readings with their times.
    last: [Option<(f64, f64)>; 2],
    /// Exponentially weighted sum of |second difference|, and of weights.
    abs_sum: f64,
    weight: f64,
}

impl NoiseEstimate {
    /// Takes a reading at `t_s`; a second difference counts only when the three
    /// readings are evenly spaced in time (consecutive frames).
    pub(crate) fn observe(&mut self, t_s: f64, obs: f64, gamma: f64) {
        if let [Some((t1, o1)), Some((t2, o2))] = self.last {
            let (h1, h2) = (t2 - t1, t_s - t2);
            if h1 > 0.0 && (h2 - h1).abs() <= 1e-6 * h1.max(1e-9) {
                let d2 = obs - 2.0 * o2 + o1;
                self.abs_sum = gamma * self.abs_sum + d2.abs();
                self.weight = gamma * self.weight + 1.0;
            }
        }
        self.last = [self.last[1], Some((t_s, obs))];
    }

    /// The reading noise's variance, once a few second differences are in.
    /// For Gaussian noise the mean absolute second difference is
    /// `sqrt(2 / pi) sqrt(6) sigma`.
    pub(crate) fn variance(&self) -> Option<f64> {
        (self.weight >= 10.0).then(|| {
            let mean_abs = self.abs_sum / self.weight;
            mean_abs * mean_abs * core::f64::consts::PI / 12.0
        })
    }
}

/// The corrected-score fit of `x ~ S(obs)`.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct EivFit {
    degree: usize,
    gamma: f64,
    /// `(centre, half_width)` of the reading's normalisation.
    interval: Option<(f64, f64)>,
    /// `sum w u^n`, n = 0..=2 degree.
    u_moments: [f64; MOMENTS],
    /// `sum w x u^n`, n = 0..=degree.
    xu_moments: [f64; MAX_EIV_DEGREE + 1],
    points: u64,
}

impl EivFit {
    /// An empty fit of `degree` (1..=MAX_EIV_DEGREE) with forgetting `gamma`.
    pub(crate) fn new(degree: usize, gamma: f64) -> Self {
        Self {
            degree,
            gamma,
            interval: None,
            u_moments: [0.0; MOMENTS],
            xu_moments: [0.0; MAX_EIV_DEGREE + 1],
            points: 0,
        }
    }

    /// Points added so far.
    pub(crate) fn points(&self) -> u64 {
        self.points
    }

    /// Adds a location `x` at reading `obs`.
    pub(crate) fn add(&mut self, obs: f64, x: f64) {
        let (centre, half_width) = match self.interval {
            None => {
                let hw = 1e-3 * obs.abs().max(f64::MIN_POSITIVE);
                self.interval = Some((obs, hw));
                (obs, hw)
            }
            Some((c, h)) if (obs - c).abs() <= h => (c, h),
            Some((c, h)) => {
                let (lo, hi) = ((c - h).min(obs), (c + h).max(obs));
                let new = (0.5 * (lo + hi), 0.5 * (hi - lo) * (1.0 + WIDEN));
                self.renormalise((c, h), new);
                new
            }
        };
        let u = (obs - centre) / half_width;
        let g = self.gamma;
        let mut p = 1.0;
        for n in 0..=2 * self.degree {
            self.u_moments[n] = g * self.u_moments[n] + p;
            if n <= self.degree {
                self.xu_moments[n] = g * self.xu_moments[n] + x * p;
            }
            p *= u;
        }
        self.points += 1;
    }

    /// Re-expresses the sums for `u_new = a u_old + b`.
    fn renormalise(&mut self, old: (f64, f64), new: (f64, f64)) {
        let a = old.1 / new.1;
        let b = (old.0 - new.0) / new.1;
        let transform = |m: &mut [f64]| {
            let old_m: [f64; MOMENTS] = core::array::from_fn(|i| m.get(i).copied().unwrap_or(0.0));
            for n in 0..m.len() {
                let mut binom = 1.0;
                let mut sum = 0.0;
                for k in 0..=n {
                    sum += binom * libm::pow(a, k as f64) * libm::pow(b, (n - k) as f64) * old_m[k];
                    binom = binom * (n - k) as f64 / (k + 1) as f64;
                }
                m[n] = sum;
            }
        };
        transform(&mut self.u_moments[..=2 * self.degree]);
        transform(&mut self.xu_moments[..=self.degree]);
        self.interval = Some(new);
    }

    /// The fitted sensor model with the readings' noise variance `noise_var`
    /// (px^2) corrected for, or `None` while the data do not determine it.
    /// If the corrected normal equations are not positive definite (too little
    /// data for the noise), the correction is halved until they are.
    pub(crate) fn sensor_model(&self, noise_var: f64) -> Option<Polynomial> {
        let (centre, half_width) = self.interval?;
        if self.points <= self.degree as u64 {
            return None;
        }
        let mut s2 = (noise_var / (half_width * half_width)).max(0.0);
        for _ in 0..20 {
            if let Some(q) = self.solve(s2) {
                return Polynomial::from_normalised(&q[..=self.degree], centre, half_width)
                    .filter(Polynomial::is_finite);
            }
            s2 *= 0.5;
        }
        self.solve(0.0).and_then(|q| {
            Polynomial::from_normalised(&q[..=self.degree], centre, half_width)
                .filter(Polynomial::is_finite)
        })
    }

    /// `sum w He_n(u; s2)` from the raw sums `m`: `He_n = sum_k c_nk s2^k
    /// u^(n - 2k)`, `c_nk = (-1)^k n! / (k! (n - 2k)! 2^k)`.
    fn corrected(m: &[f64], n: usize, s2: f64) -> f64 {
        let mut sum = 0.0;
        let mut c = 1.0; // c_n0
        let mut s2k = 1.0;
        for k in 0..=n / 2 {
            sum += c * s2k * m[n - 2 * k];
            // c_{n,k+1} = -c_nk (n - 2k)(n - 2k - 1) / (2 (k + 1))
            if n >= 2 * k + 2 {
                c = -c * ((n - 2 * k) * (n - 2 * k - 1)) as f64 / (2 * (k + 1)) as f64;
            }
            s2k *= s2;
        }
        sum
    }

    /// The corrected normal equations' solution by Cholesky, or `None` if they
    /// are not positive definite.
    fn solve(&self, s2: f64) -> Option<[f64; MAX_EIV_DEGREE + 1]> {
        let p = self.degree + 1;
        let mut a = [[0.0; MAX_EIV_DEGREE + 1]; MAX_EIV_DEGREE + 1];
        let mut b = [0.0; MAX_EIV_DEGREE + 1];
        for j in 0..p {
            for k in 0..p {
                a[j][k] = Self::corrected(&self.u_moments, j + k, s2);
            }
            b[j] = Self::corrected(&self.xu_moments, j, s2);
        }
        // Cholesky a = L L^T, in place (lower triangle).
        for j in 0..p {
            let mut d = a[j][j];
            for k in 0..j {
                d -= a[j][k] * a[j][k];
            }
            if d.is_nan() || d <= 1e-12 * a[0][0].abs() {
                return None;
            }
            let d = libm::sqrt(d);
            a[j][j] = d;
            for i in j + 1..p {
                let mut v = a[i][j];
                for k in 0..j {
                    v -= a[i][k] * a[j][k];
                }
                a[i][j] = v / d;
            }
        }
        let mut y = [0.0; MAX_EIV_DEGREE + 1];
        for i in 0..p {
            let mut v = b[i];
            for k in 0..i {
                v -= a[i][k] * y[k];
            }
            y[i] = v / a[i][i];
        }
        let mut x = [0.0; MAX_EIV_DEGREE + 1];
        for i in (0..p).rev() {
            let mut v = y[i];
            for k in i + 1..p {
                v -= a[k][i] * x[k];
            }
            x[i] = v / a[i][i];
        }
        x[..p].iter().all(|v| v.is_finite()).then_some(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::poly_fit::PolynomialFit;

    /// Pseudo-Gaussian noise (sum of uniforms) from a fixed generator.
    fn noise(state: &mut u64) -> f64 {
        (0..12)
            .map(|_| {
                *state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (*state >> 11) as f64 / (1u64 << 53) as f64
            })
            .sum::<f64>()
            - 6.0
    }

    /// A pinhole reading `40000 / x` over 1.2-3.6 m with 1.6 px of noise: the
    /// plain fit is flattened by the noise, the corrected one is not (it comes
    /// within a few mm of the noise-free fit), and the noise is estimated from
    /// the readings alone.
    #[test]
    fn the_correction_removes_the_noise_bias() {
        let (mut clean, mut plain, mut corrected) = (
            PolynomialFit::new(3, 1.0),
            PolynomialFit::new(3, 1.0),
            EivFit::new(3, 1.0),
        );
        let mut est = NoiseEstimate::default();
        let mut state = 1;
        for k in 0..20_000 {
            let t = f64::from(k) * 0.05;
            let x = 2400.0 + 1200.0 * (t * 0.05).sin();
            let o = 40_000.0 / x;
            let obs = o + 1.6 * noise(&mut state);
            est.observe(t, obs, 1.0);
            clean.add(o, x);
            plain.add(obs, x);
            corrected.add(obs, x);
        }
        let var = est.variance().expect("estimated");
        assert!((var.sqrt() - 1.6).abs() < 0.1, "sigma {:.3}", var.sqrt());
        let (clean, plain, corrected) = (
            clean.polynomial().expect("clean"),
            plain.polynomial().expect("plain"),
            corrected.sensor_model(var).expect("corrected"),
        );
        let err = |p: &Polynomial| {
            [12.0, 15.0, 20.0, 26.0, 32.0]
                .iter()
                .map(|&o| (p.eval(o) - clean.eval(o)).abs())
                .fold(0.0, f64::max)
        };
        assert!(
            err(&plain) > 100.0,
            "the plain fit is biased: {:.0}",
            err(&plain)
        );
        assert!(
            err(&corrected) < 25.0,
            "corrected misses by {:.0}",
            err(&corrected)
        );
    }

    /// With no noise the corrected fit is the plain one, whatever the interval's
    /// widenings.
    #[test]
    fn without_noise_it_is_the_least_squares_fit() {
        let (mut plain, mut corrected) = (PolynomialFit::new(3, 0.99), EivFit::new(3, 0.99));
        for k in 0..300 {
            let obs = 10.0 + 0.1 * f64::from(k);
            let x = 5.0 - 0.3 * obs + 0.01 * obs * obs + (f64::from(k) * 1.7).sin();
            plain.add(obs, x);
            corrected.add(obs, x);
        }
        let (p, c) = (
            plain.polynomial().expect("plain"),
            corrected.sensor_model(0.0).expect("corrected"),
        );
        for o in [10.0, 20.0, 30.0, 40.0] {
            assert!((p.eval(o) - c.eval(o)).abs() < 1e-6, "at {o}");
        }
    }
}
