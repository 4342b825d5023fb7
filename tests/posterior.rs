//! Learners that say how sure they are, checked against the truth: in the
//! synthetic world (a known response and camera, Gaussian reading noise), a
//! learner's predicted 90 % bands must hold the measured error in most
//! trials, be about as wide as the errors are (a band that holds everything
//! by being huge is no prediction), and be the same for the same events.
//! Both the batch learner, whose posterior is around its own models, and
//! the default online learner, `scasm`, whose posterior is the lagged
//! likelihood's around the likeliest models, not its own.

use rayon::prelude::*;
use scasm::{BatchMl, BatchMlConfig, CalibrationLearner, Mode, Polynomial, Scasm};
use testbed::learners::{self, BoxedLearner};
use testbed::predicted::{DRAWS, Predicted};
use testbed::reference::Reference;
use testbed::scenario::Scenario;
use testbed::synthetic::{self, SyntheticTrialConfig};

const SEEDS: std::ops::Range<u64> = 0..24;

/// `(measured, predicted)` of each model: `(action, sensor)`, each
/// `(measured error, (low, median, high))`.
type Trial = [(f64, (f64, f64, f64)); 2];

fn reference() -> Reference {
    Reference {
        action: synthetic::measured_action(),
        sensor: synthetic::measured_sensor(),
        changes: Vec::new(),
    }
}

/// `learner`'s synthetic trial of `seed`: its errors and predicted bands.
fn trial(learner: &mut dyn CalibrationLearner, seed: u64) -> Trial {
    let judged = synthetic::run_trial(learner, &SyntheticTrialConfig::default(), seed)
        .expect("valid events");
    let posterior = learner.posterior(DRAWS).expect("a posterior at the end");
    assert_eq!(posterior.draws.len(), DRAWS, "seed {seed}");
    assert_eq!(
        Some(&posterior),
        learner.posterior(DRAWS).as_ref(),
        "seed {seed}"
    );
    let p = Predicted::of(
        &reference(),
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

/// The bands hold at least two thirds of the measured errors, and the
/// median trial's predicted error is within 0.6-1.6 of its measured one.
fn assert_bands_hold(learner: &str, trials: &[Trial]) {
    for (k, model) in ["action", "sensor"].iter().enumerate() {
        let inside = trials
            .iter()
            .filter(|t| (t[k].1.0..=t[k].1.2).contains(&t[k].0))
            .count();
        let mut ratio: Vec<f64> = trials.iter().map(|t| t[k].1.1 / t[k].0).collect();
        ratio.sort_by(f64::total_cmp);
        let median = ratio[ratio.len() / 2];
        eprintln!(
            "{learner} {model}: {inside} of {} inside; predicted over measured, median {median:.2}",
            trials.len()
        );
        assert!(
            inside * 3 >= trials.len() * 2,
            "{learner} {model}: only {inside} of {} measured errors inside their 90 % band",
            trials.len()
        );
        assert!(
            (0.6..1.6).contains(&median),
            "{learner} {model}: the predicted error is {median:.2}x the measured one (median)"
        );
    }
}

#[test]
fn the_batch_learners_bands_hold_its_errors_and_are_as_wide_as_they_are() {
    let trials: Vec<Trial> = SEEDS
        .into_par_iter()
        .map(|seed| {
            let params = BatchMlConfig::lagged().validate().expect("valid");
            trial(&mut BatchMl::new(params), seed)
        })
        .collect();
    assert_bands_hold("batch-ml-lag", &trials);
}

/// The default learner as a host builds it, with `settings`.
fn scasm(settings: &[&str]) -> BoxedLearner {
    let mut scenario = Scenario::paper().expect("scenario");
    for s in settings {
        scenario.set(s).expect("declared");
    }
    learners::build("scasm", &scenario, &reference()).expect("scasm")
}

#[test]
fn the_default_learners_bands_hold_its_errors_and_leave_its_learning_alone() {
    let trials: Vec<Trial> = SEEDS
        .into_par_iter()
        .map(|seed| trial(scasm(&[]).as_mut(), seed))
        .collect();
    assert_bands_hold("scasm", &trials);
    // Without a posterior it learns the same models, and says nothing.
    let mut with = scasm(&["learner.scasm.keep_start=0"]);
    let mut without = scasm(&["learner.scasm.posterior=0"]);
    let config = SyntheticTrialConfig::default();
    synthetic::run_trial(with.as_mut(), &config, 0).expect("valid events");
    synthetic::run_trial(without.as_mut(), &config, 0).expect("valid events");
    assert!(without.posterior(DRAWS).is_none());
    assert_eq!(with.action_model(), without.action_model());
    assert_eq!(with.sensor_model(), without.sensor_model());
    assert_eq!(with.x_a(), without.x_a());
}

/// Keeping a start is a report, not a change of learning; where the
/// response is curved and the trial long, the evidence for the learned
/// action model is plain, so it is kept in every trial; and a sensor model
/// kept is section IV's (by the metric, the same error), kept only where
/// the two are close (here the start is up to 2.6x the learned model's
/// error, and 0.8x at best: a belief cannot tell a few per cent apart).
/// By default the sensor's start is kept only on a clear verdict (this
/// world gives none); with the action model's even odds it is kept in some.
#[test]
fn the_default_learner_keeps_a_start_only_where_it_is_nearer_the_truth() {
    let config = SyntheticTrialConfig::default();
    let scenario = Scenario::paper().expect("scenario");
    let params = scenario.learner.validate().expect("valid");
    for (settings, fires) in [
        (&[][..], false),
        (&["learner.scasm.keep_start_sensor_below=0.5"][..], true),
    ] {
        let kept: Vec<bool> = SEEDS
            .into_par_iter()
            .map(|seed| {
                let mut keeping = scasm(settings);
                let mut learned = scasm(&["learner.scasm.keep_start=0"]);
                let mut start = Scasm::new(params, Mode::SensorFromAction(Polynomial::identity()))
                    .expect("A0 is finite");
                let judged = synthetic::run_trial(keeping.as_mut(), &config, seed).expect("valid");
                let own = synthetic::run_trial(learned.as_mut(), &config, seed).expect("valid");
                let start = synthetic::run_trial(&mut start, &config, seed).expect("valid");
                assert_eq!(keeping.x_a(), learned.x_a(), "seed {seed}");
                assert_eq!(
                    keeping.action_model(),
                    learned.action_model(),
                    "seed {seed}"
                );
                let error =
                    |j: &synthetic::SyntheticOutcome| j.sensor_error.expect("a sensor model").rmse;
                let (error, own, start) = (error(&judged), error(&own), error(&start));
                let kept = keeping.sensor_model() != learned.sensor_model();
                if kept {
                    assert!(
                        (error - start).abs() <= 1e-9 * start,
                        "seed {seed}: {error} {start}"
                    );
                    assert!(start < 1.2 * own, "seed {seed}: kept {start} over {own}");
                } else {
                    assert_eq!(error, own, "seed {seed}");
                }
                kept
            })
            .collect();
        // Not a rule that never fires: with even odds the start is kept in
        // a few trials (where it is within 1.2x of the learned model).
        assert!(!fires || kept.iter().any(|&k| k), "{settings:?}: {kept:?}");
    }
}
