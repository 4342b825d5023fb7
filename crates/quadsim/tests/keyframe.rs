//! An MJCF's keyframe as the standing pose: the `home` key's `qpos` read in
//! MuJoCo's order (the free joint's 7 numbers, then the joints in the file's
//! order), the feet's height and width below the hips at those angles
//! becoming the gait's stance, and a key that cannot be read so left out
//! with a note. MuJoCo Menagerie's Go2 stands as its `home` key says.

use std::collections::BTreeMap;
use std::path::Path;

use quadsim::stance::Stance;
use quadsim::{RobotDescription, RobotFile};

include!("common/boxy_mjcf.rs");

/// `text` as `name.xml` in a fresh folder, read as MJCF and as a robot
/// description (legs found from its tree).
fn read(name: &str, text: &str) -> (quadsim::mjcf::Mjcf, RobotDescription) {
    let dir = std::env::temp_dir().join(format!("quadsim-key-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a folder");
    let path = dir.join("model.xml");
    std::fs::write(&path, text).expect("written");
    let model = quadsim::mjcf::read(&path).expect("reads");
    let map = quadsim::discover::discover(&model.urdf).expect("legs");
    let d = RobotDescription::from_urdf_in(model.urdf.clone(), &map, &dir).expect("a robot");
    std::fs::remove_dir_all(&dir).ok();
    (model, d)
}

/// The box quadruped with `keys` in its `<keyframe>` and `world` beside it.
fn with_keys(keys: &str, world: &str) -> String {
    quadruped("angle=\"degree\"", "", "").replace(
        "</worldbody>",
        &format!("{world}</worldbody><keyframe>{keys}</keyframe>"),
    )
}

const LEGS: [&str; 4] = ["fl", "fr", "hl", "hr"];

#[test]
fn the_home_keys_qpos_are_the_joints_in_the_files_order() {
    // Each joint's angle its index in the file, in hundredths of a radian.
    let angles: Vec<String> = (0..12).map(|i| format!("{}", 0.01 * i as f64)).collect();
    let keys = format!(
        r#"<key name="first" qpos="{}"/><key name="home" qpos="0 0 0.3 1 0 0 0 {}"/>"#,
        ["0"; 19].join(" "),
        angles.join(" ")
    );
    let (model, _) = read("order", &with_keys(&keys, ""));
    let mut i = 0;
    for leg in LEGS {
        for joint in ["abd", "hip", "knee"] {
            let name = format!("{leg}_{joint}");
            assert_eq!(
                model.standing.get(&name),
                Some(&(0.01 * i as f64)),
                "{name}"
            );
            i += 1;
        }
    }
}

#[test]
fn the_stance_is_where_the_feet_are_below_the_hips() {
    let (_, d) = read("stance", &with_keys("", ""));
    // Thigh and shank 0.1 m each, hanging straight at zero: the hip at 0.5
    // rad and the knee at -1.0 put each foot 0.1 (cos 0.5 + cos 0.5) below
    // its hip, in the leg's plane.
    let angles: BTreeMap<String, f64> = LEGS
        .iter()
        .flat_map(|l| {
            [
                (format!("{l}_abd"), 0.0),
                (format!("{l}_hip"), 0.5),
                (format!("{l}_knee"), -1.0),
            ]
        })
        .collect();
    let s = Stance::at(&d, &angles).expect("a stance");
    assert!((s.body_height_m - 0.2 * 0.5f64.cos()).abs() < 1e-9, "{s:?}");
    assert!(s.stance_width_m.abs() < 1e-9, "{s:?}");
    // Abducted outwards by 0.1 rad, each foot moves out of its leg's plane.
    let out: BTreeMap<String, f64> = angles
        .iter()
        .map(|(k, v)| {
            let left = k.starts_with("fl") || k.starts_with("hl");
            let v = if k.ends_with("abd") {
                if left { 0.1 } else { -0.1 }
            } else {
                *v
            };
            (k.clone(), v)
        })
        .collect();
    let wide = Stance::at(&d, &out).expect("a stance");
    assert!(wide.stance_width_m > 0.01, "{wide:?}");
    // A leg without an angle gives no stance.
    let mut partial = angles.clone();
    partial.remove("hr_knee");
    assert_eq!(Stance::at(&d, &partial), None);
}

#[test]
fn a_key_that_cannot_be_read_as_the_robots_is_left_out_with_a_note() {
    let short = r#"<key name="home" qpos="0 0 0.3 1 0 0 0 0 0.5 -1"/>"#;
    let (model, _) = read("short", &with_keys(short, ""));
    assert!(model.standing.is_empty());
    assert!(
        model
            .notes
            .iter()
            .any(|n| n.contains("left out <key>") && n.contains("10 numbers")),
        "{:?}",
        model.notes
    );
    let full = format!(r#"<key qpos="0 0 0.3 1 0 0 0 {}"/>"#, ["0.1"; 12].join(" "));
    let door =
        r#"<body name="door"><joint type="hinge"/><geom type="box" size="0.1 0.1 0.1"/></body>"#;
    let (model, _) = read("door", &with_keys(&full, door));
    assert!(model.standing.is_empty());
    assert!(
        model
            .notes
            .iter()
            .any(|n| n.contains("joints besides the robot's")),
        "{:?}",
        model.notes
    );
    // Without the door, the same key (the first, not named home) is read.
    let (model, _) = read("nodoor", &with_keys(&full, ""));
    assert_eq!(model.standing.len(), 12);
}

#[test]
fn the_go2_stands_as_its_home_key_says() {
    let dir =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/robots/menagerie/unitree_go2");
    let robot = RobotFile::from_file(&dir.join("go2.xml")).expect("the Go2");
    // go2.xml's home: thigh 0.9, calf -1.8, on a thigh of 0.213 m and a calf
    // whose foot is 0.213 m below the knee (and 2 mm back): the feet about
    // 0.213 (cos 0.9 + cos 0.9) = 0.2648 m below the hips, in their planes.
    for p in [
        robot.gait.idle,
        robot.gait.fast_forwards,
        robot.gait.fast_backwards,
    ] {
        let h = p.body_height_m.expect("from the keyframe");
        assert!((h - 0.426 * 0.9f64.cos()).abs() < 3e-3, "{h}");
        assert!(p.stance_width_m.expect("from the keyframe").abs() < 1e-3);
    }
    assert!(
        robot
            .description
            .notes
            .iter()
            .any(|n| n.contains("as the keyframe does")),
        "{:?}",
        robot.description.notes
    );
}
