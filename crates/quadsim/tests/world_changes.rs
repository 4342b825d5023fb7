//! Changing the world during a run: what can change takes effect at once and
//! in the physics; what cannot is refused and changes nothing.

use quadsim::{CameraConfig, ERS7_URDF, QuadrupedSim, RobotDescription, SimConfig, SimConfigError};

fn sim(config: SimConfig) -> QuadrupedSim {
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    QuadrupedSim::new(&d, config).expect("sim")
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

/// Steps for `seconds`, returning the readings taken.
fn run(sim: &mut QuadrupedSim, seconds: f64) -> Vec<f64> {
    let mut readings = Vec::new();
    for _ in 0..(seconds / sim.config().dt_s).round() as usize {
        sim.step();
        if let Some(f) = sim.take_frame() {
            readings.extend(f.obs_px.ok());
        }
    }
    readings
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

#[test]
fn a_taller_band_reads_taller_at_once() {
    let mut s = sim(noiseless());
    let before = mean(&run(&mut s, 1.0)[10..]);
    let mut taller = *s.config();
    taller.beacon.band_height_m *= 1.5;
    taller.beacon.band_centre_m = 0.5 * taller.beacon.band_height_m + 0.1;
    s.change_world(taller).expect("a beacon can change");
    let after = run(&mut s, 0.5);
    let ratio = mean(&after) / before;
    // Standing still, the reading is f h / d: 1.5 times, within quantisation.
    assert!((ratio - 1.5).abs() < 0.05, "ratio {ratio}");
    assert_eq!(s.config().beacon, taller.beacon);
}

/// The distance walked (away from the beacon: positive) in `after_s` at
/// `command`, with `change` applied to the config after `before_s` of walking.
fn walked_after_change(
    command: f64,
    change: impl Fn(&mut SimConfig),
    before_s: f64,
    after_s: f64,
) -> f64 {
    let mut s = sim(noiseless());
    s.set_command(command).expect("finite");
    run(&mut s, before_s);
    let mut changed = *s.config();
    change(&mut changed);
    s.change_world(changed).expect("a live change");
    let start = s.distance_along_line_m();
    run(&mut s, after_s);
    assert!(s.is_upright());
    s.distance_along_line_m() - start
}

#[test]
fn slippery_floors_and_weak_servos_slow_the_walk() {
    // Backwards at -150, where friction matters most to this robot: about
    // 75 mm/s at friction 0.9 and 60 mm/s at 0.45 (`measure_action`).
    let same = walked_after_change(-150.0, |_| {}, 2.0, 3.0);
    let again = walked_after_change(-150.0, |_| {}, 2.0, 3.0);
    assert_eq!(same.to_bits(), again.to_bits(), "deterministic");
    let slippery = walked_after_change(-150.0, |c| c.friction = 0.45, 2.0, 3.0);
    assert!(same > 0.18, "walked {same} m");
    assert!(slippery < 0.9 * same, "slippery {slippery} m vs {same} m");
    // Forwards at 250 (about 0.66 m in 3 s), servos at half their speed.
    let fast = walked_after_change(250.0, |_| {}, 2.0, 3.0);
    let weak = walked_after_change(250.0, |c| c.servo.speed_scale = 0.5, 2.0, 3.0);
    assert!(weak < 0.9 * fast, "weak {weak} m vs {fast} m");
}

#[test]
fn noisier_camera_reads_noisier() {
    let mut s = sim(noiseless());
    let quiet = run(&mut s, 2.0);
    let mut noisy = *s.config();
    noisy.camera.noise_px = 3.0;
    s.change_world(noisy).expect("noise can change");
    let loud = run(&mut s, 2.0);
    let std = |v: &[f64]| {
        let m = mean(v);
        (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
    };
    assert!(std(&loud[5..]) > 2.0 && std(&quiet[10..]) < 1.5);
}

#[test]
fn what_cannot_change_is_refused_and_changes_nothing() {
    let mut s = sim(SimConfig::default());
    let before = *s.config();
    let mut c = before;
    c.dt_s = 0.002;
    c.friction = 0.3;
    assert_eq!(
        s.change_world(c),
        Err(SimConfigError::NotLive { key: "physics.dt" })
    );
    let mut c = before;
    c.start_distance_m = 1.0;
    let err = s.change_world(c).expect_err("not live");
    assert!(
        err.to_string()
            .contains("world.start_distance_m cannot change")
    );
    let mut c = before;
    c.friction = f64::NAN;
    assert!(matches!(
        s.change_world(c),
        Err(SimConfigError::OutOfRange {
            key: "world.friction",
            ..
        })
    ));
    assert_eq!(*s.config(), before);
}
