//! The paper's experiment: the training behaviour's thresholds and the learner
//! for a scenario, and trials over many seeds in parallel.

use rayon::prelude::*;
use scasm::{CalibrationLearner, Mode, Polynomial, Scasm};

use crate::behaviour::BehaviourConfig;
use crate::metrics;
use crate::reference::{MeasuredModels, Reference};
use crate::scenario::{LearningMode, Scenario};
use crate::trial::{self, TrialConfig, TrialError, TrialOutcome};

/// How far beyond each end of the test range the behaviour turns round, m: the
/// readings of a walking robot run about a pixel below those of one standing, so
/// turning at the end's own reading would stop short of it.
pub const TURN_MARGIN_M: f64 = 0.15;

/// The behaviour's thresholds from the measured sensor model: turn round at the
/// readings expected [`TURN_MARGIN_M`] beyond the nearest and farthest test
/// distances, from the pinhole law `d = a + b / obs` fitted to the measured points
/// (or at the end points' own readings if that fit fails).
pub fn behaviour_for(models: &MeasuredModels) -> BehaviourConfig {
    let end = |i: usize| {
        models
            .sensor
            .get(i)
            .map_or((f64::NAN, f64::NAN), |s| (s.distance_mm, s.obs_px))
    };
    let (near, far) = (end(0), end(models.sensor.len().saturating_sub(1)));
    let inverse: Vec<(f64, f64)> = models
        .sensor
        .iter()
        .map(|s| (1.0 / s.obs_px, s.distance_mm))
        .collect();
    let (near_obs_px, far_obs_px) = match metrics::best_polynomial(&inverse, 1) {
        Some(p) if p.coeffs()[1] > 0.0 => {
            let (a, b) = (p.coeffs()[0], p.coeffs()[1]);
            let obs_at = |d_mm: f64| b / (d_mm - a);
            (
                obs_at(near.0 - 1000.0 * TURN_MARGIN_M),
                obs_at(far.0 + 1000.0 * TURN_MARGIN_M),
            )
        }
        _ => (near.1, far.1),
    };
    BehaviourConfig {
        max_command: 300.0,
        hold_s: 3.0,
        near_obs_px,
        far_obs_px,
        turn_median_of: crate::behaviour::TURN_MEDIAN_OF,
    }
}

/// The learner for a mode: the given model of a one-sided mode is the best
/// polynomial through the measured one, in mm (location is distance, so the
/// action model is minus the forward speed).
pub fn learner_for(scenario: &Scenario, reference: &Reference) -> Result<Scasm, String> {
    let params = scenario.learner.validate().map_err(|e| e.to_string())?;
    let mode = match scenario.mode {
        LearningMode::Simultaneous => Mode::Simultaneous,
        LearningMode::SensorFromAction => {
            let a = metrics::best_polynomial(&reference.action, scenario.learner.action_degree)
                .ok_or("cannot fit the measured action model")?;
            let minus: Vec<f64> = a.coeffs().iter().map(|c| -c).collect();
            Mode::SensorFromAction(Polynomial::new(&minus).ok_or("bad action model")?)
        }
        LearningMode::ActionFromSensor => {
            let pts: Vec<(f64, f64)> = reference.sensor.iter().map(|&(d, o)| (o, d)).collect();
            Mode::ActionFromSensor(
                metrics::best_polynomial(&pts, scenario.learner.sensor_degree)
                    .ok_or("cannot fit the measured sensor model")?,
            )
        }
    };
    Scasm::new(params, mode).map_err(|e| e.to_string())
}

/// Runs one trial of `scenario` from `seed`, judged against `models`.
pub fn run_one(
    scenario: &Scenario,
    models: &MeasuredModels,
    seed: u64,
) -> Result<(TrialOutcome, Scasm), TrialError> {
    let reference = models.reference();
    let mut learner = learner_for(scenario, &reference).map_err(TrialError::LearnerSetup)?;
    let config = TrialConfig {
        duration_s: scenario.duration_s,
        seed,
        behaviour: behaviour_for(models),
        judge_every_s: 5.0,
    };
    let outcome = trial::run_trial(
        &scenario.description,
        scenario.sim,
        config,
        &mut learner as &mut dyn CalibrationLearner,
        &reference,
    )?;
    Ok((outcome, learner))
}

/// A trial's outcome and its learner, or why it could not run.
pub type TrialResult = Result<(TrialOutcome, Scasm), TrialError>;

/// Runs one trial per seed in parallel, calling `done` as each finishes. A
/// trial that cannot run does not stop the others: its error is its result.
pub fn run_trials(
    scenario: &Scenario,
    models: &MeasuredModels,
    seeds: &[u64],
    done: &(dyn Fn(u64, Option<&TrialOutcome>) + Sync),
) -> Vec<(u64, TrialResult)> {
    seeds
        .par_iter()
        .map(|&seed| {
            let result = run_one(scenario, models, seed);
            done(seed, result.as_ref().ok().map(|r| &r.0));
            (seed, result)
        })
        .collect()
}
