//! Learners from outside the build: a program over the learner protocol
//! learns from the same recording as a Rust learner; the Python port of the
//! paper's SCASM gives the Rust `scasm-paper`'s models; every way a program
//! can misbehave fails its trial with the reason and its stderr, and only
//! its trial; and learners' own settings are checked against what each
//! declares.

use std::sync::{Mutex, OnceLock};

use scasm::Polynomial;
use testbed::experiment::{self, Job};
use testbed::learners;
use testbed::reference::MeasuredModels;
use testbed::scenario::Scenario;
use testbed::trial::{Recording, TrialError, TrialOutcome};

const PY_SCASM: &str = "exec:python3 examples/learners/scasm_paper.py";
const PY_INVERSE: &str = "exec:python3 examples/learners/inverse_fit.py";

fn bad(mode: &str) -> String {
    format!("exec:python3 tests/fixtures/learners/bad.py {mode}")
}

fn setup() -> &'static (Scenario, MeasuredModels, Recording) {
    static SETUP: OnceLock<(Scenario, MeasuredModels, Recording)> = OnceLock::new();
    SETUP.get_or_init(|| {
        let scenario = Scenario::paper().expect("scenario");
        let cache = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("reference-cache");
        let models =
            testbed::reference::measured_models(&scenario, Some(&cache)).expect("measured");
        let recording = experiment::record(&scenario, &models, 3).expect("recording");
        (scenario, models, recording)
    })
}

/// Learner `spec` over the recording, with `settings` on the scenario.
fn learn(spec: &str, settings: &[&str]) -> Result<TrialOutcome, TrialError> {
    let (scenario, models, recording) = setup();
    let mut s = scenario.clone();
    for x in settings {
        s.set(x).expect(x);
    }
    experiment::learn(&s, models, recording, spec)
}

fn largest_relative_difference(a: Option<Polynomial>, b: Option<Polynomial>) -> f64 {
    let (Some(a), Some(b)) = (a, b) else {
        return f64::INFINITY;
    };
    assert_eq!(a.coeffs().len(), b.coeffs().len());
    a.coeffs()
        .iter()
        .zip(b.coeffs())
        .map(|(x, y)| (x - y).abs() / x.abs().max(y.abs()).max(f64::MIN_POSITIVE))
        .fold(0.0, f64::max)
}

#[test]
fn the_python_scasm_gives_the_rust_scasm_papers_models() {
    let rust = learn("scasm-paper", &[]).expect("rust");
    let python = learn(PY_SCASM, &[]).expect("python");
    for (r, p) in [
        (rust.action_model, python.action_model),
        (rust.sensor_model, python.sensor_model),
    ] {
        let d = largest_relative_difference(r, p);
        assert!(d <= 1e-6, "models differ by {d:e} relative: {r:?} vs {p:?}");
    }
    // Every frame's locations, and the models judged every 5 s, too.
    assert_eq!(rust.trace.len(), python.trace.len());
    for (r, p) in rust.trace.iter().zip(&python.trace) {
        let (a, b) = (r.x_a.unwrap_or(f64::NAN), p.x_a.unwrap_or(f64::NAN));
        assert!(
            (a - b).abs() <= 1e-6 * a.abs().max(1.0),
            "x_a at {} s: {a} vs {b}",
            r.t_s
        );
        assert_eq!(r.x_s.is_some(), p.x_s.is_some(), "x_s at {} s", r.t_s);
    }
    assert_eq!(rust.over_time.len(), python.over_time.len());
    // A deterministic program gives the same bits run after run (but for
    // the wall-clock time it took).
    let mut again = learn(PY_SCASM, &[]).expect("again");
    assert!(again.learner_wall_s > 0.0 && python.learner_wall_s > 0.0);
    again.learner_wall_s = python.learner_wall_s;
    assert_eq!(again, python);
}

/// The shipped Python example that says how sure it is: its posterior
/// reaches the host, which turns it into predicted bands, the same for the
/// same events; its belief is its own (A0 as the action response, so its
/// action model's predicted error is nil), judged by the measured models.
#[test]
fn a_programs_posterior_reaches_the_host_as_predicted_bands() {
    let outcome = learn(PY_INVERSE, &[]).expect("inverse fit");
    let predicted = outcome
        .predicted
        .expect("a posterior was asked for and given");
    let sensor = predicted.learned.sensor.expect("a sensor band");
    assert!(
        0.0 < sensor.low && sensor.low < sensor.median && sensor.median < sensor.high,
        "{sensor:?}"
    );
    let action = predicted.learned.action.expect("an action band");
    assert!(action.high < 1e-9, "A0 against draws of A0: {action:?}");
    assert!(predicted.better_than_start.1.is_some());
    let mut again = learn(PY_INVERSE, &[]).expect("again");
    again.learner_wall_s = outcome.learner_wall_s;
    assert_eq!(again, outcome);
}

#[test]
fn a_programs_own_settings_reach_it_and_are_checked() {
    let default = learn(PY_INVERSE, &[]).expect("default");
    assert!(default.sensor_model.is_some() && default.action_model.is_some());
    // The same fit in other internal units: the same model, to rounding.
    let scaled = learn(PY_INVERSE, &["learner.inverse-fit-py.scale_px=50"]).expect("scaled");
    let d = largest_relative_difference(default.sensor_model, scaled.sensor_model);
    assert!(
        d < 1e-6 && d > 0.0,
        "{d:e}: the setting did not reach the program, or broke it"
    );
    let (scenario, ..) = setup();
    let mut s = scenario.clone();
    s.set(&format!("learner.name={PY_INVERSE}")).expect("named");
    s.set("learner.inverse-fit-py.scale_px=50").expect("set");
    let p = learners::parameters(&s.learner_name, &s);
    assert_eq!(p["learner.inverse-fit-py.scale_px"], 50.0);
    assert_eq!(p["name"], "inverse-fit-py");
    assert_eq!(p["exec"], PY_INVERSE);
    assert!(s.to_toml().contains("scale_px = 50"), "{}", s.to_toml());
    let below = s
        .set("learner.inverse-fit-py.scale_px=0.5")
        .expect_err("below its min");
    assert!(below.to_string().contains("[1, inf)"), "{below}");
    let other = s
        .set("learner.inverse-fit-py.gain=1")
        .expect_err("not its key");
    assert!(
        other.to_string().contains("its settings: scale_px"),
        "{other}"
    );
}

#[test]
fn each_way_a_program_misbehaves_fails_its_trial_saying_how() {
    for (mode, settings, says) in [
        ("crash", &[][..], "exited with status 3"),
        ("garbage", &[], "not the protocol"),
        ("nan", &[], "not finite"),
        ("impossible", &[], "impossible action model"),
        (
            "silent",
            &["exec.answer_timeout_s=0.5"],
            "did not answer within 0.5 s",
        ),
        ("refuse", &[], "gave up: I refuse"),
        ("twice", &[], "wrote a line nobody asked for"),
        ("refuse_event", &[], "gave up: I refuse this event"),
        ("long_line", &[], "a line of more than 1048576 bytes"),
        ("flood", &[], "wrote a line nobody asked for"),
        ("close_stdout", &[], "closed its stdout"),
        (
            "ignore_term",
            &["exec.answer_timeout_s=0.5"],
            "did not answer within 0.5 s",
        ),
        ("exit0", &[], "exited (status 0) before the trial's end"),
        ("not_utf8", &[], "not UTF-8"),
        (
            "late",
            &["exec.answer_timeout_s=0.5"],
            "did not answer within 0.5 s",
        ),
    ] {
        let spec = bad(mode);
        let failed = learn(&spec, settings).expect_err(mode);
        // Dated by the frame it was found in: the bad learners misbehave
        // after 200 events, 100 to 200 frames in (a frame has one or two);
        // a line written unasked is found when it has arrived, a frame or
        // more later.
        let (frame, t_s) = failed.at().expect("where");
        assert!((99..3000).contains(&frame), "{mode}: frame {frame}");
        assert!(
            failed
                .to_string()
                .starts_with(&format!("at {t_s:.2} s (frame {frame}): "))
        );
        match failed.root() {
            TrialError::LearnerFailed(why) => {
                assert!(why.contains(says), "{mode}: {why}");
                assert!(
                    why.contains(&format!("learner `bad-{mode}`")),
                    "{mode}: {why}"
                );
                if mode == "crash" {
                    assert!(why.contains("bad learner: crashing on purpose"), "{why}");
                }
            }
            other => panic!("{mode}: {other:?}"),
        }
    }
}

#[test]
fn a_programs_posterior_is_asked_for_at_the_end_and_checked() {
    // Its draws are its own models: it predicts no error at all.
    let ok = learn(&bad("posterior"), &[]).expect("a posterior that is right in form");
    let p = ok.predicted.expect("a prediction from its posterior");
    let a = p.learned.action.expect("an action band");
    assert!(a.low.abs() < 1e-9 && a.high.abs() < 1e-9, "{a:?}");
    let s = p.learned.sensor.expect("a sensor band");
    assert!(s.low.abs() < 1e-6 && s.high.abs() < 1e-6, "{s:?}");
    // One that declares none is asked for none.
    assert!(learn(&bad("plain"), &[]).expect("ok").predicted.is_none());
    // One whose posterior is wrong in form, or that dies when asked, fails
    // its trial at its last frame, saying how.
    let last = setup().2.frames.len() - 1;
    for (mode, says) in [
        (
            "posterior_unsorted",
            "impossible sensor table: readings not increasing",
        ),
        (
            "posterior_too_many",
            "answered 201 draws of its posterior when asked for 200",
        ),
        ("posterior_crash", "when asked for its posterior"),
    ] {
        let failed = learn(&bad(mode), &[]).expect_err(mode);
        assert_eq!(failed.at().expect("where").0, last, "{mode}");
        match failed.root() {
            TrialError::LearnerFailed(why) => assert!(why.contains(says), "{mode}: {why}"),
            other => panic!("{mode}: {other:?}"),
        }
    }
}

#[test]
fn a_program_that_cannot_start_is_refused_before_any_trial() {
    let (scenario, ..) = setup();
    let mut s = scenario.clone();
    let e = s
        .set("learner.name=exec:/no/such/learner")
        .expect_err("no program");
    assert!(e.to_string().contains("cannot start"), "{e}");
    let e = s
        .set(&format!("learner.name={}", bad("no_hello")))
        .expect_err("no hello");
    assert!(
        e.to_string().contains("before saying hello")
            && e.to_string().contains("giving up before hello"),
        "{e}"
    );
    let e = s
        .set(&format!("learner.name={}", bad("version")))
        .expect_err("version");
    assert!(e.to_string().contains("protocol version 99"), "{e}");
    assert_eq!(
        s.learner_name,
        learners::DEFAULT,
        "a refused learner changes nothing"
    );
}

#[test]
fn a_learner_that_dies_mid_trial_fails_only_its_trial() {
    let (scenario, models, _) = setup();
    let crash = bad("crash");
    let jobs: Vec<Job<'_>> = ["scasm", crash.as_str(), PY_SCASM]
        .iter()
        .flat_map(|&learner| {
            [3, 4].map(|seed| Job {
                scenario,
                models,
                seed,
                learner,
            })
        })
        .collect();
    let results = Mutex::new(vec![None; jobs.len()]);
    experiment::run_jobs(&jobs, &|i, r| {
        results.lock().expect("lock")[i] = Some(r.as_ref().map(|_| ()).map_err(|e| e.to_string()));
    });
    for (job, r) in jobs.iter().zip(results.into_inner().expect("results")) {
        let r = r.expect("every job reports");
        assert_eq!(
            r.is_ok(),
            job.learner != crash,
            "{} seed {}: {r:?}",
            job.learner,
            job.seed
        );
    }
}

#[test]
fn a_rust_learners_own_settings_change_it_and_others_keys_are_refused() {
    let default = learn("batch-ml", &[]).expect("default");
    let rare = learn("batch-ml", &["learner.batch-ml.solve_every_s=40"]).expect("rare");
    assert_ne!(default.sensor_model, rare.sensor_model);
    let (scenario, ..) = setup();
    let mut s = scenario.clone();
    let e = s
        .set("learner.batch-ml.beta=0.1")
        .expect_err("beta is shared");
    let text = e.to_string();
    assert!(
        text.contains("learner `batch-ml` has no setting `beta`"),
        "{text}"
    );
    assert!(
        text.contains("solve_every_s") && text.contains("process_noise"),
        "{text}"
    );
    let e = s
        .set("learner.scasm-paper.gamma=0.9")
        .expect_err("scasm-paper has none of its own");
    assert!(e.to_string().contains("none of its own"), "{e}");
    let e = s
        .set("learner.scasm.gamma=0.9")
        .expect_err("gamma is shared");
    assert!(e.to_string().contains("self_check"), "{e}");
    let e = s
        .set("learner.nobody.gamma=0.9")
        .expect_err("no such learner");
    assert!(
        e.to_string().contains("no learner is called `nobody`"),
        "{e}"
    );
    let e = s
        .set("learner.batch-ml.iterations=2.5")
        .expect_err("a count");
    assert!(e.to_string().contains("whole number"), "{e}");
    s.set("learner.name=batch-ml").expect("batch-ml");
    s.set("learner.batch-ml.solve_every_s=40").expect("set");
    let p = learners::parameters(&s.learner_name, &s);
    assert_eq!(p["learner.batch-ml.solve_every_s"], 40.0);
    assert_eq!(p["learner.forward_degree"], 5.0);
}

#[test]
fn learners_own_settings_are_sweep_axes() {
    use testbed::sweep::{self, Axis};
    let (scenario, ..) = setup();
    let mut base = scenario.clone();
    base.set(&format!("learner.name={PY_INVERSE}"))
        .expect("named");
    let axes = [
        Axis::parse("learner.batch-ml.solve_every_s", "5,20").expect("batch-ml's"),
        Axis::parse("learner.inverse-fit-py.scale_px", "10:10:20").expect("a program's"),
    ];
    let runs = sweep::runs(&axes, &[1]);
    assert_eq!(runs.len(), 4);
    for run in &runs {
        let s = run.scenario(&base).expect("applies");
        for (key, value) in &run.settings {
            let want: f64 = value.parse().expect("a number");
            assert_eq!(s.learner_own.get(key), Some(&want), "{key}");
        }
    }
    let bad = Axis::parse("learner.batch-ml.solve_every_s", "-1,5").expect("parses");
    let e = sweep::runs(&[bad], &[1])[0]
        .scenario(&base)
        .expect_err("out of range");
    assert!(e.to_string().contains("(0, inf)"), "{e}");
}

/// Whether process `pid` has gone (or is only a zombie waiting for its
/// reaper), within 2 s.
#[cfg(target_os = "linux")]
fn gone(pid: &str) -> bool {
    let until = std::time::Instant::now() + std::time::Duration::from_secs(2);
    loop {
        let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
        // The state is the field after the command's closing parenthesis.
        let state = stat.rsplit_once(") ").map(|(_, rest)| &rest[..1]);
        if matches!(state, None | Some("Z")) {
            return true;
        }
        if std::time::Instant::now() > until {
            return false;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

#[test]
#[cfg(target_os = "linux")]
fn a_hung_learner_behind_a_shell_leaves_nothing_running() {
    // issue 55: the shell starts a helper that holds the learner's stdout,
    // then becomes a learner that stops answering; the trial fails on the
    // time limit, and the helper must not outlive it.
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("hung-learner");
    std::fs::create_dir_all(&dir).expect("dir");
    let pid_file = dir.join("helper.pid");
    let _ = std::fs::remove_file(&pid_file);
    let spec = format!(
        "exec:sh -c 'sleep 300 & echo $! > {}; exec python3 tests/fixtures/learners/bad.py hang'",
        pid_file.display()
    );
    let failed = learn(&spec, &["exec.answer_timeout_s=0.5"]).expect_err("hangs");
    match failed.root() {
        TrialError::LearnerFailed(why) => {
            assert!(why.contains("did not answer within 0.5 s"), "{why}")
        }
        other => panic!("{other:?}"),
    }
    let pid = std::fs::read_to_string(&pid_file).expect("the helper's pid");
    assert!(
        gone(pid.trim()),
        "the helper {} outlived its learner's trial",
        pid.trim()
    );
}

#[test]
fn a_failed_trial_keeps_its_world_its_failure_and_its_learners_stderr() {
    // issue 55: a train run whose learner crashes mid-trial keeps the
    // recorded world (replayable), when and why it failed, and all that the
    // learner wrote to stderr.
    let (scenario, models, _) = setup();
    let mut s = scenario.clone();
    s.set(&format!("learner.name={}", bad("crash")))
        .expect("named");
    s.set("trial.duration=20").expect("short");
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("failed-trial");
    let _ = std::fs::remove_dir_all(&out);
    let made_by = testbed::provenance::Provenance::current();
    let results = experiment::run_trials(&s, models, &[5], &|trial| {
        testbed::run_dir::write_trial(&out, &s, models, &made_by, trial).expect("written");
    });
    assert!(results[0].1.is_err(), "the learner crashes");
    let dir = out.join("trial-5");
    let back = testbed::dataset::read(&dir).expect("the recorded world is kept, and reads back");
    assert_eq!(back.recording.frames.len(), 400);
    let failure: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("failure.json")).expect("failure"))
            .expect("json");
    let frame = failure["frame"].as_u64().expect("the frame");
    assert!((99..=201).contains(&frame), "{failure}");
    assert!(failure["t_s"].as_f64().is_some(), "{failure}");
    assert!(
        failure["reason"]
            .as_str()
            .is_some_and(|r| r.contains("exited with status 3")),
        "{failure}"
    );
    let stderr = std::fs::read_to_string(dir.join("learner_stderr.txt")).expect("stderr");
    assert!(
        stderr.contains("bad learner: crashing on purpose"),
        "{stderr}"
    );
    assert!(
        !dir.join("models.json").exists(),
        "no models of a failed run"
    );
}

#[test]
fn the_conformance_check_passes_a_good_learner_and_names_each_broken_rule() {
    use testbed::learners::exec::conformance::check;
    let good = check("exec:python3 examples/learners/quickstart.py", 5.0);
    assert!(good.iter().all(|r| r.passed), "{good:#?}");
    assert_eq!(good.len(), 8);
    let rule = |checks: &[testbed::learners::exec::conformance::RuleCheck], name: &str| {
        checks
            .iter()
            .find(|r| r.rule.contains(name))
            .cloned()
            .expect(name)
    };
    // Crashing 200 events in: a short exchange passes, the whole trial
    // fails, quoting how, and what needs a whole trial is not tried.
    let crash = check(&bad("crash"), 5.0);
    assert!(rule(&crash, "at their defaults").passed, "{crash:#?}");
    let long = rule(&crash, "150 s trial");
    assert!(
        !long.passed && long.detail.contains("exited with status 3"),
        "{long:?}"
    );
    assert!(!rule(&crash, "both models").passed);
    // No sensor model ever: every exchange passes but the trial's end.
    let no_sensor = check(&bad("no_sensor"), 5.0);
    let end = rule(&no_sensor, "both models");
    assert!(
        !end.passed && end.detail.contains("no sensor model"),
        "{end:?}"
    );
    assert!(rule(&no_sensor, "150 s trial").passed);
    // A posterior: checked when it says it has one, and only then.
    let sure = rule(&check(&bad("posterior"), 5.0), "posterior");
    assert!(sure.passed && sure.detail.contains("200 draws"), "{sure:?}");
    let unsorted = check(&bad("posterior_unsorted"), 5.0);
    let wrong = rule(&unsorted, "posterior");
    assert!(
        !wrong.passed && wrong.detail.contains("readings not increasing"),
        "{wrong:?}"
    );
    assert!(rule(&unsorted, "150 s trial").passed);
    assert!(rule(&good, "posterior").detail.contains("optional"));
    // No hello at all: said, and nothing else tried.
    let no_hello = check(&bad("no_hello"), 5.0);
    assert_eq!(no_hello.len(), 1);
    assert!(!no_hello[0].passed && no_hello[0].detail.contains("giving up before hello"));
}

#[test]
fn a_program_that_fails_while_steering_the_walk_fails_its_trial_saying_how() {
    // The explore behaviour asks its twin of the learner for its models
    // once a second; a program that crashes when asked ends the recording
    // at that frame, with its reason and its stderr.
    let (scenario, models, _) = setup();
    let mut s = scenario.clone();
    s.set("behaviour.name=explore").expect("declared");
    s.set("trial.duration=30").expect("a duration");
    let e = experiment::record_for(&s, models, 3, &bad("crash")).expect_err("the twin crashed");
    let why = e.to_string();
    assert!(e.at().is_some(), "at a frame: {why}");
    assert!(
        why.contains("exited with status 3") && why.contains("bad learner: crashing on purpose"),
        "{why}"
    );
    // The same program, well behaved, steers a whole trial.
    assert!(experiment::record_for(&s, models, 3, &bad("plain")).is_ok());
    // A run keeps the steering program's whole stderr with the failure.
    s.set(&format!("learner.name={}", bad("crash")))
        .expect("a program");
    let kept = Mutex::new(None);
    let results = experiment::run_trials(&s, models, &[3], &|t| {
        *kept.lock().expect("kept") = t.stderr.map(str::to_owned);
    });
    assert!(results[0].1.is_err());
    let stderr = kept.into_inner().expect("kept").unwrap_or_default();
    assert!(
        stderr.contains("bad learner: crashing on purpose"),
        "{stderr:?}"
    );
}
