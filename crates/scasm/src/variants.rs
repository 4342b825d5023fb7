//! The SCASM variants as a host declares them (see [`crate::declaration`]):
//! the paper's, the default and the errors-in-variables one.

use std::boxed::Box;
use std::string::ToString;
use std::vec::Vec;

use crate::batch::{Believed, KeepStart};
use crate::config::{ScasmConfig, SensorFit};
use crate::declaration::{BoxedLearner, BuildContext, Declaration, Kind, Setting};
use crate::mode::Mode;
use crate::scasm::Scasm;
use crate::self_check::SelfCheck;

/// The shared settings every variant reads.
const COMMON: [&str; 5] = ["gamma", "beta", "t_start", "sensor_degree", "action_degree"];

/// A variant with `config`, checking itself if `check` is given.
fn scasm(
    config: ScasmConfig,
    mode: Mode,
    check: Option<SelfCheck>,
) -> Result<Scasm, std::string::String> {
    let params = config.validate().map_err(|e| e.to_string())?;
    match check {
        Some(check) => Scasm::with_self_check(params, mode, check),
        None => Scasm::new(params, mode),
    }
    .map_err(|e| e.to_string())
}

/// The self-check's settings (see [`Scasm::with_self_check`]).
fn checked_settings() -> Vec<Setting> {
    vec![
        Setting::new(
            "self_check",
            Kind::Count,
            1.0,
            (0.0, false, 1.0),
            "1: while a model is not monotone over its inputs (A over the command range, S \
             over its fit's readings), report the last good models instead; 0: unchecked",
        ),
        Setting::new(
            "good_after_s",
            Kind::Number,
            10.0,
            (0.0, false, f64::INFINITY),
            "how long models must pass the self-check before they are the ones fallen back to, s",
        ),
        Setting::new(
            "keep_start",
            Kind::Count,
            1.0,
            (0.0, false, 1.0),
            "1 (with posterior 1): every keep_start_every_s, report each model's start (A0's \
             line through the origin; section IV's sensor model, learned with A0), in the \
             learner's units, while its posterior's draws do not favour the learned one (A \
             over the command range, fewer than half the draws; S over the distances walked, \
             fewer than keep_start_sensor_below of them); 0: always the learned ones",
        ),
        Setting::new(
            "keep_start_every_s",
            Kind::Number,
            30.0,
            (0.0, true, f64::INFINITY),
            "how often the keep-start decision is made (one solve of the likelihood each), s",
        ),
        Setting::new(
            "keep_start_sensor_below",
            Kind::Number,
            0.1,
            (0.0, false, 1.0),
            "the share of posterior draws favouring the learned sensor model below which the \
             start's is reported (0: never; the action model's is 0.5)",
        ),
        Setting::new(
            "posterior",
            Kind::Count,
            1.0,
            (0.0, false, 1.0),
            "1: say how sure it is (when a host asks, at a trial's end: the Laplace \
             approximation of batch-ml-lag's likelihood of every event seen, one solve); \
             0: no posterior (learning is the same either way)",
        ),
    ]
}

/// A variant with `config`, checked as its own settings say.
fn build_checked(
    config: ScasmConfig,
    c: &BuildContext,
) -> Result<BoxedLearner, std::string::String> {
    let check = (c.own.count("self_check") == 1).then(|| SelfCheck {
        good_after_s: c.own.get("good_after_s"),
    });
    let learner = scasm(config, c.mode, check)?;
    Ok(
        if c.own.count("posterior") == 1 && c.mode == Mode::Simultaneous {
            let keep = (c.own.count("keep_start") == 1).then(|| KeepStart {
                every_s: c.own.get("keep_start_every_s"),
                sensor_below: c.own.get("keep_start_sensor_below"),
            });
            Box::new(Believed::new(learner, keep))
        } else {
            Box::new(learner)
        },
    )
}

/// The paper's algorithm exactly.
pub const SCASM_PAPER: Declaration = Declaration {
    name: "scasm-paper",
    about: "SCASM exactly as the paper has it: every reading its own point of the sensor fit",
    shared: &COMMON,
    settings: Vec::new,
    one_sided: true,
    build: |c: &BuildContext| {
        let config = ScasmConfig {
            sensor_window: 1,
            action_prior: 0.0,
            action_highpass_s: 0.0,
            action_robust: 0.0,
            ..c.shared
        };
        Ok(Box::new(scasm(config, c.mode, None)?))
    },
};

/// SCASM with the sensor fit's readings averaged in windows.
pub const SCASM: Declaration = Declaration {
    name: "scasm",
    about: "SCASM with the sensor fit's readings averaged in windows (learner.sensor_window, \
            5), falling back to its last good models while a model is not monotone; says how \
            sure it is (batch-ml-lag's posterior) and keeps its start's models where that \
            posterior does not favour the learned ones",
    shared: &[
        "gamma",
        "beta",
        "t_start",
        "sensor_degree",
        "action_degree",
        "sensor_window",
        "action_prior",
        "action_highpass",
        "action_robust",
    ],
    settings: checked_settings,
    one_sided: true,
    build: |c: &BuildContext| build_checked(c.shared, c),
};

/// SCASM whose sensor fit corrects for the reading noise.
pub const SCASM_EIV: Declaration = Declaration {
    name: "scasm-eiv",
    about: "SCASM whose sensor fit corrects for the reading noise, estimated from the \
            readings (no errors-in-variables bias), with scasm's self-check",
    shared: SCASM.shared,
    settings: checked_settings,
    one_sided: true,
    build: |c: &BuildContext| {
        build_checked(
            ScasmConfig {
                sensor_fit: SensorFit::Corrected,
                ..c.shared
            },
            c,
        )
    },
};
