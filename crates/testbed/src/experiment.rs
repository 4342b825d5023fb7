//! The paper's experiment as a whole: a scenario (robot, world, learner settings),
//! the measured reference models (cached on disk), trials over many seeds in
//! parallel, and their summary beside the paper's figures.

use std::hash::{Hash, Hasher};
use std::path::Path;

use quadsim::{RobotDescription, SimConfig, SimError};
use rayon::prelude::*;
use scasm::{CalibrationLearner, Mode, Polynomial, Scasm, ScasmConfig};
use serde::{Deserialize, Serialize};

use crate::behaviour::BehaviourConfig;
use crate::measure::{self, StopwatchConfig};
use crate::metrics;
use crate::trial::{self, Reference, TrialConfig, TrialError, TrialOutcome};

/// A setting that could not be applied.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SettingError {
    /// `key=value` was not of that form.
    #[error("`{0}` is not of the form key=value")]
    Malformed(String),
    /// No such setting.
    #[error("unknown setting `{key}`; known: {known}")]
    UnknownKey {
        /// The key given.
        key: String,
        /// The keys there are.
        known: String,
    },
    /// The value does not parse or is out of range.
    #[error("bad value for `{key}`: {reason}")]
    BadValue {
        /// The key.
        key: String,
        /// What is wrong.
        reason: String,
    },
    /// A scenario or robot file cannot be read or used.
    #[error("{file}: {reason}")]
    File {
        /// The file.
        file: String,
        /// What is wrong.
        reason: String,
    },
}

/// What is learned from what (the paper's sections IV, V and VI).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LearningMode {
    /// Both models at once (section VI): the paper's experiment.
    Simultaneous,
    /// S from the measured action model, by dead reckoning (section IV).
    SensorFromAction,
    /// A from the measured sensor model (section V).
    ActionFromSensor,
}

/// Everything a trial depends on besides its seed.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// The robot.
    pub description: RobotDescription,
    /// The URDF's text (part of the reference cache's key).
    pub urdf_text: String,
    /// The world, robot controllers and camera.
    pub sim: SimConfig,
    /// The learner's hyper-parameters.
    pub learner: ScasmConfig,
    /// What is learned from what.
    pub mode: LearningMode,
    /// Trial length, s.
    pub duration_s: f64,
}

/// The settings `--set` understands.
pub const SETTING_KEYS: [&str; 18] = [
    "learner.gamma",
    "learner.beta",
    "learner.t_start",
    "learner.sensor_degree",
    "learner.action_degree",
    "learner.sensor_window",
    "camera.noise_px",
    "camera.width_px",
    "camera.height_px",
    "camera.hfov_deg",
    "camera.vfov_deg",
    "camera.frame_period_s",
    "world.friction",
    "world.start_distance_m",
    "beacon.height_m",
    "beacon.centre_m",
    "beacon.radius_m",
    "trial.duration",
];

impl Scenario {
    /// The paper's experiment on the shipped robot.
    pub fn paper() -> Result<Self, SimError> {
        let urdf_text = quadsim::ERS7_URDF.to_string();
        Ok(Self {
            description: RobotDescription::from_urdf_str(&urdf_text).map_err(SimError::from)?,
            urdf_text,
            sim: SimConfig::default(),
            learner: ScasmConfig::default(),
            mode: LearningMode::Simultaneous,
            duration_s: 150.0,
        })
    }

    /// Applies `key=value`, or changes nothing and says which key is wrong.
    pub fn set(&mut self, assignment: &str) -> Result<(), SettingError> {
        let mut changed = self.clone();
        changed.apply(assignment)?;
        *self = changed;
        Ok(())
    }

    /// The paper's scenario with the robot of `urdf` (default: the shipped one),
    /// then a scenario file's settings (if any), then `key=value` settings in
    /// order: what a command line asks for.
    pub fn from_settings(
        urdf: Option<&Path>,
        file: Option<&Path>,
        settings: &[String],
    ) -> Result<Self, SettingError> {
        let robot_error = |file: String, e: String| SettingError::File { file, reason: e };
        let mut scenario =
            Self::paper().map_err(|e| robot_error("assets/ers7.urdf".into(), e.to_string()))?;
        if let Some(path) = urdf {
            let name = path.display().to_string();
            let text = std::fs::read_to_string(path)
                .map_err(|e| robot_error(name.clone(), e.to_string()))?;
            scenario.description = RobotDescription::from_urdf_str(&text)
                .map_err(|e| robot_error(name.clone(), e.to_string()))?;
            scenario.urdf_text = text;
        }
        if let Some(path) = file {
            let text = std::fs::read_to_string(path).map_err(|e| SettingError::File {
                file: path.display().to_string(),
                reason: e.to_string(),
            })?;
            scenario.apply_toml(&path.display().to_string(), &text)?;
        }
        for s in settings {
            scenario.set(s)?;
        }
        Ok(scenario)
    }

    /// Applies a scenario file's settings (TOML: `[section]` tables of
    /// `key = value`, the same keys as [`Scenario::set`]), all or nothing.
    pub fn apply_toml(&mut self, file: &str, text: &str) -> Result<(), SettingError> {
        let file_error = |reason: String| SettingError::File {
            file: file.into(),
            reason,
        };
        let table: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| file_error(e.to_string()))?;
        let mut changed = self.clone();
        for (section, entries) in &table {
            let toml::Value::Table(entries) = entries else {
                return Err(file_error(format!(
                    "`{section}` must be a [section] of settings"
                )));
            };
            for (key, value) in entries {
                let value = match value {
                    toml::Value::Integer(i) => i.to_string(),
                    toml::Value::Float(f) => f.to_string(),
                    other => {
                        return Err(file_error(format!(
                            "`{section}.{key}` must be a number, is {}",
                            other.type_str()
                        )));
                    }
                };
                changed.apply(&format!("{section}.{key}={value}"))?;
            }
        }
        *self = changed;
        Ok(())
    }

    fn apply(&mut self, assignment: &str) -> Result<(), SettingError> {
        let (key, value) = assignment
            .split_once('=')
            .ok_or_else(|| SettingError::Malformed(assignment.into()))?;
        let (key, value) = (key.trim(), value.trim());
        let bad = |reason: String| SettingError::BadValue {
            key: key.into(),
            reason,
        };
        let number = || -> Result<f64, SettingError> {
            let v: f64 = value.parse().map_err(|e| bad(format!("`{value}`: {e}")))?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(bad(format!("`{value}` is not finite")))
            }
        };
        let count = || -> Result<usize, SettingError> {
            value.parse().map_err(|e| bad(format!("`{value}`: {e}")))
        };
        let pixels = || -> Result<u32, SettingError> {
            value.parse().map_err(|e| bad(format!("`{value}`: {e}")))
        };
        match key {
            "learner.gamma" => self.learner.gamma = number()?,
            "learner.beta" => self.learner.beta = number()?,
            "learner.t_start" => self.learner.t_start_s = number()?,
            "learner.sensor_degree" => self.learner.sensor_degree = count()?,
            "learner.action_degree" => self.learner.action_degree = count()?,
            "learner.sensor_window" => self.learner.sensor_window = count()?,
            "camera.noise_px" => self.sim.camera.noise_px = number()?,
            "camera.width_px" => self.sim.camera.intrinsics.width_px = pixels()?,
            "camera.height_px" => self.sim.camera.intrinsics.height_px = pixels()?,
            "camera.hfov_deg" => self.sim.camera.intrinsics.hfov_deg = number()?,
            "camera.vfov_deg" => self.sim.camera.intrinsics.vfov_deg = number()?,
            "camera.frame_period_s" => self.sim.camera.frame_period_s = number()?,
            "world.start_distance_m" => self.sim.start_distance_m = number()?,
            "beacon.centre_m" => self.sim.beacon.band_centre_m = number()?,
            "beacon.radius_m" => self.sim.beacon.radius_m = number()?,
            "world.friction" => self.sim.friction = number()?,
            "beacon.height_m" => self.sim.beacon.band_height_m = number()?,
            "trial.duration" => {
                let d = number()?;
                if d <= 0.0 {
                    return Err(bad(format!("{d} must be > 0")));
                }
                self.duration_s = d;
            }
            _ => {
                return Err(SettingError::UnknownKey {
                    key: key.into(),
                    known: SETTING_KEYS.join(", "),
                });
            }
        }
        // Catch range errors at the door, naming the key.
        self.learner.validate().map_err(|e| bad(e.to_string()))?;
        self.sim.validate().map_err(|e| bad(e.to_string()))?;
        Ok(())
    }

    /// A key identifying what the measured reference depends on (robot, world,
    /// controllers, camera and the protocols' settings; not the learner).
    pub fn reference_key(&self) -> String {
        let mut h = std::collections::hash_map::DefaultHasher::new();
        self.urdf_text.hash(&mut h);
        format!("{:?}", self.sim).hash(&mut h);
        format!("{:?}", StopwatchConfig::default()).hash(&mut h);
        MEASURE_READINGS.hash(&mut h);
        format!("{:016x}", h.finish())
    }
}

/// Readings per distance in the stand-and-read protocol.
pub const MEASURE_READINGS: usize = 100;

/// The measured models as stored in the cache.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct CachedReference {
    key: String,
    /// `(command, velocity mm/s, std mm/s)`.
    action: Vec<(f64, f64, f64)>,
    /// `(distance mm, obs px, std px)`.
    sensor: Vec<(f64, f64, f64)>,
}

/// The measured models with their spreads, as the protocols give them.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredModels {
    /// `(command, velocity mm/s, std mm/s)`, the 31 commands.
    pub action: Vec<(f64, f64, f64)>,
    /// `(distance mm, obs px, std px)`, the 13 distances.
    pub sensor: Vec<(f64, f64, f64)>,
    /// Whether they came from the cache.
    pub from_cache: bool,
}

impl MeasuredModels {
    /// The reference for judging.
    pub fn reference(&self) -> Reference {
        Reference {
            action: self.action.iter().map(|&(c, v, _)| (c, v)).collect(),
            sensor: self.sensor.iter().map(|&(d, o, _)| (d, o)).collect(),
        }
    }
}

/// Measures the reference models of `scenario`, or reads them from `cache_dir`
/// if they were measured before for the same robot, world and protocols.
pub fn measured_models(
    scenario: &Scenario,
    cache_dir: Option<&Path>,
) -> Result<MeasuredModels, SimError> {
    let key = scenario.reference_key();
    let path = cache_dir.map(|d| d.join(format!("reference-{key}.json")));
    if let Some(p) = &path {
        if let Ok(text) = std::fs::read_to_string(p) {
            if let Ok(c) = serde_json::from_str::<CachedReference>(&text) {
                if c.key == key {
                    return Ok(MeasuredModels {
                        action: c.action,
                        sensor: c.sensor,
                        from_cache: true,
                    });
                }
            }
        }
    }
    let action = measure::measure_action(
        &scenario.description,
        scenario.sim,
        &StopwatchConfig::default(),
        &measure::paper_commands(),
    )?
    .iter()
    .map(|m| (m.command, m.velocity_mm_s, m.std_mm_s))
    .collect::<Vec<_>>();
    let sensor = measure::measure_sensor(
        &scenario.description,
        scenario.sim,
        &measure::paper_distances_m(),
        MEASURE_READINGS,
    )?
    .iter()
    .map(|r| (r.distance_mm, r.obs_px, r.std_px))
    .collect::<Vec<_>>();
    if let Some(p) = &path {
        // A cache that cannot be written costs only time, never the run.
        let cached = CachedReference {
            key,
            action: action.clone(),
            sensor: sensor.clone(),
        };
        if let Ok(text) = serde_json::to_string(&cached) {
            let _ = p.parent().map(std::fs::create_dir_all);
            let tmp = p.with_extension("json.tmp");
            if std::fs::write(&tmp, text).is_ok() {
                let _ = std::fs::rename(&tmp, p);
            }
        }
    }
    Ok(MeasuredModels {
        action,
        sensor,
        from_cache: false,
    })
}

/// Figures of one trial, as `summary.json` has them.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Figures {
    /// Learned action model's RMSE after the best scale, mm/s.
    pub action_rmse_mm_s: f64,
    /// Learned sensor model's RMSE after the best affine map, mm.
    pub sensor_rmse_mm: f64,
    /// Best quartic through the measured action model, mm/s.
    pub action_best_rmse_mm_s: f64,
    /// Best cubic through the measured sensor model, mm.
    pub sensor_best_rmse_mm: f64,
    /// The identity model A0 after its best scale, mm/s.
    pub action_a0_rmse_mm_s: f64,
    /// `| |k / b| - 1 |`.
    pub consistency: f64,
    /// Simulated seconds per wall-clock second.
    pub realtime_factor: f64,
}

/// The best possible figures for a reference (independent of the trial).
pub fn best_possible(reference: &Reference, learner: &ScasmConfig) -> (f64, f64, f64) {
    let s: Vec<(f64, f64)> = reference.sensor.iter().map(|&(d, o)| (o, d)).collect();
    (
        metrics::best_polynomial_rmse(&reference.action, learner.action_degree).unwrap_or(f64::NAN),
        metrics::best_polynomial_rmse(&s, learner.sensor_degree).unwrap_or(f64::NAN),
        metrics::action_error(&Polynomial::identity(), &reference.action).rmse,
    )
}

impl Figures {
    /// The figures of a finished trial (NaN where a model was never learned).
    pub fn of(outcome: &TrialOutcome, best: (f64, f64, f64)) -> Self {
        Self {
            action_rmse_mm_s: outcome.last.action_rmse_mm_s.unwrap_or(f64::NAN),
            sensor_rmse_mm: outcome.last.sensor_rmse_mm.unwrap_or(f64::NAN),
            action_best_rmse_mm_s: best.0,
            sensor_best_rmse_mm: best.1,
            action_a0_rmse_mm_s: best.2,
            consistency: outcome.last.consistency.unwrap_or(f64::NAN),
            realtime_factor: outcome.realtime_factor,
        }
    }

    fn map(values: &[Self], f: impl Fn(&[f64]) -> f64) -> Self {
        let field = |g: fn(&Self) -> f64| f(&values.iter().map(g).collect::<Vec<_>>());
        Self {
            action_rmse_mm_s: field(|x| x.action_rmse_mm_s),
            sensor_rmse_mm: field(|x| x.sensor_rmse_mm),
            action_best_rmse_mm_s: field(|x| x.action_best_rmse_mm_s),
            sensor_best_rmse_mm: field(|x| x.sensor_best_rmse_mm),
            action_a0_rmse_mm_s: field(|x| x.action_a0_rmse_mm_s),
            consistency: field(|x| x.consistency),
            realtime_factor: field(|x| x.realtime_factor),
        }
    }

    /// Every field `value`.
    pub fn filled(value: f64) -> Self {
        Self {
            action_rmse_mm_s: value,
            sensor_rmse_mm: value,
            action_best_rmse_mm_s: value,
            sensor_best_rmse_mm: value,
            action_a0_rmse_mm_s: value,
            consistency: value,
            realtime_factor: value,
        }
    }

    /// Mean over trials, field by field.
    pub fn mean(values: &[Self]) -> Self {
        Self::map(values, |v| v.iter().sum::<f64>() / v.len() as f64)
    }

    /// Population standard deviation over trials, field by field.
    pub fn std(values: &[Self]) -> Self {
        Self::map(values, |v| {
            let m = v.iter().sum::<f64>() / v.len() as f64;
            (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
        })
    }

    /// The paper's reported figures (15 trials on a Sony Aibo ERS-7).
    pub fn paper() -> Self {
        Self {
            action_rmse_mm_s: 29.6,
            sensor_rmse_mm: 70.4,
            action_best_rmse_mm_s: 17.2,
            sensor_best_rmse_mm: 48.8,
            action_a0_rmse_mm_s: 43.0,
            consistency: 0.08,
            realtime_factor: f64::NAN,
        }
    }
}

/// How far beyond each end of the test range the behaviour turns round, m: the
/// readings of a walking robot run about a pixel below those of one standing, so
/// turning at the end's own reading would stop short of it.
pub const TURN_MARGIN_M: f64 = 0.15;

/// The behaviour's thresholds from the measured sensor model: turn round at the
/// readings expected [`TURN_MARGIN_M`] beyond the nearest and farthest test
/// distances, from the pinhole law `d = a + b / obs` fitted to the measured points
/// (or at the end points' own readings if that fit fails).
pub fn behaviour_for(models: &MeasuredModels) -> BehaviourConfig {
    let end = |i: usize| {
        models
            .sensor
            .get(i)
            .map_or((f64::NAN, f64::NAN), |s| (s.0, s.1))
    };
    let (near, far) = (end(0), end(models.sensor.len().saturating_sub(1)));
    let inverse: Vec<(f64, f64)> = models.sensor.iter().map(|s| (1.0 / s.1, s.0)).collect();
    let (near_obs_px, far_obs_px) = match metrics::best_polynomial(&inverse, 1) {
        Some(p) if p.coeffs()[1] > 0.0 => {
            let (a, b) = (p.coeffs()[0], p.coeffs()[1]);
            let obs_at = |d_mm: f64| b / (d_mm - a);
            (
                obs_at(near.0 - 1000.0 * TURN_MARGIN_M),
                obs_at(far.0 + 1000.0 * TURN_MARGIN_M),
            )
        }
        _ => (near.1, far.1),
    };
    BehaviourConfig {
        max_command: 300.0,
        hold_s: 3.0,
        near_obs_px,
        far_obs_px,
        turn_median_of: crate::behaviour::TURN_MEDIAN_OF,
    }
}

/// The learner for a mode: the given model of a one-sided mode is the best
/// polynomial through the measured one, in mm (location is distance, so the
/// action model is minus the forward speed).
pub fn learner_for(scenario: &Scenario, reference: &Reference) -> Result<Scasm, String> {
    let params = scenario.learner.validate().map_err(|e| e.to_string())?;
    let mode = match scenario.mode {
        LearningMode::Simultaneous => Mode::Simultaneous,
        LearningMode::SensorFromAction => {
            let a = metrics::best_polynomial(&reference.action, scenario.learner.action_degree)
                .ok_or("cannot fit the measured action model")?;
            let minus: Vec<f64> = a.coeffs().iter().map(|c| -c).collect();
            Mode::SensorFromAction(Polynomial::new(&minus).ok_or("bad action model")?)
        }
        LearningMode::ActionFromSensor => {
            let pts: Vec<(f64, f64)> = reference.sensor.iter().map(|&(d, o)| (o, d)).collect();
            Mode::ActionFromSensor(
                metrics::best_polynomial(&pts, scenario.learner.sensor_degree)
                    .ok_or("cannot fit the measured sensor model")?,
            )
        }
    };
    Scasm::new(params, mode).map_err(|e| e.to_string())
}

/// Runs one trial of `scenario` from `seed`, judged against `models`.
pub fn run_one(
    scenario: &Scenario,
    models: &MeasuredModels,
    seed: u64,
) -> Result<(TrialOutcome, Scasm), TrialError> {
    let reference = models.reference();
    let mut learner = learner_for(scenario, &reference).map_err(TrialError::LearnerSetup)?;
    let config = TrialConfig {
        duration_s: scenario.duration_s,
        seed,
        behaviour: behaviour_for(models),
        judge_every_s: 5.0,
    };
    let outcome = trial::run_trial(
        &scenario.description,
        scenario.sim,
        config,
        &mut learner as &mut dyn CalibrationLearner,
        &reference,
    )?;
    Ok((outcome, learner))
}

/// Runs one trial per seed in parallel, calling `done` as each finishes.
pub fn run_trials(
    scenario: &Scenario,
    models: &MeasuredModels,
    seeds: &[u64],
    done: &(dyn Fn(&TrialOutcome) + Sync),
) -> Result<Vec<(TrialOutcome, Scasm)>, TrialError> {
    seeds
        .par_iter()
        .map(|&seed| {
            let result = run_one(scenario, models, seed)?;
            done(&result.0);
            Ok(result)
        })
        .collect()
}
