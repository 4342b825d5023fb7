//! The learner's hyper-parameters: [`ScasmConfig`] as written by a user (defaults
//! are the paper's constants, except the sensor fit's reading window, which the
//! paper does not have), checked once into [`ScasmParams`] which code can trust.

use crate::MAX_REGRESSORS;
use crate::eiv_fit::MAX_EIV_DEGREE;
use crate::error::ConfigError;

/// SCASM's hyper-parameters as a user writes them. Check them with
/// [`ScasmConfig::validate`].
///
/// ```
/// let params = scasm::ScasmConfig { gamma: 0.995, ..Default::default() }.validate()?;
/// assert_eq!(params.gamma(), 0.995);
/// # Ok::<(), scasm::ConfigError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields, default)
)]
pub struct ScasmConfig {
    /// Forgetting factor in (0, 1]: point k of n weighs `gamma^(n-k)`.
    pub gamma: f64,
    /// Pull of `x_a` towards `x_s` at each reading, in [0, 1].
    pub beta: f64,
    /// Ramp-up time in seconds: only S learns before it, A learns from it, and
    /// dead reckoning uses the learned A from twice it.
    #[cfg_attr(feature = "serde", serde(rename = "t_start"))]
    pub t_start_s: f64,
    /// Degree of the sensor model S (pixels -> location), 1..=MAX_REGRESSORS.
    pub sensor_degree: usize,
    /// Degree of the action model A (command -> velocity), 1..MAX_REGRESSORS.
    pub action_degree: usize,
    /// Commands are divided by this inside the action fit (the largest command
    /// magnitude is a good choice); the fitted function does not depend on it.
    pub command_scale: f64,
    /// Readings averaged, with their `x_a`, into each point of the sensor fit
    /// (1..=MAX_SENSOR_WINDOW; 1 is the paper's algorithm). Averaging k readings
    /// divides the reading noise's variance by k, which shrinks the bias of
    /// regressing location on a noisy reading (errors in variables). Each such
    /// point is discounted by `gamma^k`, so the fit's memory in time is unchanged.
    pub sensor_window: usize,
    /// How S is fitted: as the paper does, or with the reading's noise
    /// corrected for (no errors-in-variables bias).
    pub sensor_fit: SensorFit,
    /// Degree of the forward sensor model `obs ~ g(x)` a batch learner fits,
    /// 1..=MAX_REGRESSORS.
    pub forward_degree: usize,
    /// Strength `k` of the action fit's prior that A is nearly linear
    /// (maximum a posteriori, in place of Eq. 5's least squares): each of A's
    /// coefficients of degree 2 and above, with commands divided by
    /// `command_scale`, is taken as `~ N(0, (command_scale / k)^2)`, weighed
    /// against the fit's own residual noise. Early in a trial, when the
    /// commands seen so far leave a quartic free to swing, A stays close to a
    /// line; as data come, they outweigh it. Finite and at least 0; 0 is no
    /// prior (the paper's).
    pub action_prior: f64,
    /// Time constant, s, of the high-pass both sides of the action fit go
    /// through, so that a distance lost in a stall fades from it (0: none,
    /// the paper's Eq. 5; see `action_fit`'s doc).
    #[cfg_attr(feature = "serde", serde(rename = "action_highpass"))]
    pub action_highpass_s: f64,
    /// The action fit's robust weight: a point whose residual is beyond this
    /// many residual standard deviations is weighed down (Huber's; 0: least
    /// squares, the paper's).
    pub action_robust: f64,
}

/// How the sensor model is fitted to `(reading, x_a)` pairs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
pub enum SensorFit {
    /// The paper's: location regressed on the reading (Eq. 2-7). Noise in the
    /// reading biases it (errors in variables).
    #[default]
    Inverse,
    /// The same regression with the reading's noise corrected for (corrected
    /// score), its variance estimated from the readings themselves: no
    /// errors-in-variables bias. Degree at most 5.
    Corrected,
}

/// The largest [`ScasmConfig::sensor_window`].
pub const MAX_SENSOR_WINDOW: usize = 100;

impl Default for ScasmConfig {
    /// The paper's values (gamma 0.999, degrees 3 and 4) but for six of
    /// ours, chosen on the testbed's development seeds: readings averaged in
    /// fives for the sensor fit (a quarter of a second at 20 Hz; the paper has
    /// 1), a weaker pull (beta 0.01; the paper's is 1/30), a longer start
    /// (t_start 30 s; the paper's is 20 s), a prior that A is nearly linear
    /// (action_prior 10; the paper has none), and an action fit that a stall
    /// moves less (a high-pass of 5 s and a robust weight beyond 1.5
    /// standard deviations; the paper's is least squares on Eq. 5).
    /// [`ScasmConfig::paper`] is the paper's exactly.
    fn default() -> Self {
        Self {
            gamma: 0.999,
            beta: 0.01,
            t_start_s: 30.0,
            sensor_degree: 3,
            action_degree: 4,
            command_scale: 300.0,
            sensor_window: 5,
            sensor_fit: SensorFit::Inverse,
            forward_degree: 5,
            action_prior: 10.0,
            action_highpass_s: 5.0,
            action_robust: 1.5,
        }
    }
}

impl ScasmConfig {
    /// The same memory, pull and start measured in time, for an experiment
    /// whose times are all `factor` times longer (a larger robot walking the
    /// same gait more slowly; readings still come at the same rate): `t_start`
    /// times `factor`, and `gamma` and `beta`, which act once per reading,
    /// such that `factor` times as many readings forget and pull as much.
    /// `factor` 1 changes nothing.
    #[must_use]
    pub fn time_scaled(self, factor: f64) -> Self {
        if factor == 1.0 {
            return self;
        }
        Self {
            gamma: libm::pow(self.gamma, 1.0 / factor),
            beta: 1.0 - libm::pow(1.0 - self.beta, 1.0 / factor),
            t_start_s: self.t_start_s * factor,
            action_highpass_s: self.action_highpass_s * factor,
            ..self
        }
    }

    /// Checks every value's range.
    pub fn validate(self) -> Result<ScasmParams, ConfigError> {
        if !(self.gamma > 0.0 && self.gamma <= 1.0) {
            return Err(ConfigError::Gamma { gamma: self.gamma });
        }
        if !(0.0..=1.0).contains(&self.beta) {
            return Err(ConfigError::Beta { beta: self.beta });
        }
        if !(self.t_start_s.is_finite() && self.t_start_s >= 0.0) {
            return Err(ConfigError::TStart {
                t_start_s: self.t_start_s,
            });
        }
        if !(1..=MAX_REGRESSORS).contains(&self.sensor_degree) {
            return Err(ConfigError::SensorDegree {
                degree: self.sensor_degree,
                max: MAX_REGRESSORS,
            });
        }
        if !(1..MAX_REGRESSORS).contains(&self.action_degree) {
            return Err(ConfigError::ActionDegree {
                degree: self.action_degree,
                max: MAX_REGRESSORS - 1,
            });
        }
        if !(self.command_scale.is_finite() && self.command_scale > 0.0) {
            return Err(ConfigError::CommandScale {
                command_scale: self.command_scale,
            });
        }
        if self.sensor_fit == SensorFit::Corrected && self.sensor_degree > MAX_EIV_DEGREE {
            return Err(ConfigError::SensorDegree {
                degree: self.sensor_degree,
                max: MAX_EIV_DEGREE,
            });
        }
        if !(1..=MAX_REGRESSORS).contains(&self.forward_degree) {
            return Err(ConfigError::ForwardDegree {
                degree: self.forward_degree,
                max: MAX_REGRESSORS,
            });
        }
        if !(1..=MAX_SENSOR_WINDOW).contains(&self.sensor_window) {
            return Err(ConfigError::SensorWindow {
                window: self.sensor_window,
                max: MAX_SENSOR_WINDOW,
            });
        }
        if !(self.action_prior.is_finite() && self.action_prior >= 0.0) {
            return Err(ConfigError::ActionPrior {
                action_prior: self.action_prior,
            });
        }
        if !(self.action_highpass_s.is_finite() && self.action_highpass_s >= 0.0) {
            return Err(ConfigError::ActionHighpass {
                action_highpass_s: self.action_highpass_s,
            });
        }
        if !(self.action_robust.is_finite() && self.action_robust >= 0.0) {
            return Err(ConfigError::ActionRobust {
                action_robust: self.action_robust,
            });
        }
        Ok(ScasmParams(self))
    }

    /// The paper's values exactly: gamma 0.999, beta 1/30, t_start 20 s,
    /// degrees 3 and 4, every reading its own point of the sensor fit, and
    /// A fitted by least squares (no prior).
    #[must_use]
    pub fn paper() -> Self {
        Self {
            beta: 1.0 / 30.0,
            t_start_s: 20.0,
            sensor_window: 1,
            action_prior: 0.0,
            action_highpass_s: 0.0,
            action_robust: 0.0,
            ..Self::default()
        }
    }
}

/// Checked hyper-parameters: every value is in range. The default is
/// [`ScasmConfig::default`]: the paper's constants but for a reading window of
/// 5, beta 0.01, t_start 30 s, a prior on A and a high-passed, robust action
/// fit (the paper's are [`ScasmConfig::paper`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(try_from = "ScasmConfig", into = "ScasmConfig")
)]
pub struct ScasmParams(ScasmConfig);

impl TryFrom<ScasmConfig> for ScasmParams {
    type Error = ConfigError;
    fn try_from(config: ScasmConfig) -> Result<Self, ConfigError> {
        config.validate()
    }
}

impl From<ScasmParams> for ScasmConfig {
    fn from(params: ScasmParams) -> Self {
        params.0
    }
}

impl ScasmParams {
    /// Forgetting factor in (0, 1].
    pub fn gamma(&self) -> f64 {
        self.0.gamma
    }
    /// Pull towards `x_s`, in [0, 1].
    pub fn beta(&self) -> f64 {
        self.0.beta
    }
    /// Ramp-up time in seconds.
    pub fn t_start_s(&self) -> f64 {
        self.0.t_start_s
    }
    /// Degree of S.
    pub fn sensor_degree(&self) -> usize {
        self.0.sensor_degree
    }
    /// Degree of A.
    pub fn action_degree(&self) -> usize {
        self.0.action_degree
    }
    /// Readings per point of the sensor fit.
    pub fn sensor_window(&self) -> usize {
        self.0.sensor_window
    }
    /// How S is fitted.
    pub fn sensor_fit(&self) -> SensorFit {
        self.0.sensor_fit
    }
    /// Degree of a batch learner's forward sensor model.
    pub fn forward_degree(&self) -> usize {
        self.0.forward_degree
    }
    /// Strength of the action fit's prior that A is nearly linear (0: none).
    pub fn action_prior(&self) -> f64 {
        self.0.action_prior
    }
    /// Time constant of the action fit's high-pass, s (0: none).
    pub fn action_highpass_s(&self) -> f64 {
        self.0.action_highpass_s
    }
    /// Threshold of the action fit's robust weight, in residual standard
    /// deviations (0: none).
    pub fn action_robust(&self) -> f64 {
        self.0.action_robust
    }

    /// See [`ScasmConfig::command_scale`].
    pub fn command_scale(&self) -> f64 {
        self.0.command_scale
    }
    /// The values as a plain config.
    pub fn config(&self) -> ScasmConfig {
        self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_scaling_keeps_memory_and_pull_per_second() {
        let base = ScasmConfig::default();
        assert_eq!(base.time_scaled(1.0), base);
        let slow = base.time_scaled(2.0);
        // Twice as many readings forget and pull as much as before.
        assert!((slow.gamma * slow.gamma - base.gamma).abs() < 1e-15);
        assert!(((1.0 - slow.beta) * (1.0 - slow.beta) - (1.0 - base.beta)).abs() < 1e-15);
        assert_eq!(slow.t_start_s, 2.0 * base.t_start_s);
        assert_eq!(slow.action_highpass_s, 2.0 * base.action_highpass_s);
        assert_eq!(
            (slow.sensor_degree, slow.command_scale),
            (base.sensor_degree, base.command_scale)
        );
        assert!(slow.validate().is_ok());
    }

    #[test]
    fn the_action_fits_defences_refuse_what_is_not_a_time_or_a_threshold() {
        for bad in [-1.0, f64::NAN, f64::INFINITY] {
            let highpass = ScasmConfig {
                action_highpass_s: bad,
                ..Default::default()
            };
            assert!(
                matches!(highpass.validate(), Err(ConfigError::ActionHighpass { .. })),
                "action_highpass {bad}"
            );
            let robust = ScasmConfig {
                action_robust: bad,
                ..Default::default()
            };
            assert!(
                matches!(robust.validate(), Err(ConfigError::ActionRobust { .. })),
                "action_robust {bad}"
            );
        }
        let paper = ScasmConfig::paper();
        assert_eq!((paper.action_highpass_s, paper.action_robust), (0.0, 0.0));
    }
}
