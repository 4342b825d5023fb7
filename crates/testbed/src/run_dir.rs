//! A run's directory as `train` and `replay` write it: the measured models
//! (and those of each changed world), each trial's dataset and learner run,
//! and the section IV and V demonstrations.

use std::path::Path;

use crate::dataset::{self, DatasetMeta};
use crate::demos::Demos;
use crate::experiment::RecordedTrial;
use crate::output;
use crate::provenance::Provenance;
use crate::reference::MeasuredModels;
use crate::scenario::Scenario;

/// The measured models: `measured_action.csv` and `measured_sensor.csv` in
/// `out`, and in `out/world-<i>/` those of the world after change `i`.
pub fn write_reference(out: &Path, models: &MeasuredModels) -> std::io::Result<()> {
    output::write_measured_action(out, &models.action)?;
    output::write_measured_sensor(out, &models.sensor)?;
    for (i, changed) in models.changes.iter().enumerate() {
        let dir = out.join(format!("world-{}", i + 1));
        std::fs::create_dir_all(&dir)?;
        output::write_measured_action(&dir, &changed.models.action)?;
        output::write_measured_sensor(&dir, &changed.models.sensor)?;
    }
    Ok(())
}

/// A trial's directory, `out/trial-<seed>/`: its dataset (the recorded
/// world, replayable) and its learner's trace, errors over time and models.
pub fn write_trial(
    out: &Path,
    scenario: &Scenario,
    models: &MeasuredModels,
    made_by: &Provenance,
    (recording, outcome): &RecordedTrial,
) -> std::io::Result<()> {
    let dir = out.join(format!("trial-{}", recording.seed));
    dataset::write(
        &dir,
        recording,
        &DatasetMeta::new(scenario, models, recording, made_by),
    )?;
    output::write_learner_run(&dir, outcome)
}

/// The demonstrations' traces and models, in `out/demos/`.
pub fn write_demos(out: &Path, demos: &Demos) -> std::io::Result<()> {
    let dir = out.join("demos");
    std::fs::create_dir_all(&dir)?;
    for (name, run) in [
        ("constant_walk", &demos.constant_walk),
        ("sensor_from_a0", &demos.sensor_from_a0),
        ("action_from_rough_sensor", &demos.action_from_rough_sensor),
    ] {
        output::write_trace(&dir.join(format!("{name}.csv")), &run.trace)?;
        output::write_models(&dir.join(format!("{name}.json")), run.action, run.sensor)?;
    }
    Ok(())
}
