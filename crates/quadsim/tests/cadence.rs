//! The walk test and the cadence it finds for a scaled robot
//! (`quadsim::cadence`), and how robot files ask for it.

use std::path::{Path, PathBuf};

use quadsim::cadence::{self, MAX_RMS_TILT_RAD};
use quadsim::{ERS7_URDF, RobotDescription, RobotFile, SimConfig};

fn ers7() -> RobotDescription {
    RobotDescription::from_urdf_str(ERS7_URDF).expect("the ERS-7 parses")
}

/// The default settings with the gait's cadence times `factor`.
fn slowed(factor: f64) -> SimConfig {
    let mut c = SimConfig::default();
    c.walk.gait = cadence::quicken(c.walk.gait, factor);
    c
}

fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("quadsim-cadence-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("dir");
    d
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write");
    p
}

/// The ERS-7 made `s` times larger, dynamically similar: lengths times `s`,
/// masses times `s^3`, inertias times `s^5`, torques times `s^4`.
fn scaled_ers7(s: f64) -> String {
    scaled_ers7_with_torque(s, 1.0)
}

/// [`scaled_ers7`] with its joints' torques times `weaker` besides.
fn scaled_ers7_with_torque(s: f64, weaker: f64) -> String {
    let mut r = urdf_rs::read_from_string(ERS7_URDF).expect("parses");
    let scale3 = |v: &mut urdf_rs::Vec3| v.0 = v.0.map(|x| x * s);
    for link in &mut r.links {
        let i = &mut link.inertial;
        i.mass.value *= s.powi(3);
        for m in [
            &mut i.inertia.ixx,
            &mut i.inertia.iyy,
            &mut i.inertia.izz,
            &mut i.inertia.ixy,
            &mut i.inertia.ixz,
            &mut i.inertia.iyz,
        ] {
            *m *= s.powi(5);
        }
        scale3(&mut i.origin.xyz);
        for c in &mut link.collision {
            scale3(&mut c.origin.xyz);
            match &mut c.geometry {
                urdf_rs::Geometry::Box { size } => scale3(size),
                urdf_rs::Geometry::Sphere { radius } => *radius *= s,
                urdf_rs::Geometry::Cylinder { radius, length }
                | urdf_rs::Geometry::Capsule { radius, length } => {
                    *radius *= s;
                    *length *= s;
                }
                urdf_rs::Geometry::Mesh { .. } => {}
            }
        }
    }
    for j in &mut r.joints {
        scale3(&mut j.origin.xyz);
        j.limit.effort *= s.powi(4) * weaker;
    }
    urdf_rs::write_to_string(&r).expect("writes")
}

#[test]
fn the_ers7_walks_its_own_gait() {
    let check = cadence::check_walk(&ers7(), SimConfig::default()).expect("runs");
    assert_eq!(check.failure(), None, "{check:?}");
    assert_eq!(check.walks.len(), 31);
    assert!(
        check
            .walks
            .iter()
            .all(|w| w.rms_tilt_rad <= MAX_RMS_TILT_RAD)
    );
}

#[test]
fn a_gait_too_slow_for_the_robot_fails_and_the_fit_quickens_it() {
    let d = ers7();
    // 1.6 times slower than its own, the ERS-7's trot rocks about its
    // diagonals and stalls.
    let slow = cadence::check_walk(&d, slowed(1.6)).expect("runs");
    assert!(slow.failure().is_some(), "{slow:?}");
    let fit = cadence::fit(&d, |f| slowed(1.6 * f))
        .expect("runs")
        .expect("some cadence walks");
    assert!(fit.factor < 1.0, "{fit:?}");
    assert_eq!(fit.rejected.first().map(|r| r.0), Some(1.0), "{fit:?}");
    assert!(
        cadence::check_walk(&d, slowed(1.6 * fit.factor))
            .expect("runs")
            .failure()
            .is_none()
    );
}

#[test]
fn a_robot_like_the_ers7_twice_its_size_keeps_the_scaled_cadence_and_records_it() {
    let d = dir("similar");
    let bare = RobotFile::from_file(&write(&d, "big.urdf", &scaled_ers7(2.0))).expect("loads");
    let fit = bare.cadence_fit.clone().expect("the walk test ran");
    assert_eq!(fit.factor, 1.0, "{fit:?}");
    assert_eq!(bare.gait.cadence, Some(1.0));
    assert!(bare.text.contains("cadence = 1.0"), "{}", bare.text);
    // The recorded robot file gives the cadence: read back, it is the same
    // robot and the walk test does not run again.
    let again = RobotFile::from_file(&write(&d, "found.toml", &bare.text)).expect("reads back");
    assert!(again.cadence_fit.is_none());
    assert_eq!(again.sim_config(), bare.sim_config());
}

#[test]
fn the_shipped_robots_walk_as_their_files_say() {
    // The ERS-7 is the defaults' own size; the trotter's file gives periods.
    for name in RobotFile::shipped_names() {
        let robot = RobotFile::shipped(name).expect("shipped");
        assert!(robot.cadence_fit.is_none(), "{name}");
        assert_eq!(robot.gait.cadence, None, "{name}");
    }
}

#[test]
fn a_robot_files_cadence_quickens_the_scaled_gait_and_is_checked() {
    let d = dir("given");
    write(&d, "robot.urdf", ERS7_URDF);
    let file =
        include_str!("../../../assets/robots/ers7.toml").replace("../ers7.urdf", "robot.urdf");
    let with =
        |value: &str| file.replace("[camera]", &format!("[gait]\ncadence = {value}\n[camera]"));
    let robot = RobotFile::from_file(&write(&d, "robot.toml", &with("0.8"))).expect("valid");
    assert!(robot.cadence_fit.is_none(), "a given cadence is not tested");
    let (got, base) = (robot.sim_config().walk.gait, SimConfig::default().walk.gait);
    assert_eq!(got, cadence::quicken(base, 0.8));
    assert!((got.fast_forwards.period_s - 0.8 * base.fast_forwards.period_s).abs() < 1e-15);
    assert_eq!(got.v_max_mm_s, base.v_max_mm_s, "the speeds stay");
    for bad in ["0.0", "-1.0", "2.5", "nan", "1e-300"] {
        let e = RobotFile::from_file(&write(&d, "bad.toml", &with(bad)))
            .expect_err(bad)
            .to_string();
        assert!(e.contains("gait.cadence must be in [0.1, 2]"), "{bad}: {e}");
    }
}

#[test]
fn a_robot_that_walks_at_no_cadence_is_refused_with_each_cadences_failure() {
    // Twice the ERS-7's size with a twentieth of its torque: it cannot
    // stand, at any cadence.
    let d = dir("weak");
    let path = write(&d, "weak.urdf", &scaled_ers7_with_torque(2.0, 0.05));
    let e = RobotFile::from_file(&path)
        .expect_err("refused")
        .to_string();
    assert!(e.contains("weak.urdf"), "{e}");
    assert!(
        e.contains("does not walk this robot at any cadence tried"),
        "{e}"
    );
    for factor in cadence::FACTORS {
        assert!(e.contains(&format!("cadence {factor}:")), "{factor}: {e}");
    }
    assert!(e.contains("[gait]"), "says what to do: {e}");
}
