//! Files that would make a read run away are refused at once, naming the file
//! (issue 61): a robot path naming a device or a FIFO, a robot file whose URDF
//! does, and a URDF nested deep enough to make urdf-rs's parser crawl.

use quadsim::RobotFile;

fn refused(path: &str, needle: &str) {
    let e = RobotFile::load(path).expect_err("must be refused");
    let msg = e.to_string();
    assert!(msg.contains(needle), "`{msg}` should mention `{needle}`");
}

#[test]
#[cfg(unix)]
fn a_robot_path_naming_a_device_is_refused_not_read() {
    refused("/dev/zero", "a character device");
}

#[test]
#[cfg(target_os = "linux")]
fn a_robot_files_urdf_naming_a_fifo_is_refused_not_waited_on() {
    let dir = std::env::temp_dir().join(format!("unbounded-fifo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let fifo = dir.join("robot.urdf");
    let _ = std::fs::remove_file(&fifo);
    if !std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
    {
        return; // no mkfifo here: nothing to check
    }
    // The trotter's robot file, its URDF the FIFO.
    let trotter = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/robots/trotter.toml"
    ))
    .expect("the trotter");
    let file = dir.join("robot.toml");
    std::fs::write(&file, trotter.replace("trotter.urdf", "robot.urdf")).expect("robot file");
    refused(&file.display().to_string(), "a FIFO");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_urdf_nested_a_hundred_thousand_deep_is_refused_by_its_depth() {
    let dir = std::env::temp_dir().join(format!("unbounded-deep-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let urdf = dir.join("deep.urdf");
    let n = 100_000;
    std::fs::write(
        &urdf,
        format!(
            "<robot name=\"deep\">{}{}</robot>",
            "<link>".repeat(n),
            "</link>".repeat(n)
        ),
    )
    .expect("urdf");
    refused(&urdf.display().to_string(), "nested more than 256 deep");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_bare_urdfs_nan_camera_origin_is_named_not_a_toml_error() {
    // issue 61: the error is about the file the user gave, not the robot
    // file the project writes for a bare URDF.
    let dir = std::env::temp_dir().join(format!("nan-camera-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let urdf = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/ers7.urdf"
    ))
    .expect("the ERS-7's URDF");
    let at = urdf
        .find("<joint name=\"camera_mount")
        .expect("a camera joint");
    let origin = at + urdf[at..].find("xyz=\"").expect("its origin") + 5;
    let end = origin + urdf[origin..].find('"').expect("its end");
    let mut nan = urdf.clone();
    nan.replace_range(origin..end, "NaN 0 0");
    let path = dir.join("nan.urdf");
    std::fs::write(&path, nan).expect("write");
    let e = RobotFile::load(&path.display().to_string()).expect_err("refused");
    let msg = e.to_string();
    assert!(
        msg.contains("not finite") && !msg.contains("TOML"),
        "`{msg}`"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
