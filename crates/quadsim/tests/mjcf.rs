//! MJCF as MuJoCo reads it: MuJoCo Menagerie's Unitree Go2 as published
//! (`assets/robots/menagerie/unitree_go2`), read with no robot file, is the
//! robot its file describes (masses, legs, feet, joint ranges, actuator
//! limits); the scene that includes it is the same robot; a body with no
//! `<inertial>` gets MuJoCo's mass from its geoms; and what cannot be
//! simulated is refused, naming the element and its line.

use std::path::{Path, PathBuf};

use quadsim::{RobotDescription, RobotFile};

fn go2_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/robots/menagerie/unitree_go2")
}

/// An MJCF model read as a robot's description (legs found from its tree),
/// without the walk test a robot file runs.
fn described(path: &Path) -> Result<(RobotDescription, Vec<String>), String> {
    let model = quadsim::mjcf::read(path).map_err(|e| e.to_string())?;
    let map = quadsim::discover::discover(&model.urdf).map_err(|e| e.to_string())?;
    let dir = path.parent().expect("a folder");
    let d = RobotDescription::from_urdf_in(model.urdf, &map, dir).map_err(|e| e.to_string())?;
    Ok((d, model.notes))
}

#[test]
fn the_go2_as_published_is_the_robot_its_file_describes() {
    let (d, notes) = described(&go2_dir().join("go2.xml")).expect("the Go2 reads");
    // Menagerie's masses: the base and four legs of hip, thigh and calf.
    let mass = 6.921 + 4.0 * (0.678 + 1.152 + 0.241352);
    assert!((d.total_mass_kg - mass).abs() < 1e-9, "{}", d.total_mass_kg);
    assert_eq!(d.root_link, "base");
    let joints: Vec<_> = d.legs.iter().map(|l| l.joints.clone()).collect();
    for (leg, prefix) in joints.iter().zip(["FL", "FR", "RL", "RR"]) {
        assert_eq!(
            leg,
            &["hip", "thigh", "calf"].map(|j| format!("{prefix}_{j}_joint")),
        );
    }
    for leg in &d.legs {
        // The foot class's sphere, 0.213 m below the knee, on 0.213 m thighs.
        assert!((leg.foot_radius_m - 0.022).abs() < 1e-12);
        assert!((leg.thigh_m - 0.213).abs() < 1e-9, "{}", leg.thigh_m);
        assert!((leg.shank_m - 0.213f64.hypot(0.002)).abs() < 1e-9);
        // The motors' control ranges, N m (gear 1); MuJoCo has no speed limit.
        assert_eq!(leg.effort_nm, [23.7, 23.7, 45.43]);
        assert!(leg.velocity_rad_s.iter().all(|v| v.is_infinite()));
        // The knee class's range, in radians as the compiler says.
        let [lo, hi] = leg.limits_rad[2];
        assert!((lo + 2.7227).abs() < 1e-12 && (hi + 0.83776).abs() < 1e-12);
    }
    // Visual meshes are not read (their files are not here), the primitives
    // collide: the base's box, cylinder and sphere.
    let base = d
        .urdf
        .links
        .iter()
        .find(|l| l.name == "base")
        .expect("base");
    assert_eq!(base.collision.len(), 3);
    // The keyframe is read (tests/keyframe.rs), not left out.
    assert!(!notes.iter().any(|n| n.contains("<key")), "{notes:?}");
}

#[test]
fn the_scene_that_includes_the_go2_is_the_same_robot() {
    let (a, _) = described(&go2_dir().join("go2.xml")).expect("go2.xml");
    let (b, notes) = described(&go2_dir().join("scene.xml")).expect("scene.xml");
    assert_eq!(a.legs, b.legs);
    assert_eq!(a.camera, b.camera);
    assert_eq!(a.total_mass_kg, b.total_mass_kg);
    // The scene's floor is the world's, not the robot's.
    assert!(
        notes
            .iter()
            .any(|n| n.starts_with("left out the world's <geom>")),
        "{notes:?}"
    );
}

#[test]
fn the_go2_walks_with_no_robot_file() {
    // The robot file's path: legs found, the walk test choosing its cadence.
    let robot = RobotFile::from_file(&go2_dir().join("go2.xml")).expect("a robot");
    assert!(robot.cadence_fit.is_some(), "the walk test ran");
    assert!(robot.text.contains("FL_hip_joint"), "{}", robot.text);
    let mut sim =
        quadsim::QuadrupedSim::new(&robot.description, robot.sim_config()).expect("a world");
    sim.advance(1.0);
    let x0 = sim.torso().position_m[0];
    sim.set_command(300.0 * quadsim::RobotScale::of(&robot.description).speed())
        .expect("finite");
    sim.advance(4.0);
    assert!(sim.is_upright());
    assert!(sim.torso().position_m[0] > x0 + 0.3, "walked forwards");
}

/// A small model written to a fresh folder, read.
fn model(name: &str, files: &[(&str, &str)]) -> Result<(RobotDescription, Vec<String>), String> {
    let dir = std::env::temp_dir().join(format!("quadsim-mjcf-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a folder");
    for (file, text) in files {
        std::fs::write(dir.join(file), text).expect("written");
    }
    let out = described(&dir.join(files[0].0));
    std::fs::remove_dir_all(&dir).ok();
    out
}

include!("common/boxy_mjcf.rs");

#[test]
fn a_body_without_inertial_has_mujocos_mass_from_its_geoms() {
    let (d, _) = model("inertia", &[("boxy.xml", &quadruped("", "", ""))]).expect("reads");
    let base = d
        .urdf
        .links
        .iter()
        .find(|l| l.name == "base")
        .expect("base");
    // A box of half-sizes 0.2, 0.1, 0.05 at 500 kg/m^3.
    let m = 500.0 * 8.0 * 0.2 * 0.1 * 0.05;
    assert!((base.inertial.mass.value - m).abs() < 1e-12);
    let ixx = m * (0.1f64.powi(2) + 0.05f64.powi(2)) / 3.0;
    assert!((base.inertial.inertia.ixx - ixx).abs() < 1e-12);
    // Degrees by default: the knee's range is 150 degrees.
    let [lo, _] = d.legs[0].limits_rad[2];
    assert!((lo + 150f64.to_radians()).abs() < 1e-12, "{lo}");
    // The foot's sphere, a thigh and a shank of 0.1 m.
    assert!(
        (d.legs[0].thigh_m - 0.1).abs() < 1e-12 && (d.legs[0].foot_radius_m - 0.015).abs() < 1e-12
    );
}

#[test]
fn a_camera_on_the_robot_is_its_camera() {
    // MuJoCo's camera looks along its -z: these axes look along the base's +x.
    let camera = r#"<camera name="eye" pos="0.2 0 0.03" xyaxes="0 -1 0 0 0 1"/>"#;
    let (d, _) = model("camera", &[("boxy.xml", &quadruped("", camera, ""))]).expect("reads");
    assert_eq!(d.camera.parent, "base");
    assert_eq!(d.camera.xyz, [0.2, 0.0, 0.03]);
    assert!(
        d.camera.rpy.iter().all(|a| a.abs() < 1e-12),
        "{:?}",
        d.camera.rpy
    );
}

#[test]
fn what_cannot_be_simulated_is_refused_naming_the_element_and_its_line() {
    let plain = quadruped("", "", "");
    let edit = |from: &str, to: &str| {
        assert!(plain.contains(from), "{from}");
        plain.replacen(from, to, 1)
    };
    let hinge = r#"<joint name="fl_hip" axis="0 1 0" range="-90 90"/>"#;
    let cases = [
        (
            edit(hinge, r#"<joint name="fl_hip" type="ball"/>"#),
            "<joint> at",
            "a ball joint",
        ),
        (
            quadruped("", "", r#"<joint name="extra" axis="1 0 0"/>"#),
            "<joint> at",
            "second joint",
        ),
        (
            quadruped("", "", r#"<geom type="ellipsoid" size="0.1 0.02 0.02"/>"#),
            "<geom> at",
            "ellipsoid",
        ),
        (
            quadruped("", r#"<geom class="nope" size="0.1"/>"#, ""),
            "<geom> at",
            "class `nope`",
        ),
        (
            quadruped("", r#"<frame pos="0 0 0"/>"#, ""),
            "<frame> at",
            "not an element of <body>",
        ),
        (
            quadruped(r#"angle="gradian""#, "", ""),
            "<compiler> at",
            "gradian",
        ),
        (
            edit("</mujoco>", "<tendon><fixed name=\"t\"/></tendon></mujoco>"),
            "<tendon> at",
            "constrains",
        ),
        (edit("<freejoint/>", ""), "<mujoco> at", "free joint"),
        (
            edit("<worldbody>", "<include file=\"missing.xml\"/><worldbody>"),
            "missing.xml",
            "",
        ),
    ];
    for (i, (text, at, why)) in cases.iter().enumerate() {
        let e = model(&format!("bad{i}"), &[("boxy.xml", text)]).expect_err("refused");
        assert!(e.contains(at) && e.contains(why), "case {i}: {e}");
        assert!(
            at.contains("missing") || e.contains("boxy.xml line"),
            "case {i}: {e}"
        );
    }
    // An include that includes itself is stopped.
    let e = model(
        "loop",
        &[("boxy.xml", "<mujoco><include file=\"boxy.xml\"/></mujoco>")],
    )
    .expect_err("refused");
    assert!(e.contains("nested more than"), "{e}");
}
