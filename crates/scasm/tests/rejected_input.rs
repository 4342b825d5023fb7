//! Bad configuration and bad events are typed errors, and a refused event leaves
//! the learner exactly as it was.

mod common;

use scasm::{
    CalibrationLearner, ConfigError, Event, EventError, Mode, Polynomial, Scasm, ScasmConfig,
};

fn trained() -> Scasm {
    let mut l = Scasm::default();
    common::feed(&mut l, &common::events(0, 900)); // 45 s: both models exist
    assert!(l.action_model().is_some() && l.sensor_model().is_some());
    l
}

/// Whether an error is the one an event should get.
type IsExpected = fn(&EventError) -> bool;

#[test]
fn refused_events_change_nothing() {
    let learner = trained();
    let clock = learner.clock_s();
    let bad: [(Event, IsExpected); 10] = [
        (
            Event::Reading {
                t_s: clock,
                obs_px: f64::NAN,
            },
            |e| {
                matches!(
                    e,
                    EventError::NonFinite {
                        field: "obs_px",
                        ..
                    }
                )
            },
        ),
        (
            Event::Reading {
                t_s: clock,
                obs_px: f64::INFINITY,
            },
            |e| {
                matches!(
                    e,
                    EventError::NonFinite {
                        field: "obs_px",
                        ..
                    }
                )
            },
        ),
        (
            Event::Reading {
                t_s: clock,
                obs_px: 0.0,
            },
            |e| matches!(e, EventError::NonPositiveReading { .. }),
        ),
        (
            Event::Reading {
                t_s: clock - 1.0,
                obs_px: 30.0,
            },
            |e| matches!(e, EventError::TimeWentBackwards { .. }),
        ),
        (
            Event::Reading {
                t_s: clock + 1.0,
                obs_px: 30.0,
            },
            |e| matches!(e, EventError::TimeGap { .. }),
        ),
        (
            Event::Reading {
                t_s: f64::NAN,
                obs_px: 30.0,
            },
            |e| matches!(e, EventError::NonFinite { field: "t_s", .. }),
        ),
        (
            Event::Command {
                t_s: clock,
                dt_s: 0.05,
                command: f64::NAN,
            },
            |e| {
                matches!(
                    e,
                    EventError::NonFinite {
                        field: "command",
                        ..
                    }
                )
            },
        ),
        (
            Event::Command {
                t_s: clock,
                dt_s: 0.05,
                command: f64::NEG_INFINITY,
            },
            |e| {
                matches!(
                    e,
                    EventError::NonFinite {
                        field: "command",
                        ..
                    }
                )
            },
        ),
        (
            Event::Command {
                t_s: clock,
                dt_s: 0.0,
                command: 100.0,
            },
            |e| matches!(e, EventError::NonPositiveDuration { .. }),
        ),
        (
            Event::Command {
                t_s: clock - 0.05,
                dt_s: 0.05,
                command: 100.0,
            },
            |e| matches!(e, EventError::TimeWentBackwards { .. }),
        ),
    ];
    for (event, expected) in bad {
        let mut l = learner.clone();
        let err = l.handle(event).expect_err("must be refused");
        assert!(expected(&err), "{event:?} gave {err:?}");
        assert_eq!(l, learner, "{event:?} changed the learner");
        assert!(!err.to_string().is_empty());
    }
    // And the learner goes on as if nothing had happened.
    let mut l = learner.clone();
    l.handle(Event::Command {
        t_s: clock,
        dt_s: 0.05,
        command: 100.0,
    })
    .expect("valid");
}

#[test]
fn out_of_range_configuration_is_refused_by_name() {
    let cases: [(ScasmConfig, &str); 13] = [
        (
            ScasmConfig {
                gamma: 0.0,
                ..Default::default()
            },
            "learner.gamma",
        ),
        (
            ScasmConfig {
                gamma: 1.5,
                ..Default::default()
            },
            "learner.gamma",
        ),
        (
            ScasmConfig {
                gamma: f64::NAN,
                ..Default::default()
            },
            "learner.gamma",
        ),
        (
            ScasmConfig {
                beta: -0.1,
                ..Default::default()
            },
            "learner.beta",
        ),
        (
            ScasmConfig {
                beta: 1.01,
                ..Default::default()
            },
            "learner.beta",
        ),
        (
            ScasmConfig {
                t_start_s: -1.0,
                ..Default::default()
            },
            "learner.t_start",
        ),
        (
            ScasmConfig {
                t_start_s: f64::INFINITY,
                ..Default::default()
            },
            "learner.t_start",
        ),
        (
            ScasmConfig {
                sensor_degree: 0,
                ..Default::default()
            },
            "learner.sensor_degree",
        ),
        (
            ScasmConfig {
                sensor_degree: 9,
                ..Default::default()
            },
            "learner.sensor_degree",
        ),
        (
            ScasmConfig {
                action_degree: 8,
                ..Default::default()
            },
            "learner.action_degree",
        ),
        (
            ScasmConfig {
                command_scale: 0.0,
                ..Default::default()
            },
            "learner.command_scale",
        ),
        (
            ScasmConfig {
                sensor_window: 0,
                ..Default::default()
            },
            "learner.sensor_window",
        ),
        (
            ScasmConfig {
                sensor_window: scasm::MAX_SENSOR_WINDOW + 1,
                ..Default::default()
            },
            "learner.sensor_window",
        ),
    ];
    for (config, key) in cases {
        let err = config.validate().expect_err("must be refused");
        assert!(err.to_string().contains(key), "{err} should name {key}");
    }
    assert!(ScasmConfig::default().validate().is_ok());
    let bad_model = Polynomial::new(&[0.0, f64::NAN]).expect("poly");
    assert_eq!(
        Scasm::new(Default::default(), Mode::SensorFromAction(bad_model)),
        Err(ConfigError::GivenModel { which: "action" })
    );
}

#[test]
fn a_checkpoint_with_out_of_range_values_is_refused() {
    let json = serde_json::to_string(&Scasm::default()).expect("serialise");
    let broken = json.replacen("\"gamma\":0.999", "\"gamma\":1.5", 1);
    assert_ne!(json, broken);
    let err = serde_json::from_str::<Scasm>(&broken).expect_err("must be refused");
    assert!(err.to_string().contains("learner.gamma"), "{err}");
}
