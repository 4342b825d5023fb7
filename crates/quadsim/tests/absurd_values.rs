//! A URDF with a number no physical robot has is refused, naming the element,
//! the value and what it must be (issue 61), where it used to load and run
//! trials that mean nothing.

use quadsim::{ERS7_URDF, RobotDescription};

/// The ERS-7's URDF with its first `from` replaced by `to`.
fn with(from: &str, to: &str) -> String {
    assert!(ERS7_URDF.contains(from), "{from}");
    ERS7_URDF.replacen(from, to, 1)
}

fn refused(text: &str, needles: &[&str]) {
    let e = RobotDescription::from_urdf_str(text).expect_err("must be refused");
    let msg = e.to_string();
    for n in needles {
        assert!(msg.contains(n), "`{msg}` should mention `{n}`");
    }
}

#[test]
fn collision_shapes_of_nan_negative_or_zero_size_are_refused() {
    let torso_box = r#"<box size="0.20 0.10 0.08"/>"#;
    for size in ["NaN 0.10 0.08", "-0.20 0.10 0.08", "0 0.10 0.08"] {
        refused(
            &with(torso_box, &format!(r#"<box size="{size}"/>"#)),
            &["link `torso`", "box size"],
        );
    }
    refused(
        &with(r#"<sphere radius="0.012"/>"#, r#"<sphere radius="NaN"/>"#),
        &["sphere radius", "not finite"],
    );
}

#[test]
fn a_mass_or_centre_of_mass_no_body_has_is_refused() {
    for mass in ["1e-300", "1e308"] {
        refused(
            &with(
                r#"<mass value="0.95"/>"#,
                &format!(r#"<mass value="{mass}"/>"#),
            ),
            &["link `torso`", "mass", "kg"],
        );
    }
    refused(
        &with(
            r#"<origin xyz="0 0 0" rpy="0 0 0"/>
      <mass value="0.95"/>"#,
            r#"<origin xyz="NaN 0 0" rpy="0 0 0"/>
      <mass value="0.95"/>"#,
        ),
        &["inertial origin", "not finite"],
    );
}

#[test]
fn an_inertia_that_breaks_the_triangle_inequality_is_refused() {
    refused(
        &with(
            r#"ixx="1.298e-03" ixy="0" ixz="0" iyy="3.673e-03" iyz="0" izz="3.958e-03""#,
            r#"ixx="1.0e-03" ixy="0" ixz="0" iyy="1.0e-03" iyz="0" izz="3.0e-03""#,
        ),
        &["link `torso`", "triangle inequality"],
    );
}

#[test]
fn a_joint_effort_of_1e_minus_300_is_refused() {
    refused(
        &with(
            r#"lower="-0.6" upper="0.6" effort="1.0""#,
            r#"lower="-0.6" upper="0.6" effort="1e-300""#,
        ),
        &["joint `", "effort limit"],
    );
}

#[test]
fn the_shipped_robot_has_none_of_these() {
    RobotDescription::from_urdf_str(ERS7_URDF).expect("the ERS-7 loads");
}

#[test]
fn legs_mapped_left_for_right_or_sharing_joints_or_with_giant_feet_are_refused() {
    use quadsim::robot_file::RobotFile;
    let ers7 = include_str!("../../../assets/robots/ers7.toml");
    let dir = std::env::temp_dir().join(format!("legs-mapped-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    std::fs::write(dir.join("robot.urdf"), ERS7_URDF).expect("urdf");
    let load = |text: String| {
        let file = dir.join("robot.toml");
        std::fs::write(&file, text.replace("../ers7.urdf", "robot.urdf")).expect("file");
        RobotFile::from_file(&file)
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    load(ers7.to_string()).expect("the ERS-7 as shipped");
    let swapped = ers7
        .replace("front_left = ", "front_right_was = ")
        .replace("front_right = ", "front_left = ")
        .replace("front_right_was = ", "front_right = ");
    let e = load(swapped).expect_err("left for right");
    assert!(e.contains("legs mapped left for right"), "{e}");
    let line = |key: &str| {
        ers7.lines()
            .find(|l| l.starts_with(key))
            .expect(key)
            .split_once('=')
            .expect("=")
            .1
            .trim()
            .to_string()
    };
    let shared = ers7.replace(
        &format!("rear_left = {}", line("rear_left")),
        &format!("rear_left = {}", line("front_left")),
    );
    let e = load(shared).expect_err("two legs on the same joints");
    assert!(e.contains("each leg has joints of its own"), "{e}");
    let giant = ERS7_URDF.replacen(
        r#"<sphere radius="0.012"/>"#,
        r#"<sphere radius="1.0"/>"#,
        1,
    );
    let e = RobotDescription::from_urdf_str(&giant)
        .expect_err("a 1 m foot on a 0.14 m leg")
        .to_string();
    assert!(e.contains("half its leg's length"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
