//! What published URDFs are made of, taken as they are: a foot that is a
//! link of any shape fixed below the shank (not a sphere), a point mass on a
//! fixed joint (an IMU with mass and no inertia), a cover whose inertia is
//! singular, a mesh named by a
//! `package://` path from a package that holds many robots, and a binary STL
//! whose header begins with "solid".

use std::path::{Path, PathBuf};

use quadsim::{ERS7_URDF, QuadrupedSim, RobotDescription, SimConfig};

const SHANK_SPHERE: &str = r#"<collision><origin xyz="0 0 -0.07" rpy="0 0 0"/><geometry><sphere radius="0.012"/></geometry></collision>"#;
const TORSO_BOX: &str = r#"<geometry><box size="0.20 0.10 0.08"/></geometry></collision>"#;

fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("quadsim-published-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("dir");
    d
}

/// Loads `text` with its legs found from the tree (no robot file), from `dir`.
fn discovered(text: &str, dir: &Path) -> Result<RobotDescription, quadsim::RobotError> {
    let urdf = urdf_rs::read_from_string(text).expect("parses");
    let map = quadsim::discover::discover(&urdf)?;
    RobotDescription::from_urdf_in(urdf, &map, dir)
}

/// The robot stands, walks forwards at a forwards command, and stays upright.
fn walks(d: &RobotDescription) {
    let mut sim = QuadrupedSim::new(d, SimConfig::default()).expect("a world");
    sim.advance(1.0);
    sim.set_command(150.0).expect("finite");
    sim.advance(2.0);
    assert!(sim.is_upright());
    assert!(sim.distance_along_line_m() < SimConfig::default().start_distance_m - 0.1);
}

/// The ERS-7 with each shank's sphere foot moved onto a link of its own,
/// fixed where the sphere was, as `geometry`.
fn with_toe_links(geometry: &str) -> String {
    let mut text = ERS7_URDF.to_string();
    for leg in ["fl", "fr", "hl", "hr"] {
        let shank = format!(r#"<link name="{leg}_shank">"#);
        let at = text.find(&shank).expect("shank");
        let sphere = at + text[at..].find(SHANK_SPHERE).expect("sphere");
        let end = sphere + text[sphere..].find("</link>").expect("end") + "</link>".len();
        let toe = format!(
            r#"</link>
  <link name="{leg}_toe"><collision><origin xyz="0 0 0" rpy="0 0 0"/>{geometry}</collision></link>
  <joint name="{leg}_toe_fixed" type="fixed"><parent link="{leg}_shank"/><child link="{leg}_toe"/>
    <origin xyz="0 0 -0.07" rpy="0 0 0"/></joint>"#
        );
        text.replace_range(sphere..end, &toe);
    }
    text
}

#[test]
fn a_box_or_mesh_toe_fixed_below_the_shank_is_the_foot() {
    let d = dir("toe");
    let ers7 = RobotDescription::from_urdf_str(ERS7_URDF).expect("the ERS-7");
    // A cube, and a mesh of it, the sphere's width: the foot is the shape's
    // centre, its radius half the shape's smallest extent.
    std::fs::write(d.join("toe.obj"), cube_obj(0.012)).expect("write");
    for geometry in [
        r#"<geometry><box size="0.024 0.024 0.024"/></geometry>"#,
        r#"<geometry><mesh filename="toe.obj"/></geometry>"#,
    ] {
        let text = with_toe_links(geometry);
        assert!(!text.contains("sphere"), "no sphere foot is left");
        let toes = discovered(&text, &d).expect(geometry);
        for (a, b) in toes.legs.iter().zip(&ers7.legs) {
            assert_eq!(a.joints, b.joints);
            assert!(
                (a.shank_m - b.shank_m).abs() < 1e-6,
                "{geometry}: {} {}",
                a.shank_m,
                b.shank_m
            );
            assert!(
                (a.foot_radius_m - b.foot_radius_m).abs() < 1e-6,
                "{geometry}: {}",
                a.foot_radius_m
            );
        }
        walks(&toes);
    }
}

#[test]
fn a_point_mass_on_a_fixed_joint_is_folded_into_its_parent() {
    // An IMU as URDFs give it: mass, and no inertia (HyQ's `trunk_imu`).
    let imu = r#"<link name="imu"><inertial><origin xyz="0 0 0" rpy="0 0 0"/><mass value="0.018"/>
    <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>
  <joint name="imu_fixed" type="fixed"><parent link="torso"/><child link="imu"/>
    <origin xyz="0.05 0 0.02" rpy="0 0 0"/></joint>
</robot>"#;
    let text = ERS7_URDF.replacen("</robot>", imu, 1);
    let ers7 = RobotDescription::from_urdf_str(ERS7_URDF).expect("the ERS-7");
    let with_imu = RobotDescription::from_urdf_str(&text).expect("loads");
    assert!((with_imu.total_mass_kg - ers7.total_mass_kg - 0.018).abs() < 1e-12);
    walks(&with_imu);
}

/// A cover as ANYmal C's `hatch` is published: 142 g whose inertia is every
/// entry 0.001, a singular tensor no body has. Fixed to the torso, it is
/// folded into it, and the robot walks without its physics blowing up. (As
/// a body of its own it threw the ANYmal C over; the ERS-7, with it as a
/// body, happens not to blow up in these 4 s.)
#[test]
fn a_cover_with_a_singular_inertia_is_folded_into_the_body_it_is_fixed_to() {
    let hatch = r#"<link name="hatch"><inertial><origin xyz="0 0 0" rpy="0 0 0"/><mass value="0.142"/>
    <inertia ixx="0.001" ixy="0.001" ixz="0.001" iyy="0.001" iyz="0.001" izz="0.001"/></inertial></link>
  <joint name="hatch_fixed" type="fixed"><parent link="torso"/><child link="hatch"/>
    <origin xyz="-0.05 0 0.04" rpy="0 0 0"/></joint>
</robot>"#;
    let text = ERS7_URDF.replacen("</robot>", hatch, 1);
    let ers7 = RobotDescription::from_urdf_str(ERS7_URDF).expect("the ERS-7");
    let with_hatch = RobotDescription::from_urdf_str(&text).expect("loads");
    assert!((with_hatch.total_mass_kg - ers7.total_mass_kg - 0.142).abs() < 1e-12);
    // The hatch is a massless frame, its mass in the torso's body.
    let mass = |d: &RobotDescription, link: &str| {
        let l = d.urdf.links.iter().find(|l| l.name == link).expect(link);
        l.inertial.mass.value
    };
    assert_eq!(mass(&with_hatch, "hatch"), 0.0);
    assert!((mass(&with_hatch, "torso") - mass(&ers7, "torso") - 0.142).abs() < 1e-12);
    let mut sim = QuadrupedSim::new(&with_hatch, SimConfig::default()).expect("a world");
    sim.advance(1.0);
    sim.set_command(-300.0).expect("finite");
    sim.advance(3.0);
    assert_eq!(sim.blew_up_at_s(), None);
    assert!(sim.is_upright());
    assert!(sim.distance_along_line_m() > SimConfig::default().start_distance_m + 0.1);
}

/// A link that moves by its own joint cannot pass mass with an inertia no
/// body has to anything: the robot is refused, naming the link.
#[test]
fn a_moving_link_with_a_singular_inertia_is_refused_naming_it() {
    let shank =
        r#"<inertia ixx="2.200e-05" ixy="0" ixz="0" iyy="2.200e-05" iyz="0" izz="3.000e-06"/>"#;
    assert!(ERS7_URDF.contains(shank));
    let text = ERS7_URDF.replacen(
        shank,
        r#"<inertia ixx="2e-05" ixy="2e-05" ixz="2e-05" iyy="2e-05" iyz="2e-05" izz="2e-05"/>"#,
        1,
    );
    let err = RobotDescription::from_urdf_str(&text).expect_err("refused");
    let text = err.to_string();
    assert!(
        matches!(err, quadsim::RobotError::BadInertia { .. }),
        "{text}"
    );
    assert!(
        text.contains("fl_shank") && text.contains("principal moments"),
        "{text}"
    );
    assert!(text.contains("it moves (joint `fl_knee`)"), "{text}");
}

#[test]
fn a_package_path_is_found_from_a_package_of_many_robots() {
    // example-robot-data's layout: PACKAGE/robots/NAME/urdf/NAME.urdf,
    // meshes named package://PACKAGE/robots/NAME/meshes/...
    let root = dir("package");
    let robot = root.join("robots/ers7_description");
    std::fs::create_dir_all(robot.join("meshes")).expect("dir");
    std::fs::create_dir_all(robot.join("urdf")).expect("dir");
    std::fs::write(robot.join("meshes/torso.stl"), binary_stl_box(true)).expect("write");
    let text = ERS7_URDF.replacen(
        TORSO_BOX,
        r#"<geometry><mesh filename="package://some_robots/robots/ers7_description/meshes/torso.stl"/></geometry></collision>"#,
        1,
    );
    let d = discovered(&text, &robot.join("urdf")).expect("loads");
    assert_eq!(d.meshes.len(), 1);
    walks(&d);
}

#[test]
fn a_binary_stl_whose_header_begins_with_solid_is_read_as_binary() {
    let d = dir("stl");
    for (name, solid) in [("plain.stl", false), ("solid.stl", true)] {
        std::fs::write(d.join(name), binary_stl_box(solid)).expect("write");
        let text = ERS7_URDF.replacen(
            TORSO_BOX,
            &format!(r#"<geometry><mesh filename="{name}"/></geometry></collision>"#),
            1,
        );
        let robot = discovered(&text, &d).expect(name);
        let [mesh] = robot.meshes.as_slice() else {
            panic!("one mesh");
        };
        let aabb = mesh.parts[0].0.compute_local_aabb();
        for k in 0..3 {
            let half = [0.10, 0.05, 0.04][k];
            assert!(
                (aabb.maxs[k] as f64 - half).abs() < 1e-5,
                "{name}: {aabb:?}"
            );
            assert!(
                (aabb.mins[k] as f64 + half).abs() < 1e-5,
                "{name}: {aabb:?}"
            );
        }
    }
}

include!("common/cube.rs");

/// A cube of half-width `h` as Wavefront OBJ.
fn cube_obj(h: f64) -> String {
    let mut s = String::new();
    for v in cube_corners([h; 3]) {
        s += &format!("v {} {} {}\n", v[0], v[1], v[2]);
    }
    for f in CUBE_FACES {
        s += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    s
}

/// The ERS-7's torso box (0.20 x 0.10 x 0.08 m) as binary STL, with one face
/// given twice so that its triangle count, 13, is a carriage return (as the
/// Solo 12's foot's is); its header begins "solid" if `solid`.
fn binary_stl_box(solid: bool) -> Vec<u8> {
    let corners = cube_corners([0.10, 0.05, 0.04]);
    let mut faces = CUBE_FACES.to_vec();
    faces.push(CUBE_FACES[0]);
    let mut out = vec![b' '; 80];
    if solid {
        out[..10].copy_from_slice(b"solid foot");
    }
    out.extend_from_slice(&(faces.len() as u32).to_le_bytes());
    for f in faces {
        out.extend_from_slice(&[0u8; 12]);
        for i in f {
            for v in corners[i] {
                out.extend_from_slice(&(v as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&[0u8; 2]);
    }
    out
}
