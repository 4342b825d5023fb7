//! The SCASM learner (the paper's Fig. 4) and its one-sided special cases
//! (sections IV and V), all driven through [`CalibrationLearner`].

use crate::action_fit::ActionFit;
use crate::config::{ScasmParams, SensorFit};
use crate::eiv_fit::{EivFit, NoiseEstimate};
use crate::error::{ConfigError, EventError};
use crate::learner::{CalibrationLearner, Event};
use crate::mode::Mode;
use crate::poly_fit::PolynomialFit;
use crate::polynomial::Polynomial;
use crate::self_check::{Guard, SelfCheck};

/// How far (s) an event's time may stray from the learner's clock, for hosts
/// that add up their time steps in another order.
const TIME_TOLERANCE_S: f64 = 1e-6;

/// Simultaneous Calibration of Action and Sensor Models.
///
/// Dead reckoning `x_a` starts at 0 with the identity action model A0; S learns
/// from `(obs, x_a)` from the start, A learns from `(t, S(obs))` after `t_start`,
/// and from `2 t_start` dead reckoning uses the learned A. Each reading pulls
/// `x_a` a fraction `beta` towards `x_s`, which keeps the pair from drifting apart.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Scasm {
    params: ScasmParams,
    mode: Mode,
    /// End of the last command interval, s.
    clock_s: f64,
    x_a: f64,
    x_s: Option<f64>,
    sensor_fit: SensorFitState,
    action_fit: ActionFit,
    sensor_model: Option<Polynomial>,
    action_model: Option<Polynomial>,
    /// The intercept `x(0)` of the action fit (Eq. 5).
    #[cfg_attr(feature = "serde", serde(default))]
    action_start: Option<f64>,
    /// Readings (and their `x_a`) gathered for the next point of the sensor fit.
    #[cfg_attr(feature = "serde", serde(default))]
    window: ReadingWindow,
    /// The check on itself, if it has one (see [`Scasm::with_self_check`]).
    #[cfg_attr(feature = "serde", serde(default))]
    guard: Option<Guard>,
}

/// The sensor fit in use (see [`SensorFit`]). A learner holds one, inline:
/// boxing the larger variant would need an allocator, which the crate does not.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[allow(clippy::large_enum_variant)]
enum SensorFitState {
    Inverse(PolynomialFit),
    Corrected {
        fit: EivFit,
        noise: NoiseEstimate,
        /// Readings averaged per point: the noise of a point's mean reading
        /// is the readings' over this.
        window: usize,
    },
}

impl SensorFitState {
    fn new(params: &ScasmParams) -> Self {
        // A point of the fit stands for `sensor_window` readings, so it is
        // discounted as many times: the fit's memory in time is gamma's.
        let gamma = libm::pow(params.gamma(), params.sensor_window() as f64);
        match params.sensor_fit() {
            SensorFit::Inverse => Self::Inverse(PolynomialFit::new(params.sensor_degree(), gamma)),
            SensorFit::Corrected => Self::Corrected {
                fit: EivFit::new(params.sensor_degree(), gamma),
                noise: NoiseEstimate::default(),
                window: params.sensor_window(),
            },
        }
    }

    /// Takes every reading as it comes (for the noise estimate).
    fn observe(&mut self, t_s: f64, obs_px: f64, gamma: f64) {
        if let Self::Corrected { noise, .. } = self {
            noise.observe(t_s, obs_px, gamma);
        }
    }

    fn add(&mut self, obs_px: f64, x: f64) {
        match self {
            Self::Inverse(f) => f.add(obs_px, x),
            Self::Corrected { fit, .. } => fit.add(obs_px, x),
        }
    }

    fn sensor_model(&self) -> Option<Polynomial> {
        match self {
            Self::Inverse(f) => f.polynomial(),
            Self::Corrected { fit, noise, window } => {
                fit.sensor_model(noise.variance()? / *window as f64)
            }
        }
    }

    fn points(&self) -> u64 {
        match self {
            Self::Inverse(f) => f.points(),
            Self::Corrected { fit, .. } => fit.points(),
        }
    }
}

/// Sums of the readings, and of `x_a` at them, for one point of the sensor fit.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct ReadingWindow {
    obs_sum: f64,
    x_a_sum: f64,
    count: usize,
}

impl Default for Scasm {
    /// The simultaneous learner with the default hyper-parameters (the paper's,
    /// with readings averaged in fives for the sensor fit: see [`crate::ScasmConfig`]).
    fn default() -> Self {
        Self::build(ScasmParams::default(), Mode::Simultaneous)
    }
}

impl Scasm {
    /// A learner in the given mode; a model given to a one-sided mode must be finite.
    pub fn new(params: ScasmParams, mode: Mode) -> Result<Self, ConfigError> {
        match mode {
            Mode::SensorFromAction(a) if !a.is_finite() => {
                Err(ConfigError::GivenModel { which: "action" })
            }
            Mode::ActionFromSensor(s) if !s.is_finite() => {
                Err(ConfigError::GivenModel { which: "sensor" })
            }
            _ => Ok(Self::build(params, mode)),
        }
    }

    fn build(params: ScasmParams, mode: Mode) -> Self {
        Self {
            params,
            mode,
            clock_s: 0.0,
            x_a: 0.0,
            x_s: None,
            sensor_fit: SensorFitState::new(&params),
            action_fit: ActionFit::new(
                params.action_degree(),
                params.gamma(),
                params.command_scale(),
                params.action_prior(),
            )
            .robust(params.action_highpass_s(), params.action_robust()),
            sensor_model: None,
            action_model: None,
            action_start: None,
            window: ReadingWindow::default(),
            guard: None,
        }
    }

    /// A learner in the given mode that checks itself (simultaneous mode
    /// only: the one-sided modes, which learn from a model given, are built
    /// as by [`Scasm::new`]). From `2 t_start`, when dead reckoning uses the
    /// learned action model, each reading checks that both models are still
    /// monotone over their inputs: A over the command range
    /// (`±command_scale`, and any command seen beyond it), S over the
    /// readings of its fit's points so far (each the mean of
    /// `sensor_window` readings), within [`crate::self_check::TURN_TOLERANCE`]
    /// of their values' range. A walk's response and a camera's reading of a
    /// beacon are; a coupling whose model has turned back on itself has
    /// learned something false. From a failed check until
    /// the next pass, the learner reports the last models that passed every
    /// check for `good_after_s` (if they pass over the inputs seen by then)
    /// instead of its own; the coupling itself runs on unchanged, and
    /// reports its own models again as soon as they pass. In a trial whose
    /// models never fail, it is [`Scasm::new`]'s learner, bit for bit.
    pub fn with_self_check(
        params: ScasmParams,
        mode: Mode,
        check: SelfCheck,
    ) -> Result<Self, ConfigError> {
        if !(check.good_after_s.is_finite() && check.good_after_s >= 0.0) {
            return Err(ConfigError::GoodAfter {
                good_after_s: check.good_after_s,
            });
        }
        let mut learner = Self::new(params, mode)?;
        if mode == Mode::Simultaneous {
            learner.guard = Some(Guard::new(check, params.command_scale()));
        }
        Ok(learner)
    }

    /// How many times the self-check has failed with good models to fall
    /// back to (0 for a learner without one).
    pub fn fallbacks(&self) -> u32 {
        self.guard.as_ref().map_or(0, Guard::fallbacks)
    }

    fn fallback(&self) -> Option<(Polynomial, Polynomial)> {
        self.guard.as_ref().and_then(Guard::fallback)
    }

    /// The hyper-parameters in use.
    pub fn params(&self) -> &ScasmParams {
        &self.params
    }

    /// The learning mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The learner's clock: the end of the last command interval, s.
    pub fn clock_s(&self) -> f64 {
        self.clock_s
    }

    /// The location at time 0 that the action fit (Eq. 5) found beside A: the
    /// learned path is `x(t) = x(0) + integral of A(C(s)) ds`, in S's units.
    pub fn action_start(&self) -> Option<f64> {
        self.action_start
    }

    /// Points the sensor fit has learned from (each the mean of `sensor_window`
    /// readings).
    pub fn sensor_points(&self) -> u64 {
        self.sensor_fit.points()
    }

    /// The action model dead reckoning uses for a command starting at `t_s`.
    fn reckoning_model(&self, t_s: f64) -> Polynomial {
        match self.mode {
            Mode::SensorFromAction(a) => a,
            Mode::SensorFromConstantAction => Polynomial::constant(1.0),
            Mode::ActionFromSensor(_) => self.action_model.unwrap_or_else(Polynomial::identity),
            Mode::Simultaneous if t_s < 2.0 * self.params.t_start_s() => Polynomial::identity(),
            Mode::Simultaneous => self.action_model.unwrap_or_else(Polynomial::identity),
        }
    }

    fn check_time(&self, t_s: f64) -> Result<(), EventError> {
        finite("t_s", t_s)?;
        if t_s < self.clock_s - TIME_TOLERANCE_S {
            return Err(EventError::TimeWentBackwards {
                t_s,
                clock_s: self.clock_s,
            });
        }
        if t_s > self.clock_s + TIME_TOLERANCE_S {
            return Err(EventError::TimeGap {
                t_s,
                clock_s: self.clock_s,
            });
        }
        Ok(())
    }

    fn on_command(&mut self, t_s: f64, dt_s: f64, command: f64) -> Result<(), EventError> {
        self.check_time(t_s)?;
        finite("dt_s", dt_s)?;
        finite("command", command)?;
        if dt_s <= 0.0 {
            return Err(EventError::NonPositiveDuration { dt_s });
        }
        let velocity = self.reckoning_model(t_s).eval(command);
        if velocity.is_finite() {
            self.x_a += velocity * dt_s;
        }
        self.action_fit.integrate(command, dt_s);
        if let Some(g) = &mut self.guard {
            g.saw_command(command);
        }
        self.clock_s = t_s + dt_s;
        Ok(())
    }

    fn on_reading(&mut self, t_s: f64, obs_px: f64) -> Result<(), EventError> {
        self.check_time(t_s)?;
        finite("obs_px", obs_px)?;
        if obs_px <= 0.0 {
            return Err(EventError::NonPositiveReading { obs_px });
        }
        self.sensor_fit.observe(t_s, obs_px, self.params.gamma());
        match self.mode {
            Mode::Simultaneous => {
                if t_s > self.params.t_start_s() {
                    if let Some(x_s) = self.sensor_estimate(obs_px) {
                        self.learn_action(x_s);
                        let beta = self.params.beta();
                        self.x_a = (1.0 - beta) * self.x_a + beta * x_s;
                    }
                }
                self.learn_sensor(obs_px);
                self.check_self(t_s);
            }
            Mode::SensorFromConstantAction | Mode::SensorFromAction(_) => {
                self.learn_sensor(obs_px);
                self.x_s = self.sensor_model.map(|s| s.eval(obs_px));
            }
            Mode::ActionFromSensor(s) => {
                let x_s = s.eval(obs_px);
                self.x_s = Some(x_s);
                self.learn_action(x_s);
            }
        }
        Ok(())
    }

    /// The self-check after a reading at `t_s` (see [`Scasm::with_self_check`]).
    fn check_self(&mut self, t_s: f64) {
        if t_s < 2.0 * self.params.t_start_s() {
            return;
        }
        let models = self.action_model.zip(self.sensor_model);
        if let (Some(guard), Some(models)) = (&mut self.guard, models) {
            guard.check(t_s, models);
        }
    }

    /// `S_t(obs)`, recorded as the latest `x_s`, if S exists and gives a number.
    fn sensor_estimate(&mut self, obs_px: f64) -> Option<f64> {
        self.x_s = self
            .sensor_model
            .map(|s| s.eval(obs_px))
            .filter(|x| x.is_finite());
        self.x_s
    }

    fn learn_action(&mut self, x_s: f64) {
        self.action_fit.add(x_s);
        let fit = self.action_fit.model();
        self.action_model = fit.map(|(a, _)| a);
        self.action_start = fit.map(|(_, x0)| x0);
    }

    /// Adds the reading and `x_a` to the window; a full window becomes one point
    /// of the sensor fit, at the means of both.
    fn learn_sensor(&mut self, obs_px: f64) {
        if !self.x_a.is_finite() {
            return;
        }
        let w = &mut self.window;
        w.obs_sum += obs_px;
        w.x_a_sum += self.x_a;
        w.count += 1;
        if w.count >= self.params.sensor_window() {
            let n = w.count as f64;
            self.sensor_fit.add(w.obs_sum / n, w.x_a_sum / n);
            // S is checked over the readings it is fitted to: the points'
            // (a noisy camera's single extremes would raise false alarms).
            if let Some(guard) = &mut self.guard {
                guard.saw_reading(w.obs_sum / n);
            }
            self.window = ReadingWindow::default();
            self.sensor_model = self.sensor_fit.sensor_model();
        }
    }
}

fn finite(field: &'static str, value: f64) -> Result<(), EventError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(EventError::NonFinite { field, value })
    }
}

impl CalibrationLearner for Scasm {
    /// The variant its settings make it: `scasm-eiv` (noise-corrected sensor
    /// fit), `scasm-paper` (every reading its own point, A by least squares)
    /// or `scasm`.
    fn name(&self) -> &str {
        let paper = self.params.sensor_window() == 1
            && self.params.action_prior() == 0.0
            && self.params.action_highpass_s() == 0.0
            && self.params.action_robust() == 0.0;
        match (self.params.sensor_fit(), paper) {
            (SensorFit::Corrected, _) => "scasm-eiv",
            (SensorFit::Inverse, true) => "scasm-paper",
            (SensorFit::Inverse, false) => "scasm",
        }
    }

    fn handle(&mut self, event: Event) -> Result<(), EventError> {
        match event {
            Event::Command { t_s, dt_s, command } => self.on_command(t_s, dt_s, command),
            Event::Reading { t_s, obs_px } => self.on_reading(t_s, obs_px),
        }
    }

    fn action_model(&self) -> Option<Polynomial> {
        match self.mode {
            Mode::SensorFromAction(a) => Some(a),
            _ => self.fallback().map(|(a, _)| a).or(self.action_model),
        }
    }

    fn sensor_model(&self) -> Option<Polynomial> {
        match self.mode {
            Mode::ActionFromSensor(s) => Some(s),
            _ => self.fallback().map(|(_, s)| s).or(self.sensor_model),
        }
    }

    fn x_a(&self) -> Option<f64> {
        Some(self.x_a)
    }

    fn x_s(&self) -> Option<f64> {
        self.x_s
    }

    fn falling_back(&self) -> Option<bool> {
        self.guard.as_ref().map(|g| g.fallback().is_some())
    }
}
