//! The paper's trial in the synthetic world ([`crate::world::SyntheticWorld`])
//! at the ERS-7's scale, for checking a learner on its own in tests and
//! benchmarks: the trial is walked by the same runner as any other
//! ([`TrialRunner`]), fed to the learner the one way learners are fed
//! ([`trial::feed`]), and judged against the world's own truth. A run of
//! trials in it with every figure is `train --world synthetic`.

use scasm::{CalibrationLearner, Polynomial};

use crate::behaviour::BehaviourConfig;
use crate::metrics::{self, AffineError, ScaledError};
use crate::trial::{self, Recording, TrialConfig, TrialError, TrialRunner};
use crate::world::synthetic::{SyntheticConfig, SyntheticWorld};
pub use crate::world::synthetic::{true_obs_px, true_velocity_mm_s};

/// The paper's 31 test commands: every multiple of 20 in [-300, 300].
pub fn test_commands() -> impl Iterator<Item = f64> {
    (-15..=15).map(|k| 20.0 * f64::from(k))
}

/// The paper's 13 test distances, mm: 1.2, 1.4, ..., 3.6 m.
pub fn test_distances_mm() -> impl Iterator<Item = f64> {
    (0..13).map(|k| 1200.0 + 200.0 * f64::from(k))
}

/// Settings of a synthetic trial.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyntheticTrialConfig {
    /// Trial length, s.
    pub duration_s: f64,
    /// Camera frame interval, s (the learner runs once per frame).
    pub frame_dt_s: f64,
    /// Standard deviation of the Gaussian reading noise, px.
    pub noise_px: f64,
    /// Where the robot starts, mm from the beacon.
    pub start_distance_mm: f64,
}

impl Default for SyntheticTrialConfig {
    /// The paper's trial: 150 s at 20 Hz, 1 px noise, starting mid-range.
    fn default() -> Self {
        Self {
            duration_s: 150.0,
            frame_dt_s: 0.05,
            noise_px: 1.0,
            start_distance_mm: 2400.0,
        }
    }
}

/// How a synthetic trial came out, judged by the paper's protocol.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyntheticOutcome {
    /// The learned action model, if any.
    pub action_model: Option<Polynomial>,
    /// The learned sensor model, if any.
    pub sensor_model: Option<Polynomial>,
    /// Action error after the best scale, mm/s.
    pub action_error: Option<ScaledError>,
    /// Sensor error after the best affine map, mm.
    pub sensor_error: Option<AffineError>,
    /// `| |k / b| - 1 |`.
    pub consistency: Option<f64>,
}

/// The true action model at the 31 test commands: `(command, mm/s)`.
pub fn measured_action() -> Vec<(f64, f64)> {
    test_commands()
        .map(|c| (c, true_velocity_mm_s(c)))
        .collect()
}

/// The true sensor model at the 13 test distances: `(mm, px)`.
pub fn measured_sensor() -> Vec<(f64, f64)> {
    test_distances_mm().map(|d| (d, true_obs_px(d))).collect()
}

/// Records one trial of the paper's behaviour (turning at the readings of
/// 1.1 and 3.8 m) in the synthetic world from `seed`.
pub fn record(config: &SyntheticTrialConfig, seed: u64) -> Result<Recording, TrialError> {
    let world = SyntheticWorld::new(
        SyntheticConfig {
            frame_period_s: config.frame_dt_s,
            noise_px: config.noise_px,
            start_distance_mm: config.start_distance_mm,
            scale: quadsim::RobotScale::ONE,
        },
        seed,
    );
    let trial = TrialConfig {
        duration_s: config.duration_s,
        seed,
        behaviour: BehaviourConfig::paper(300.0, true_obs_px(1100.0), true_obs_px(3800.0)),
        judge_every_s: config.duration_s,
        blank: Default::default(),
        changes: Vec::new(),
    };
    let frames = TrialRunner::in_world(world, trial)?.record_until(|_| false)?;
    Ok(Recording {
        seed,
        frames,
        realtime_factor: f64::NAN,
    })
}

/// Runs one trial of `learner` in the synthetic world from `seed`
/// ([`record`], then every frame fed to it) and judges it.
pub fn run_trial(
    learner: &mut dyn CalibrationLearner,
    config: &SyntheticTrialConfig,
    seed: u64,
) -> Result<SyntheticOutcome, TrialError> {
    for frame in &record(config, seed)?.frames {
        trial::feed(learner, frame)?;
    }
    Ok(judge(learner))
}

/// Judges the learner's current models against the synthetic truth.
pub fn judge(learner: &dyn CalibrationLearner) -> SyntheticOutcome {
    let action_model = learner.action_model();
    let sensor_model = learner.sensor_model();
    let action_error = action_model.map(|a| metrics::action_error(&a, &measured_action()));
    let sensor_error = sensor_model.map(|s| metrics::sensor_error(&s, &measured_sensor()));
    let consistency = action_error
        .zip(sensor_error)
        .map(|(a, s)| metrics::consistency(a.scale, s.scale));
    SyntheticOutcome {
        action_model,
        sensor_model,
        action_error,
        sensor_error,
        consistency,
    }
}
