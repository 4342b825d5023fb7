//! The one run pipeline every run kind uses: a scenario's trial is recorded
//! (its world, [`crate::world`], with the training behaviour's thresholds from the measured
//! sensor model), then any learner runs over the recording and is judged
//! against the measured models; many seeds run in parallel.

use quadsim::SimConfig;
use rayon::prelude::*;

use crate::behaviour::BehaviourConfig;
use crate::learners;
use crate::metrics;
use crate::reference::MeasuredModels;
use crate::scenario::Scenario;
use crate::trial::{self, Recording, TrialConfig, TrialError, TrialOutcome};
use crate::world::{self, World};

/// Where the behaviour turns round, relative to the ends of the test range, m:
/// at the reading expected this far inside the near end (the robot needs about
/// 0.1 m to stop and turn) and this far beyond the far end (a median of noisy
/// small readings turns it a little early). Chosen on the development seeds
/// 100-107 so that the robot roams the test range and no more: on average it
/// turns at 1.19 m and 3.66 m. A learned cubic is judged over the test range,
/// and one fitted over a wider range (the earlier 0.95-3.7 m) fits the test
/// range worse, whatever the learner.
pub const TURN_NEAR_INSIDE_M: f64 = 0.08;
/// See [`TURN_NEAR_INSIDE_M`].
pub const TURN_FAR_BEYOND_M: f64 = 0.05;

/// The behaviour's thresholds from the measured sensor model: turn round at the
/// readings expected at [`TURN_NEAR_INSIDE_M`] inside the nearest and
/// [`TURN_FAR_BEYOND_M`] beyond the farthest test distance, from the pinhole law
/// `d = a + b / obs` fitted to the measured points (or at the end points' own
/// readings if that fit fails).
pub fn behaviour_for(scenario: &Scenario, models: &MeasuredModels) -> BehaviourConfig {
    let length = scenario.scale().length;
    let end = |i: usize| {
        models
            .sensor
            .get(i)
            .map_or((f64::NAN, f64::NAN), |s| (s.distance_mm, s.obs_px))
    };
    let (near, far) = (end(0), end(models.sensor.len().saturating_sub(1)));
    let inverse: Vec<(f64, f64)> = models
        .sensor
        .iter()
        .map(|s| (1.0 / s.obs_px, s.distance_mm))
        .collect();
    let (near_obs_px, far_obs_px) = match metrics::best_polynomial(&inverse, 1) {
        Some(p) if p.coeffs()[1] > 0.0 => {
            let (a, b) = (p.coeffs()[0], p.coeffs()[1]);
            let obs_at = |d_mm: f64| b / (d_mm - a);
            (
                obs_at(near.0 + 1000.0 * TURN_NEAR_INSIDE_M * length),
                obs_at(far.0 + 1000.0 * TURN_FAR_BEYOND_M * length),
            )
        }
        _ => (near.1, far.1),
    };
    BehaviourConfig {
        name: scenario.behaviour_name,
        action_degree: scenario.learner.action_degree,
        design_extra_degree: scenario.behaviour_design_extra_degree,
        max_command: scenario.max_command(),
        hold_s: 3.0,
        near_obs_px,
        far_obs_px,
        turn_median_of: crate::behaviour::TURN_MEDIAN_OF,
    }
}

/// How often the learned models are judged during a trial (Fig. 8), s.
pub const JUDGE_EVERY_S: f64 = 5.0;

/// The trial settings of `scenario` from `seed`.
pub fn trial_config(
    scenario: &Scenario,
    models: &MeasuredModels,
    seed: u64,
) -> Result<TrialConfig, TrialError> {
    Ok(TrialConfig {
        duration_s: scenario.duration_s,
        seed,
        behaviour: behaviour_for(scenario, models),
        judge_every_s: JUDGE_EVERY_S,
        blank: scenario.blank,
        changes: scenario.worlds()?.split_off(1),
    })
}

/// The world of `scenario` for a trial of `config` (its seed and its changes
/// of the world), with the world's settings `sim`: the scenario's, or a
/// demonstration's own start.
pub fn world_for(
    scenario: &Scenario,
    sim: SimConfig,
    config: &TrialConfig,
) -> Result<Box<dyn World>, TrialError> {
    Ok(world::build(
        scenario.world,
        &scenario.description,
        sim,
        scenario.scale(),
        config.seed,
        config.changes.clone(),
    )?)
}

/// Records one trial of `scenario` from `seed`: the world only, or, for a
/// behaviour that steers by the learner's models, with the scenario's
/// learner in the loop ([`record_for`]).
pub fn record(
    scenario: &Scenario,
    models: &MeasuredModels,
    seed: u64,
) -> Result<Recording, TrialError> {
    record_for(scenario, models, seed, &scenario.learner_name)
}

/// Whether `scenario`'s behaviour steers by the learner's models
/// ([`crate::behaviour::Declaration::steered`]).
pub fn steered(scenario: &Scenario) -> bool {
    crate::behaviour::resolve(scenario.behaviour_name).is_ok_and(|d| d.steered)
}

/// [`record`] for a run of `learner`: a behaviour that steers by the
/// learner's models sees one of its own, built as the run's will be
/// ([`trial::record_steered`]); any other records the world alone.
pub fn record_for(
    scenario: &Scenario,
    models: &MeasuredModels,
    seed: u64,
    learner: &str,
) -> Result<Recording, TrialError> {
    record_kept(scenario, models, seed, learner).recording
}

/// A recording, or why it could not be made, and what the learner program
/// that steered it (if one did) wrote to its stderr.
#[derive(Debug)]
pub struct RecordRun {
    /// The recording, or why it could not be made.
    pub recording: Result<Recording, TrialError>,
    /// The steering twin's whole stderr, if it was a learner program.
    pub stderr: Option<String>,
}

/// [`record_for`], keeping what a steering learner program wrote to its
/// stderr, so that a trial it failed keeps it.
pub fn record_kept(
    scenario: &Scenario,
    models: &MeasuredModels,
    seed: u64,
    learner: &str,
) -> RecordRun {
    let mut twin = None;
    let recording = record_steering(scenario, models, seed, learner, &mut twin);
    RecordRun {
        recording,
        stderr: twin.and_then(learners::Built::end),
    }
}

/// [`record_for`], leaving the steering twin (if any) in `twin`.
fn record_steering(
    scenario: &Scenario,
    models: &MeasuredModels,
    seed: u64,
    learner: &str,
    twin: &mut Option<learners::Built>,
) -> Result<Recording, TrialError> {
    let config = trial_config(scenario, models, seed)?;
    let world = world_for(scenario, scenario.sim, &config)?;
    *twin = steering_twin(scenario, models, learner)?;
    match twin {
        Some(built) => trial::record_steered(world, config, built.learner.as_mut()),
        None => trial::record_in(world, config),
    }
}

/// The twin of `learner` that a behaviour steering by the learner's models
/// consults while the robot walks (built as the run's own will be), or
/// `None` if `scenario`'s behaviour does not steer.
pub fn steering_twin(
    scenario: &Scenario,
    models: &MeasuredModels,
    learner: &str,
) -> Result<Option<learners::Built>, TrialError> {
    if !steered(scenario) {
        return Ok(None);
    }
    learners::build_kept(learner, scenario, &models.reference())
        .map(Some)
        .map_err(TrialError::LearnerSetup)
}

/// Runs learner `name` (set up for `scenario`) over a recording, judged
/// against `models` every [`JUDGE_EVERY_S`].
pub fn learn(
    scenario: &Scenario,
    models: &MeasuredModels,
    recording: &Recording,
    name: &str,
) -> Result<TrialOutcome, TrialError> {
    learn_every(scenario, models, recording, name, JUDGE_EVERY_S)
}

/// [`learn`], judging the models every `judge_every_s` (the learner's run
/// does not depend on it).
pub fn learn_every(
    scenario: &Scenario,
    models: &MeasuredModels,
    recording: &Recording,
    name: &str,
    judge_every_s: f64,
) -> Result<TrialOutcome, TrialError> {
    learn_kept(scenario, models, recording, name, judge_every_s).outcome
}

/// A learner's run over a recording, and what it wrote beside its models.
#[derive(Debug)]
pub struct LearnerRun {
    /// The run judged, or why it failed.
    pub outcome: Result<TrialOutcome, TrialError>,
    /// A learner program's whole stderr (`None` for a Rust learner).
    pub stderr: Option<String>,
}

/// [`learn_every`], keeping what a learner program wrote to its stderr.
pub fn learn_kept(
    scenario: &Scenario,
    models: &MeasuredModels,
    recording: &Recording,
    name: &str,
    judge_every_s: f64,
) -> LearnerRun {
    let reference = models.reference();
    let mut built = match learners::build_kept(name, scenario, &reference) {
        Ok(b) => b,
        Err(e) => {
            return LearnerRun {
                outcome: Err(TrialError::LearnerSetup(e)),
                stderr: None,
            };
        }
    };
    let outcome = learn_built(
        scenario,
        recording,
        built.learner.as_mut(),
        &reference,
        judge_every_s,
    );
    LearnerRun {
        outcome,
        stderr: built.end(),
    }
}

fn learn_built(
    scenario: &Scenario,
    recording: &Recording,
    learner: &mut dyn scasm::CalibrationLearner,
    reference: &crate::reference::Reference,
    judge_every_s: f64,
) -> Result<TrialOutcome, TrialError> {
    // The localisation baseline: S learned from the identity action model A0
    // (the paper's section IV), with the scenario's learner settings.
    let params = scenario
        .learner
        .validate()
        .map_err(|e| TrialError::LearnerSetup(e.to_string()))?;
    let mut a0_baseline = scasm::Scasm::new(
        params,
        scasm::Mode::SensorFromAction(scasm::Polynomial::identity()),
    )
    .map_err(|e| TrialError::LearnerSetup(e.to_string()))?;
    trial::learn(
        recording,
        learner,
        trial::Comparators {
            a0_baseline: Some(&mut a0_baseline),
            best_degrees: Some((
                scenario.learner.action_degree,
                scenario.learner.sensor_degree,
            )),
        },
        reference,
        judge_every_s,
    )
}

/// A recorded trial and the scenario's learner's run over it.
pub type RecordedTrial = (Recording, TrialOutcome);

/// A recorded trial and its learner's run, or why it could not run.
pub type TrialResult = Result<RecordedTrial, TrialError>;

/// Records one trial of `scenario` from `seed` and runs the scenario's learner
/// over it.
pub fn run_one(scenario: &Scenario, models: &MeasuredModels, seed: u64) -> TrialResult {
    let recording = record(scenario, models, seed)?;
    let outcome = learn(scenario, models, &recording, &scenario.learner_name)?;
    Ok((recording, outcome))
}

/// One trial as it ended, for whoever keeps its files: the recording (if the
/// world could be recorded), the learner's outcome or why it failed, and a
/// learner program's stderr.
#[derive(Debug, Clone, Copy)]
pub struct TrialRecord<'a> {
    /// The trial's seed.
    pub seed: u64,
    /// The recorded world, if it could be recorded.
    pub recording: Option<&'a Recording>,
    /// The learner's run judged, or why the trial failed.
    pub outcome: Result<&'a TrialOutcome, &'a TrialError>,
    /// A learner program's whole stderr.
    pub stderr: Option<&'a str>,
}

/// Runs one trial per seed in parallel, calling `done` as each finishes
/// (with its recording and its learner's stderr, kept also when the learner
/// failed). A trial that cannot run does not stop the others: its error is
/// its result.
pub fn run_trials(
    scenario: &Scenario,
    models: &MeasuredModels,
    seeds: &[u64],
    done: &(dyn Fn(&TrialRecord<'_>) + Sync),
) -> Vec<(u64, TrialResult)> {
    seeds
        .par_iter()
        .map(|&seed| {
            let made = record_kept(scenario, models, seed, &scenario.learner_name);
            let recording = match made.recording {
                Ok(r) => r,
                Err(e) => {
                    done(&TrialRecord {
                        seed,
                        recording: None,
                        outcome: Err(&e),
                        stderr: made.stderr.as_deref(),
                    });
                    return (seed, Err(e));
                }
            };
            let run = learn_kept(
                scenario,
                models,
                &recording,
                &scenario.learner_name,
                JUDGE_EVERY_S,
            );
            done(&TrialRecord {
                seed,
                recording: Some(&recording),
                outcome: run.outcome.as_ref(),
                stderr: run.stderr.as_deref(),
            });
            (seed, run.outcome.map(|o| (recording, o)))
        })
        .collect()
}

/// One learner's trial in a batch of runs.
#[derive(Debug, Clone, Copy)]
pub struct Job<'a> {
    /// The scenario (world and learner settings).
    pub scenario: &'a Scenario,
    /// Its measured reference.
    pub models: &'a MeasuredModels,
    /// The trial's seed.
    pub seed: u64,
    /// The learner's name.
    pub learner: &'a str,
}

/// What a recording depends on: the robot, world and camera (the reference
/// key), the behaviour (its thresholds set from the reference; which one it
/// is and what it reads, [`crate::behaviour::Declaration::key`]), the
/// trial's length, its blanked intervals, its changes of the world, and its
/// seed. Jobs with the same key can share one recording, whatever their
/// learners, unless the behaviour steers by the learner's models: see
/// [`world_key_for`].
pub fn world_key(scenario: &Scenario, seed: u64) -> String {
    world_key_for(scenario, seed, &scenario.learner_name)
}

/// [`world_key`] for a run of `learner`: with a behaviour that steers by
/// the learner's models, the learner and its settings are part of the key.
pub fn world_key_for(scenario: &Scenario, seed: u64, learner: &str) -> String {
    let steering = if steered(scenario) {
        let own = learners::resolve(learner)
            .map_or_else(|e| e, |l| format!("{:?}", scenario.own_settings(&l)));
        format!("/{learner}:{:?}:{own}", scenario.learner)
    } else {
        String::new()
    };
    let behaviour = crate::behaviour::resolve(scenario.behaviour_name).map_or_else(
        |e| e,
        |d| {
            (d.key)(&BehaviourConfig {
                name: scenario.behaviour_name,
                action_degree: scenario.learner.action_degree,
                design_extra_degree: scenario.behaviour_design_extra_degree,
                ..BehaviourConfig::paper(0.0, 0.0, 0.0)
            })
        },
    );
    format!(
        "{}/{behaviour}{steering}/{}/{}/{}/{seed}",
        scenario.reference_key(),
        scenario.duration_s,
        scenario.blank.to_text(),
        scenario.changes_text()
    )
}

/// Runs every job, recording each distinct world once (see [`world_key`]) and
/// feeding it to every learner that shares it; worlds and learners run in
/// parallel. `done(index of the job, its result)` is called as each finishes.
pub fn run_jobs(
    jobs: &[Job<'_>],
    done: &(dyn Fn(usize, &Result<TrialOutcome, TrialError>) + Sync),
) {
    let mut worlds: std::collections::BTreeMap<String, Vec<usize>> = Default::default();
    for (i, job) in jobs.iter().enumerate() {
        worlds
            .entry(world_key_for(job.scenario, job.seed, job.learner))
            .or_default()
            .push(i);
    }
    worlds.into_values().par_bridge().for_each(|members| {
        let first = &jobs[members[0]];
        match record_for(first.scenario, first.models, first.seed, first.learner) {
            Ok(recording) => members.par_iter().for_each(|&i| {
                let job = &jobs[i];
                done(i, &learn(job.scenario, job.models, &recording, job.learner));
            }),
            Err(e) => {
                let message = e.to_string();
                for &i in &members {
                    done(i, &Err(TrialError::Recording(message.clone())));
                }
            }
        }
    });
}
