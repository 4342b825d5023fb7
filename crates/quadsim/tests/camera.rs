//! The head camera's reading of the beacon: geometry, bearing, noise, and the
//! cases where it must give no reading.

use quadsim::beacon::BeaconConfig;
use quadsim::camera::CameraIntrinsics;
use quadsim::vision::{self, NoReading};
use quadsim::{CameraConfig, ERS7_URDF, QuadrupedSim, RobotDescription, SimConfig};
use rapier3d::geometry::ColliderBuilder;
use rapier3d::math::{Pose, Vector};
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::RigidBodyBuilder;

fn standing(config: SimConfig, seconds: f64) -> (QuadrupedSim, Vec<quadsim::Frame>) {
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let mut sim = QuadrupedSim::new(&d, config).expect("sim");
    let mut frames = Vec::new();
    for _ in 0..(seconds / 0.004).round() as usize {
        sim.step();
        frames.extend(sim.take_frame());
    }
    (sim, frames)
}

fn noiseless() -> SimConfig {
    SimConfig {
        camera: CameraConfig {
            noise_px: 0.0,
            ..Default::default()
        },
        ..Default::default()
    }
}

#[test]
fn frames_come_at_20_hz_of_simulated_time() {
    let (_, frames) = standing(noiseless(), 2.0);
    assert_eq!(frames.len(), 40);
    for (k, f) in frames.iter().enumerate() {
        assert!((f.t_s - 0.05 * (k + 1) as f64).abs() < 1e-9);
    }
}

#[test]
fn reading_is_f_h_over_d_within_quantisation() {
    let fy = CameraIntrinsics::default().fy();
    for d in [1.2, 2.0, 3.0] {
        let config = SimConfig {
            start_distance_m: d,
            ..noiseless()
        };
        let (sim, frames) = standing(config, 1.0);
        let obs = frames.last().expect("frames").obs_px.expect("seen");
        // Distance from the camera to the band's near face.
        let cam = sim.camera_pose().translation;
        let range = (0.0 - f64::from(cam.x)) - 0.05;
        let expected = fy * 0.2 / range;
        assert!(
            (obs - expected).abs() <= 1.5,
            "at {d} m: {obs} px vs {expected:.1} px"
        );
    }
}

#[test]
fn readings_fall_with_distance() {
    let mut last = f64::INFINITY;
    for d in [1.2, 1.6, 2.0, 2.4, 2.8, 3.2, 3.6] {
        let (_, frames) = standing(
            SimConfig {
                start_distance_m: d,
                ..noiseless()
            },
            0.6,
        );
        let obs = frames.last().expect("frame").obs_px.expect("seen");
        assert!(obs < last, "{obs} px at {d} m is not below {last} px");
        last = obs;
    }
}

#[test]
fn bearing_is_positive_for_a_beacon_on_the_left() {
    let beacon = BeaconConfig {
        xy_m: [0.0, 0.3],
        ..Default::default()
    };
    // The robot starts at (beacon x - d, beacon y): shift the beacon, not the robot.
    let config = SimConfig {
        beacon,
        ..noiseless()
    };
    let (sim, frames) = standing(config, 0.2);
    let f = frames.last().expect("frame");
    // Straight ahead: the robot starts on the beacon's line, so the bearing is small.
    let b = f.bearing_rad.expect("seen");
    assert!(b.abs() < 0.02, "bearing {b}");
    let _ = sim;
    // Now look at a beacon off to the left of a camera facing +x.
    let mut world = PhysicsWorld::new();
    let beacon = BeaconConfig {
        xy_m: [2.0, 0.3],
        ..Default::default()
    };
    let band = beacon.insert(&mut world);
    world.step();
    let camera = Pose::translation(0.0, 0.0, 0.2);
    let blob = vision::find_band(
        &world,
        &camera,
        &CameraIntrinsics::default(),
        &beacon,
        band,
        &[],
    )
    .expect("seen");
    let bearing = CameraIntrinsics::default().bearing_of_column(blob.mean_column());
    assert!(
        (bearing - (0.3f64).atan2(2.0)).abs() < 0.02,
        "bearing {bearing}"
    );
}

#[test]
fn no_reading_out_of_view_behind_cut_or_occluded() {
    let intr = CameraIntrinsics::default();
    let beacon = BeaconConfig {
        xy_m: [2.0, 0.0],
        ..Default::default()
    };
    let mut world = PhysicsWorld::new();
    let band = beacon.insert(&mut world);
    let blocker = world
        .bodies
        .insert(RigidBodyBuilder::fixed().translation(Vector::new(1.0, 0.0, 0.2)));
    world.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.05, 0.05, 0.02),
        blocker,
        &mut world.bodies,
    );
    world.step();
    let look = |x: f64, y: f64, yaw: f64| {
        let pose = Pose::from_parts(
            Vector::new(x as f32, y as f32, 0.2),
            rapier3d::math::Rotation::from_rotation_z(yaw as f32),
        );
        vision::find_band(&world, &pose, &intr, &beacon, band, &[])
    };
    // Facing away.
    assert_eq!(
        look(0.0, 0.5, std::f64::consts::PI).map(|_| ()),
        Err(NoReading::OutOfView)
    );
    // Far off to the side of the view.
    assert_eq!(look(0.0, 3.0, 0.0).map(|_| ()), Err(NoReading::OutOfView));
    // So close the band fills the image: cut by the border.
    assert!(matches!(
        look(1.85, 0.0, 0.0).map(|_| ()),
        Err(NoReading::OutOfView | NoReading::CutByBorder)
    ));
    // The blocker stands in the way of part of the band.
    assert_eq!(look(0.0, 0.0, 0.0).map(|_| ()), Err(NoReading::Occluded));
    // Step aside and the band is seen whole.
    assert!(look(0.0, 0.6, -0.3).is_ok());
}

/// With nothing in the way the camera finds the band's rows by their two ends
/// (a row's pixels are one run): the blob must be exactly the pixels whose rays
/// meet the band, found ray by ray over the whole image, from every side,
/// height, distance and tilt.
#[test]
fn an_unoccluded_blob_is_every_pixel_whose_ray_meets_the_band() {
    use rand::{RngExt, SeedableRng};
    use rapier3d::math::Rotation;
    let intr = CameraIntrinsics::default();
    let beacon = BeaconConfig::default();
    let mut world = PhysicsWorld::new();
    let band = beacon.insert(&mut world);
    world.step();
    let rays = intr.pixel_rays();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    let (mut seen, mut compared) = (0, 0);
    for _ in 0..400 {
        let range: f64 = rng.random_range(0.3..4.0);
        let around: f64 = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
        let x = beacon.xy_m[0] + range * around.cos();
        let y = beacon.xy_m[1] + range * around.sin();
        let z: f64 = rng.random_range(0.0..0.5);
        // Face the beacon, off by up to a third of a radian each way.
        let yaw = (beacon.xy_m[1] - y).atan2(beacon.xy_m[0] - x) + rng.random_range(-0.35..0.35);
        let (pitch, roll): (f64, f64) = (rng.random_range(-0.4..0.4), rng.random_range(-0.5..0.5));
        let pose = Pose::from_parts(
            Vector::new(x as f32, y as f32, z as f32),
            Rotation::from_rotation_z(yaw as f32)
                * Rotation::from_rotation_y(pitch as f32)
                * Rotation::from_rotation_x(roll as f32),
        );
        let o = pose.translation;
        let origin = [o.x, o.y, o.z].map(f64::from);
        let mut every = Vec::new();
        for row in 0..intr.height_px {
            for col in 0..intr.width_px {
                let [a, b, c] = rays.ray(col, row).map(|v| v as f32);
                let d = (pose.rotation * Vector::new(a, b, c)).normalize();
                if beacon
                    .ray_hits_band(origin, [d.x, d.y, d.z].map(f64::from))
                    .is_some()
                {
                    every.push((col, row));
                }
            }
        }
        if let Ok(blob) = vision::find_band(&world, &pose, &intr, &beacon, band, &[]) {
            assert_eq!(
                blob.pixels().collect::<Vec<_>>(),
                every,
                "camera at {pose:?}"
            );
            seen += 1;
        }
        compared += 1;
    }
    assert!(
        seen > 100,
        "the band was seen in {seen} of {compared} poses"
    );
}

#[test]
fn standing_noise_is_about_the_configured_spread() {
    let config = SimConfig {
        start_distance_m: 2.0,
        ..Default::default()
    };
    let (_, frames) = standing(config, 6.0);
    let obs: Vec<f64> = frames
        .iter()
        .skip(20)
        .map(|f| f.obs_px.expect("seen"))
        .collect();
    let n = obs.len() as f64;
    let mean = obs.iter().sum::<f64>() / n;
    let std = (obs.iter().map(|o| (o - mean).powi(2)).sum::<f64>() / n).sqrt();
    assert!(
        (0.7..=1.3).contains(&std),
        "std {std:.2} px over {n} readings"
    );
}

#[test]
fn same_seed_same_readings_other_seed_other_noise() {
    let run = |seed| {
        let config = SimConfig {
            camera: CameraConfig {
                noise_seed: seed,
                ..Default::default()
            },
            ..Default::default()
        };
        standing(config, 1.0)
            .1
            .iter()
            .map(|f| f.obs_px.map(f64::to_bits).ok())
            .collect::<Vec<_>>()
    };
    assert_eq!(run(1), run(1));
    assert_ne!(run(1), run(2));
}

/// The frames of `d` walking at `command` from the start, for `seconds`.
fn walking(d: &RobotDescription, command: f64, seconds: f64) -> Vec<quadsim::Frame> {
    let mut sim = QuadrupedSim::new(d, SimConfig::default()).expect("sim");
    sim.set_command(command).expect("finite");
    let mut frames = Vec::new();
    while sim.time_s() < seconds {
        sim.step();
        frames.extend(sim.take_frame());
    }
    frames
}

#[test]
fn a_camera_on_its_links_face_is_not_hidden_by_the_link() {
    // The camera on the middle of the torso box's front face (x = 0.10), as a
    // bare URDF's camera is mounted: the lens looks out of the link, so the
    // link never hides the band, whichever side of the face each step's
    // rounding puts the lens.
    let urdf = urdf_rs::read_from_string(ERS7_URDF).expect("urdf");
    let mut map = quadsim::description::RobotMap::conventional(&urdf).expect("map");
    map.camera = quadsim::description::CameraMount {
        parent: "torso".into(),
        xyz: [0.10, 0.0, 0.0],
        rpy: [0.0; 3],
    };
    let d = RobotDescription::from_urdf(urdf, &map).expect("mounted");
    let frames = walking(&d, 300.0, 6.0);
    let hidden = frames
        .iter()
        .filter(|f| f.obs_px == Err(NoReading::Occluded))
        .count();
    assert_eq!(hidden, 0, "{hidden} of {} frames hidden", frames.len());
    assert!(frames.iter().all(|f| f.obs_px.is_ok()), "{frames:?}");
}

#[test]
fn a_camera_inside_a_link_fixed_to_its_own_looks_out_of_it() {
    // The head's camera moved back inside the torso box (the head is fixed to
    // the torso by the neck): as a camera behind a face plate or inside a
    // shell bolted to its link, it looks out through its housing. Without
    // that, the torso, another body, hides the band in every frame.
    let urdf = urdf_rs::read_from_string(ERS7_URDF).expect("urdf");
    let mut map = quadsim::description::RobotMap::conventional(&urdf).expect("map");
    // The head sits at x = 0.125 on the torso, whose box ends at x = 0.10.
    map.camera.xyz = [-0.075, 0.0, -0.05];
    let d = RobotDescription::from_urdf(urdf, &map).expect("mounted");
    let frames = walking(&d, 200.0, 3.0);
    assert!(frames.iter().all(|f| f.obs_px.is_ok()), "{frames:?}");
}

#[test]
fn a_camera_mounts_rpy_turns_it_as_a_urdf_origin_does() {
    // rpy about the fixed x, y, z axes: R = Rz(yaw) Ry(pitch) Rx(roll), on
    // the torso, whose orientation the sim reports.
    let [roll, pitch, yaw] = [0.3_f64, 0.2, 0.1];
    let urdf = urdf_rs::read_from_string(ERS7_URDF).expect("urdf");
    let mut map = quadsim::description::RobotMap::conventional(&urdf).expect("map");
    map.camera = quadsim::description::CameraMount {
        parent: "torso".into(),
        xyz: [0.1, 0.0, 0.0],
        rpy: [roll, pitch, yaw],
    };
    let d = RobotDescription::from_urdf(urdf, &map).expect("mounted");
    let sim = QuadrupedSim::new(&d, SimConfig::default()).expect("sim");
    let (sr, cr, sp, cp, sy, cy) = (
        roll.sin(),
        roll.cos(),
        pitch.sin(),
        pitch.cos(),
        yaw.sin(),
        yaw.cos(),
    );
    // The columns of R: where the mount turns x (the optical axis) and z
    // (image up), in the torso's frame.
    let expected = [
        [cy * cp, sy * cp, -sp],
        [cy * sp * cr + sy * sr, sy * sp * cr - cy * sr, cp * cr],
    ];
    let [qx, qy, qz, qw] = sim.torso().orientation.map(|v| v as f32);
    let torso = rapier3d::math::Rotation::from_xyzw(qx, qy, qz, qw);
    let camera = sim.camera_pose().rotation;
    for (axis, want) in [Vector::X, Vector::Z].into_iter().zip(expected) {
        let got = torso.inverse() * (camera * axis);
        for k in 0..3 {
            assert!(
                (f64::from(got[k]) - want[k]).abs() < 1e-5,
                "{axis:?}: {got:?} against {want:?}"
            );
        }
    }
}
