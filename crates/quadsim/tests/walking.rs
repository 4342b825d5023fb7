//! The robot walks the way it is told, by its feet alone, and its world is
//! deterministic.

use quadsim::{ERS7_URDF, QuadrupedSim, RobotDescription, SimConfig};

/// Mean velocity towards the beacon (mm/s) over `seconds` after settling, and
/// whether the torso stayed upright.
fn walk(command: f64, seconds: f64) -> (f64, bool) {
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let mut sim = QuadrupedSim::new(&d, SimConfig::default()).expect("sim");
    sim.advance(0.5);
    sim.set_command(command).expect("finite");
    sim.advance(2.0);
    let d0 = sim.distance_along_line_m();
    let mut upright = true;
    for _ in 0..(seconds / 0.1) as usize {
        sim.advance(0.1);
        upright &= sim.is_upright();
    }
    (
        1000.0 * (d0 - sim.distance_along_line_m()) / seconds,
        upright,
    )
}

#[test]
fn forwards_backwards_and_idle_move_the_right_way() {
    let (fwd, up1) = walk(250.0, 3.0);
    let (back, up2) = walk(-250.0, 3.0);
    let (idle, up3) = walk(0.0, 3.0);
    assert!(up1 && up2 && up3, "fell");
    assert!(fwd > 150.0, "forwards at {fwd:.0} mm/s");
    assert!(back < -150.0, "backwards at {back:.0} mm/s");
    assert!(idle.abs() < 30.0, "idle creeps at {idle:.0} mm/s");
}

#[test]
fn stands_still_without_stepping_only_on_its_feet() {
    // Standing (before any command) the robot rests on its four feet: torso level
    // and at the stance height, nowhere near the floor.
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let mut sim = QuadrupedSim::new(&d, SimConfig::default()).expect("sim");
    sim.advance(1.0);
    let t = sim.torso();
    assert!(t.up[2] > 0.99, "tilted: {:?}", t.up);
    assert!(t.position_m[2] > 0.12, "torso at {:.3} m", t.position_m[2]);
}

#[test]
fn non_finite_commands_are_refused() {
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let mut sim = QuadrupedSim::new(&d, SimConfig::default()).expect("sim");
    sim.set_command(100.0).expect("finite");
    assert!(sim.set_command(f64::NAN).is_err());
    assert_eq!(sim.command(), 100.0);
}

#[test]
fn out_of_range_settings_are_named() {
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let bad = SimConfig {
        friction: -1.0,
        ..Default::default()
    };
    let err = QuadrupedSim::new(&d, bad).expect_err("refused");
    assert!(err.to_string().contains("world.friction"), "{err}");
    let bad = SimConfig {
        dt_s: 0.0,
        ..Default::default()
    };
    assert!(
        QuadrupedSim::new(&d, bad)
            .expect_err("refused")
            .to_string()
            .contains("physics.dt")
    );
}

#[test]
fn the_gyro_heading_follows_the_true_heading_through_turns() {
    // A minute of commands changing both ways, through the trot's roll, pitch
    // and turns: the attitude integrated from the gyro must not drift from the
    // torso's true yaw (a gyro read from the body's end-of-step angular
    // velocity drifted by 0.002 rad a minute and 0.9 rad in ten).
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let mut sim = QuadrupedSim::new(&d, SimConfig::default()).expect("sim");
    let mut worst: f64 = 0.0;
    for (k, command) in [300.0, -250.0, 120.0, -60.0, 280.0, 0.0, -300.0, 200.0]
        .into_iter()
        .cycle()
        .take(24)
        .enumerate()
    {
        sim.set_command(command).expect("finite");
        sim.advance(2.5);
        let diff = sim.heading_estimate_rad() - sim.torso().yaw_rad;
        let diff =
            (diff + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        worst = worst.max(diff.abs());
        assert!(sim.is_upright(), "fell at leg {k}");
    }
    assert!(worst < 1e-3, "heading estimate off by {worst:.4} rad");
}
