//! Ten minutes of the paper's behaviour on each shipped robot: random commands
//! held 3 s, turning round at 1.2 m and 3.6 m (at the robot's scale). It must
//! never fall, must keep facing the beacon and stay near its line of approach,
//! and a run must be bit-identical per seed.
//!
//! The behaviour is driven by ideal readings computed from the true distance: this
//! is a test of the robot, not of a learner, and no learner is involved.

use quadsim::{QuadrupedSim, RobotFile, RobotScale};
use testbed::behaviour::{Behaviour, BehaviourConfig, Phase, TrainingBehaviour};
use testbed::seeds::{self, Stream};

const K_PX_M: f64 = 38.4; // an ideal 200 mm band through a 192 px lens, px * m

#[derive(Debug, Default, PartialEq)]
struct Walk {
    min_up: f64,
    max_lateral_m: f64,
    max_yaw_rad: f64,
    turns: usize,
    final_bits: Vec<u64>,
}

fn walk(robot: &str, seconds: f64, seed: u64) -> Walk {
    let file = RobotFile::shipped(robot).expect("robot");
    let description = &file.description;
    let scale = RobotScale::of(description);
    let mut sim = QuadrupedSim::new(description, file.sim_config()).expect("sim");
    // The beacon scales with the robot, so the turning readings do not.
    let k_px_m = K_PX_M * scale.length;
    let mut behaviour = TrainingBehaviour::new(
        BehaviourConfig::paper(
            300.0 * scale.speed(),
            k_px_m / (1.2 * scale.length),
            k_px_m / (3.6 * scale.length),
        ),
        seeds::rng(seed, Stream::Behaviour),
        Phase::Forwards,
    );
    let mut out = Walk {
        min_up: 1.0,
        ..Default::default()
    };
    let mut phase = behaviour.phase();
    let frame_s = 0.05;
    let frames = (seconds / frame_s) as u64;
    for k in 0..frames {
        let t = k as f64 * frame_s;
        sim.set_command(behaviour.command(t)).expect("finite");
        sim.advance(frame_s);
        behaviour.observe(t + frame_s, Some(k_px_m / sim.distance_along_line_m()));
        if behaviour.phase() != phase {
            out.turns += 1;
            phase = behaviour.phase();
        }
        let s = sim.torso();
        out.min_up = out.min_up.min(s.up[2]);
        out.max_lateral_m = out.max_lateral_m.max(sim.lateral_offset_m().abs());
        out.max_yaw_rad = out.max_yaw_rad.max(s.yaw_rad.abs());
    }
    let s = sim.torso();
    out.final_bits = s
        .position_m
        .iter()
        .chain(&s.orientation)
        .map(|v| v.to_bits())
        .collect();
    out
}

/// Ten simulated minutes of `robot`: upright, facing the beacon, near its line
/// (0.1 m at the ERS-7's scale), across the whole range again and again.
fn ten_minutes_hold(robot: &str) {
    let w = walk(robot, 600.0, 0);
    eprintln!("{robot}: {w:?}");
    let scale = RobotScale::of(&RobotFile::shipped(robot).expect("robot").description);
    assert!(
        w.min_up > 0.8,
        "{robot}: torso tipped: up z {:.3}",
        w.min_up
    );
    // 0.2 rad keeps the beacon well inside the camera's 28 degree half-width.
    assert!(
        w.max_yaw_rad < 0.2,
        "{robot}: turned {:.3} rad away from the beacon",
        w.max_yaw_rad
    );
    assert!(
        w.max_lateral_m < 0.1 * scale.length,
        "{robot}: drifted {:.3} m off the line",
        w.max_lateral_m
    );
    // Six crossings of the range at the ERS-7's pace; fewer, by sqrt(s), for
    // a larger robot walking the same gait more slowly.
    let crossings = (6.0 / scale.time()).floor() as usize;
    assert!(
        w.turns >= crossings,
        "{robot}: covered the range only {} times",
        w.turns
    );
}

#[test]
fn ten_minutes_of_training_behaviour_hold_on_the_ers7() {
    ten_minutes_hold("ers7");
}

#[test]
fn ten_minutes_of_training_behaviour_hold_on_the_trotter() {
    ten_minutes_hold("trotter");
}

#[test]
fn a_walk_is_bit_identical_per_seed() {
    assert_eq!(walk("ers7", 20.0, 5), walk("ers7", 20.0, 5));
    assert_ne!(
        walk("ers7", 20.0, 5).final_bits,
        walk("ers7", 20.0, 6).final_bits
    );
}
