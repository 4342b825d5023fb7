//! A run's directory as `train` and `replay` write it: the measured models
//! (and those of each changed world), each trial's dataset and learner run,
//! and the section IV and V demonstrations.

use std::path::Path;

use crate::dataset::{self, DatasetMeta};
use crate::demos::Demos;
use crate::experiment::TrialRecord;
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
/// world, replayable), kept whatever became of the learner, and its
/// learner's files ([`write_learner_files`]).
pub fn write_trial(
    out: &Path,
    scenario: &Scenario,
    models: &MeasuredModels,
    made_by: &Provenance,
    trial: &TrialRecord<'_>,
) -> std::io::Result<()> {
    let dir = out.join(format!("trial-{}", trial.seed));
    match trial.recording {
        Some(recording) => dataset::write(
            &dir,
            recording,
            &DatasetMeta::new(scenario, models, recording, made_by),
        )?,
        None => std::fs::create_dir_all(&dir)?,
    }
    write_learner_files(&dir, trial.outcome, trial.stderr)
}

/// A learner's files in a trial's folder `dir`: its trace, errors over time
/// and models if its trial ran to the end, or `failure.json` (the status,
/// and the frame and time of the failure where known) if it did not; and a
/// learner program's whole stderr, `learner_stderr.txt`.
pub fn write_learner_files(
    dir: &Path,
    outcome: Result<&crate::trial::TrialOutcome, &crate::trial::TrialError>,
    stderr: Option<&str>,
) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    match outcome {
        Ok(o) => output::write_learner_run(dir, o)?,
        Err(e) => {
            let at = e.at();
            output::write_json(
                &dir.join("failure.json"),
                &serde_json::json!({
                    "status": e.to_string(),
                    "reason": e.root().to_string(),
                    "frame": at.map(|(frame, _)| frame),
                    "t_s": at.map(|(_, t_s)| t_s),
                }),
            )?;
        }
    }
    if let Some(text) = stderr {
        output::write_atomic(&dir.join("learner_stderr.txt"), text.as_bytes())?;
    }
    Ok(())
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
