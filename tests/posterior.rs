//! A learner that says how sure it is, checked against the truth: in the
//! synthetic world (a known response and camera, Gaussian reading noise), the
//! batch learner's predicted 90 % bands must hold the measured error in most
//! trials, be about as wide as the errors are (a band that holds everything
//! by being huge is no prediction), and be the same for the same events.

use rayon::prelude::*;
use scasm::{BatchMl, BatchMlConfig, CalibrationLearner};
use testbed::predicted::{DRAWS, Predicted};
use testbed::reference::Reference;
use testbed::synthetic::{self, SyntheticTrialConfig};

const SEEDS: std::ops::Range<u64> = 0..24;

/// `(measured, predicted)` of each model: `(action, sensor)`, each
/// `(measured error, (low, median, high))`.
type Trial = [(f64, (f64, f64, f64)); 2];

fn trial(seed: u64) -> Trial {
    let params = BatchMlConfig::lagged().validate().expect("valid");
    let mut learner = BatchMl::new(params);
    let judged = synthetic::run_trial(&mut learner, &SyntheticTrialConfig::default(), seed)
        .expect("valid events");
    let posterior = learner.posterior(DRAWS).expect("a posterior after a solve");
    assert_eq!(posterior.draws.len(), DRAWS, "seed {seed}");
    assert_eq!(
        Some(&posterior),
        learner.posterior(DRAWS).as_ref(),
        "seed {seed}"
    );
    let reference = Reference {
        action: synthetic::measured_action(),
        sensor: synthetic::measured_sensor(),
        changes: Vec::new(),
    };
    let p = Predicted::of(
        &reference,
        150.0,
        learner.action_model(),
        learner.sensor_model(),
        &posterior,
    );
    let (a, s) = (
        p.action.expect("action band"),
        p.sensor.expect("sensor band"),
    );
    [
        (
            judged.action_error.expect("action").rmse,
            (a.low, a.median, a.high),
        ),
        (
            judged.sensor_error.expect("sensor").rmse,
            (s.low, s.median, s.high),
        ),
    ]
}

#[test]
fn the_batch_learners_bands_hold_its_errors_and_are_as_wide_as_they_are() {
    let trials: Vec<Trial> = SEEDS.into_par_iter().map(trial).collect();
    for (k, model) in ["action", "sensor"].iter().enumerate() {
        let inside = trials
            .iter()
            .filter(|t| (t[k].1.0..=t[k].1.2).contains(&t[k].0))
            .count();
        let mut ratio: Vec<f64> = trials.iter().map(|t| t[k].1.1 / t[k].0).collect();
        ratio.sort_by(f64::total_cmp);
        let median = ratio[ratio.len() / 2];
        eprintln!(
            "{model}: {inside} of {} inside; predicted over measured, median {median:.2}",
            trials.len()
        );
        assert!(
            inside * 3 >= trials.len() * 2,
            "{model}: only {inside} of {} measured errors inside their 90 % band",
            trials.len()
        );
        assert!(
            (0.6..1.6).contains(&median),
            "{model}: the predicted error is {median:.2}x the measured one (median)"
        );
    }
}
