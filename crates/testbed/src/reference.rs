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
use crate::scenario::{Scenario, SettingError};
use crate::world::WorldKind;
use crate::world::synthetic::SyntheticConfig;

/// Readings per distance in the stand-and-read protocol (the paper's 100).
pub const MEASURE_READINGS: usize = 100;

/// Bumped whenever a protocol or the physics changes in a way the settings do
/// not show, so that cached references measured the old way are measured again
/// (3: the patched rapier3d's mass matrix; 4: the camera's own link hides
/// nothing, and a scaled robot's cadence is found by the walk test; 5: nor
/// does any link rigidly fixed to it).
const PROTOCOL_VERSION: u32 = 6;

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
    // The robot as loaded (mass folded across fixed joints, say): a change
    // in how a URDF is read is a change of robot.
    format!("{:?}", scenario.description.urdf).hash(&mut h);
    if let Some((_, robot_text)) = &scenario.robot_file {
        robot_text.hash(&mut h);
    }
    format!("{:?}", scenario.sim).hash(&mut h);
    // The robot in rapier, the default, keeps the keys it had before the
    // world was a setting.
    if scenario.world != WorldKind::Rapier {
        scenario.world.name().hash(&mut h);
    }
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
    /// The robot fell while the stopwatch timed a command: a fallen robot's
    /// speed is no reference.
    #[error(
        "the robot fell while the stopwatch timed command {command:.1} ({world}), so no reference \
         can be measured: the robot must stay upright at every paper command. See which commands \
         it walks with `cargo run --release --example measure_action -- --robot ...`; a robot \
         file's [gait] may steady it (README, \"Bring your own robot\")"
    )]
    Fell {
        /// The command it fell at.
        command: f64,
        /// Which world: "the scenario's world", or after which change.
        world: String,
    },
    /// The physics blew up while the stopwatch timed a command (see
    /// [`quadsim::QuadrupedSim::blew_up_at_s`]): the solver, not the robot,
    /// threw it about.
    #[error(
        "the physics blew up while the stopwatch timed command {command:.1} ({world}): the robot's \
         kinetic energy passed {factor} times that of its fall from its own height, which no walk \
         or fall gives, so no reference can be measured. More solver iterations \
         (`physics.solver_iterations`, e.g. 4) or a shorter physics step (`physics.dt`) may \
         cure it (README, \"Robots by other makers\")",
        factor = quadsim::BLOW_UP_ENERGY
    )]
    BlewUp {
        /// The command it blew up at.
        command: f64,
        /// Which world: "the scenario's world", or after which change.
        world: String,
    },
    /// The camera never saw the beacon at one of the stand-and-read
    /// distances: there is no reading to label.
    #[error(
        "the camera saw no beacon standing at {distance_mm:.0} mm ({world}; {missed} frames, none \
         with a reading), so the sensor model cannot be measured. A link of the robot may hide the \
         beacon from the camera found for it: place the camera with a robot file's [camera] table \
         (README, \"Bring your own robot\")"
    )]
    Unseen {
        /// The distance the robot was put at, mm.
        distance_mm: f64,
        /// Frames taken there, every one without a reading.
        missed: usize,
        /// Which world: "the scenario's world", or after which change.
        world: String,
    },
}

/// The reference measured for `world` (named in errors), refused if a row of
/// it is not a measurement: the robot fell while it was timed, or the camera
/// never saw the beacon at a distance.
fn check_measured(models: &MeasuredModels, world: &str) -> Result<(), MeasureError> {
    if let Some(m) = models.action.iter().find(|m| m.blew_up) {
        return Err(MeasureError::BlewUp {
            command: m.command,
            world: world.to_string(),
        });
    }
    if let Some(m) = models.action.iter().find(|m| !m.upright) {
        return Err(MeasureError::Fell {
            command: m.command,
            world: world.to_string(),
        });
    }
    if let Some(r) = models.sensor.iter().find(|r| !r.obs_px.is_finite()) {
        return Err(MeasureError::Unseen {
            distance_mm: r.nominal_mm,
            missed: r.missed,
            world: world.to_string(),
        });
    }
    Ok(())
}

/// Measures the reference models of `scenario` (and of its world after each
/// scheduled change), or reads them from `cache_dir` if they were measured
/// before for the same robot, world and protocols. Refused, with what to do,
/// if the robot fell while it was timed or its camera never saw the beacon at
/// a distance ([`MeasureError::Fell`], [`MeasureError::Unseen`]).
pub fn measured_models(
    scenario: &Scenario,
    cache_dir: Option<&Path>,
) -> Result<MeasuredModels, MeasureError> {
    if scenario.world == WorldKind::Synthetic && !scenario.changes.is_empty() {
        return Err(MeasureError::Setting(SettingError::BadValue {
            key: "trial.world".into(),
            reason: "the synthetic world cannot change during a trial (a point robot has no \
                     friction, payload or gait to change): remove the scenario's [[change]]s"
                .into(),
        }));
    }
    let mut models = measured_world(&scenario.world(0)?, cache_dir)?;
    check_measured(&models, "the scenario's world")?;
    for (i, change) in scenario.changes.iter().enumerate() {
        let after = measured_world(&scenario.world(i + 1)?, cache_dir)?;
        check_measured(
            &after,
            &format!("the world after its change at {} s", change.at_s),
        )?;
        models.from_cache &= after.from_cache;
        models.changes.push(ChangedModels {
            at_s: change.at_s,
            models: after,
        });
    }
    Ok(models)
}

/// The models of one world (`scenario` with no changes: see [`Scenario::world`]),
/// measured or from the cache, as the protocols gave them: not checked, so
/// that a tool can show what a robot that fell or a camera that saw nothing
/// measured. Judging uses [`measured_models`], which refuses them.
pub fn measured_world(
    scenario: &Scenario,
    cache_dir: Option<&Path>,
) -> Result<MeasuredModels, SimError> {
    if scenario.world == WorldKind::Synthetic {
        return Ok(synthetic_models(scenario));
    }
    let key = key(scenario);
    let path = cache_dir.map(|d| d.join(format!("reference-{key}.json")));
    if let Some(p) = &path {
        let cached = quadsim::files::read_text(p, quadsim::files::SETTINGS_LIMIT)
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

/// The synthetic world's models at the paper's commands and distances (at
/// the robot's scale), as the protocols would measure them with no noise:
/// its truth, known exactly.
fn synthetic_models(scenario: &Scenario) -> MeasuredModels {
    let world = SyntheticConfig::of(scenario.sim, scenario.scale());
    let action = scenario
        .scale()
        .paper_commands()
        .into_iter()
        .map(|command| {
            let v = world.velocity_mm_s(command);
            MeasuredVelocity {
                command,
                velocity_mm_s: v,
                std_mm_s: 0.0,
                timings_mm_s: vec![v],
                upright: true,
                blew_up: false,
            }
        })
        .collect();
    let sensor = measure::paper_distances_m(scenario.scale())
        .into_iter()
        .map(|d_m| MeasuredReading {
            nominal_mm: 1000.0 * d_m,
            distance_mm: 1000.0 * d_m,
            distance_std_mm: 0.0,
            obs_px: world.obs_px(1000.0 * d_m),
            std_px: 0.0,
            missed: 0,
        })
        .collect();
    MeasuredModels {
        action,
        sensor,
        from_cache: false,
        changes: Vec::new(),
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A reference as the protocols would give it: every command timed
    /// upright, every distance read.
    fn measured() -> MeasuredModels {
        let action = (-15..=15)
            .map(|k| {
                let command = 35.0 * f64::from(k);
                MeasuredVelocity {
                    command,
                    velocity_mm_s: 0.8 * command,
                    std_mm_s: 1.0,
                    timings_mm_s: vec![0.8 * command; 5],
                    upright: true,
                    blew_up: false,
                }
            })
            .collect();
        let sensor = (0..13)
            .map(|k| {
                let d = 1200.0 + 200.0 * f64::from(k);
                MeasuredReading {
                    nominal_mm: d,
                    distance_mm: d,
                    distance_std_mm: 1.0,
                    obs_px: 60_000.0 / d,
                    std_px: 0.1,
                    missed: 0,
                }
            })
            .collect();
        MeasuredModels {
            action,
            sensor,
            from_cache: false,
            changes: Vec::new(),
        }
    }

    #[test]
    fn a_fallen_timing_or_an_unseen_beacon_is_no_reference() {
        assert!(check_measured(&measured(), "w").is_ok());

        let mut fell = measured();
        fell.action[3].upright = false;
        let err = check_measured(&fell, "w").expect_err("a fallen timing");
        assert!(
            matches!(&err, MeasureError::Fell { command, .. } if *command == -420.0),
            "{err}"
        );
        assert!(err.to_string().contains("measure_action"), "{err}");

        // A blow-up usually throws the robot over too: it is named as what it is.
        let mut blew_up = measured();
        blew_up.action[5].upright = false;
        blew_up.action[5].blew_up = true;
        let err = check_measured(&blew_up, "w").expect_err("a blown-up timing");
        assert!(
            matches!(&err, MeasureError::BlewUp { command, .. } if *command == -350.0),
            "{err}"
        );
        assert!(
            err.to_string().contains("physics.solver_iterations"),
            "{err}"
        );

        let mut unseen = measured();
        unseen.sensor[12].obs_px = f64::NAN;
        unseen.sensor[12].distance_mm = f64::NAN;
        unseen.sensor[12].missed = 400;
        let err = check_measured(&unseen, "w").expect_err("an unseen beacon");
        assert!(
            matches!(&err, MeasureError::Unseen { distance_mm, missed: 400, .. } if *distance_mm == 3600.0),
            "{err}"
        );
        assert!(err.to_string().contains("[camera]"), "{err}");
    }

    #[test]
    fn a_cached_reference_with_a_fallen_timing_is_refused() {
        // Written as an older build would have cached it: measured_models must
        // refuse it, not judge learners against a fallen robot's speed.
        let scenario = Scenario::paper().expect("scenario");
        let dir = std::env::temp_dir().join(format!("scasm-fallen-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let mut models = measured();
        models.action[0].upright = false;
        let key = key(&scenario);
        let cached = CachedReference {
            key: key.clone(),
            models,
        };
        std::fs::write(
            dir.join(format!("reference-{key}.json")),
            serde_json::to_string(&cached).expect("json"),
        )
        .expect("write");
        let got = measured_models(&scenario, Some(&dir));
        let _ = std::fs::remove_dir_all(&dir);
        assert!(
            matches!(got, Err(MeasureError::Fell { command, .. }) if command == -525.0),
            "{got:?}"
        );
    }
}
