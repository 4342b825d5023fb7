//! SCASM in a closed loop with no physics: a point robot with a made-up nonlinear
//! action model, an ideal pinhole camera with 1 px Gaussian noise, the paper's
//! behaviour, 150 s at 20 Hz. Both learned models must match the truth after the
//! paper's scaling, and their two scales must agree.

use scasm::{CalibrationLearner, Scasm};
use testbed::synthetic::{self, SyntheticTrialConfig};

const SEEDS: std::ops::Range<u64> = 0..5;

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

#[test]
fn simultaneous_learning_matches_the_truth_after_scaling() {
    let config = SyntheticTrialConfig::default();
    let (mut action, mut sensor, mut consistency) = (Vec::new(), Vec::new(), Vec::new());
    for seed in SEEDS {
        let mut learner = Scasm::default();
        let out = synthetic::run_trial(&mut learner, &config, seed).expect("valid events");
        action.push(out.action_error.expect("action model learned").rmse);
        sensor.push(out.sensor_error.expect("sensor model learned").rmse);
        consistency.push(out.consistency.expect("both models"));
    }
    let velocities: Vec<f64> = synthetic::measured_action().iter().map(|p| p.1).collect();
    let velocity_range = velocities.iter().cloned().fold(f64::MIN, f64::max)
        - velocities.iter().cloned().fold(f64::MAX, f64::min);
    let distance_range = 2400.0;
    let (a, s, c) = (mean(&action), mean(&sensor), mean(&consistency));
    eprintln!("action {action:?}\nsensor {sensor:?}\nconsistency {consistency:?}");
    assert!(
        a < 0.03 * velocity_range,
        "mean action RMSE {a:.1} mm/s >= 3 % of {velocity_range:.0}"
    );
    assert!(
        s < 0.02 * distance_range,
        "mean sensor RMSE {s:.1} mm >= 2 % of {distance_range}"
    );
    assert!(c < 0.05, "mean consistency {c:.3} >= 0.05");
}

#[test]
fn learning_beats_the_identity_model() {
    // The start (A0 = identity) misses the nonlinear truth; learning must do better.
    let a0 = testbed::metrics::action_error(
        &scasm::Polynomial::identity(),
        &synthetic::measured_action(),
    );
    let mut learner = Scasm::default();
    let out =
        synthetic::run_trial(&mut learner, &SyntheticTrialConfig::default(), 0).expect("valid");
    let learned = out.action_error.expect("learned").rmse;
    assert!(
        learned < 0.6 * a0.rmse,
        "learned {learned:.1} vs A0 {:.1}",
        a0.rmse
    );
}

#[test]
fn a_trial_is_bit_identical_per_seed() {
    let run = |seed| {
        let mut learner = Scasm::default();
        synthetic::run_trial(
            &mut learner,
            &SyntheticTrialConfig {
                duration_s: 60.0,
                ..Default::default()
            },
            seed,
        )
        .expect("valid");
        let bits = |p: Option<scasm::Polynomial>| -> Vec<u64> {
            p.map(|p| p.coeffs().iter().map(|c| c.to_bits()).collect())
                .unwrap_or_default()
        };
        (
            bits(learner.action_model()),
            bits(learner.sensor_model()),
            learner.x_a().map(f64::to_bits),
        )
    };
    assert_eq!(run(3), run(3));
    assert_ne!(run(3), run(4));
}

/// The learners beyond the paper, in the synthetic world where the truth is
/// known exactly and the camera's 1 px of noise is the only error: the
/// errors-in-variables correction and the batch fit must each beat SCASM's
/// sensor model, and the batch fit SCASM's action model too (mean over the
/// seeds), with consistent scales.
#[test]
fn the_learners_beyond_the_paper_beat_scasm_where_the_truth_is_known() {
    use scasm::{BatchMl, BatchMlConfig, ScasmConfig, SensorFit};
    let config = SyntheticTrialConfig::default();
    let eiv = ScasmConfig {
        sensor_fit: SensorFit::Corrected,
        ..Default::default()
    };
    let figures = |make: &dyn Fn() -> Box<dyn CalibrationLearner>| {
        let (mut a, mut s, mut c) = (Vec::new(), Vec::new(), Vec::new());
        for seed in SEEDS {
            let mut learner = make();
            let out = synthetic::run_trial(learner.as_mut(), &config, seed).expect("valid");
            a.push(out.action_error.expect("action").rmse);
            s.push(out.sensor_error.expect("sensor").rmse);
            c.push(out.consistency.expect("both"));
        }
        (mean(&a), mean(&s), mean(&c))
    };
    let scasm = figures(&|| Box::new(Scasm::default()));
    let corrected = figures(&|| {
        Box::new(
            Scasm::new(eiv.validate().expect("valid"), scasm::Mode::Simultaneous).expect("mode"),
        )
    });
    // The likelihood fit's own sensor model, at the path's readings: this
    // trial walks from 0.1 m short of the nearest judged distance to 0.2 m
    // past the farthest, and the default even fit (`sensor_even`) spreads S
    // alike over the distances walked, judged or not, which costs it here
    // (23.5 against 21.2 mm over seeds 100-129; the book's "worse than the
    // start" page says where it gains and where not).
    let batch = figures(&|| {
        let c = BatchMlConfig {
            online: eiv,
            sensor_even: false,
            ..Default::default()
        };
        Box::new(BatchMl::new(c.validate().expect("valid")))
    });
    eprintln!("scasm {scasm:?}\nscasm-eiv {corrected:?}\nbatch-ml {batch:?}");
    assert!(corrected.1 < scasm.1, "scasm-eiv's sensor model");
    assert!(batch.1 < scasm.1, "batch-ml's sensor model");
    assert!(batch.0 < scasm.0, "batch-ml's action model");
    assert!(batch.2 < 0.05, "batch-ml's consistency {:.3}", batch.2);
}

/// `batch-ml` past its window (a 450 s trial, window 150 s) learns the models
/// solving the whole trial every time learns, within 3 %; and a window at
/// least the trial's length is the whole-trial learner, bit for bit.
#[test]
fn batch_ml_windowed_learns_what_the_whole_trial_solve_learns() {
    use scasm::{BatchMl, BatchMlConfig};
    let run = |duration_s: f64, window_s: f64| {
        let config = SyntheticTrialConfig {
            duration_s,
            ..Default::default()
        };
        let params = BatchMlConfig {
            window_s,
            ..BatchMlConfig::default()
        }
        .validate()
        .expect("valid");
        let mut learner = BatchMl::new(params);
        let out = synthetic::run_trial(&mut learner, &config, 4).expect("valid events");
        (
            out.action_error.expect("A").rmse,
            out.sensor_error.expect("S").rmse,
        )
    };
    let (windowed, whole) = (run(450.0, 150.0), run(450.0, 1e9));
    eprintln!("windowed {windowed:?}, whole {whole:?}");
    assert!(
        (windowed.0 / whole.0 - 1.0).abs() < 0.03,
        "{windowed:?} vs {whole:?}"
    );
    assert!(
        (windowed.1 / whole.1 - 1.0).abs() < 0.03,
        "{windowed:?} vs {whole:?}"
    );
    let (short, short_whole) = (run(150.0, 150.0), run(150.0, 1e9));
    assert_eq!(short.0.to_bits(), short_whole.0.to_bits());
    assert_eq!(short.1.to_bits(), short_whole.1.to_bits());
}
