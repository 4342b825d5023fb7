//! `physics.multibody = tree` steps the same robot as rapier's own dynamics
//! (`rapier`): from the same start, at the same commands, the torso's path
//! agrees over seconds of walking to within what the two integrators' rounding
//! and the gait's contacts make of it.

use quadsim::{ERS7_URDF, MultibodyDynamics, QuadrupedSim, RobotDescription, SimConfig};

fn sim(multibody: MultibodyDynamics) -> QuadrupedSim {
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let config = SimConfig {
        multibody,
        ..SimConfig::default()
    };
    QuadrupedSim::new(&d, config).expect("sim")
}

#[test]
fn the_tree_dynamics_walk_the_robot_rapier_walks() {
    let (mut tree, mut rapier) = (sim(MultibodyDynamics::Tree), sim(MultibodyDynamics::Rapier));
    for (command, seconds) in [(0.0, 0.5), (300.0, 3.0), (-200.0, 3.0)] {
        tree.set_command(command).expect("finite");
        rapier.set_command(command).expect("finite");
        let mut worst = (0.0f64, 0.0f64);
        for _ in 0..(seconds * 10.0) as usize {
            tree.advance(0.1);
            rapier.advance(0.1);
            let (a, b) = (tree.torso(), rapier.torso());
            let apart = ((a.position_m[0] - b.position_m[0]).powi(2)
                + (a.position_m[1] - b.position_m[1]).powi(2))
            .sqrt();
            let yaw = (a.yaw_rad - b.yaw_rad).abs();
            worst = (worst.0.max(apart), worst.1.max(yaw));
        }
        eprintln!(
            "command {command}: torsos at most {:.2} mm and {:.3} deg apart",
            worst.0 * 1e3,
            worst.1.to_degrees()
        );
        // Seen: 0.17 mm and 0.04 deg walking at 300 for 3 s, 0.20 mm and
        // 0.06 deg walking back; the gait's stride is 30-40 mm.
        assert!(worst.0 < 2e-3, "command {command}: {} m apart", worst.0);
        assert!(
            worst.1 < 0.5f64.to_radians(),
            "command {command}: {} rad",
            worst.1
        );
    }
}
