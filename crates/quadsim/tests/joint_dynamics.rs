//! A joint's own dynamics as the model file gives them (URDF's `<dynamics
//! damping friction>`, MJCF's `damping frictionloss armature`) are simulated:
//! zeros are the same robot to the bit as none; damping or dry friction
//! comparable to what the servos can exert hold the legs back, so the robot
//! walks a fraction of the way; MuJoCo Menagerie's Go2 carries its
//! armature, damping and frictionloss into the description; a negative or
//! non-finite value is refused naming the joint.

use std::path::Path;

use quadsim::{ERS7_URDF, QuadrupedSim, RobotDescription, RobotFile, SimConfig};

/// The ERS-7 with `dynamics` on every revolute joint.
fn with_dynamics(dynamics: Option<urdf_rs::Dynamics>) -> Result<RobotDescription, String> {
    let mut urdf = urdf_rs::read_from_string(ERS7_URDF).expect("parses");
    for j in &mut urdf.joints {
        if matches!(j.joint_type, urdf_rs::JointType::Revolute) {
            j.dynamics = dynamics.clone();
        }
    }
    let map = quadsim::description::RobotMap::conventional(&urdf).expect("the ERS-7's names");
    RobotDescription::from_urdf(urdf, &map).map_err(|e| e.to_string())
}

fn dynamics(damping: f64, friction: f64) -> Option<urdf_rs::Dynamics> {
    Some(urdf_rs::Dynamics { damping, friction })
}

include!("common/walked.rs");

#[test]
fn zero_dynamics_are_none_to_the_bit() {
    let none = with_dynamics(None).expect("loads");
    let zeros = with_dynamics(dynamics(0.0, 0.0)).expect("loads");
    assert_eq!(walked(&zeros), walked(&none));
}

#[test]
fn damping_and_dry_friction_in_the_file_resist_the_legs() {
    let start = |d: &RobotDescription| {
        let mut sim = QuadrupedSim::new(d, SimConfig::default()).expect("a world");
        sim.advance(0.5);
        sim.torso().position_m[0]
    };
    let none = with_dynamics(None).expect("loads");
    let gone = |d: &RobotDescription| walked(d)[0] - start(d);
    let free = gone(&none);
    // The ERS-7's servos exert at most 1.0 N m (its URDF's effort limits)
    // and turn its joints at several rad/s while walking.
    for (damping, friction) in [(1.0, 0.0), (0.0, 1.0)] {
        let resisted = with_dynamics(dynamics(damping, friction)).expect("loads");
        let slowed = gone(&resisted);
        assert!(
            slowed < 0.5 * free,
            "damping {damping} friction {friction}: {slowed} m walked, {free} m without"
        );
    }
}

#[test]
fn a_negative_or_non_finite_dynamics_value_is_refused_naming_the_joint() {
    for (damping, friction) in [
        (-1.0, 0.0),
        (0.0, -0.1),
        (f64::NAN, 0.0),
        (0.0, f64::INFINITY),
    ] {
        let e = with_dynamics(dynamics(damping, friction)).expect_err("refused");
        assert!(e.contains("joint `"), "{e}");
        assert!(e.contains("dynamics"), "{e}");
    }
}

#[test]
fn the_go2s_armature_damping_and_frictionloss_are_its_joints() {
    let dir =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/robots/menagerie/unitree_go2");
    let robot = RobotFile::from_file(&dir.join("go2.xml")).expect("the Go2");
    let d = &robot.description;
    let leg_joints: Vec<&String> = d.legs.iter().flat_map(|l| &l.joints).collect();
    assert_eq!(leg_joints.len(), 12);
    for name in leg_joints {
        // go2.xml's class `go2`: damping="2" armature="0.01" frictionloss="0.2".
        assert_eq!(d.armature.get(name), Some(&0.01), "{name}");
        let joint = d
            .urdf
            .joints
            .iter()
            .find(|j| &j.name == name)
            .expect("the joint");
        let dynamics = joint.dynamics.as_ref().expect("dynamics");
        assert_eq!((dynamics.damping, dynamics.friction), (2.0, 0.2), "{name}");
    }
    assert!(
        !d.notes.iter().any(|n| n.contains("armature")),
        "armature is simulated, not left out: {:?}",
        d.notes
    );
}
