//! The learners a run can name (`--learner NAME`, `learner.name`): each a
//! [`CalibrationLearner`] from the physics-free `scasm` crate, built from a
//! scenario's learner settings. Every run kind (train, replay, benchmark,
//! sweep, view) builds its learners here.

use scasm::{
    BatchMl, BatchMlConfig, CalibrationLearner, Mode, Polynomial, Scasm, ScasmConfig, SensorFit,
};

pub mod registry;

use crate::metrics;
use crate::reference::Reference;
use crate::scenario::{LearningMode, Scenario};

pub use registry::{DEFAULT, LEARNERS, names};

/// A learner a host can own and send between threads.
pub type BoxedLearner = Box<dyn CalibrationLearner + Send>;

/// SCASM's settings for a named SCASM variant.
fn scasm_config(name: &str, scenario: &Scenario) -> Option<ScasmConfig> {
    let base = scenario.learner;
    match name {
        "scasm-paper" => Some(ScasmConfig {
            sensor_window: 1,
            ..base
        }),
        "scasm" => Some(base),
        "scasm-eiv" => Some(ScasmConfig {
            sensor_fit: SensorFit::Corrected,
            ..base
        }),
        _ => None,
    }
}

/// The batch learner's settings for a scenario.
fn batch_config(scenario: &Scenario) -> BatchMlConfig {
    BatchMlConfig {
        online: ScasmConfig {
            sensor_fit: SensorFit::Corrected,
            ..scenario.learner
        },
        ..BatchMlConfig::default()
    }
}

/// The learner `name` for `scenario`. In the one-sided modes (sections IV and
/// V) the given model is the best polynomial through the measured one, in mm
/// (location is distance, so the action model is minus the forward speed); only
/// the SCASM variants learn in those modes.
pub fn build(
    name: &str,
    scenario: &Scenario,
    reference: &Reference,
) -> Result<BoxedLearner, String> {
    if name == "batch-ml" {
        if scenario.mode != LearningMode::Simultaneous {
            return Err(
                "batch-ml learns both models at once only (trial.mode simultaneous)".into(),
            );
        }
        let params = batch_config(scenario)
            .validate()
            .map_err(|e| e.to_string())?;
        return Ok(Box::new(BatchMl::new(params)));
    }
    let config = scasm_config(name, scenario).ok_or_else(|| {
        format!(
            "unknown learner `{name}`; known: {}",
            names().collect::<Vec<_>>().join(", ")
        )
    })?;
    let params = config.validate().map_err(|e| e.to_string())?;
    let mode = match scenario.mode {
        LearningMode::Simultaneous => Mode::Simultaneous,
        LearningMode::SensorFromAction => {
            let a = metrics::best_polynomial(&reference.action, config.action_degree)
                .ok_or("cannot fit the measured action model")?;
            let minus: Vec<f64> = a.coeffs().iter().map(|c| -c).collect();
            Mode::SensorFromAction(Polynomial::new(&minus).ok_or("bad action model")?)
        }
        LearningMode::ActionFromSensor => {
            let pts: Vec<(f64, f64)> = reference.sensor.iter().map(|&(d, o)| (o, d)).collect();
            Mode::ActionFromSensor(
                metrics::best_polynomial(&pts, config.sensor_degree)
                    .ok_or("cannot fit the measured sensor model")?,
            )
        }
    };
    Ok(Box::new(
        Scasm::new(params, mode).map_err(|e| e.to_string())?,
    ))
}

/// The effective parameters of learner `name` in `scenario`, for a run's record.
pub fn parameters(name: &str, scenario: &Scenario) -> serde_json::Value {
    match (name, scasm_config(name, scenario)) {
        ("batch-ml", _) => serde_json::to_value(batch_config(scenario)).unwrap_or_default(),
        (_, Some(config)) => serde_json::to_value(config).unwrap_or_default(),
        _ => serde_json::Value::Null,
    }
}
