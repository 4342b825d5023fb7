//! The world seam (`testbed::world`): a trial walks the robot in rapier, the
//! synthetic point robot, or a recording walked again, through one runner.
//! The synthetic world goes through the whole run pipeline (its models are
//! its truth, at the robot's scale), a recording walked again with the
//! behaviour that made it gives back its frames bit for bit and refuses
//! another behaviour where it departs, and what a world cannot do is refused
//! with a reason.

mod common;

use testbed::experiment;
use testbed::reference;
use testbed::scenario::Scenario;
use testbed::trial::{TrialError, TrialRunner};
use testbed::world::synthetic::true_velocity_mm_s;
use testbed::world::{Replayed, WorldKind};

fn synthetic(settings: &[&str]) -> Scenario {
    let mut settings: Vec<String> = settings.iter().map(|s| s.to_string()).collect();
    settings.push("trial.world=synthetic".into());
    Scenario::from_settings(None, None, &settings).expect("a synthetic scenario")
}

#[test]
fn the_synthetic_world_walks_its_truth_and_reads_through_the_scenarios_camera() {
    let scenario = synthetic(&["camera.noise_px=2", "trial.duration=60"]);
    assert_eq!(scenario.world, WorldKind::Synthetic);
    let models = reference::measured_models(&scenario, None).expect("its truth");
    // The models are the truth, measured with no noise.
    for m in &models.action {
        assert_eq!(m.velocity_mm_s, true_velocity_mm_s(m.command));
        assert_eq!(m.std_mm_s, 0.0);
    }
    let recording = experiment::record(&scenario, &models, 7).expect("recorded");
    assert_eq!(recording.frames.len(), 1200);
    // Each frame's truth moves by the true velocity of its command.
    let mut x = 1000.0 * scenario.sim.start_distance_m;
    let mut residuals = Vec::new();
    for f in &recording.frames {
        x -= true_velocity_mm_s(f.command) * f.dt_s;
        assert_eq!(f.truth.x_mm.to_bits(), x.to_bits(), "frame at {} s", f.t_s);
        residuals.push(f.obs_px.expect("always in view") - 76_800.0 / x);
    }
    // The readings' noise is the scenario's camera's.
    let n = residuals.len() as f64;
    let mean = residuals.iter().sum::<f64>() / n;
    let std = (residuals.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / n).sqrt();
    assert!((std - 2.0).abs() < 0.15, "reading noise {std} px, asked 2");
    assert!(mean.abs() < 0.15, "reading bias {mean} px");
    // Same seed, same bits; another seed, other readings.
    let again = experiment::record(&scenario, &models, 7).expect("recorded");
    assert_eq!(again.frames, recording.frames);
    let other = experiment::record(&scenario, &models, 8).expect("recorded");
    assert_ne!(other.frames, recording.frames);
}

#[test]
fn the_synthetic_world_takes_another_robots_scale() {
    let ers7 = synthetic(&[]);
    let trotter = synthetic(&["robot.file=trotter"]);
    let scale = trotter.scale();
    assert!(
        (scale.length - 1.0).abs() > 0.1,
        "the trotter is not the ERS-7's size"
    );
    let (a, b) = (
        reference::measured_models(&ers7, None).expect("truth"),
        reference::measured_models(&trotter, None).expect("truth"),
    );
    // The same curve at scaled commands and speeds, the same readings at
    // scaled distances.
    for (m, n) in a.action.iter().zip(&b.action) {
        assert!((n.command - m.command * scale.speed()).abs() < 1e-9);
        assert!((n.velocity_mm_s - m.velocity_mm_s * scale.speed()).abs() < 1e-9);
    }
    for (m, n) in a.sensor.iter().zip(&b.sensor) {
        assert!((n.distance_mm - m.distance_mm * scale.length).abs() < 1e-9);
        assert!((n.obs_px - m.obs_px).abs() < 1e-9);
    }
    // And its trials learn, judged against that truth.
    let learned = experiment::run_one(&trotter, &b, 3).expect("a trial");
    let action = learned.1.last.action_rmse_mm_s.expect("an action model");
    assert!(
        action < 0.03 * b.velocity_range_mm_s(),
        "action {action} mm/s"
    );
}

#[test]
fn a_recording_walked_again_gives_its_frames_back_and_refuses_another_behaviour() {
    let (paper, models) = common::paper_reference();
    let mut scenario = paper.clone();
    scenario.set("trial.duration=20").expect("duration");
    let recording = experiment::record(&scenario, models, 5).expect("recorded");
    let config = experiment::trial_config(&scenario, models, 5).expect("config");

    let mut runner = TrialRunner::in_world(Replayed::new(recording.frames.clone()), config.clone())
        .expect("a trial");
    let again = runner.record_until(|_| false).expect("walked again");
    assert_eq!(again, recording.frames, "bit for bit");

    let mut other = config;
    other.behaviour.name = testbed::behaviour::registry::resolve("design")
        .expect("declared")
        .name;
    let mut runner =
        TrialRunner::in_world(Replayed::new(recording.frames.clone()), other).expect("a trial");
    let err = runner.record_until(|_| false).expect_err("departs");
    let text = err.to_string();
    assert!(
        matches!(err, TrialError::Recording(_)) && text.contains("the behaviour commands"),
        "{text}"
    );
}

#[test]
fn what_a_world_cannot_do_is_refused_with_a_reason() {
    let err = Scenario::from_settings(None, None, &["trial.world=mujoco".into()])
        .expect_err("no such world")
        .to_string();
    assert!(err.contains("rapier, synthetic"), "{err}");

    let mut changing = synthetic(&[]);
    changing
        .apply_toml(
            "change.toml",
            "[[change]]\nat_s = 60.0\nkey = \"world.friction\"\nvalue = \"0.3\"\n",
        )
        .expect("a change of the world");
    let err = reference::measured_models(&changing, None)
        .expect_err("a point robot has nothing to change")
        .to_string();
    assert!(err.contains("[[change]]"), "{err}");
}
