//! Learning the action model from location estimates (the paper's Eq. 5): a
//! linear regression of `x_s(t_k)` on `V_i(t_k) = integral_0^t C(s)^i ds`,
//! `i = 0..d` (`V_0 = t`), with intercept `x(0)`. Commands are normalised by a
//! fixed scale so that `|C / scale| <= 1` and every `V_i` grows no faster than `t`.
//!
//! With a prior (`ScasmConfig::action_prior`, strength `k > 0`) the fit is the
//! maximum a posteriori one: each coefficient of degree 2 and above, in
//! normalised command units, is `~ N(0, (scale / k)^2)`. Weighed against the
//! fit's residual noise `sigma` (estimated from the fit itself: its weighted
//! residual sum of squares over its weighted points less its unknowns), each
//! is one pseudo-observation `b_i = 0` of weight `sigma k / scale`. A quartic
//! fitted to the first seconds' few commands swings wildly between and beyond
//! them; the prior keeps it near a line until the data say otherwise.

use crate::polynomial::Polynomial;
use crate::wls::{IncrementalWls, MAX_COLS};

/// The running integrals `V_i` and the fit of locations on them.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct ActionFit {
    wls: IncrementalWls,
    degree: usize,
    command_scale: f64,
    /// The prior's strength (0: none).
    #[cfg_attr(feature = "serde", serde(default))]
    prior: f64,
    /// `V_i = integral_0^t (C / command_scale)^i ds`, `i = 0..=degree`.
    integrals: [f64; MAX_COLS],
}

impl ActionFit {
    /// An empty fit of an action model of the given degree (its `degree + 1`
    /// regressors are at most MAX_REGRESSORS), forgetting factor, command
    /// scale and prior strength (0: none; see the module's doc).
    pub(crate) fn new(degree: usize, gamma: f64, command_scale: f64, prior: f64) -> Self {
        Self {
            wls: IncrementalWls::new(degree + 1, gamma),
            degree,
            command_scale,
            prior,
            integrals: [0.0; MAX_COLS],
        }
    }

    /// Accounts for `command` held for `dt_s` seconds.
    pub(crate) fn integrate(&mut self, command: f64, dt_s: f64) {
        let u = command / self.command_scale;
        let mut p = 1.0;
        for v in &mut self.integrals[..=self.degree] {
            *v += p * dt_s;
            p *= u;
        }
    }

    /// Adds the location estimate `x_s` at the current time.
    pub(crate) fn add(&mut self, x_s: f64) {
        self.wls.add(&self.integrals[..=self.degree], x_s);
    }

    /// The prior's pseudo-observation weights, per column of the fit
    /// (intercept, `V_0..V_d`); `None` without a prior, for a line (which the
    /// prior leaves alone) and while the fit has no residual degrees of
    /// freedom to measure its noise by (the fit is then least squares').
    fn ridge(&self) -> Option<[f64; MAX_COLS]> {
        let unknowns = (self.degree + 2) as f64;
        let dof = self.wls.weight() - unknowns;
        if self.prior == 0.0 || self.degree < 2 || dof <= 0.0 {
            return None;
        }
        let sigma = libm::sqrt(self.wls.residual_ss() / dof);
        let w = sigma * self.prior / self.command_scale;
        let mut ridge = [0.0; MAX_COLS];
        for r in &mut ridge[3..=self.degree + 1] {
            *r = w;
        }
        Some(ridge)
    }

    /// The fitted action model (command -> location units per second) in raw
    /// command units, and the fitted start location `x(0)`; `None` while the
    /// data do not determine them.
    pub(crate) fn model(&self) -> Option<(Polynomial, f64)> {
        let b = match self.ridge() {
            Some(ridge) => self.wls.solve_with_ridge(&ridge)?,
            None => self.wls.solve()?,
        };
        let mut coeffs = [0.0; MAX_COLS];
        let mut scale_pow = 1.0;
        for (c, &bi) in coeffs[..=self.degree]
            .iter_mut()
            .zip(&b[1..=self.degree + 1])
        {
            *c = bi / scale_pow;
            scale_pow *= self.command_scale;
        }
        let model = Polynomial::new(&coeffs[..=self.degree]).filter(Polynomial::is_finite)?;
        Some((model, b[0]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fit fed `x(t) = x0 + integral of v(C)` (plus a small deterministic
    /// wobble, so that the fit has residual noise to weigh its prior by) over
    /// `commands`, each held for 2 s, sampled at 20 Hz.
    fn fit(prior: f64, commands: &[f64], v: impl Fn(f64) -> f64) -> ActionFit {
        let mut f = ActionFit::new(4, 1.0, 300.0, prior);
        let (mut x, mut k) = (100.0, 0u32);
        for &c in commands {
            for _ in 0..40 {
                f.integrate(c, 0.05);
                x += v(c) * 0.05;
                k += 1;
                f.add(x + 3.0 * libm::sin(f64::from(k) * 1.7));
            }
        }
        f
    }

    #[test]
    fn no_prior_needs_as_many_commands_as_unknowns_and_the_prior_fills_in_a_line() {
        let line = |c: f64| 0.8 * c + 20.0;
        // Two command levels cannot determine a quartic by least squares...
        assert!(
            fit(0.0, &[100.0, -200.0, 100.0, -200.0], line)
                .model()
                .is_none()
        );
        // ...but with the prior they determine it as nearly the line through them.
        let (a, _) = fit(10.0, &[100.0, -200.0, 100.0, -200.0], line)
            .model()
            .expect("the prior determines the fit");
        for c in [-300.0, -100.0, 0.0, 200.0, 300.0] {
            assert!((a.eval(c) - line(c)).abs() < 5.0, "A({c}) = {}", a.eval(c));
        }
    }

    #[test]
    fn plentiful_data_outweigh_the_prior() {
        // A curved response seen at many commands: the prior (a line) is
        // outweighed, and the fit follows the curve.
        let curve = |c: f64| 0.5 * c + 0.002 * c * c - 1e-8 * c * c * c * c;
        let commands: Vec<f64> = (0..200)
            .map(|i| 300.0 * libm::sin(f64::from(i) * 2.39))
            .collect();
        let (a, _) = fit(10.0, &commands, curve).model().expect("determined");
        let (ls, _) = fit(0.0, &commands, curve).model().expect("determined");
        for c in [-300.0, -150.0, 0.0, 150.0, 300.0] {
            // The curve's departure from a line is about 180 mm/s at the ends.
            assert!((a.eval(c) - curve(c)).abs() < 3.0, "A({c}) = {}", a.eval(c));
            assert!(
                (ls.eval(c) - curve(c)).abs() < 3.0,
                "LS({c}) = {}",
                ls.eval(c)
            );
        }
    }
}
