//! Training trials on the simulated robot: a trial learns, is bit-identical per
//! seed, feeds the learner nothing but command and reading events, and a trial
//! resumed from a learner checkpoint ends exactly as one never stopped.

use scasm::{CalibrationLearner, Event, EventError, Polynomial, Scasm};
use testbed::experiment;
use testbed::metrics;
use testbed::scenario::Scenario;
use testbed::trial::{self, TrialConfig};

mod common;
use common::paper_reference as setup;

fn config(seed: u64, duration_s: f64) -> TrialConfig {
    TrialConfig {
        duration_s,
        seed,
        behaviour: experiment::behaviour_for(&setup().0, &setup().1),
        judge_every_s: 5.0,
        blank: Default::default(),
        changes: Vec::new(),
    }
}

fn bits(p: Option<Polynomial>) -> Vec<u64> {
    p.map(|p| p.coeffs().iter().map(|c| c.to_bits()).collect())
        .unwrap_or_default()
}

/// README's default `train` has `scasm`'s action model at 0.34x A0's error
/// and its sensor model at 37 mm, means over 15 trials (std 3.2 mm/s and 17
/// mm). Six trials on development seeds, against the same claim with the
/// margin their mean's sampling spread needs (twice the standard error, 0.13x
/// A0 and 20 mm): a mean under 0.6x A0 and 75 mm, and at most one trial of
/// the six with an action model worse than A0 (the default learner's tail:
/// 2 of 100 on development seeds 100-199 end with A worse than A0, 1 of them
/// among these six; two of six would be far outside it).
#[test]
fn trials_learn_both_models_as_readme_says() {
    let (scenario, models) = setup();
    let seeds: Vec<u64> = (100..106).collect();
    let results = experiment::run_trials(scenario, models, &seeds, &|_| {});
    let reference = models.reference();
    let a0 = metrics::action_error(&Polynomial::identity(), &reference.action).rmse;
    let (mut action, mut sensor) = (Vec::new(), Vec::new());
    for (seed, result) in &results {
        let (recording, out) = result.as_ref().expect("the trial runs");
        assert!(!recording.fell(), "seed {seed}: the robot tipped over");
        let a = out.last.action_rmse_mm_s.expect("action model learned");
        if a >= a0 {
            eprintln!("seed {seed}: action error {a:.1} mm/s vs A0's {a0:.1}");
        }
        action.push(a);
        sensor.push(out.last.sensor_rmse_mm.expect("sensor model learned"));
    }
    let worse = action.iter().filter(|&&a| a >= a0).count();
    assert!(worse <= 1, "{worse} of 6 trials end with A worse than A0");
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (a, s) = (mean(&action), mean(&sensor));
    eprintln!(
        "mean action {a:.1} mm/s ({:.2}x A0), sensor {s:.1} mm",
        a / a0
    );
    assert!(
        a < 0.6 * a0,
        "mean action error {a:.1} mm/s vs A0's {a0:.1}"
    );
    assert!(s < 75.0, "mean sensor error {s:.1} mm");
}

#[test]
fn a_trial_is_bit_identical_per_seed() {
    let (scenario, models) = setup();
    let run = |seed| {
        let mut learner = Scasm::default();
        let out = trial::run_trial(
            &scenario.description,
            scenario.sim,
            config(seed, 25.0),
            &mut learner,
            &models.reference(),
        )
        .expect("trial");
        let trace: Vec<u64> = out
            .trace
            .iter()
            .flat_map(|r| {
                [
                    r.x_true_mm.to_bits(),
                    r.obs_px.unwrap_or(-1.0).to_bits(),
                    r.x_a.unwrap_or(0.0).to_bits(),
                ]
            })
            .collect();
        (trace, bits(out.action_model), bits(out.sensor_model))
    };
    let a = run(7);
    assert_eq!(a, run(7));
    assert_ne!(a.0, run(8).0);
}

/// Delegates to SCASM and checks that what it is fed is a well-formed stream of
/// command and reading events and nothing else.
struct Witness {
    inner: Scasm,
    clock_s: f64,
    commands: usize,
    readings: usize,
}

impl CalibrationLearner for Witness {
    fn name(&self) -> &'static str {
        "witness"
    }
    fn handle(&mut self, event: Event) -> Result<(), EventError> {
        match event {
            Event::Command { t_s, dt_s, command } => {
                assert!(
                    (t_s - self.clock_s).abs() < 1e-9,
                    "commands must be back to back"
                );
                assert!((dt_s - 0.05).abs() < 1e-12, "one command per 20 Hz frame");
                assert!(
                    command.abs() <= 300.0 * 1.0001,
                    "command {command} out of the behaviour's range"
                );
                self.clock_s = t_s + dt_s;
                self.commands += 1;
            }
            Event::Reading { t_s, obs_px } => {
                assert!(
                    (t_s - self.clock_s).abs() < 1e-9,
                    "readings come at the end of a frame"
                );
                assert!(obs_px.is_finite() && obs_px > 0.0);
                self.readings += 1;
            }
        }
        self.inner.handle(event)
    }
    fn action_model(&self) -> Option<Polynomial> {
        self.inner.action_model()
    }
    fn sensor_model(&self) -> Option<Polynomial> {
        self.inner.sensor_model()
    }
    fn x_a(&self) -> Option<f64> {
        self.inner.x_a()
    }
    fn x_s(&self) -> Option<f64> {
        self.inner.x_s()
    }
}

#[test]
fn the_learner_gets_only_commands_and_readings() {
    let (scenario, models) = setup();
    let mut w = Witness {
        inner: Scasm::default(),
        clock_s: 0.0,
        commands: 0,
        readings: 0,
    };
    let out = trial::run_trial(
        &scenario.description,
        scenario.sim,
        config(3, 20.0),
        &mut w,
        &models.reference(),
    )
    .expect("trial");
    assert_eq!(w.commands, 400);
    assert_eq!(
        w.readings,
        out.trace.iter().filter(|r| r.obs_px.is_some()).count()
    );
    assert!(
        w.readings > 380,
        "the beacon was seen in only {} of 400 frames",
        w.readings
    );
}

#[test]
fn a_trial_resumed_from_a_learner_checkpoint_ends_bit_identical() {
    let (scenario, _) = setup();
    let recording =
        trial::record(&scenario.description, scenario.sim, config(11, 45.0)).expect("recording");
    let (first, second) = recording.frames.split_at(recording.frames.len() / 2);
    let mut straight = Scasm::default();
    let mut first_half = Scasm::default();
    for f in first {
        trial::feed(&mut straight, f).expect("frame");
        trial::feed(&mut first_half, f).expect("frame");
    }
    // Stop: save the learner and go on with one restored from the checkpoint alone.
    let checkpoint = serde_json::to_string(&first_half).expect("save");
    let mut resumed: Scasm = serde_json::from_str(&checkpoint).expect("restore");
    for f in second {
        trial::feed(&mut straight, f).expect("frame");
        trial::feed(&mut resumed, f).expect("frame");
        assert_eq!(
            straight.x_a().map(f64::to_bits),
            resumed.x_a().map(f64::to_bits)
        );
    }
    assert_eq!(bits(straight.action_model()), bits(resumed.action_model()));
    assert_eq!(bits(straight.sensor_model()), bits(resumed.sensor_model()));
    assert_eq!(
        serde_json::to_string(&straight).expect("save"),
        serde_json::to_string(&resumed).expect("save")
    );
}

#[test]
fn unknown_or_out_of_range_settings_are_named() {
    let mut s = Scenario::paper().expect("scenario");
    let e = s.set("learner.gama=0.9").expect_err("unknown key");
    assert!(e.to_string().contains("learner.gama"), "{e}");
    let e = s.set("learner.gamma=1.5").expect_err("out of range");
    assert!(e.to_string().contains("learner.gamma"), "{e}");
    let e = s.set("world.friction=abc").expect_err("not a number");
    assert!(e.to_string().contains("world.friction"), "{e}");
    let e = s.set("camera.noise_px=NaN").expect_err("not finite");
    assert!(e.to_string().contains("camera.noise_px"), "{e}");
    assert!(s.set("noequals").is_err());
    // A trial the machine cannot hold is refused at the door, not by the
    // allocator.
    let e = s.set("trial.duration=1e12").expect_err("too long");
    assert!(e.to_string().contains("trial.duration"), "{e}");
    // Nothing of the refused settings stuck.
    assert_eq!(s.learner.gamma, 0.999);
    s.set("learner.beta=0.05").expect("valid");
    assert_eq!(s.learner.beta, 0.05);
}

#[test]
fn blanked_readings_leave_the_localiser_to_dead_reckoning_until_they_return() {
    let (scenario, models) = setup();
    let reference = models.reference();
    let run = |blank: trial::Blanks| {
        let mut learner = Scasm::default();
        trial::run_trial(
            &scenario.description,
            scenario.sim,
            TrialConfig {
                blank,
                ..config(1, 80.0)
            },
            &mut learner,
            &reference,
        )
        .expect("trial")
    };
    // Blind while mid-range, for 2 s: the world is the same up to the blank,
    // so an unblanked run says when the robot is mid-range. (Blind near an end,
    // the behaviour cannot see where to turn and walks out of the range.)
    // Once the learner has both models and dead-reckons with its own A
    // (from 2 t_start), so that the localiser has a belief to carry.
    let clear = run(trial::Blanks::default());
    let learned_s = 2.0 * scasm::ScasmConfig::default().t_start_s;
    let start = clear
        .trace
        .iter()
        .find(|r| r.t_s >= learned_s && (2000.0..2800.0).contains(&r.x_true_mm))
        .expect("mid-range once both models are in use")
        .t_s;
    assert!(
        start + 5.0 <= 80.0,
        "no time left after the blank: {start} s"
    );
    let end = start + 2.0;
    let out = run(trial::Blanks::parse(&format!("{start}..{end}"), 80.0).expect("interval"));
    let row = |t: f64| {
        out.trace
            .iter()
            .find(|r| r.t_s >= t - 1e-6)
            .expect("a frame ends then")
    };
    assert!(
        out.trace
            .iter()
            .filter(|r| r.t_s > start + 1e-6 && r.t_s < end - 1e-6)
            .all(|r| r.obs_px.is_none()),
        "a reading in the blank"
    );
    let std = |t| row(t).x_loc_std.expect("the localiser has a belief");
    // Blind, the uncertainty only grows (from the action model alone); once
    // readings return, it comes down.
    let blind: Vec<f64> = out
        .trace
        .iter()
        .filter(|r| r.t_s > start + 1e-6 && r.t_s < end - 1e-6)
        .filter_map(|r| r.x_loc_std)
        .collect();
    assert!(blind.len() >= 30, "{} blind frames", blind.len());
    assert!(
        blind.windows(2).all(|w| w[1] > w[0]),
        "std fell while blind: {blind:?}"
    );
    // Against the same trial unblinded: blind, the belief is less sure than
    // it would have been; 3 s after readings return, it has closed most of
    // that gap.
    let clear_std = |t: f64| {
        clear
            .trace
            .iter()
            .find(|r| r.t_s >= t - 1e-6)
            .and_then(|r| r.x_loc_std)
            .expect("the unblinded localiser has a belief")
    };
    let gap = |t: f64| std(t) - clear_std(t);
    let (at_end, after) = (gap(end - 0.05), gap(end + 3.0));
    assert!(
        std(end - 0.05) > std(start) && at_end > 0.0 && after.abs() < 0.5 * at_end,
        "std {:.1} at the blank's start, {:.1} at its end ({at_end:.1} over the unblinded \
         run's), {after:.1} over it 3 s later",
        std(start),
        std(end - 0.05)
    );
}

#[test]
fn a_scheduled_change_changes_the_world_and_the_yardstick_at_its_time() {
    let mut scenario = setup().0.clone();
    scenario
        .apply_toml(
            "taller_band.toml",
            "[trial]\nduration = 40.0\n\n[[change]]\nat_s = 30.0\nkey = \"beacon.height_m\"\nvalue = 0.3\n",
        )
        .expect("valid");
    let cache = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("reference-cache");
    let models = testbed::reference::measured_models(&scenario, Some(&cache)).expect("measured");
    // The changed world is measured by the same protocols: standing at each
    // distance, a band 1.5 times as tall reads about 1.5 times as tall.
    assert_eq!(models.changes.len(), 1);
    let changed = &models.changes[0];
    assert_eq!(changed.at_s, 30.0);
    for (before, after) in models.sensor.iter().zip(&changed.models.sensor) {
        let ratio = after.obs_px / before.obs_px;
        assert!(
            (ratio - 1.5).abs() < 0.08,
            "{ratio} at {} mm",
            before.distance_mm
        );
    }
    // Every judgement is against the world in force when it is made.
    let reference = models.reference();
    assert_eq!(reference.at(30.0).sensor, reference.sensor);
    assert_eq!(reference.at(30.05).sensor, reference.changes[0].1.sensor);
    assert_eq!(reference.last().sensor, reference.changes[0].1.sensor);

    // The recorded trial's readings (times the distance, to take out the
    // robot's motion) jump by 1.5 at 30 s, and not before.
    let recording = experiment::record(&scenario, &models, 2).expect("recorded");
    let scaled = |from_s: f64, to_s: f64| {
        let v: Vec<f64> = recording
            .frames
            .iter()
            .filter(|f| f.t_s >= from_s - 1e-9 && f.t_s < to_s - 1e-9)
            .filter_map(|f| f.obs_px.map(|o| o * f.truth.x_mm))
            .collect();
        assert!(v.len() >= 8, "{} readings in [{from_s}, {to_s})", v.len());
        v.iter().sum::<f64>() / v.len() as f64
    };
    let jump = scaled(30.0, 30.5) / scaled(29.5, 30.0);
    let steady = scaled(29.5, 30.0) / scaled(29.0, 29.5);
    assert!((jump - 1.5).abs() < 0.1, "jump {jump}");
    assert!((steady - 1.0).abs() < 0.05, "steady {steady}");
    let outcome = experiment::learn(&scenario, &models, &recording, "scasm").expect("learned");
    assert_eq!(outcome.world_changes_s, vec![30.0]);
}

#[test]
fn the_best_polynomial_filter_is_the_model_class_floor() {
    // The filter with the best polynomials of the learner's degrees through
    // the measured models: a quartic S fits the measured curve better than a
    // cubic, so its filter is nearer the one with the measured models.
    let (scenario, models) = setup();
    let recording = experiment::record(scenario, models, 2).expect("record");
    let figures = |sensor_degree: usize| {
        let mut s = scenario.clone();
        s.set(&format!("learner.sensor_degree={sensor_degree}"))
            .expect("degree");
        let outcome = experiment::learn(&s, models, &recording, "batch-ml").expect("learn");
        assert!(outcome.trace.iter().all(|r| r.x_loc_best_mm.is_some()));
        testbed::summary::Figures::of(&outcome, (f64::NAN, f64::NAN, f64::NAN))
    };
    let (cubic, quartic) = (figures(3), figures(4));
    let truth = cubic.localisation_true_models_rmse_mm;
    assert_eq!(truth, quartic.localisation_true_models_rmse_mm);
    let (c, q) = (
        cubic.localisation_best_poly_rmse_mm,
        quartic.localisation_best_poly_rmse_mm,
    );
    assert!(
        q < c && 0.8 * truth < q,
        "best-polynomial filters: cubic S {c:.1} mm, quartic S {q:.1} mm; measured models {truth:.1} mm"
    );
}

#[test]
fn batch_ml_with_a_quartic_sensor_localises_within_1_5x_of_the_true_models() {
    // Issue 14's criterion, on three development seeds (never the evaluation
    // seeds 0-14): the filter with `batch-ml`'s models, sensor degree 4, over
    // the last 60 s, against the filter with the measured models.
    let (scenario, models) = setup();
    let mut s = scenario.clone();
    s.set("learner.sensor_degree=4").expect("degree");
    let figures: Vec<_> = (100..103)
        .map(|seed| {
            let recording = experiment::record(&s, models, seed).expect("record");
            let outcome = experiment::learn(&s, models, &recording, "batch-ml").expect("learn");
            testbed::summary::Figures::of(&outcome, (f64::NAN, f64::NAN, f64::NAN))
        })
        .collect();
    let mean = |f: fn(&testbed::summary::Figures) -> f64| {
        figures.iter().map(f).sum::<f64>() / figures.len() as f64
    };
    let learned = mean(|f| f.localisation_rmse_mm);
    let truth = mean(|f| f.localisation_true_models_rmse_mm);
    let raw = mean(|f| f.x_s_rmse_mm);
    assert!(
        learned < 1.5 * truth && learned < raw,
        "filter with learned models {learned:.1} mm, with the measured ones {truth:.1} mm, raw x_s {raw:.1} mm"
    );
}
