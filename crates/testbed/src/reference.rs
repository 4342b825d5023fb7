//! The yardstick: the robot's true models, measured by the paper's protocols
//! (section VII) and cached on disk, and the judging of learned models against
//! them. Every accuracy figure the testbed reports is measured against these.

use std::hash::{Hash, Hasher};
use std::path::Path;

use quadsim::SimError;
use scasm::{CalibrationLearner, Polynomial};
use serde::{Deserialize, Serialize};

use crate::measure::{self, MeasuredReading, MeasuredVelocity, StopwatchConfig};
use crate::metrics;
use crate::scenario::Scenario;

/// Readings per distance in the stand-and-read protocol (the paper's 100).
pub const MEASURE_READINGS: usize = 100;

/// Bumped whenever a protocol or the physics changes in a way the settings do
/// not show, so that cached references measured the old way are measured again
/// (3: the patched rapier3d's mass matrix; 4: the camera's own link hides
/// nothing, and a scaled robot's cadence is found by the walk test).
const PROTOCOL_VERSION: u32 = 4;

/// The measured models with their spreads, as the protocols give them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeasuredModels {
    /// The stopwatch protocol at the 31 commands.
    pub action: Vec<MeasuredVelocity>,
    /// The stand-and-read protocol at the 13 distances.
    pub sensor: Vec<MeasuredReading>,
    /// Whether they came from the cache.
    #[serde(skip)]
    pub from_cache: bool,
    /// If the world changes during a trial: the models of the world after
    /// each change, measured by the same protocols.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub changes: Vec<ChangedModels>,
}

/// The measured models of the world after a change during a trial.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChangedModels {
    /// When the change is made, s.
    pub at_s: f64,
    /// The models of the changed world.
    pub models: MeasuredModels,
}

impl MeasuredModels {
    /// The reference for judging (with the changed worlds' models, if any).
    pub fn reference(&self) -> Reference {
        Reference {
            action: self
                .action
                .iter()
                .map(|m| (m.command, m.velocity_mm_s))
                .collect(),
            sensor: self
                .sensor
                .iter()
                .map(|r| (r.distance_mm, r.obs_px))
                .collect(),
            changes: self
                .changes
                .iter()
                .map(|c| (c.at_s, c.models.reference()))
                .collect(),
        }
    }

    /// The models of the world as it ends (after its last change, if any).
    pub fn last(&self) -> &MeasuredModels {
        self.changes.last().map_or(self, |c| &c.models)
    }

    /// Fastest forwards minus fastest backwards velocity, mm/s.
    pub fn velocity_range_mm_s(&self) -> f64 {
        span(self.action.iter().map(|m| m.velocity_mm_s))
    }

    /// Farthest minus nearest measured distance, mm.
    pub fn distance_range_mm(&self) -> f64 {
        span(self.sensor.iter().map(|r| r.distance_mm))
    }

    /// The largest standard deviation of the five timings of any command, mm/s.
    pub fn worst_velocity_std_mm_s(&self) -> f64 {
        self.action.iter().map(|m| m.std_mm_s).fold(0.0, f64::max)
    }

    /// The largest standard deviation of the readings at any distance, px.
    pub fn worst_reading_std_px(&self) -> f64 {
        self.sensor.iter().map(|r| r.std_px).fold(0.0, f64::max)
    }

    /// One line saying how the reference was taken (with `stopwatch`) and how
    /// tight it is.
    pub fn describe(&self, stopwatch: &StopwatchConfig) -> String {
        let s = stopwatch;
        format!(
            "reference: stopwatch at {} commands, {} timings of {:.2} m each after {:.1} s of walking \
             (std <= {:.1} mm/s); {} readings standing at each of {} distances, labelled by the \
             distance actually held (std <= {:.2} px)",
            self.action.len(),
            s.repeats,
            s.distance_m,
            s.settle_s,
            self.worst_velocity_std_mm_s(),
            MEASURE_READINGS,
            self.sensor.len(),
            self.worst_reading_std_px(),
        )
    }
}

fn span(values: impl Iterator<Item = f64>) -> f64 {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    hi - lo
}

/// A key identifying what the measured reference of `scenario` depends on
/// (robot, world, controllers, camera and the protocols; not the learner).
pub fn key(scenario: &Scenario) -> String {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    scenario.urdf_text.hash(&mut h);
    if let Some((_, robot_text)) = &scenario.robot_file {
        robot_text.hash(&mut h);
    }
    format!("{:?}", scenario.sim).hash(&mut h);
    format!("{:?}", scenario.stopwatch()).hash(&mut h);
    MEASURE_READINGS.hash(&mut h);
    PROTOCOL_VERSION.hash(&mut h);
    format!("{:016x}", h.finish())
}

impl Scenario {
    /// A key identifying what the measured reference depends on (robot, world,
    /// controllers, camera and the protocols; not the learner): [`key`].
    pub fn reference_key(&self) -> String {
        key(self)
    }
}

/// The measured models as stored in the cache.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct CachedReference {
    key: String,
    models: MeasuredModels,
}

/// What could not be measured.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MeasureError {
    /// A world could not be built.
    #[error(transparent)]
    Sim(#[from] SimError),
    /// A scheduled change of the world cannot be made.
    #[error(transparent)]
    Setting(#[from] crate::scenario::SettingError),
}

/// Measures the reference models of `scenario` (and of its world after each
/// scheduled change), or reads them from `cache_dir` if they were measured
/// before for the same robot, world and protocols.
pub fn measured_models(
    scenario: &Scenario,
    cache_dir: Option<&Path>,
) -> Result<MeasuredModels, MeasureError> {
    let mut models = measured_world(&scenario.world(0)?, cache_dir)?;
    for (i, change) in scenario.changes.iter().enumerate() {
        let after = measured_world(&scenario.world(i + 1)?, cache_dir)?;
        models.from_cache &= after.from_cache;
        models.changes.push(ChangedModels {
            at_s: change.at_s,
            models: after,
        });
    }
    Ok(models)
}

/// The models of one world (no changes), measured or from the cache.
fn measured_world(
    scenario: &Scenario,
    cache_dir: Option<&Path>,
) -> Result<MeasuredModels, SimError> {
    let key = key(scenario);
    let path = cache_dir.map(|d| d.join(format!("reference-{key}.json")));
    if let Some(p) = &path {
        let cached = std::fs::read_to_string(p)
            .ok()
            .and_then(|text| serde_json::from_str::<CachedReference>(&text).ok());
        if let Some(c) = cached.filter(|c| c.key == key) {
            return Ok(MeasuredModels {
                from_cache: true,
                ..c.models
            });
        }
    }
    let scale = scenario.scale();
    let action = measure::measure_action(
        &scenario.description,
        scenario.sim,
        &scenario.stopwatch(),
        &scale.paper_commands(),
    )?;
    let sensor = measure::measure_sensor(
        &scenario.description,
        scenario.sim,
        &measure::paper_distances_m(scale),
        MEASURE_READINGS,
        measure::hold_command(&action),
    )?;
    let models = MeasuredModels {
        action,
        sensor,
        from_cache: false,
        changes: Vec::new(),
    };
    if let Some(p) = &path {
        // A cache that cannot be written costs only time, never the run.
        let cached = CachedReference {
            key,
            models: models.clone(),
        };
        if let Ok(text) = serde_json::to_string(&cached) {
            let _ = p.parent().map(std::fs::create_dir_all);
            let tmp = p.with_extension("json.tmp");
            if std::fs::write(&tmp, text).is_ok() {
                let _ = std::fs::rename(&tmp, p);
            }
        }
    }
    Ok(models)
}

/// The reference the learned models are judged against: the measured models.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    /// `(command, velocity mm/s)` by the stopwatch protocol.
    pub action: Vec<(f64, f64)>,
    /// `(distance mm, reading px)` by the stand-and-read protocol.
    pub sensor: Vec<(f64, f64)>,
    /// If the world changes during a trial: from when (s), the reference of
    /// the changed world (with no changes of its own).
    pub changes: Vec<(f64, Reference)>,
}

/// The learned models at one moment, and their errors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Judgement {
    /// When, s.
    pub t_s: f64,
    /// The learned action model judged, if there was one.
    pub action_model: Option<Polynomial>,
    /// The learned sensor model judged, if there was one.
    pub sensor_model: Option<Polynomial>,
    /// Action RMSE after the best scale, mm/s.
    pub action_rmse_mm_s: Option<f64>,
    /// Sensor RMSE after the best affine map, mm.
    pub sensor_rmse_mm: Option<f64>,
    /// `| |k / b| - 1 |`.
    pub consistency: Option<f64>,
}

impl Reference {
    /// The reference of the world as it is at `t_s`: a change made at `at_s`
    /// is in force for models judged after it (a judgement at `at_s` itself is
    /// of the world before).
    pub fn at(&self, t_s: f64) -> &Reference {
        self.changes
            .iter()
            .rev()
            .find(|(at_s, _)| *at_s < t_s)
            .map_or(self, |(_, r)| r)
    }

    /// Each world of the trial: from when (s; the first from minus
    /// infinity), and its reference.
    pub fn worlds(&self) -> impl Iterator<Item = (f64, &Reference)> {
        std::iter::once((f64::NEG_INFINITY, self))
            .chain(self.changes.iter().map(|(at_s, r)| (*at_s, r)))
    }

    /// The reference of the world as it ends.
    pub fn last(&self) -> &Reference {
        self.at(f64::INFINITY)
    }

    /// Judges a pair of models against the world as it is at `t_s`.
    pub fn judge_models(
        &self,
        t_s: f64,
        action: Option<Polynomial>,
        sensor: Option<Polynomial>,
    ) -> Judgement {
        let world = self.at(t_s);
        let a = action.map(|m| metrics::action_error(&m, &world.action));
        let s = sensor.map(|m| metrics::sensor_error(&m, &world.sensor));
        Judgement {
            t_s,
            action_model: action,
            sensor_model: sensor,
            action_rmse_mm_s: a.map(|e| e.rmse),
            sensor_rmse_mm: s.map(|e| e.rmse),
            consistency: a
                .zip(s)
                .map(|(a, s)| metrics::consistency(a.scale, s.scale)),
        }
    }

    /// Judges a learner's current models.
    pub fn judge(&self, t_s: f64, learner: &dyn CalibrationLearner) -> Judgement {
        self.judge_models(t_s, learner.action_model(), learner.sensor_model())
    }
}
