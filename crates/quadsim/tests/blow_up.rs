//! A physics blow-up is told from a walk or a fall by the robot's kinetic
//! energy (`QuadrupedSim::blew_up_at_s`): walking, the ERS-7 stays far below
//! the line, and a body with a singular inertia blows up across it.

use quadsim::{ERS7_URDF, MultibodyDynamics, QuadrupedSim, RobotDescription, SimConfig};

/// The peak kinetic energy over `seconds` at `command`, as a share of the
/// blow-up line, and when the physics blew up, if it did.
fn peak_share(urdf: &str, command: f64, seconds: f64) -> (f64, Option<f64>) {
    let d = RobotDescription::from_urdf_str(urdf).expect("urdf");
    let mut sim = QuadrupedSim::new(&d, SimConfig::default()).expect("sim");
    sim.advance(0.5);
    sim.set_command(command).expect("finite");
    let mut peak = 0.0_f64;
    let steps = (seconds / sim.config().dt_s).round() as usize;
    for _ in 0..steps {
        sim.step();
        let energy = sim.kinetic_energy_j();
        assert!(energy.is_finite() && energy >= 0.0, "{energy} J");
        // The cheap bound the step tests first is never below the energy.
        let bound = sim.kinetic_energy_bound_j();
        assert!(
            bound >= energy * (1.0 - 1e-6),
            "bound {bound} J below {energy} J"
        );
        peak = peak.max(energy);
    }
    assert!(sim.is_upright());
    (peak / sim.blow_up_energy_j(), sim.blew_up_at_s())
}

#[test]
fn walking_either_way_at_full_speed_is_far_below_a_blow_up() {
    for command in [300.0, -300.0, 0.0] {
        let (share, blew_up) = peak_share(ERS7_URDF, command, 20.0);
        assert_eq!(blew_up, None, "command {command}");
        // The walk moves: its energy is not zero, but a small part of the line.
        assert!(share > 1e-5 && share < 0.02, "command {command}: {share}");
    }
}

/// A body whose inertia is singular (every entry alike, as ANYmal C's
/// `hatch` was published) blows the physics up. The loader folds such mass
/// into the body it is fixed to, and refuses a moving link with it, so the
/// description is altered after loading, to make the blow-up the line must
/// see. It blows up rapier's own dynamics (`physics.multibody = rapier`),
/// whose Coriolis terms are linearised into the mass matrix; the tree
/// dynamics (the default) walks it.
#[test]
fn a_body_with_a_singular_inertia_blows_up_and_the_line_sees_it() {
    let mut d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let shank = d.urdf.links.iter_mut().find(|l| l.name == "fl_shank");
    let i = &mut shank.expect("fl_shank").inertial.inertia;
    (i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz) = (2e-5, 2e-5, 2e-5, 2e-5, 2e-5, 2e-5);
    let config = SimConfig {
        multibody: MultibodyDynamics::Rapier,
        ..SimConfig::default()
    };
    let mut sim = QuadrupedSim::new(&d, config).expect("sim");
    sim.advance(0.5);
    sim.set_command(300.0).expect("finite");
    sim.advance(4.0);
    let at = sim.blew_up_at_s().expect("the physics blew up");
    assert!(at > 0.5 && at <= sim.time_s(), "{at}");
    assert!(!sim.is_upright());
}
