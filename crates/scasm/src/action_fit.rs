//! Learning the action model from location estimates (the paper's Eq. 5): a
//! linear regression of `x_s(t_k)` on `V_i(t_k) = integral_0^t C(s)^i ds`,
//! `i = 0..d` (`V_0 = t`), with intercept `x(0)`. Commands are normalised by a
//! fixed scale so that `|C / scale| <= 1` and every `V_i` grows no faster than `t`.

use crate::polynomial::Polynomial;
use crate::wls::{IncrementalWls, MAX_COLS};

/// The running integrals `V_i` and the fit of locations on them.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct ActionFit {
    wls: IncrementalWls,
    degree: usize,
    command_scale: f64,
    /// `V_i = integral_0^t (C / command_scale)^i ds`, `i = 0..=degree`.
    integrals: [f64; MAX_COLS],
}

impl ActionFit {
    /// An empty fit of an action model of the given degree (its `degree + 1`
    /// regressors are at most MAX_REGRESSORS), forgetting factor and command scale.
    pub(crate) fn new(degree: usize, gamma: f64, command_scale: f64) -> Self {
        Self {
            wls: IncrementalWls::new(degree + 1, gamma),
            degree,
            command_scale,
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

    /// The fitted action model (command -> location units per second) in raw
    /// command units, and the fitted start location `x(0)`; `None` while the
    /// data do not determine them.
    pub(crate) fn model(&self) -> Option<(Polynomial, f64)> {
        let b = self.wls.solve()?;
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
