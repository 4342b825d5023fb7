//! A world with no physics for checking a learner: a point robot on a line whose
//! true action model is a made-up, clearly nonlinear monotone curve and whose
//! camera is an ideal pinhole (`obs = k / distance`) with Gaussian pixel noise.
//! It runs the paper's behaviour and judges the result by the paper's protocol.

use rand_distr::{Distribution, Normal};
use scasm::{CalibrationLearner, Event, EventError, Polynomial};

use crate::behaviour::{Behaviour, BehaviourConfig, Phase, TrainingBehaviour};
use crate::metrics::{self, AffineError, ScaledError};
use crate::seeds::{self, Stream};

/// The synthetic robot's true forward speed (mm/s) under `command`: monotone,
/// saturating forwards, slower backwards, and not a polynomial.
pub fn true_velocity_mm_s(command: f64) -> f64 {
    let u = command / 300.0;
    330.0 * (1.3 * u).tanh() / 1.3_f64.tanh() + 25.0 * u * u
}

/// The synthetic camera's noise-free reading (px) of a 200 mm band at `distance_mm`
/// through a lens of focal length 192 px.
pub fn true_obs_px(distance_mm: f64) -> f64 {
    SENSOR_K_PX_MM / distance_mm
}

const SENSOR_K_PX_MM: f64 = 384.0 * 200.0;

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

/// Runs one trial of `learner` with the paper's behaviour from `seed`.
pub fn run_trial(
    learner: &mut dyn CalibrationLearner,
    config: &SyntheticTrialConfig,
    seed: u64,
) -> Result<SyntheticOutcome, EventError> {
    let behaviour_config = BehaviourConfig::paper(300.0, true_obs_px(1100.0), true_obs_px(3800.0));
    let mut behaviour = TrainingBehaviour::new(
        behaviour_config,
        seeds::rng(seed, Stream::Behaviour),
        Phase::Forwards,
    );
    let mut noise_rng = seeds::rng(seed, Stream::SensorNoise);
    let noise = Normal::new(0.0, config.noise_px.max(0.0)).unwrap_or_else(|_| unreachable!());

    let frames = (config.duration_s / config.frame_dt_s).round() as u64;
    let mut distance_mm = config.start_distance_mm;
    for k in 0..frames {
        let t_s = k as f64 * config.frame_dt_s;
        let command = behaviour.command(t_s);
        learner.handle(Event::Command {
            t_s,
            dt_s: config.frame_dt_s,
            command,
        })?;
        distance_mm -= true_velocity_mm_s(command) * config.frame_dt_s;
        let t_next = (k + 1) as f64 * config.frame_dt_s;
        let obs_px = true_obs_px(distance_mm) + noise.sample(&mut noise_rng);
        learner.handle(Event::Reading {
            t_s: t_next,
            obs_px,
        })?;
        behaviour.observe(t_next, Some(obs_px));
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
