//! Robot files: the shipped robots load, the ERS-7's file describes the same
//! robot as its bare URDF, the scaling rules leave the ERS-7's settings as they
//! are, a robot file that cannot be used names the file and what is wrong, and
//! every shipped robot stays on its feet stepping in place and walking.

use std::path::PathBuf;

use quadsim::{ERS7_URDF, QuadrupedSim, RobotDescription, RobotFile, RobotScale, SimConfig};

fn assets() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/robots")
}

#[test]
fn every_shipped_robot_loads_from_its_name_and_its_path() {
    for name in RobotFile::shipped_names() {
        let shipped = RobotFile::shipped(name).expect("shipped robot");
        let from_path = RobotFile::load(
            assets()
                .join(format!("{name}.toml"))
                .to_str()
                .expect("utf-8 path"),
        )
        .expect("robot file on disk");
        assert_eq!(shipped.name, name);
        assert_eq!(shipped.urdf_text, from_path.urdf_text, "{name}");
        assert_eq!(shipped.description.legs, from_path.description.legs);
    }
}

#[test]
fn the_ers7_file_is_the_default_robot_and_scales_to_the_defaults() {
    let file = RobotFile::shipped("ers7").expect("ers7");
    let bare = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    assert_eq!(file.description.legs, bare.legs);
    assert_eq!(file.description.camera, bare.camera);
    assert_eq!(file.description.root_link, "torso");
    assert_eq!(RobotScale::of(&file.description), RobotScale::ONE);
    assert_eq!(
        SimConfig::for_robot(&file.description),
        SimConfig::default()
    );
}

#[test]
fn the_trotter_is_a_research_class_robot_with_offset_hips() {
    let d = RobotFile::shipped("trotter").expect("trotter").description;
    assert!(
        (10.0..=15.0).contains(&d.total_mass_kg),
        "{}",
        d.total_mass_kg
    );
    for leg in &d.legs {
        assert!((leg.thigh_m - 0.2).abs() < 1e-9 && (leg.shank_m - 0.2).abs() < 1e-9);
        assert!((leg.hip_offset_m.abs() - 0.06).abs() < 1e-9);
        assert_eq!(leg.hip_offset_m.signum(), leg.side());
        assert_eq!(leg.effort_nm, [24.0; 3]);
    }
    let scale = RobotScale::of(&d);
    assert!((scale.length - 0.4 / 0.14).abs() < 1e-9, "{scale:?}");
    let c = SimConfig::for_robot(&d);
    let base = SimConfig::default();
    // Froude scaling: lengths by s, periods and speeds by sqrt(s).
    let s = scale.length;
    let g = (c.walk.gait, base.walk.gait);
    assert!((g.0.idle.body_height_m - s * g.1.idle.body_height_m).abs() < 1e-12);
    assert!((g.0.fast_forwards.period_s - s.sqrt() * g.1.fast_forwards.period_s).abs() < 1e-12);
    assert!((g.0.v_max_mm_s - s.sqrt() * g.1.v_max_mm_s).abs() < 1e-9);
    assert!((c.beacon.band_height_m - s * base.beacon.band_height_m).abs() < 1e-12);
    assert!((c.servo.kp_nm_per_rad - scale.mass * s * base.servo.kp_nm_per_rad).abs() < 1e-9);
}

fn write(dir: &std::path::Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    path
}

fn expect_error(robot_toml: &str, needles: &[&str]) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!(
        "quadsim-robot-file-{}-{}",
        std::process::id(),
        needles[0].replace(|c: char| !c.is_ascii_alphanumeric(), "_")
    ));
    std::fs::create_dir_all(&dir).expect("dir");
    write(&dir, "robot.urdf", ERS7_URDF);
    let path = write(&dir, "robot.toml", robot_toml);
    let err = RobotFile::from_file(&path).expect_err("must be refused");
    let msg = err.to_string();
    assert!(msg.contains("robot.toml"), "`{msg}` should name the file");
    for needle in needles {
        assert!(msg.contains(needle), "`{msg}` should mention `{needle}`");
    }
}

const ERS7_FILE: &str = include_str!("../../../assets/robots/ers7.toml");

#[test]
fn an_unusable_robot_file_names_the_file_and_the_fault() {
    let local = ERS7_FILE.replace("../ers7.urdf", "robot.urdf");
    // (what is edited, into what, what the error must name)
    for (from, to, needle) in [
        ("name = \"ers7\"", "name = \"ers7\"\nwheels = 4", "wheels"),
        ("robot.urdf", "missing.urdf", "missing.urdf"),
        ("\"hl_knee\"", "\"hl_kne\"", "hl_kne"),
        ("parent = \"head\"", "parent = \"antenna\"", "antenna"),
        ("xyz = [0.041, 0.0, 0.005]", "xyz = [0.041, 0.0]", "xyz"),
        // The [gait] section: unknown keys, impossible values, out of reach.
        ("[camera]", "[gait]\nstride = 1.0\n[camera]", "stride"),
        ("[camera]", "[gait.trot]\nperiod_s = 0.4\n[camera]", "trot"),
        (
            "[camera]",
            "[gait]\nv_min_mm_s = 100.0\n[camera]",
            "gait.v_min_mm_s",
        ),
        (
            "[camera]",
            "[gait.idle]\nperiod_s = 0.0\n[camera]",
            "gait.idle.period_s",
        ),
        (
            "[camera]",
            "[gait.fast_forwards]\nduty_factor = 1.5\n[camera]",
            "gait.fast_forwards.duty_factor",
        ),
        (
            "[camera]",
            "[gait.fast_backwards]\nstep_length_m = 0.05\n[camera]",
            "gait.fast_backwards.step_length_m",
        ),
        (
            "[camera]",
            "[gait.fast_forwards]\nbody_height_m = 0.5\n[camera]",
            "cannot walk the gait",
        ),
    ] {
        assert!(local.contains(from), "the edit `{from}` applies");
        expect_error(&local.replace(from, to), &[needle]);
    }
    assert!(RobotFile::load("no-such-robot").is_err());
}

#[test]
fn a_robot_files_gait_replaces_the_scaled_gait() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("quadsim-gait-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    write(&dir, "robot.urdf", ERS7_URDF);
    let local = ERS7_FILE.replace("../ers7.urdf", "robot.urdf");
    let text = local.replace(
        "[camera]",
        "[gait]\nv_max_mm_s = 400.0\n[gait.fast_forwards]\nperiod_s = 0.35\n[camera]",
    );
    let file = RobotFile::from_file(&write(&dir, "robot.toml", &text)).expect("valid");
    let (got, base) = (file.sim_config(), SimConfig::default());
    assert_eq!(got.walk.gait.v_max_mm_s, 400.0);
    assert_eq!(got.walk.gait.fast_forwards.period_s, 0.35);
    // Everything else is the scaled default (the ERS-7's own, unscaled).
    let mut expected = base;
    expected.walk.gait.v_max_mm_s = 400.0;
    expected.walk.gait.fast_forwards.period_s = 0.35;
    assert_eq!(got, expected);
}

#[test]
fn a_massless_urdf_names_the_file_and_the_link() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("quadsim-massless-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let massless = with_zero_masses(ERS7_URDF);
    write(&dir, "robot.urdf", &massless);
    let local = ERS7_FILE.replace("../ers7.urdf", "robot.urdf");
    let path = write(&dir, "robot.toml", &local);
    let msg = RobotFile::from_file(&path)
        .expect_err("refused")
        .to_string();
    assert!(
        msg.contains("robot.toml") && msg.contains("robot.urdf") && msg.contains("torso"),
        "{msg}"
    );
    assert!(msg.contains("mass"), "{msg}");
}

/// Every `<mass value="..."/>` set to zero.
fn with_zero_masses(urdf: &str) -> String {
    urdf.split("<mass value=\"")
        .enumerate()
        .map(|(i, part)| {
            if i == 0 {
                part.to_string()
            } else {
                let rest = part.split_once('"').map_or("", |(_, r)| r);
                format!("<mass value=\"0\"{rest}")
            }
        })
        .collect()
}

/// `seconds` at `fraction` of the robot's top command (its scaled 300 mm/s):
/// whether it stayed upright, and its mean speed towards the beacon, as a
/// fraction of the top command.
fn walk(robot: &RobotFile, fraction: f64, seconds: f64) -> (bool, f64) {
    let d = &robot.description;
    let scale = RobotScale::of(d);
    let mut config = robot.sim_config();
    // Walking away starts near the beacon, walking towards it far away.
    config.start_distance_m = if fraction < 0.0 { 1.2 } else { 3.6 } * scale.length;
    let mut sim = QuadrupedSim::new(d, config).expect("sim");
    let top = 300.0 * scale.speed();
    sim.set_command(top * fraction).expect("command");
    let start = sim.distance_along_line_m();
    let mut upright = true;
    for _ in 0..(seconds / 0.1) as usize {
        sim.advance(0.1);
        upright &= sim.is_upright();
    }
    let speed_mm_s = 1000.0 * (start - sim.distance_along_line_m()) / sim.time_s();
    (upright, speed_mm_s / top)
}

#[test]
fn every_shipped_robot_walks_forwards_backwards_and_in_place() {
    for name in RobotFile::shipped_names() {
        let d = RobotFile::shipped(name).expect("robot");
        let (upright, forwards) = walk(&d, 1.0, 8.0);
        assert!(upright && forwards > 0.5, "{name} forwards: {forwards:.2}");
        let (upright, backwards) = walk(&d, -1.0, 8.0);
        assert!(
            upright && backwards < -0.5,
            "{name} backwards: {backwards:.2}"
        );
        let (upright, in_place) = walk(&d, 0.0, 8.0);
        assert!(
            upright && in_place.abs() < 0.1,
            "{name} in place: {in_place:.2}"
        );
    }
}

#[test]
fn a_bare_urdf_is_a_robot_whose_legs_are_found_from_its_tree() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("quadsim-bare-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let bare = RobotFile::from_file(&write(&dir, "ers7.urdf", ERS7_URDF)).expect("legs found");
    let named = RobotDescription::from_urdf_str(ERS7_URDF).expect("the ERS-7's naming");
    let joints = |d: &RobotDescription| d.legs.iter().map(|l| l.joints.clone()).collect::<Vec<_>>();
    assert_eq!(joints(&bare.description), joints(&named));
    assert_eq!(bare.description.legs, named.legs);
    // The URDF's own camera frame is the camera: the ERS-7 to the bit.
    assert_eq!(bare.description.camera, named.camera);
    assert_eq!(bare.sim_config(), quadsim::SimConfig::default());
    // Without one, the camera looks forward from the torso's front face.
    let no_camera = ERS7_URDF
        .replace(r#"<link name="camera"/>"#, "")
        .replace(
            r#"<joint name="camera_mount" type="fixed"><parent link="head"/><child link="camera"/><origin xyz="0.041 0 0.005" rpy="0 0 0"/></joint>"#,
            "",
        );
    let faced =
        RobotFile::from_file(&write(&dir, "no_camera.urdf", &no_camera)).expect("legs found");
    assert_eq!(faced.description.camera.parent, "torso");
    assert_eq!(faced.description.camera.xyz, [0.1, 0.0, 0.0]);
    // Its robot file says what was found, and reads back to the same robot.
    assert!(
        bare.text
            .contains("front_left = [\"fl_abduction\", \"fl_hip\", \"fl_knee\"]"),
        "{}",
        bare.text
    );
    let again = RobotFile::from_file(&write(&dir, "found.toml", &bare.text)).expect("reads back");
    assert_eq!(again.description.legs, bare.description.legs);
    // Three legs (a foot turned into a box) are named as what was found.
    let three = ERS7_URDF.replacen(
        r#"<geometry><sphere radius="0.012"/></geometry>"#,
        r#"<geometry><box size="0.02 0.02 0.02"/></geometry>"#,
        1,
    );
    let e = RobotFile::from_file(&write(&dir, "three.urdf", &three))
        .expect_err("three legs")
        .to_string();
    assert!(
        e.contains("three.urdf") && e.contains("3 chains") && e.contains("hr_abduction"),
        "{e}"
    );
}
