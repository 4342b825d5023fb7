//! URDF as ROS's parser (urdfdom) and PyBullet read it: a xacro output with
//! comments inside `<geometry>` and elements the simulator has no use for
//! (`<gazebo>`, `<transmission>`), and a robot whose root is a footprint
//! frame joined to its body by a `floating` joint. Each is the shipped robot
//! edited into the convention, and must be the same robot, moving the same to
//! the bit; what cannot be simulated (a floating joint elsewhere, a
//! footprint with mass, a `<mimic>` joint) is refused by name.

use quadsim::{ERS7_URDF, QuadrupedSim, RobotDescription, RobotFile, SimConfig};

fn edited(from: &str, to: &str, text: &str) -> String {
    assert!(text.contains(from), "the edit `{from}` applies");
    text.replace(from, to)
}

/// The ERS-7 as xacro writes it: a comment inside every `<geometry>`, a
/// processing instruction, the xacro namespace, Gazebo's and ros_control's
/// elements.
fn as_xacro_writes_it(urdf: &str) -> String {
    let text = urdf.replace("<geometry>", "<geometry> <!-- from the CAD export -->");
    let text = edited(
        "<robot name=\"ers7\">",
        "<?xml-stylesheet href=\"urdf.xsl\"?>\n<robot name=\"ers7\" \
         xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n  <gazebo reference=\"torso\">\
         <mu1>0.8</mu1></gazebo>\n  <transmission name=\"fl_knee_tr\"><type>SimpleTransmission\
         </type><joint name=\"fl_knee\"/></transmission>",
        &text,
    );
    edited(
        "<link name=\"head\">",
        "<link name=\"head\"><!-- the head -->",
        &text,
    )
}

/// The ERS-7 with a ROS footprint: `base_footprint`, joined to the torso by
/// a floating joint, as its root.
fn with_footprint(urdf: &str, joint_type: &str) -> String {
    edited(
        "  <link name=\"torso\">",
        &format!(
            "  <link name=\"base_footprint\"/>\n  <joint name=\"footprint_joint\" \
             type=\"{joint_type}\">\n    <parent link=\"base_footprint\"/>\n    <child \
             link=\"torso\"/>\n  </joint>\n  <link name=\"torso\">"
        ),
        urdf,
    )
}

include!("common/walked.rs");

fn same_robot(d: &RobotDescription, shipped: &RobotDescription) {
    assert_eq!(d.root_link, shipped.root_link);
    assert_eq!(d.legs, shipped.legs);
    assert_eq!(d.camera, shipped.camera);
    assert_eq!(d.total_mass_kg, shipped.total_mass_kg);
    assert_eq!(walked(d), walked(shipped), "the same motion, to the bit");
}

#[test]
fn a_xacro_output_with_comments_and_gazebo_elements_is_the_same_robot() {
    assert!(ERS7_URDF.matches("<geometry>").count() >= 5);
    let shipped = RobotDescription::from_urdf_str(ERS7_URDF).expect("shipped");
    let text = as_xacro_writes_it(ERS7_URDF);
    let d = RobotDescription::from_urdf_str(&text).expect("loads");
    let line_of = |tag: &str| {
        1 + text[..text.find(tag).expect("as written")]
            .matches('\n')
            .count()
    };
    same_robot(&d, &shipped);
    assert!(shipped.notes.is_empty(), "{:?}", shipped.notes);
    // One line each for what was left out, with where it is.
    assert_eq!(d.notes.len(), 2, "{:?}", d.notes);
    for (note, tag) in d.notes.iter().zip(["gazebo", "transmission"]) {
        let at = format!("ignored <{tag}> at line {} ", line_of(&format!("<{tag} ")));
        assert!(note.starts_with(&at), "{note}");
    }
}

#[test]
fn a_floating_joint_from_a_footprint_makes_its_child_the_root() {
    let shipped = RobotDescription::from_urdf_str(ERS7_URDF).expect("shipped");
    for kind in ["floating", "planar"] {
        let d = RobotDescription::from_urdf_str(&with_footprint(ERS7_URDF, kind))
            .unwrap_or_else(|e| panic!("{kind}: {e}"));
        same_robot(&d, &shipped);
        assert_eq!(d.notes.len(), 1, "{:?}", d.notes);
        assert!(
            d.notes[0].contains("`base_footprint`")
                && d.notes[0].contains(&format!("{kind} joint `footprint_joint`"))
                && d.notes[0].contains("`torso` is the root"),
            "{}",
            d.notes[0]
        );
    }
}

#[test]
fn a_bare_urdf_with_both_conventions_is_found_as_the_plain_one_is() {
    let dir = std::env::temp_dir().join(format!("quadsim-ros-urdf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("as written");
    let plain = dir.join("plain.urdf");
    let ros = dir.join("ros.urdf");
    std::fs::write(&plain, ERS7_URDF).expect("as written");
    std::fs::write(
        &ros,
        with_footprint(&as_xacro_writes_it(ERS7_URDF), "floating"),
    )
    .expect("as written");
    let a = RobotFile::from_file(&plain).expect("plain");
    let b = RobotFile::from_file(&ros).expect("ROS's conventions");
    assert_eq!(a.description.legs, b.description.legs);
    assert_eq!(a.description.camera, b.description.camera);
    assert_eq!(a.gait, b.gait);
    assert_eq!(b.description.notes.len(), 3, "{:?}", b.description.notes);
    std::fs::remove_dir_all(&dir).ok();
}

fn refused(text: &str) -> String {
    RobotDescription::from_urdf_str(text)
        .expect_err("refused")
        .to_string()
}

#[test]
fn what_cannot_be_simulated_is_refused_by_name() {
    // A floating joint that is not from the root, or from a root that holds
    // more than the robot's body.
    let e = refused(&edited(
        "<joint name=\"fl_knee\" type=\"revolute\">",
        "<joint name=\"fl_knee\" type=\"floating\">",
        ERS7_URDF,
    ));
    assert!(
        e.contains("`fl_knee`") && e.contains("`fl_thigh` is not the root"),
        "{e}"
    );
    let e = refused(&edited(
        "<joint name=\"neck\" type=\"fixed\">",
        "<joint name=\"neck\" type=\"floating\">",
        ERS7_URDF,
    ));
    assert!(
        e.contains("`neck`") && e.contains("`torso` holds joint"),
        "{e}"
    );
    // A footprint that has mass is a body, not a frame.
    let e = refused(&edited(
        "<link name=\"base_footprint\"/>",
        "<link name=\"base_footprint\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" \
         ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>",
        &with_footprint(ERS7_URDF, "floating"),
    ));
    assert!(
        e.contains("`footprint_joint`") && e.contains("has mass"),
        "{e}"
    );
    // Two free joints.
    let two = edited(
        "<joint name=\"neck\" type=\"fixed\">",
        "<joint name=\"neck\" type=\"floating\">",
        &with_footprint(ERS7_URDF, "floating"),
    );
    assert!(refused(&two).contains("`neck` is another"));
    // A joint that follows another.
    let e = refused(&edited(
        "<joint name=\"fl_knee\" type=\"revolute\">",
        "<joint name=\"fl_knee\" type=\"revolute\"><mimic joint=\"fl_hip\"/>",
        ERS7_URDF,
    ));
    assert!(e.contains("`fl_knee`") && e.contains("<mimic>"), "{e}");
}
