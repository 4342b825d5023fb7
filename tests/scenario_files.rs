//! Scenario files: the shipped ones load, a typo or an out-of-range value is an
//! error that names it, a malformed file says where, and a refused file changes
//! nothing.

use testbed::scenario::Scenario;

const PAPER: &str = include_str!("../assets/scenarios/paper.toml");

#[test]
fn the_paper_scenario_file_is_the_default() {
    let mut s = Scenario::paper().expect("scenario");
    let defaults = (s.learner, s.sim, s.duration_s);
    s.apply_toml("paper.toml", PAPER).expect("valid");
    assert_eq!(s.learner, defaults.0);
    assert_eq!(s.sim, defaults.1);
    assert_eq!(s.duration_s, defaults.2);
}

#[test]
fn every_shipped_scenario_loads() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenarios");
    let mut n = 0;
    for dir in [root.clone(), root.join("suite")] {
        for entry in std::fs::read_dir(dir).expect("scenarios") {
            let path = entry.expect("entry").path();
            if path.extension().is_some_and(|x| x == "toml") {
                Scenario::from_settings(None, Some(&path), &[])
                    .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                n += 1;
            }
        }
    }
    assert!(n >= 9, "{n} scenario files");
}

fn refused(text: &str, needle: &str) {
    let mut s = Scenario::paper().expect("scenario");
    let before = (s.learner, s.sim, s.duration_s);
    let e = s.apply_toml("bad.toml", text).expect_err("must be refused");
    assert!(
        e.to_string().contains(needle),
        "`{e}` should mention `{needle}`"
    );
    assert_eq!(
        (s.learner, s.sim, s.duration_s),
        before,
        "a refused file changed the scenario"
    );
}

#[test]
fn unknown_keys_and_sections_are_named() {
    refused("[learner]\ngama = 0.9\n", "learner.gama");
    refused("[lerner]\ngamma = 0.9\n", "lerner.gamma");
}

#[test]
fn out_of_range_values_are_named_and_nothing_is_applied() {
    // The first setting is valid, the second is not: neither may stick.
    refused("[learner]\nbeta = 0.05\ngamma = 1.5\n", "learner.gamma");
    refused("[world]\nfriction = -1.0\n", "world.friction");
    refused("[learner]\nsensor_degree = 0\n", "learner.sensor_degree");
}

#[test]
fn malformed_files_say_where() {
    refused("[learner\ngamma = 0.9\n", "bad.toml");
    refused("gamma = 0.9\n", "`gamma` must be a [section]");
    refused(
        "[learner]\ngamma = \"high\"\n",
        "learner.gamma` must be a number",
    );
}

#[test]
fn a_robot_that_cannot_walk_the_gait_is_refused_naming_its_file() {
    // The shipped robot with front-left knee limits of +-0.2 rad: a
    // consistent description, but the gait bends that knee by about a radian.
    let urdf = include_str!("../assets/ers7.urdf");
    let start = urdf.find(r#"<joint name="fl_knee""#).expect("fl_knee");
    let end = start + urdf[start..].find("</joint>").expect("end");
    let joint = urdf[start..end].replacen(
        r#"lower="-2.4" upper="2.4""#,
        r#"lower="-0.2" upper="0.2""#,
        1,
    );
    let text = format!("{}{joint}{}", &urdf[..start], &urdf[end..]);
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("scasm-stiff-knee-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("stiff_knee.urdf");
    std::fs::write(&path, text).expect("write");
    let mut s = Scenario::paper().expect("scenario");
    let e = s
        .set(&format!("robot.urdf={}", path.display()))
        .expect_err("must be refused");
    let msg = e.to_string();
    for needle in ["stiff_knee.urdf", "joint `fl_knee`", "[-0.2, 0.2]"] {
        assert!(msg.contains(needle), "`{msg}` should mention `{needle}`");
    }
    assert!(
        s.robot_file.is_none(),
        "a refused robot changed the scenario"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_robot_file_sets_the_robot_and_the_world_at_its_scale_before_anything_else() {
    // The robot is applied first wherever it is set: a beacon setting given
    // before it still holds.
    let settings = [
        "beacon.height_m=0.9".to_string(),
        "robot.file=trotter".to_string(),
    ];
    let s = Scenario::from_settings(None, None, &settings).expect("trotter");
    let scale = s.scale();
    assert!((scale.length - 0.4 / 0.14).abs() < 1e-9, "{scale:?}");
    assert_eq!(s.description.root_link, "trunk");
    assert_eq!(s.sim.beacon.band_height_m, 0.9);
    let base = Scenario::paper().expect("paper");
    assert!((s.sim.start_distance_m - scale.length * base.sim.start_distance_m).abs() < 1e-9);
    assert!((s.max_command() - 300.0 * scale.speed()).abs() < 1e-9);
    assert!((s.learner.command_scale - s.max_command()).abs() < 1e-9);
    // Times scale by sqrt(s): the trial and the learner's time constants.
    let t = scale.time();
    assert!((s.duration_s - t * base.duration_s).abs() < 1e-9);
    assert!((s.learner.t_start_s - t * base.learner.t_start_s).abs() < 1e-9);
    assert!((s.learner.gamma.powf(t) - base.learner.gamma).abs() < 1e-12);
    assert_ne!(s.reference_key(), base.reference_key());
    // Written out, it reads back to the same scenario.
    reads_back(&s);
    // The ERS-7 by name is the default robot, to the bit.
    let ers7 = Scenario::from_settings(None, None, &["robot.file=ers7".to_string()]).expect("ers7");
    assert_eq!(ers7.sim, base.sim);
    assert_eq!(ers7.learner, base.learner);
}

#[test]
fn an_unknown_robot_is_named_and_changes_nothing() {
    let mut s = Scenario::paper().expect("scenario");
    let before = s.reference_key();
    let err = s.set("robot.file=no_such_robot").expect_err("refused");
    assert!(err.to_string().contains("no_such_robot"), "{err}");
    assert_eq!(s.reference_key(), before);
}

#[test]
fn blanked_intervals_are_checked_against_the_trial() {
    let set = |settings: &[&str]| {
        let settings: Vec<String> = settings.iter().map(|s| s.to_string()).collect();
        Scenario::from_settings(None, None, &settings)
    };
    // The trial's length applies first, wherever it is given.
    let s = set(&["camera.blank_s=300..310,400..420", "trial.duration=600"]).expect("valid");
    assert_eq!(s.blank.intervals(), &[(300.0, 310.0), (400.0, 420.0)]);
    for (bad, needle) in [
        ("camera.blank_s=100..90", "100..90"),
        ("camera.blank_s=100-110", "100-110"),
        ("camera.blank_s=140..160", "140..160"),
        ("camera.blank_s=10..20,15..30", "15..30"),
    ] {
        let err = set(&[bad]).expect_err(bad).to_string();
        assert!(
            err.contains(needle) && err.contains("camera.blank_s"),
            "{err}"
        );
    }
    let err = set(&["camera.blank_s=100..140", "trial.duration=120"])
        .expect_err("blank past the trial")
        .to_string();
    assert!(
        err.contains("camera.blank_s") && err.contains("120"),
        "{err}"
    );
    // Shortening the trial later is refused too, and changes nothing.
    let mut s = set(&["camera.blank_s=100..140"]).expect("within 150 s");
    let err = s
        .set("trial.duration=120")
        .expect_err("cuts the blank")
        .to_string();
    assert!(
        err.contains("trial.duration") && err.contains("140"),
        "{err}"
    );
    assert_eq!(s.duration_s, 150.0);
}

const FRICTION_CHANGE: &str = include_str!("../assets/scenarios/friction_change.toml");

#[test]
fn a_scheduled_change_is_read_checked_and_written_back() {
    let mut s = Scenario::paper().expect("scenario");
    s.apply_toml("friction_change.toml", FRICTION_CHANGE)
        .expect("valid");
    assert_eq!(s.duration_s, 600.0);
    assert_eq!(s.changes.len(), 1);
    let worlds = s.worlds().expect("valid changes");
    assert_eq!(worlds.len(), 2);
    assert_eq!((worlds[0].0, worlds[0].1.friction), (0.0, 0.9));
    assert_eq!((worlds[1].0, worlds[1].1.friction), (300.0, 0.45));
    // Only the friction differs between the two worlds.
    let mut after = worlds[1].1;
    after.friction = 0.9;
    assert_eq!(after, worlds[0].1);
    // The run's config.toml reads back to the same schedule.
    let mut back = Scenario::paper().expect("scenario");
    back.apply_toml("config.toml", &s.to_toml()).expect("valid");
    assert_eq!(back.changes, s.changes);
    assert_eq!(back.to_toml(), s.to_toml());
    // A world setting given on top applies to both worlds, the change on top.
    s.set("servo.torque_scale=0.8").expect("valid");
    let worlds = s.worlds().expect("valid");
    assert_eq!(worlds[1].1.servo.torque_scale, 0.8);
    assert_eq!(worlds[1].1.friction, 0.45);
}

fn change(at_s: &str, key: &str, value: &str) -> String {
    format!(
        "[trial]\nduration = 600.0\n\n[[change]]\nat_s = {at_s}\nkey = \"{key}\"\nvalue = {value}\n"
    )
}

#[test]
fn a_change_that_cannot_be_made_is_named() {
    for (text, needles) in [
        (
            change("300.0", "world.frictoin", "0.5"),
            vec!["world.frictoin", "300", "unknown setting"],
        ),
        (
            change("300.0", "physics.dt", "0.002"),
            vec!["physics.dt", "cannot change during a run"],
        ),
        (
            change("300.0", "camera.hfov_deg", "40"),
            vec!["camera.hfov_deg", "camera intrinsics cannot change"],
        ),
        (
            change("300.0", "learner.gamma", "0.99"),
            vec!["learner.gamma", "not part of the world"],
        ),
        (
            change("700.0", "world.friction", "0.5"),
            vec!["world.friction", "700", "outside the trial"],
        ),
        (
            change("300.0", "world.friction", "-1"),
            vec!["world.friction", "in [0, 5]"],
        ),
        (
            change("300.0", "world.friction", "\"slippery\""),
            vec!["world.friction", "slippery"],
        ),
        (
            "[[change]]\nat_s = 10.0\nkey = \"world.friction\"\nvalue = 0.5\nwhen = 3\n".into(),
            vec!["[[change]]", "when"],
        ),
        (
            "[[change]]\nkey = \"world.friction\"\nvalue = 0.5\n".into(),
            vec!["[[change]]", "at_s"],
        ),
        ("[change]\nat_s = 10.0\n".into(), vec!["[[change]]"]),
        (
            format!(
                "{}\n[[change]]\nat_s = 100.0\nkey = \"camera.noise_px\"\nvalue = 2\n",
                change("300.0", "world.friction", "0.5")
            ),
            vec!["camera.noise_px", "time order"],
        ),
    ] {
        for needle in &needles {
            refused(&text, needle);
        }
    }
    // Shortening the trial past a change is refused, naming both.
    let mut s = Scenario::paper().expect("scenario");
    s.apply_toml("friction_change.toml", FRICTION_CHANGE)
        .expect("valid");
    let err = s
        .set("trial.duration=200")
        .expect_err("cuts the change")
        .to_string();
    assert!(
        err.contains("world.friction") && err.contains("300"),
        "{err}"
    );
    assert_eq!(s.duration_s, 600.0);
}

/// `s` written out as a config.toml reads back to the same world and reference.
fn reads_back(s: &Scenario) {
    let mut again = Scenario::paper().expect("paper");
    again
        .apply_toml("config.toml", &s.to_toml())
        .expect("round trip");
    assert_eq!(again.sim, s.sim);
    assert_eq!(again.reference_key(), s.reference_key());
}

#[test]
fn the_solver_iterations_are_a_setting_checked_and_written_back() {
    let s = Scenario::from_settings(None, None, &["physics.solver_iterations=2".to_string()])
        .expect("two iterations");
    let base = Scenario::paper().expect("paper");
    assert_eq!(s.sim.solver_iterations, 2);
    assert_eq!(base.sim.solver_iterations, 1, "the default is one");
    assert_ne!(s.reference_key(), base.reference_key());
    reads_back(&s);
    refused(
        "[physics]\nsolver_iterations = 0\n",
        "physics.solver_iterations",
    );
    refused(
        "[physics]\nsolver_iterations = 1.5\n",
        "physics.solver_iterations",
    );
}

#[test]
fn the_multibody_dynamics_is_a_setting_checked_and_written_back() {
    let base = Scenario::paper().expect("paper");
    for name in quadsim::MultibodyDynamics::NAMES {
        let s = Scenario::from_settings(None, None, &[format!("physics.multibody={name}")])
            .expect("a multibody dynamics");
        assert_eq!(s.sim.multibody.as_str(), name);
        assert_eq!(
            s.reference_key() == base.reference_key(),
            s.sim.multibody == base.sim.multibody,
            "the reference depends on it"
        );
        reads_back(&s);
    }
    refused(
        "[physics]\nmultibody = \"featherstone\"\n",
        "physics.multibody",
    );
    refused("[physics]\nmultibody = 2\n", "physics.multibody");
}

/// `key=value` is taken, read back and keyed into the reference, `field`
/// reads it (`default` in the paper's scenario), and each of `bad` (TOML
/// values) is refused naming the key.
fn a_walk_setting(key: &str, value: f64, default: f64, field: fn(&Scenario) -> f64, bad: &[&str]) {
    let base = Scenario::paper().expect("paper");
    let s = Scenario::from_settings(None, None, &[format!("walk.{key}={value}")]).expect("taken");
    assert_eq!(field(&s), value);
    assert_eq!(field(&base), default, "the default");
    assert_ne!(
        s.reference_key(),
        base.reference_key(),
        "the reference depends on it"
    );
    reads_back(&s);
    for b in bad {
        refused(&format!("[walk]\n{key} = {b}\n"), &format!("walk.{key}"));
    }
}

#[test]
fn the_walk_engines_command_slew_is_a_setting_checked_and_written_back() {
    a_walk_setting(
        "command_slew",
        750.0,
        1500.0,
        |s| s.sim.walk.command_slew_mm_s2,
        &["0.0", "-500.0", "\"fast\""],
    );
}

#[test]
fn the_walk_engines_pitch_gain_is_a_setting_checked_and_written_back() {
    // The default is open loop.
    a_walk_setting(
        "pitch_gain",
        0.3,
        0.0,
        |s| s.sim.walk.pitch_gain,
        &["-0.1", "1.5"],
    );
}

#[test]
fn settings_a_run_cannot_use_are_refused_with_their_range() {
    // issue 61: each of these used to load, and a run then took forever or
    // learned from nothing.
    for (setting, range) in [
        ("physics.dt=1e-300", "[0.0001, 0.01] s"),
        ("camera.frame_period_s=1e9", "[physics.dt, 1] s"),
        (
            "trial.seeds=0..18446744073709551615",
            "a run takes at most 1000000",
        ),
    ] {
        let e = Scenario::from_settings(None, None, &[setting.to_string()])
            .expect_err(setting)
            .to_string();
        assert!(e.contains(range), "{setting}: {e}");
    }
    // A robot path that is not a regular file is refused at once.
    #[cfg(unix)]
    {
        let e = Scenario::from_settings(None, None, &["robot.file=/dev/zero".into()])
            .expect_err("a device")
            .to_string();
        assert!(e.contains("a character device"), "{e}");
    }
}
