//! A malformed or incomplete robot description gives an error that names what is
//! wrong; the shipped description loads.

use quadsim::{ERS7_URDF, RobotDescription, RobotError};

fn load(text: &str) -> Result<RobotDescription, RobotError> {
    RobotDescription::from_urdf_str(text)
}

#[test]
fn the_shipped_robot_loads_with_its_real_proportions() {
    let d = load(ERS7_URDF).expect("valid");
    assert!(
        (d.total_mass_kg - 1.6).abs() < 0.05,
        "mass {}",
        d.total_mass_kg
    );
    assert_eq!(d.legs.len(), 4);
    for leg in &d.legs {
        assert!((leg.thigh_m - 0.07).abs() < 0.01 && (leg.shank_m - 0.07).abs() < 0.01);
    }
}

fn expect_error(text: &str, needle: &str) {
    let err = load(text).expect_err("must be refused");
    let msg = err.to_string();
    assert!(msg.contains(needle), "`{msg}` should mention `{needle}`");
}

#[test]
fn not_xml_is_a_parse_error() {
    expect_error("<robot name='x'><link name=", "malformed URDF");
}

#[test]
fn a_missing_camera_frame_is_named() {
    let text = ERS7_URDF
        .replace(r#"<link name="camera"/>"#, "")
        .replace(
            r#"<joint name="camera_mount" type="fixed"><parent link="head"/><child link="camera"/><origin xyz="0.041 0 0.005" rpy="0 0 0"/></joint>"#,
            "",
        );
    expect_error(&text, "`camera`");
}

#[test]
fn a_camera_not_on_the_head_is_refused() {
    let text = ERS7_URDF.replace(
        r#"<parent link="head"/><child link="camera"/>"#,
        r#"<parent link="torso"/><child link="camera"/>"#,
    );
    expect_error(&text, "`camera` link must be fixed directly to `head`");
}

#[test]
fn a_missing_joint_is_named() {
    let text = ERS7_URDF.replace(r#"joint name="hr_knee""#, r#"joint name="hr_knee_typo""#);
    expect_error(&text, "`hr_knee`");
}

#[test]
fn a_joint_to_a_missing_link_is_named() {
    let text = ERS7_URDF.replace(r#"<child link="fl_shank"/>"#, r#"<child link="fl_shin"/>"#);
    expect_error(&text, "`fl_shin`");
}

#[test]
fn a_wrong_joint_type_or_axis_is_named() {
    let text = ERS7_URDF.replace(
        r#"joint name="fr_hip" type="revolute""#,
        r#"joint name="fr_hip" type="prismatic""#,
    );
    expect_error(&text, "`fr_hip`: must be revolute or continuous");
    let text = ERS7_URDF.replacen(r#"<axis xyz="0 1 0"/>"#, r#"<axis xyz="0 0 1"/>"#, 1);
    expect_error(&text, "`fl_hip`: axis must be");
}

#[test]
fn inverted_limits_are_named() {
    let text = ERS7_URDF.replacen(
        r#"lower="-2.4" upper="2.4""#,
        r#"lower="2.4" upper="-2.4""#,
        1,
    );
    expect_error(&text, "`fl_knee`: limits");
}

#[test]
fn a_link_with_no_mass_is_named() {
    let text = ERS7_URDF.replacen(r#"<mass value="0.06"/>"#, r#"<mass value="-1"/>"#, 1);
    expect_error(&text, "`fl_thigh`");
}

#[test]
fn a_leg_without_a_foot_is_named() {
    let text = ERS7_URDF.replacen(
        r#"<geometry><sphere radius="0.012"/></geometry>"#,
        r#"<geometry><box size="0.02 0.02 0.02"/></geometry>"#,
        1,
    );
    // A box on the shank itself is the lower leg's shape, not a foot; a
    // shape on a link fixed below it would be one.
    expect_error(&text, "`fl_shank` needs a foot: a sphere collision on it");
}

#[test]
fn a_link_with_two_parents_is_refused() {
    let text = ERS7_URDF.replace(
        "</robot>",
        r#"<joint name="extra" type="fixed"><parent link="torso"/><child link="hr_shank"/><origin xyz="0 0 0" rpy="0 0 0"/></joint></robot>"#,
    );
    expect_error(&text, "`hr_shank` is not in one tree");
}

#[test]
fn a_missing_file_names_the_path() {
    let err = RobotDescription::from_file("/nonexistent/robot.urdf").expect_err("no file");
    assert!(err.to_string().contains("/nonexistent/robot.urdf"));
}

/// The URDF's text with the joint `joint`'s line after its opening tag edited.
fn edit_joint(joint: &str, from: &str, to: &str) -> String {
    let start = ERS7_URDF
        .find(&format!(r#"<joint name="{joint}""#))
        .expect("joint");
    let end = start + ERS7_URDF[start..].find("</joint>").expect("end");
    let edited = ERS7_URDF[start..end].replacen(from, to, 1);
    assert_ne!(edited, ERS7_URDF[start..end], "{from} not in {joint}");
    format!("{}{edited}{}", &ERS7_URDF[..start], &ERS7_URDF[end..])
}

fn expect_sim_error(text: &str, needles: &[&str]) {
    let d = load(text).expect("loads: the description alone is consistent");
    let err = quadsim::QuadrupedSim::new(&d, quadsim::SimConfig::default())
        .expect_err("the gait cannot be walked");
    let msg = err.to_string();
    for needle in needles {
        assert!(msg.contains(needle), "`{msg}` should mention `{needle}`");
    }
}

#[test]
fn joint_limits_the_gait_cannot_keep_to_are_named() {
    // The front knees bend backwards by about a radian in every gait.
    let text = edit_joint(
        "fl_knee",
        r#"lower="-2.4" upper="2.4""#,
        r#"lower="-0.2" upper="0.2""#,
    );
    expect_sim_error(
        &text,
        &["joint `fl_knee`", "outside its limits [-0.2, 0.2]"],
    );
}

#[test]
fn legs_too_short_for_the_gait_are_named() {
    // A 2 cm thigh and a 7 cm shank cannot hold the hips 10.5 cm up.
    let text = edit_joint("fl_knee", r#"xyz="0 0 -0.07""#, r#"xyz="0 0 -0.02""#);
    expect_sim_error(&text, &["leg `fl`", "thigh of 0.02 m"]);
}
