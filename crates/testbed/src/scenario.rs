//! A scenario: everything a trial depends on besides its seed (robot, world,
//! camera, learner settings, trial length), built from defaults, a scenario file
//! and `key=value` settings, each checked at the door.

use std::path::{Path, PathBuf};

use quadsim::{RobotDescription, RobotFile, RobotScale, SimConfig, SimError};
use scasm::ScasmConfig;
use serde::{Deserialize, Serialize};

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
    /// A scheduled change of the world cannot be made.
    #[error("the change of `{key}` at {at_s} s: {reason}")]
    Change {
        /// The setting it changes.
        key: String,
        /// When, s.
        at_s: f64,
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
    /// Where the URDF was read from (`None`: the shipped robot).
    pub urdf_path: Option<PathBuf>,
    /// The robot file, as named (a shipped robot's name or a path), and its
    /// text (`None`: the default ERS-7, or a bare `robot.urdf`).
    pub robot_file: Option<(String, String)>,
    /// The world, robot controllers and camera.
    pub sim: SimConfig,
    /// The learner's name (see [`crate::learners`]).
    pub learner_name: String,
    /// The learner's hyper-parameters.
    pub learner: ScasmConfig,
    /// What is learned from what.
    pub mode: LearningMode,
    /// Trial length, s.
    pub duration_s: f64,
    /// The seeds of a run's trials, `first..end` (end excluded).
    pub seeds: (u64, u64),
    /// When the camera sees no beacon.
    pub blank: crate::blanks::Blanks,
    /// Changes of the world during each trial, in time order.
    pub changes: Vec<Change>,
}

/// A change of the world during a trial: at `at_s`, the setting `key` becomes
/// `value` (a scenario file's `[[change]]`). Only what the world can change
/// while it runs may change (see [`quadsim::SimConfig::check_live_change`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Change {
    /// When, s from the trial's start (within the trial).
    pub at_s: f64,
    /// The setting, e.g. `world.friction`.
    pub key: String,
    /// Its new value, as `--set` would write it.
    pub value: String,
}

/// The paper's trial length, s (at the ERS-7's scale).
pub const PAPER_DURATION_S: f64 = 150.0;

/// The longest trial, s (a day): a trial keeps every frame in memory, about
/// 0.1 kB each at 20 Hz.
pub const MAX_DURATION_S: f64 = 86_400.0;

/// A setting's type, as a scenario file writes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Number,
    Count,
    Text,
}

/// Every setting: its key and type. `--set`, scenario files and a run's
/// `config.toml` all use these.
const SETTINGS: [(&str, Kind); 28] = [
    ("robot.file", Kind::Text),
    ("robot.urdf", Kind::Text),
    ("trial.duration", Kind::Number),
    ("trial.seeds", Kind::Text),
    ("trial.mode", Kind::Text),
    ("learner.name", Kind::Text),
    ("learner.gamma", Kind::Number),
    ("learner.beta", Kind::Number),
    ("learner.t_start", Kind::Number),
    ("learner.sensor_degree", Kind::Count),
    ("learner.action_degree", Kind::Count),
    ("learner.sensor_window", Kind::Count),
    ("learner.forward_degree", Kind::Count),
    ("camera.noise_px", Kind::Number),
    ("camera.width_px", Kind::Count),
    ("camera.height_px", Kind::Count),
    ("camera.hfov_deg", Kind::Number),
    ("camera.vfov_deg", Kind::Number),
    ("camera.frame_period_s", Kind::Number),
    ("camera.blank_s", Kind::Text),
    ("world.friction", Kind::Number),
    ("world.start_distance_m", Kind::Number),
    ("servo.torque_scale", Kind::Number),
    ("servo.speed_scale", Kind::Number),
    ("beacon.height_m", Kind::Number),
    ("beacon.centre_m", Kind::Number),
    ("beacon.radius_m", Kind::Number),
    ("physics.dt", Kind::Number),
];

/// The settings `--set` understands, in the order `config.toml` writes them.
pub fn setting_keys() -> impl Iterator<Item = &'static str> {
    SETTINGS.iter().map(|s| s.0)
}

impl Scenario {
    /// The paper's experiment on the shipped robot, with the default learner
    /// (the paper's constants and a sensor reading window of 5, which the
    /// paper does not have).
    pub fn paper() -> Result<Self, SimError> {
        let urdf_text = quadsim::ERS7_URDF.to_string();
        Ok(Self {
            description: RobotDescription::from_urdf_str(&urdf_text).map_err(SimError::from)?,
            urdf_text,
            urdf_path: None,
            robot_file: None,
            sim: SimConfig::default(),
            learner_name: crate::learners::registry::DEFAULT.into(),
            learner: ScasmConfig::default(),
            mode: LearningMode::Simultaneous,
            duration_s: PAPER_DURATION_S,
            seeds: (0, 15),
            blank: Default::default(),
            changes: Vec::new(),
        })
    }

    /// Applies `key=value`, or changes nothing and says which key is wrong.
    pub fn set(&mut self, assignment: &str) -> Result<(), SettingError> {
        let mut changed = self.clone();
        changed.apply(assignment)?;
        *self = changed;
        Ok(())
    }

    /// [`Scenario::paper`] with the robot of `urdf` (default: the shipped one),
    /// then a scenario file's settings (if any), then `key=value` settings in
    /// order: what a command line asks for. The robot is chosen first wherever
    /// it is set (`robot.*` settings reset the world to the robot's scale, see
    /// [`RobotScale`]), so other settings always apply on top of it.
    pub fn from_settings(
        urdf: Option<&Path>,
        file: Option<&Path>,
        settings: &[String],
    ) -> Result<Self, SettingError> {
        let mut scenario = Self::paper().map_err(|e| SettingError::File {
            file: "assets/ers7.urdf".into(),
            reason: e.to_string(),
        })?;
        if let Some(path) = urdf {
            scenario.set(&format!("robot.urdf={}", path.display()))?;
        }
        if let Some(path) = file {
            let text = std::fs::read_to_string(path).map_err(|e| SettingError::File {
                file: path.display().to_string(),
                reason: e.to_string(),
            })?;
            scenario.apply_toml(&path.display().to_string(), &text)?;
        }
        // The robot first, then the trial (a blanked interval is checked
        // against the trial's length), then the rest, each in the order given.
        let mut ordered: Vec<&String> = settings.iter().collect();
        ordered.sort_by_key(|s| section_rank(s.trim_start().split('.').next().unwrap_or("")));
        for s in ordered {
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
        // The robot first (it resets the world to its scale), then the trial
        // (a blanked interval is checked against its length), then the rest.
        let mut ordered: Vec<(&String, &toml::Value)> = table.iter().collect();
        ordered.sort_by_key(|(section, _)| section_rank(section));
        for (section, entries) in ordered {
            if section == "change" {
                changed.add_changes(file, entries)?;
                continue;
            }
            let toml::Value::Table(entries) = entries else {
                return Err(file_error(format!(
                    "`{section}` must be a [section] of settings"
                )));
            };
            for (key, value) in entries {
                let full = format!("{section}.{key}");
                let kind = SETTINGS.iter().find(|s| s.0 == full).map(|s| s.1);
                let value = match (value, kind) {
                    (toml::Value::String(text), Some(Kind::Text) | None) => text.clone(),
                    (toml::Value::Integer(i), Some(Kind::Number | Kind::Count) | None) => {
                        i.to_string()
                    }
                    (toml::Value::Float(f), Some(Kind::Number | Kind::Count) | None) => {
                        f.to_string()
                    }
                    (other, Some(Kind::Text)) => {
                        return Err(file_error(format!(
                            "`{full}` must be a string, is {}",
                            other.type_str()
                        )));
                    }
                    (other, _) => {
                        return Err(file_error(format!(
                            "`{full}` must be a number, is {}",
                            other.type_str()
                        )));
                    }
                };
                changed.apply(&format!("{full}={value}"))?;
            }
        }
        *self = changed;
        Ok(())
    }

    /// Adds a scenario file's `[[change]]` entries (an array of tables with
    /// `at_s`, `key` and `value`) after the changes already scheduled.
    fn add_changes(&mut self, file: &str, entries: &toml::Value) -> Result<(), SettingError> {
        let bad = |reason: String| SettingError::File {
            file: file.into(),
            reason,
        };
        let toml::Value::Array(list) = entries else {
            return Err(bad(
                "`change` must be an array of tables: [[change]] with at_s, key and value".into(),
            ));
        };
        for entry in list {
            let mut entry = entry.clone();
            // The value as `--set` writes it, whatever its TOML type.
            if let Some(t) = entry.as_table_mut() {
                if let Some(v) = t.get("value").cloned() {
                    let text = match v {
                        toml::Value::String(s) => s,
                        other => other.to_string(),
                    };
                    t.insert("value".into(), toml::Value::String(text));
                }
                if let Some(toml::Value::Integer(i)) = t.get("at_s").cloned() {
                    t.insert("at_s".into(), toml::Value::Float(i as f64));
                }
            }
            let change: Change = entry
                .try_into()
                .map_err(|e: toml::de::Error| bad(format!("[[change]]: {}", e.message())))?;
            self.changes.push(change);
        }
        self.worlds().map(|_| ())
    }

    /// The world as it starts and after each scheduled change: `(from s,
    /// settings)`, the first from 0. Says which change cannot be made: a time
    /// outside the trial or out of order, an unknown key or a bad value, or a
    /// setting that cannot change during a run.
    pub fn worlds(&self) -> Result<Vec<(f64, SimConfig)>, SettingError> {
        let mut world = self.clone();
        world.changes.clear();
        let mut out = vec![(0.0, world.sim)];
        for c in &self.changes {
            let fail = |reason: String| SettingError::Change {
                key: c.key.clone(),
                at_s: c.at_s,
                reason,
            };
            if !(c.at_s > 0.0 && c.at_s < self.duration_s) {
                return Err(fail(format!(
                    "outside the trial: must be in (0, {}) s",
                    self.duration_s
                )));
            }
            if c.at_s < out.last().map_or(0.0, |w| w.0) {
                return Err(fail("changes must be in time order".into()));
            }
            let (before, settings) = (world.sim, world.to_toml());
            world
                .set(&format!("{}={}", c.key, c.value))
                .map_err(|e| fail(e.to_string()))?;
            let mut rest = world.clone();
            rest.sim = before;
            if rest.to_toml() != settings {
                return Err(fail(
                    "not part of the world: it cannot change during a run".into(),
                ));
            }
            before
                .check_live_change(&world.sim)
                .map_err(|e| fail(e.to_string()))?;
            out.push((c.at_s, world.sim));
        }
        Ok(out)
    }

    /// The scenario of the world after change `i` (0: as it starts), with no
    /// changes: what the reference of that world is measured on.
    pub fn world(&self, i: usize) -> Result<Scenario, SettingError> {
        let worlds = self.worlds()?;
        let mut s = self.clone();
        s.changes.clear();
        s.sim = worlds.get(i).map_or(s.sim, |w| w.1);
        Ok(s)
    }

    /// The changes, as `at:key=value;...` (for keys and logs).
    pub fn changes_text(&self) -> String {
        self.changes
            .iter()
            .map(|c| format!("{}:{}={}", c.at_s, c.key, c.value))
            .collect::<Vec<_>>()
            .join(";")
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
            "robot.file" => {
                let robot = RobotFile::load(value).map_err(|e| SettingError::File {
                    file: value.into(),
                    reason: e.to_string(),
                })?;
                // Its gait was checked within the legs' reach as it was read.
                let sim = robot.sim_config();
                // The paper's experiment at the robot's scale: its commands,
                // trial length and the learner's time constants scale too.
                let scale = RobotScale::of(&robot.description);
                let paper = ScasmConfig::default();
                self.learner = ScasmConfig {
                    command_scale: paper.command_scale * scale.speed(),
                    ..paper.time_scaled(scale.time())
                };
                self.duration_s = PAPER_DURATION_S * scale.time();
                self.sim = sim;
                self.description = robot.description;
                self.urdf_text = robot.urdf_text;
                self.urdf_path = None;
                self.robot_file = Some((value.into(), robot.text));
            }
            "robot.urdf" => {
                let (text, description) = read_urdf(Path::new(value))?;
                // A robot that cannot walk the gait is refused here, naming
                // its file, rather than in every trial.
                quadsim::walk::WalkEngine::check_feasible(&self.sim.walk, &description.legs)
                    .map_err(|e| SettingError::File {
                        file: value.into(),
                        reason: e.to_string(),
                    })?;
                self.description = description;
                self.urdf_text = text;
                self.urdf_path = Some(PathBuf::from(value));
                self.robot_file = None;
            }
            "trial.duration" => {
                let d = number()?;
                if !(d > 0.0 && d <= MAX_DURATION_S) {
                    return Err(bad(format!(
                        "{d} s must be in (0, {MAX_DURATION_S}]: a trial keeps every 50 ms \
                         frame in memory"
                    )));
                }
                if let Some(&(_, end)) = self.blank.intervals().last() {
                    if end > d {
                        return Err(bad(format!(
                            "{d} s ends before camera.blank_s's interval ending at {end} s"
                        )));
                    }
                }
                self.duration_s = d;
            }
            "trial.seeds" => self.seeds = parse_seeds(value).map_err(bad)?,
            "trial.mode" => {
                self.mode = match value {
                    "simultaneous" => LearningMode::Simultaneous,
                    "sensor-from-action" => LearningMode::SensorFromAction,
                    "action-from-sensor" => LearningMode::ActionFromSensor,
                    other => {
                        return Err(bad(format!(
                            "`{other}`; known: simultaneous, sensor-from-action, action-from-sensor"
                        )));
                    }
                }
            }
            "learner.name" => {
                if !crate::learners::registry::names().any(|n| n == value) {
                    return Err(bad(format!(
                        "unknown learner `{value}`; known: {}",
                        crate::learners::registry::names()
                            .collect::<Vec<_>>()
                            .join(", ")
                    )));
                }
                self.learner_name = value.into();
            }
            "learner.gamma" => self.learner.gamma = number()?,
            "learner.beta" => self.learner.beta = number()?,
            "learner.t_start" => self.learner.t_start_s = number()?,
            "learner.sensor_degree" => self.learner.sensor_degree = count()?,
            "learner.action_degree" => self.learner.action_degree = count()?,
            "learner.sensor_window" => self.learner.sensor_window = count()?,
            "learner.forward_degree" => self.learner.forward_degree = count()?,
            "camera.noise_px" => self.sim.camera.noise_px = number()?,
            "camera.width_px" => self.sim.camera.intrinsics.width_px = pixels()?,
            "camera.height_px" => self.sim.camera.intrinsics.height_px = pixels()?,
            "camera.hfov_deg" => self.sim.camera.intrinsics.hfov_deg = number()?,
            "camera.vfov_deg" => self.sim.camera.intrinsics.vfov_deg = number()?,
            "camera.frame_period_s" => self.sim.camera.frame_period_s = number()?,
            "camera.blank_s" => {
                self.blank = crate::blanks::Blanks::parse(value, self.duration_s).map_err(bad)?;
            }
            "world.start_distance_m" => self.sim.start_distance_m = number()?,
            "world.friction" => self.sim.friction = number()?,
            "servo.torque_scale" => self.sim.servo.torque_scale = number()?,
            "servo.speed_scale" => self.sim.servo.speed_scale = number()?,
            "beacon.centre_m" => self.sim.beacon.band_centre_m = number()?,
            "beacon.radius_m" => self.sim.beacon.radius_m = number()?,
            "beacon.height_m" => self.sim.beacon.band_height_m = number()?,
            "physics.dt" => self.sim.dt_s = number()?,
            _ => {
                return Err(SettingError::UnknownKey {
                    key: key.into(),
                    known: setting_keys().collect::<Vec<_>>().join(", "),
                });
            }
        }
        // Catch range errors at the door, naming the key.
        self.learner.validate().map_err(|e| bad(e.to_string()))?;
        self.sim.validate().map_err(|e| bad(e.to_string()))?;
        // A setting may also make a scheduled change impossible (a trial
        // shorter than it, say).
        self.worlds()?;
        Ok(())
    }

    /// The value of a setting, as a scenario file writes it.
    pub fn get(&self, key: &str) -> Option<toml::Value> {
        use toml::Value::{Float, Integer, String as Text};
        let count = |n: usize| Integer(n as i64);
        Some(match key {
            "robot.file" => Text(
                self.robot_file
                    .as_ref()
                    .map_or_else(String::new, |(name, _)| name.clone()),
            ),
            "robot.urdf" => Text(
                self.urdf_path
                    .as_ref()
                    .map_or_else(String::new, |p| p.display().to_string()),
            ),
            "trial.duration" => Float(self.duration_s),
            "trial.seeds" => Text(format!("{}..{}", self.seeds.0, self.seeds.1)),
            "trial.mode" => Text(
                match self.mode {
                    LearningMode::Simultaneous => "simultaneous",
                    LearningMode::SensorFromAction => "sensor-from-action",
                    LearningMode::ActionFromSensor => "action-from-sensor",
                }
                .into(),
            ),
            "learner.name" => Text(self.learner_name.clone()),
            "learner.gamma" => Float(self.learner.gamma),
            "learner.beta" => Float(self.learner.beta),
            "learner.t_start" => Float(self.learner.t_start_s),
            "learner.sensor_degree" => count(self.learner.sensor_degree),
            "learner.action_degree" => count(self.learner.action_degree),
            "learner.sensor_window" => count(self.learner.sensor_window),
            "learner.forward_degree" => count(self.learner.forward_degree),
            "camera.noise_px" => Float(self.sim.camera.noise_px),
            "camera.width_px" => Integer(self.sim.camera.intrinsics.width_px.into()),
            "camera.height_px" => Integer(self.sim.camera.intrinsics.height_px.into()),
            "camera.hfov_deg" => Float(self.sim.camera.intrinsics.hfov_deg),
            "camera.vfov_deg" => Float(self.sim.camera.intrinsics.vfov_deg),
            "camera.frame_period_s" => Float(self.sim.camera.frame_period_s),
            "camera.blank_s" => Text(self.blank.to_text()),
            "world.start_distance_m" => Float(self.sim.start_distance_m),
            "world.friction" => Float(self.sim.friction),
            "servo.torque_scale" => Float(self.sim.servo.torque_scale),
            "servo.speed_scale" => Float(self.sim.servo.speed_scale),
            "beacon.centre_m" => Float(self.sim.beacon.band_centre_m),
            "beacon.radius_m" => Float(self.sim.beacon.radius_m),
            "beacon.height_m" => Float(self.sim.beacon.band_height_m),
            "physics.dt" => Float(self.sim.dt_s),
            _ => return None,
        })
    }

    /// Every setting as a scenario file (TOML): what a run records as its
    /// `config.toml`, and what `--config` reads back to the same scenario. The
    /// shipped robot's `robot.urdf` is left out (it is the default).
    pub fn to_toml(&self) -> String {
        let mut table = toml::Table::new();
        for key in setting_keys() {
            let Some(value) = self.get(key) else { continue };
            if (key == "robot.urdf" && self.urdf_path.is_none())
                || (key == "robot.file" && self.robot_file.is_none())
            {
                continue;
            }
            let (section, name) = key.split_once('.').unwrap_or(("", key));
            if let toml::Value::Table(t) = table
                .entry(section)
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            {
                t.insert(name.into(), value);
            }
        }
        if !self.changes.is_empty() {
            let list = self
                .changes
                .iter()
                .map(|c| {
                    let mut t = toml::Table::new();
                    t.insert("at_s".into(), toml::Value::Float(c.at_s));
                    t.insert("key".into(), toml::Value::String(c.key.clone()));
                    let value = c
                        .value
                        .parse::<f64>()
                        .map_or_else(|_| toml::Value::String(c.value.clone()), toml::Value::Float);
                    t.insert("value".into(), value);
                    toml::Value::Table(t)
                })
                .collect();
            table.insert("change".into(), toml::Value::Array(list));
        }
        toml::to_string(&table).unwrap_or_default()
    }

    /// The robot's size relative to the ERS-7 (see [`RobotScale`]): the test
    /// range, the protocols' distances and the commands scale with it.
    pub fn scale(&self) -> RobotScale {
        if self.robot_file.is_some() {
            RobotScale::of(&self.description)
        } else {
            RobotScale::ONE
        }
    }

    /// The stopwatch protocol at the robot's scale.
    pub fn stopwatch(&self) -> crate::measure::StopwatchConfig {
        crate::measure::StopwatchConfig::scaled(self.scale())
    }

    /// The largest walk command, mm/s: the paper's 300 at the robot's scale.
    pub fn max_command(&self) -> f64 {
        300.0 * self.scale().speed()
    }
}

/// The order settings are applied in, by section: the robot first (it resets
/// the world to its scale), then the trial (a blanked interval is checked
/// against its length), then the rest, and a file's `[[change]]`s last (each
/// changes the world as the rest made it); a stable sort keeps the given
/// order within each.
fn section_rank(section: &str) -> u8 {
    match section {
        "robot" => 0,
        "trial" => 1,
        "change" => 3,
        _ => 2,
    }
}

/// The robot of a URDF file.
fn read_urdf(path: &Path) -> Result<(String, RobotDescription), SettingError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| SettingError::File {
        file: file.clone(),
        reason: e.to_string(),
    })?;
    let description = RobotDescription::from_urdf_str(&text).map_err(|e| SettingError::File {
        file,
        reason: e.to_string(),
    })?;
    Ok((text, description))
}

/// Seeds written `A..B` (B excluded, at least one seed).
pub fn parse_seeds(text: &str) -> Result<(u64, u64), String> {
    let (a, b) = text
        .split_once("..")
        .ok_or_else(|| format!("`{text}` is not of the form A..B"))?;
    let parse = |v: &str| {
        v.trim()
            .parse::<u64>()
            .map_err(|e| format!("`{text}`: {e}"))
    };
    let (a, b) = (parse(a)?, parse(b)?);
    if a >= b {
        return Err(format!("`{text}` holds no seed"));
    }
    Ok((a, b))
}
