//! What viewers draw: the scene's bodies and shapes come from the URDF and the
//! world, and their placements are where the physics has them.

use quadsim::scene::{Role, Shape};
use quadsim::{ERS7_URDF, QuadrupedSim, RobotDescription, SimConfig};

fn walked(seconds: f64) -> QuadrupedSim {
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let mut sim = QuadrupedSim::new(&d, SimConfig::default()).expect("sim");
    sim.set_command(200.0).expect("command");
    sim.advance(seconds);
    sim
}

#[test]
fn the_scene_is_the_urdf_s_links_and_the_world() {
    let sim = walked(0.5);
    let scene = sim.scene();
    let names: Vec<&str> = scene.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(&names[..4], ["floor", "beacon", "torso", "head"]);
    for leg in ["fl", "fr", "hl", "hr"] {
        for part in ["shoulder", "thigh", "shank"] {
            assert!(
                names.contains(&format!("{leg}_{part}").as_str()),
                "{names:?}"
            );
        }
    }
    let index = |n: &str| names.iter().position(|&m| m == n).expect(n);
    // The kinematic tree: shank -> thigh -> shoulder -> torso (the root).
    assert_eq!(
        scene.bodies[index("fl_shank")].parent,
        Some(index("fl_thigh"))
    );
    assert_eq!(
        scene.bodies[index("fl_shoulder")].parent,
        Some(index("torso"))
    );
    assert_eq!(scene.bodies[index("torso")].parent, None);
    let robot: Vec<bool> = scene.bodies.iter().map(|b| b.robot_link).collect();
    assert!(!robot[0] && !robot[1] && robot[2..].iter().all(|&r| r));
    // The URDF's collision shapes: the torso's 0.20 x 0.10 x 0.08 box, a
    // 12 mm ball 7 cm down each shank.
    let torso = &scene.bodies[index("torso")].parts;
    assert_eq!(torso.len(), 1);
    match torso[0].shape {
        Shape::Cuboid { half_extents_m } => {
            for (a, b) in half_extents_m.iter().zip([0.10, 0.05, 0.04]) {
                assert!((a - b).abs() < 1e-6, "{half_extents_m:?}");
            }
        }
        other => panic!("torso is {other:?}"),
    }
    let foot = &scene.bodies[index("fl_shank")].parts[0];
    assert!(matches!(foot.shape, Shape::Ball { radius_m } if (radius_m - 0.012).abs() < 1e-6));
    assert!((foot.in_body.translation_m[2] + 0.07).abs() < 1e-6);
    // The world: one floor part, the beacon's pole and band.
    let roles: Vec<Role> = scene.bodies[1].parts.iter().map(|p| p.role).collect();
    assert_eq!(roles, [Role::BeaconPole, Role::BeaconBand]);
    assert_eq!(scene.bodies[0].parts[0].role, Role::Floor);
}

#[test]
fn placements_are_where_the_physics_has_the_bodies() {
    let sim = walked(2.0);
    let scene = sim.scene();
    let placements = sim.placements();
    assert_eq!(placements.len(), scene.bodies.len());
    let torso = scene
        .bodies
        .iter()
        .position(|b| b.name == "torso")
        .expect("torso");
    assert_eq!(placements[torso].translation_m, sim.torso().position_m);
    // Walking, the feet touch the floor: the lowest foot ball's centre is
    // about its radius above it.
    let lowest = scene
        .bodies
        .iter()
        .zip(&placements)
        .filter(|(b, _)| b.name.ends_with("_shank"))
        .map(|(b, p)| p.apply(b.parts[0].in_body.translation_m)[2])
        .fold(f64::INFINITY, f64::min);
    assert!(
        (lowest - 0.012).abs() < 0.004,
        "lowest foot centre {lowest} m"
    );
    // The beacon stands where the config puts it.
    let beacon = placements[1].translation_m;
    assert_eq!([beacon[0], beacon[1]], SimConfig::default().beacon.xy_m);
}
