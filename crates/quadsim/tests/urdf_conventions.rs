//! URDF conventions of published robots that the testbed reads as they are:
//! knees whose range does not hold the straight leg (and which bend the way
//! that range says), continuous joints, and a foot on a link fixed to the
//! lower leg (a toe). Each test edits the shipped ERS-7 into the convention;
//! without its support, the robot is refused.

use quadsim::{ERS7_URDF, QuadrupedSim, RobotDescription, SimConfig};

fn edited(from: &str, to: &str) -> String {
    assert!(ERS7_URDF.contains(from), "the edit `{from}` applies");
    ERS7_URDF.replace(from, to)
}

/// Stands the robot for two seconds and steps in place for two more.
fn stands(d: &RobotDescription) {
    let mut sim = QuadrupedSim::new(d, SimConfig::default()).expect("a world");
    sim.advance(2.0);
    assert!(sim.is_upright(), "standing");
    sim.set_command(150.0).expect("finite");
    sim.advance(2.0);
    assert!(sim.is_upright(), "walking");
}

#[test]
fn a_knee_that_is_never_straight_bends_the_way_its_range_allows() {
    // The hind knees may only bend backwards (negative), unlike the ERS-7's.
    let mut text = ERS7_URDF.to_string();
    for leg in ["hl", "hr"] {
        let joint = format!(r#"<joint name="{leg}_knee" type="revolute">"#);
        let at = text.find(&joint).expect("the knee");
        let range = r#"lower="-2.4" upper="2.4""#;
        let limit = text[at..].find(range).expect("its limit") + at;
        text.replace_range(limit..limit + range.len(), r#"lower="-2.4" upper="-0.1""#);
    }
    let d = RobotDescription::from_urdf_str(&text).expect("a knee range without zero loads");
    for leg in &d.legs {
        assert_eq!(leg.knee_sign(), -1.0, "{}", leg.name);
    }
    let shipped = RobotDescription::from_urdf_str(ERS7_URDF).expect("shipped");
    let signs: Vec<f64> = shipped.legs.iter().map(|l| l.knee_sign()).collect();
    assert_eq!(
        signs,
        [-1.0, -1.0, 1.0, 1.0],
        "the ERS-7 keeps its elbows and knees"
    );
    stands(&d);
}

#[test]
fn a_continuous_joint_takes_the_gaits_own_range() {
    let text = edited(
        r#"<joint name="fl_abduction" type="revolute">"#,
        r#"<joint name="fl_abduction" type="continuous">"#,
    );
    let d = RobotDescription::from_urdf_str(&text).expect("a continuous abduction loads");
    assert_eq!(d.legs[0].limits_rad[0], [f64::NEG_INFINITY, f64::INFINITY]);
    stands(&d);
}

#[test]
fn a_foot_on_a_link_fixed_to_the_lower_leg_is_the_foot() {
    let sphere = r#"<collision><origin xyz="0 0 -0.07" rpy="0 0 0"/><geometry><sphere radius="0.012"/></geometry></collision>"#;
    let mut text = ERS7_URDF.to_string();
    for leg in ["fl", "fr", "hl", "hr"] {
        let link = format!(r#"<link name="{leg}_shank">"#);
        let at = text.find(&link).expect("the shank");
        let s = text[at..].find(sphere).expect("its foot") + at;
        text.replace_range(s..s + sphere.len(), "");
        // The toe hangs 0.05 m below the knee, turned upside down (a half
        // turn about x), so its sphere, 0.02 m "up" in its own frame, is
        // 0.02 m further down.
        let toe = format!(
            r#"<link name="{leg}_toe"><inertial><mass value="0.002"/><inertia ixx="1e-7" ixy="0" ixz="0" iyy="1e-7" iyz="0" izz="1e-7"/></inertial>
            <collision><origin xyz="0 0 0.02" rpy="0 0 0"/><geometry><sphere radius="0.012"/></geometry></collision></link>
            <joint name="{leg}_toe_fixed" type="fixed"><parent link="{leg}_shank"/><child link="{leg}_toe"/><origin xyz="0 0 -0.05" rpy="3.141592653589793 0 0"/></joint>"#
        );
        text = text.replace("</robot>", &format!("{toe}\n</robot>"));
    }
    let d = RobotDescription::from_urdf_str(&text).expect("a toe's sphere is the foot");
    let shipped = RobotDescription::from_urdf_str(ERS7_URDF).expect("shipped");
    for (toe, own) in d.legs.iter().zip(&shipped.legs) {
        assert!(
            (toe.shank_m - own.shank_m).abs() < 1e-12,
            "{} {}",
            toe.shank_m,
            own.shank_m
        );
        assert_eq!(toe.foot_radius_m, own.foot_radius_m);
    }
    stands(&d);
    // A leg that ends in no collision shape at all is still refused, naming
    // its link (a toe of another shape is a foot: tests/published_shapes.rs).
    let bare = text.replace(
        r#"<collision><origin xyz="0 0 0.02" rpy="0 0 0"/><geometry><sphere radius="0.012"/></geometry></collision>"#,
        "",
    );
    let e = RobotDescription::from_urdf_str(&bare)
        .expect_err("no foot")
        .to_string();
    assert!(e.contains("fl_shank") && e.contains("foot"), "{e}");
}

#[test]
fn a_link_with_no_inertial_carries_no_mass() {
    // The head (a collision box, fixed to the torso) with no <inertial>.
    let head = r#"<link name="head">
    <inertial>"#;
    let at = ERS7_URDF.find(head).expect("the head");
    let end = ERS7_URDF[at..].find("</inertial>").expect("its inertial") + at;
    let mut text = ERS7_URDF.to_string();
    text.replace_range(
        at + head.len() - "<inertial>".len()..end + "</inertial>".len(),
        "",
    );
    let d = RobotDescription::from_urdf_str(&text).expect("a massless fixed link loads");
    let shipped = RobotDescription::from_urdf_str(ERS7_URDF).expect("shipped");
    assert!(d.total_mass_kg < shipped.total_mass_kg);
    stands(&d);
    // A moving link with no mass anywhere in its body is refused.
    let thigh = r#"<link name="fl_thigh">
    <inertial>"#;
    let at = text.find(thigh).expect("the thigh");
    let end = text[at..].find("</inertial>").expect("its inertial") + at;
    let mut moving = text.clone();
    moving.replace_range(
        at + thigh.len() - "<inertial>".len()..end + "</inertial>".len(),
        "",
    );
    let e = RobotDescription::from_urdf_str(&moving)
        .expect_err("a moving link without mass")
        .to_string();
    assert!(e.contains("fl_thigh") && e.contains("fl_hip"), "{e}");
}

#[test]
fn a_joint_whose_axis_points_the_other_way_moves_the_robot_the_same() {
    // Every knee's axis flipped (0 -1 0): the same joints, their angles
    // counted the other way, so the same robot.
    let text = ERS7_URDF.replace(
        r#"<origin xyz="0 0 -0.07" rpy="0 0 0"/><axis xyz="0 1 0"/><limit lower="-2.4" upper="2.4""#,
        r#"<origin xyz="0 0 -0.07" rpy="0 0 0"/><axis xyz="0 -1 0"/><limit lower="-2.4" upper="2.4""#,
    );
    assert_eq!(
        text.matches(r#"<axis xyz="0 -1 0"/>"#).count(),
        4,
        "the four knees"
    );
    let flipped = RobotDescription::from_urdf_str(&text).expect("a flipped axis loads");
    assert!(
        flipped
            .legs
            .iter()
            .all(|l| l.axis_signs == [1.0, 1.0, -1.0])
    );
    let shipped = RobotDescription::from_urdf_str(ERS7_URDF).expect("shipped");
    let run = |d: &RobotDescription| {
        let mut sim = QuadrupedSim::new(d, SimConfig::default()).expect("a world");
        sim.advance(0.5);
        sim.set_command(300.0).expect("finite");
        sim.advance(2.0);
        sim.torso().position_m
    };
    // The same robot up to rounding (rapier's f32, which 2.5 s of footfalls
    // amplify to tens of micrometres); a wrong sign would fold the knees.
    let (a, b) = (run(&flipped), run(&shipped));
    for k in 0..3 {
        assert!((a[k] - b[k]).abs() < 1e-3, "torso at {a:?} against {b:?}");
    }
    assert!(b[0] - (-2.4) > 0.3, "it walked: {b:?}");
    // An axis along neither way is still refused.
    let skew = ERS7_URDF.replacen(r#"<axis xyz="0 1 0"/>"#, r#"<axis xyz="0 0.7 0.7"/>"#, 1);
    let e = RobotDescription::from_urdf_str(&skew)
        .expect_err("skew")
        .to_string();
    assert!(e.contains("or its opposite"), "{e}");
}

/// The ERS-7 parsed, edited by `edit`, and read with its usual legs.
fn edited_urdf(edit: impl FnOnce(&mut urdf_rs::Robot)) -> RobotDescription {
    let mut urdf = urdf_rs::read_from_string(ERS7_URDF).expect("parses");
    edit(&mut urdf);
    let map = quadsim::description::RobotMap::conventional(&urdf).expect("the ERS-7's names");
    RobotDescription::from_urdf(urdf, &map).expect("loads")
}

fn joint_mut<'a>(urdf: &'a mut urdf_rs::Robot, name: &str) -> &'a mut urdf_rs::Joint {
    urdf.joints
        .iter_mut()
        .find(|j| j.name == name)
        .expect("the joint")
}

fn link_mut<'a>(urdf: &'a mut urdf_rs::Robot, name: &str) -> &'a mut urdf_rs::Link {
    urdf.links
        .iter_mut()
        .find(|l| l.name == name)
        .expect("the link")
}

include!("common/walked.rs");

/// `d` walks as the shipped ERS-7 does, up to rapier's f32 rounding (which
/// 2.5 s of footfalls amplify to tens of micrometres).
fn walks_as_the_ers7(d: &RobotDescription) {
    let shipped = RobotDescription::from_urdf_str(ERS7_URDF).expect("shipped");
    let (a, b) = (walked(d), walked(&shipped));
    for k in 0..3 {
        assert!((a[k] - b[k]).abs() < 1e-3, "torso at {a:?} against {b:?}");
    }
}

const LEGS: [&str; 4] = ["fl", "fr", "hl", "hr"];

#[test]
fn joint_origins_that_turn_the_legs_frames_are_the_same_robot() {
    // Every abduction joint's frame turned half round about z, its axis
    // written the other way: in the torso's frame the same axis, and the
    // hip and knee axes below it now (0, -1, 0). The legs' contents are
    // symmetric about z, so the robot is the same.
    let d = edited_urdf(|u| {
        for leg in LEGS {
            let j = joint_mut(u, &format!("{leg}_abduction"));
            j.origin.rpy.0 = [0.0, 0.0, std::f64::consts::PI];
            j.axis.xyz.0 = [-1.0, 0.0, 0.0];
        }
    });
    for leg in &d.legs {
        assert_eq!(leg.axis_signs, [1.0, -1.0, -1.0], "{}", leg.name);
    }
    walks_as_the_ers7(&d);
}

#[test]
fn a_zero_pose_with_the_thigh_pointing_back_is_the_same_robot() {
    // Each thigh written pointing backwards at the zero pose (the knee along
    // -x of its frame, its mass and inertia turned with it) and the shank
    // hanging down from it: the hip's and knee's ranges shift by a quarter
    // turn, and the robot is the same.
    let quarter = std::f64::consts::FRAC_PI_2;
    let d = edited_urdf(|u| {
        for leg in LEGS {
            let knee = joint_mut(u, &format!("{leg}_knee"));
            knee.origin.xyz.0 = [-0.07, 0.0, 0.0];
            knee.limit.lower += quarter;
            knee.limit.upper += quarter;
            let hip = joint_mut(u, &format!("{leg}_hip"));
            hip.limit.lower -= quarter;
            hip.limit.upper -= quarter;
            let thigh = &mut link_mut(u, &format!("{leg}_thigh")).inertial;
            thigh.origin.xyz.0 = [-0.035, 0.0, 0.0];
            std::mem::swap(&mut thigh.inertia.ixx, &mut thigh.inertia.izz);
        }
    });
    for leg in &d.legs {
        assert!((leg.thigh_zero_rad - quarter).abs() < 1e-12, "{leg:?}");
        assert!((leg.knee_zero_rad + quarter).abs() < 1e-12, "{leg:?}");
        assert!((leg.thigh_m - 0.07).abs() < 1e-12);
    }
    let shipped = RobotDescription::from_urdf_str(ERS7_URDF).expect("shipped");
    let signs = |d: &RobotDescription| d.legs.iter().map(|l| l.knee_sign()).collect::<Vec<_>>();
    assert_eq!(signs(&d), signs(&shipped), "the knees bend as the ERS-7's");
    walks_as_the_ers7(&d);
}

#[test]
fn a_hip_ahead_of_the_abduction_joint_is_the_same_robot() {
    // Each abduction joint 1 cm further forwards along its own axis, the
    // hip 1 cm back from it (and the shoulder's mass kept where it was):
    // the same axes in the same places, so the same robot.
    let d = edited_urdf(|u| {
        for leg in LEGS {
            joint_mut(u, &format!("{leg}_abduction")).origin.xyz.0[0] += 0.01;
            joint_mut(u, &format!("{leg}_hip")).origin.xyz.0[0] = -0.01;
            link_mut(u, &format!("{leg}_shoulder"))
                .inertial
                .origin
                .xyz
                .0[0] = -0.01;
        }
    });
    for leg in &d.legs {
        assert_eq!(leg.hip_at_m, [-0.01, 0.0]);
    }
    walks_as_the_ers7(&d);
    // A hip below the abduction axis is another robot, and it walks too.
    let lower = edited_urdf(|u| {
        for leg in LEGS {
            joint_mut(u, &format!("{leg}_abduction")).origin.xyz.0[2] += 0.01;
            joint_mut(u, &format!("{leg}_hip")).origin.xyz.0[2] = -0.01;
        }
    });
    assert_eq!(lower.legs[0].hip_at_m, [0.0, -0.01]);
    stands(&lower);
}

#[test]
fn a_continuous_joint_with_no_limit_has_none() {
    let text = ERS7_URDF.replace(
        r#"<joint name="fl_abduction" type="revolute">"#,
        r#"<joint name="fl_abduction" type="continuous">"#,
    );
    let limit = r#"<limit lower="-0.6" upper="0.6" effort="1.0" velocity="6.0"/>"#;
    let at = text.find(r#"name="fl_abduction""#).expect("the joint");
    let l = text[at..].find(limit).expect("its limit") + at;
    let mut text = text;
    text.replace_range(l..l + limit.len(), "");
    let d = RobotDescription::from_urdf_str(&text).expect("a continuous joint needs no limit");
    assert_eq!(d.legs[0].effort_nm[0], f64::INFINITY);
    assert_eq!(d.legs[0].velocity_rad_s[0], f64::INFINITY);
    stands(&d);
    // A revolute joint still needs its limits.
    let revolute = text.replace(
        r#"<joint name="fl_abduction" type="continuous">"#,
        r#"<joint name="fl_abduction" type="revolute">"#,
    );
    assert!(RobotDescription::from_urdf_str(&revolute).is_err());
}

#[test]
fn links_fixed_between_a_legs_joints_are_the_same_robot() {
    // A massless mount fixed to the torso carries each abduction joint, and a
    // massless housing fixed halfway down each thigh carries its knee.
    let d = edited_urdf(|u| {
        for leg in LEGS {
            // An empty link and a fixed joint, from the ERS-7's camera frame
            // and its neck.
            let empty = u
                .links
                .iter()
                .find(|l| l.name == "camera")
                .expect("camera")
                .clone();
            let neck = u
                .joints
                .iter()
                .find(|j| j.name == "neck")
                .expect("neck")
                .clone();
            let frame = |name: String| urdf_rs::Link {
                name,
                ..empty.clone()
            };
            let fixed = |name: String, parent: &str, child: &str, xyz: [f64; 3]| urdf_rs::Joint {
                name,
                origin: urdf_rs::Pose {
                    xyz: urdf_rs::Vec3(xyz),
                    rpy: urdf_rs::Vec3([0.0; 3]),
                },
                parent: urdf_rs::LinkName {
                    link: parent.into(),
                },
                child: urdf_rs::LinkName { link: child.into() },
                ..neck.clone()
            };
            let (mount, housing) = (format!("{leg}_mount"), format!("{leg}_housing"));
            let abduction = joint_mut(u, &format!("{leg}_abduction"));
            let at = abduction.origin.xyz.0;
            abduction.origin.xyz.0 = [0.0; 3];
            abduction.parent.link.clone_from(&mount);
            let knee = joint_mut(u, &format!("{leg}_knee"));
            knee.origin.xyz.0 = [0.0, 0.0, -0.035];
            knee.parent.link.clone_from(&housing);
            u.links.push(frame(mount.clone()));
            u.links.push(frame(housing.clone()));
            u.joints
                .push(fixed(format!("{leg}_mount_fixed"), "torso", &mount, at));
            let thigh = format!("{leg}_thigh");
            u.joints.push(fixed(
                format!("{leg}_housing_fixed"),
                &thigh,
                &housing,
                [0.0, 0.0, -0.035],
            ));
        }
    });
    let shipped = RobotDescription::from_urdf_str(ERS7_URDF).expect("shipped");
    for (leg, own) in d.legs.iter().zip(&shipped.legs) {
        assert_eq!(leg.hip_in_torso_m, own.hip_in_torso_m);
        assert!((leg.thigh_m - own.thigh_m).abs() < 1e-15);
    }
    walks_as_the_ers7(&d);
    // And a bare URDF's legs are found through them.
    let urdf = urdf_rs::write_to_string(&d.urdf).expect("writes");
    let found = quadsim::discover::discover(&urdf_rs::read_from_string(&urdf).expect("reads"))
        .expect("legs found");
    assert_eq!(
        found.legs[0],
        ["fl_abduction", "fl_hip", "fl_knee"].map(String::from)
    );
}
