//! Rerun recordings of trials (the `rerun` feature): a finished trial is
//! simulated again for its scene, and every frame is checked against its
//! recording, bit for bit.
#![cfg(feature = "rerun")]

use report::rrd::{RrdError, TrialLog, log_trial};
use testbed::experiment;
use testbed::scenario::Scenario;

#[test]
fn a_trial_simulated_again_is_checked_frame_by_frame() {
    let mut scenario = Scenario::paper().expect("scenario");
    scenario.set("trial.duration=5").expect("duration");
    let cache = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("reference-cache");
    let models = testbed::reference::measured_models(&scenario, Some(&cache)).expect("models");
    let recording = experiment::record(&scenario, &models, 3).expect("record");
    let name = scenario.learner_name.clone();
    // Recorded afresh, then simulated again for the scene: the same frames
    // both times, and those of any other recording of the trial.
    let (mut log, storage) = TrialLog::memory(&models).expect("log");
    let (again, outcome) =
        log_trial(&mut log, &scenario, &models, 3, &name, None).expect("the trial");
    assert_eq!(again.frames, recording.frames);
    assert_eq!(outcome.trace.len(), recording.frames.len());
    log.finish().expect("flush");
    assert!(!storage.take().is_empty(), "nothing was recorded");
    // A recording that is not this trial's is caught at its first different
    // frame.
    let mut other = recording.clone();
    other.frames[40].command += 1.0;
    let (mut log, _) = TrialLog::memory(&models).expect("log");
    match log_trial(&mut log, &scenario, &models, 3, &name, Some(&other)) {
        Err(RrdError::NotReproduced { seed: 3, frame: 40 }) => {}
        other => panic!("expected frame 40 to differ, got {other:?}"),
    }
}
