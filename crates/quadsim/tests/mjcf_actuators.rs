//! An MJCF's actuators: `position` actuators that all give one `kp` (times
//! the gear squared: MuJoCo's joint-space gain) are read and named in a
//! note with the setting that gives the servos that gain (the testbed's
//! servos keep their gains scaled from the ERS-7's: the book's MJCF page
//! says why); differing gains or kinds are said to differ; a gain that is
//! not positive is refused.

include!("common/boxy_mjcf.rs");

/// The box quadruped with `actuators` (the joints are `{leg}_{abd,hip,knee}`).
fn with_actuators(actuators: &str) -> String {
    quadruped("angle=\"degree\"", "", "").replace(
        "</worldbody>",
        &format!("</worldbody><actuator>{actuators}</actuator>"),
    )
}

/// One actuator element per joint, `each(joint)` writing it.
fn every_joint(each: impl Fn(&str) -> String) -> String {
    ["fl", "fr", "hl", "hr"]
        .iter()
        .flat_map(|l| ["abd", "hip", "knee"].map(|j| format!("{l}_{j}")))
        .map(|j| each(&j))
        .collect()
}

fn read(name: &str, text: &str) -> Result<quadsim::mjcf::Mjcf, String> {
    let dir = std::env::temp_dir().join(format!("quadsim-act-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a folder");
    let path = dir.join("model.xml");
    std::fs::write(&path, text).expect("written");
    let out = quadsim::mjcf::read(&path).map_err(|e| e.to_string());
    std::fs::remove_dir_all(&dir).ok();
    out
}

#[test]
fn position_servos_with_one_gain_are_the_servos_gain() {
    let m = read(
        "one",
        &with_actuators(&every_joint(|j| {
            format!(r#"<position joint="{j}" kp="3"/>"#)
        })),
    )
    .expect("reads");
    assert_eq!(m.servo_kp_nm_per_rad, Some(3.0));
    assert!(
        m.notes
            .iter()
            .any(|n| n.contains("kp 3 N") && n.contains("--set servo.kp=3")),
        "{:?}",
        m.notes
    );
    // Through a gear of 2 the joint feels four times the gain.
    let geared = read(
        "gear",
        &with_actuators(&every_joint(|j| {
            format!(r#"<position joint="{j}" kp="3" gear="2"/>"#)
        })),
    )
    .expect("reads");
    assert_eq!(geared.servo_kp_nm_per_rad, Some(12.0));
    // MuJoCo's default kp is 1.
    let unsaid = read(
        "default",
        &with_actuators(&every_joint(|j| format!(r#"<position joint="{j}"/>"#))),
    )
    .expect("reads");
    assert_eq!(unsaid.servo_kp_nm_per_rad, Some(1.0));
}

#[test]
fn differing_gains_or_kinds_leave_the_scaled_gain() {
    let differing = every_joint(|j| {
        let kp = if j.ends_with("knee") { 5 } else { 3 };
        format!(r#"<position joint="{j}" kp="{kp}"/>"#)
    });
    let mixed = every_joint(|j| {
        if j.starts_with("fl") {
            format!(r#"<motor joint="{j}" ctrlrange="-1 1"/>"#)
        } else {
            format!(r#"<position joint="{j}" kp="3"/>"#)
        }
    });
    for (name, actuators) in [("differing", differing), ("mixed", mixed)] {
        let m = read(name, &with_actuators(&actuators)).expect("reads");
        assert_eq!(m.servo_kp_nm_per_rad, None, "{name}");
        assert!(
            m.notes.iter().any(|n| n.contains("differ")),
            "{name}: {:?}",
            m.notes
        );
    }
    let motors = read(
        "motors",
        &with_actuators(&every_joint(|j| {
            format!(r#"<motor joint="{j}" ctrlrange="-1 1"/>"#)
        })),
    )
    .expect("reads");
    assert_eq!(motors.servo_kp_nm_per_rad, None);
    assert!(
        motors
            .notes
            .iter()
            .any(|n| n.contains("own position servos")),
        "{:?}",
        motors.notes
    );
}

#[test]
fn a_gain_that_is_not_positive_is_refused() {
    for kp in ["0", "-2"] {
        let e = read(
            "bad",
            &with_actuators(&every_joint(|j| {
                format!(r#"<position joint="{j}" kp="{kp}"/>"#)
            })),
        )
        .expect_err("refused");
        assert!(e.contains("<position>") && e.contains("line"), "{e}");
    }
}
