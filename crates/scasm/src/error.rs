//! Typed errors: what was wrong, with the offending value.

/// A configuration value outside its valid range.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ConfigError {
    /// The forgetting factor must lie in (0, 1].
    #[error("learner.gamma must be in (0, 1], got {gamma}")]
    Gamma {
        /// The value given.
        gamma: f64,
    },
    /// The pull towards the sensor estimate must lie in [0, 1].
    #[error("learner.beta must be in [0, 1], got {beta}")]
    Beta {
        /// The value given.
        beta: f64,
    },
    /// The ramp-up time must be finite and non-negative.
    #[error("learner.t_start must be a finite number of seconds >= 0, got {t_start_s}")]
    TStart {
        /// The value given.
        t_start_s: f64,
    },
    /// The sensor model's degree is out of range.
    #[error("learner.sensor_degree must be in 1..={max}, got {degree}")]
    SensorDegree {
        /// The value given.
        degree: usize,
        /// The largest degree supported.
        max: usize,
    },
    /// The forward sensor model's degree is out of range.
    #[error("learner.forward_degree must be in 1..={max}, got {degree}")]
    ForwardDegree {
        /// The value given.
        degree: usize,
        /// The largest degree supported.
        max: usize,
    },
    /// The action fit's prior strength is negative or not finite.
    #[error("learner.action_prior must be finite and at least 0 (0: no prior), got {action_prior}")]
    ActionPrior {
        /// The value given.
        action_prior: f64,
    },
    /// The action fit's high-pass time constant is negative or not finite.
    #[error(
        "learner.action_highpass must be finite and at least 0 s (0: no high-pass), got {action_highpass_s}"
    )]
    ActionHighpass {
        /// The value given.
        action_highpass_s: f64,
    },
    /// The action fit's robust threshold is negative or not finite.
    #[error(
        "learner.action_robust must be finite and at least 0 (0: least squares), got {action_robust}"
    )]
    ActionRobust {
        /// The value given.
        action_robust: f64,
    },
    /// The sensor fit's reading window is out of range.
    #[error("learner.sensor_window must be in 1..={max}, got {window}")]
    SensorWindow {
        /// The value given.
        window: usize,
        /// The largest window supported.
        max: usize,
    },
    /// The action model's degree is out of range.
    #[error("learner.action_degree must be in 1..={max}, got {degree}")]
    ActionDegree {
        /// The value given.
        degree: usize,
        /// The largest degree supported.
        max: usize,
    },
    /// The command normalisation must be finite and positive.
    #[error("learner.command_scale must be finite and > 0, got {command_scale}")]
    CommandScale {
        /// The value given.
        command_scale: f64,
    },
    /// The self-check's confirmation time must be finite and non-negative.
    #[error(
        "the self-check's good_after_s must be a finite number of seconds >= 0, got {good_after_s}"
    )]
    GoodAfter {
        /// The value given.
        good_after_s: f64,
    },
    /// The batch learner's solve period must be finite and positive.
    #[error("batch-ml's solve_every_s must be finite and > 0, got {solve_every_s}")]
    SolveEvery {
        /// The value given.
        solve_every_s: f64,
    },
    /// The batch learner needs at least one iteration.
    #[error("batch-ml needs iterations >= 1, got {iterations}")]
    Iterations {
        /// Iterations per solve.
        iterations: usize,
    },
    /// A batch learner noise setting must be finite and positive.
    #[error("batch-ml's {name} must be finite and > 0, got {value}")]
    BatchNoise {
        /// Which setting.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// The batch learner's window must be positive.
    #[error("batch-ml's window_s must be > 0, got {window_s}")]
    Window {
        /// The value given.
        window_s: f64,
    },
    /// A model given to a one-sided mode has a non-finite coefficient.
    #[error("the given {which} model has a non-finite coefficient")]
    GivenModel {
        /// `"action"` or `"sensor"`.
        which: &'static str,
    },
}

/// An event the learner refused; a refused event changes nothing.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EventError {
    /// A time, duration, command or reading is NaN or infinite.
    #[error("{field} must be finite, got {value}")]
    NonFinite {
        /// Which field.
        field: &'static str,
        /// The value given.
        value: f64,
    },
    /// A command's duration is zero or negative.
    #[error("a command's duration must be > 0 s, got {dt_s}")]
    NonPositiveDuration {
        /// The value given.
        dt_s: f64,
    },
    /// A reading of zero or negative pixels is no reading.
    #[error("a reading must be > 0 px, got {obs_px}")]
    NonPositiveReading {
        /// The value given.
        obs_px: f64,
    },
    /// An event is earlier than the learner's clock.
    #[error("time went backwards: event at {t_s} s, learner clock at {clock_s} s")]
    TimeWentBackwards {
        /// The event's time.
        t_s: f64,
        /// The learner's clock (end of the last command interval).
        clock_s: f64,
    },
    /// An event is later than the learner's clock: the command in force over the
    /// gap is unknown.
    #[error("gap in commands: event at {t_s} s, but commands are known only up to {clock_s} s")]
    TimeGap {
        /// The event's time.
        t_s: f64,
        /// The learner's clock (end of the last command interval).
        clock_s: f64,
    },
    /// The learner has failed and takes no more events (see
    /// [`crate::CalibrationLearner::failure`] for why).
    #[error("the learner has failed")]
    Failed,
}
