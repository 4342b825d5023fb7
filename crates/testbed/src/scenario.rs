//! A scenario: everything a trial depends on besides its seed (robot, world,
//! camera, learner settings, trial length), built from defaults, a scenario file
//! and `key=value` settings, each checked at the door.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use quadsim::{RobotDescription, RobotFile, RobotScale, SimConfig, SimError};
use scasm::ScasmConfig;
use scasm::declaration::Values;
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
    /// The shared learner settings (`learner.gamma`, the degrees, ...).
    pub learner: ScasmConfig,
    /// Learners' own settings as set, by full key (`learner.batch-ml.gamma`);
    /// a learner's settings not here have their declared defaults.
    pub learner_own: BTreeMap<String, f64>,
    /// How long a learner program may take to answer, s.
    pub answer_timeout_s: f64,
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

/// One setting of the scenario: its key, type and a line of doc, and how it
/// is written and read. [`SETTINGS`] and the learners' declarations are the
/// one table that `--set`, scenario files, a run's `config.toml` and
/// `--set list` all read.
struct Entry {
    key: &'static str,
    kind: Kind,
    doc: &'static str,
    set: fn(&mut Scenario, &str) -> Result<(), String>,
    get: fn(&Scenario) -> toml::Value,
}

fn number(value: &str) -> Result<f64, String> {
    let v: f64 = value.parse().map_err(|e| format!("`{value}`: {e}"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("`{value}` is not finite"))
    }
}

fn count<T: std::str::FromStr<Err: std::fmt::Display>>(value: &str) -> Result<T, String> {
    value.parse().map_err(|e| format!("`{value}`: {e}"))
}

/// A number setting of the world, by where it lives in [`SimConfig`].
macro_rules! world_number {
    ($key:literal, $doc:literal, $($field:ident).+) => {
        Entry {
            key: $key,
            kind: Kind::Number,
            doc: $doc,
            set: |s, v| {
                s.sim.$($field).+ = number(v)?;
                Ok(())
            },
            get: |s| toml::Value::Float(s.sim.$($field).+),
        }
    };
}

/// Every setting of the robot, trial, camera, world and host; the learners'
/// settings (`learner.*`) are declared by the learners.
const SETTINGS: [Entry; 22] = [
    Entry {
        key: "robot.file",
        kind: Kind::Text,
        doc: "a robot file (a shipped robot's name or a path): its URDF, gait and scale",
        set: Scenario::set_robot_file,
        get: |s| {
            toml::Value::String(
                s.robot_file
                    .as_ref()
                    .map_or_else(String::new, |(name, _)| name.clone()),
            )
        },
    },
    Entry {
        key: "robot.urdf",
        kind: Kind::Text,
        doc: "a URDF file of a quadruped, walked with the current gait",
        set: Scenario::set_urdf,
        get: |s| {
            toml::Value::String(
                s.urdf_path
                    .as_ref()
                    .map_or_else(String::new, |p| p.display().to_string()),
            )
        },
    },
    Entry {
        key: "trial.duration",
        kind: Kind::Number,
        doc: "trial length, s",
        set: Scenario::set_duration,
        get: |s| toml::Value::Float(s.duration_s),
    },
    Entry {
        key: "trial.seeds",
        kind: Kind::Text,
        doc: "the seeds of a run's trials, A..B (B excluded)",
        set: |s, v| {
            s.seeds = parse_seeds(v)?;
            Ok(())
        },
        get: |s| toml::Value::String(format!("{}..{}", s.seeds.0, s.seeds.1)),
    },
    Entry {
        key: "trial.mode",
        kind: Kind::Text,
        doc: "what is learned from what: simultaneous, sensor-from-action, action-from-sensor",
        set: |s, v| {
            s.mode = LearningMode::parse(v)?;
            Ok(())
        },
        get: |s| toml::Value::String(s.mode.as_str().into()),
    },
    Entry {
        key: "learner.name",
        kind: Kind::Text,
        doc: "the learner: a built-in's name, or exec:COMMAND for a program (--learner list)",
        set: |s, v| {
            crate::learners::registry::resolve(v)?;
            s.learner_name = v.into();
            Ok(())
        },
        get: |s| toml::Value::String(s.learner_name.clone()),
    },
    Entry {
        key: "exec.answer_timeout_s",
        kind: Kind::Number,
        doc: "how long a learner program may take to answer, s",
        set: |s, v| {
            let t = number(v)?;
            if !(t > 0.0 && t <= 3600.0) {
                return Err(format!("{t} s must be in (0, 3600]"));
            }
            s.answer_timeout_s = t;
            Ok(())
        },
        get: |s| toml::Value::Float(s.answer_timeout_s),
    },
    world_number!(
        "camera.noise_px",
        "reading noise, px (standard deviation)",
        camera.noise_px
    ),
    Entry {
        key: "camera.width_px",
        kind: Kind::Count,
        doc: "image width, px",
        set: |s, v| {
            s.sim.camera.intrinsics.width_px = count(v)?;
            Ok(())
        },
        get: |s| toml::Value::Integer(s.sim.camera.intrinsics.width_px.into()),
    },
    Entry {
        key: "camera.height_px",
        kind: Kind::Count,
        doc: "image height, px",
        set: |s, v| {
            s.sim.camera.intrinsics.height_px = count(v)?;
            Ok(())
        },
        get: |s| toml::Value::Integer(s.sim.camera.intrinsics.height_px.into()),
    },
    world_number!(
        "camera.hfov_deg",
        "horizontal field of view, degrees",
        camera.intrinsics.hfov_deg
    ),
    world_number!(
        "camera.vfov_deg",
        "vertical field of view, degrees",
        camera.intrinsics.vfov_deg
    ),
    world_number!(
        "camera.frame_period_s",
        "time between readings, s",
        camera.frame_period_s
    ),
    Entry {
        key: "camera.blank_s",
        kind: Kind::Text,
        doc: "intervals with no reading, A-B,C-D (s)",
        set: |s, v| {
            s.blank = crate::blanks::Blanks::parse(v, s.duration_s)?;
            Ok(())
        },
        get: |s| toml::Value::String(s.blank.to_text()),
    },
    world_number!(
        "world.friction",
        "the ground's friction coefficient",
        friction
    ),
    world_number!(
        "world.start_distance_m",
        "the robot's start, m from the beacon",
        start_distance_m
    ),
    world_number!(
        "servo.torque_scale",
        "the servos' torque, times the robot's",
        servo.torque_scale
    ),
    world_number!(
        "servo.speed_scale",
        "the servos' speed, times the robot's",
        servo.speed_scale
    ),
    world_number!(
        "beacon.height_m",
        "the beacon's coloured band's height, m",
        beacon.band_height_m
    ),
    world_number!(
        "beacon.centre_m",
        "the band's centre above the ground, m",
        beacon.band_centre_m
    ),
    world_number!("beacon.radius_m", "the beacon's radius, m", beacon.radius_m),
    world_number!("physics.dt", "the physics step, s", dt_s),
];

/// The settings `--set` understands besides a learner's own
/// (`learner.<name>.<key>`): the scenario's, then the shared learner ones.
pub fn setting_keys() -> impl Iterator<Item = String> {
    SETTINGS.iter().map(|e| e.key.to_string()).chain(
        scasm::declaration::SHARED
            .iter()
            .map(|s| format!("learner.{}", s.key)),
    )
}

/// Every setting with its type and a line of doc: what `--set list` prints.
pub fn describe_settings() -> String {
    let defaults = Scenario::paper().ok();
    let mut out = String::new();
    for e in &SETTINGS {
        let value = defaults
            .as_ref()
            .map(e.get)
            .map_or_else(String::new, |v| v.to_string());
        out += &format!(
            "{:<26} {:<7} {:<14} {}\n",
            e.key,
            kind_name(e.kind),
            value,
            e.doc
        );
    }
    for s in &scasm::declaration::SHARED {
        let setting = s.setting(&ScasmConfig::default());
        out += &format!(
            "{:<26} {:<7} {:<14} {} (in {})\n",
            format!("learner.{}", s.key),
            kind_name(if s.kind == scasm::declaration::Kind::Count {
                Kind::Count
            } else {
                Kind::Number
            }),
            setting.default,
            s.doc,
            setting.range()
        );
    }
    out += "learner.<name>.<key>       each learner's own: see --learner list\n";
    out
}

fn kind_name(kind: Kind) -> &'static str {
    match kind {
        Kind::Number => "number",
        Kind::Count => "count",
        Kind::Text => "text",
    }
}

impl LearningMode {
    fn parse(text: &str) -> Result<Self, String> {
        Ok(match text {
            "simultaneous" => Self::Simultaneous,
            "sensor-from-action" => Self::SensorFromAction,
            "action-from-sensor" => Self::ActionFromSensor,
            other => {
                return Err(format!(
                    "`{other}`; known: simultaneous, sensor-from-action, action-from-sensor"
                ));
            }
        })
    }

    fn as_str(self) -> &'static str {
        match self {
            Self::Simultaneous => "simultaneous",
            Self::SensorFromAction => "sensor-from-action",
            Self::ActionFromSensor => "action-from-sensor",
        }
    }
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
            learner_own: BTreeMap::new(),
            answer_timeout_s: crate::learners::exec::ANSWER_TIMEOUT_S,
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
        ordered.sort_by_key(|s| {
            let key = s.split('=').next().unwrap_or("").trim();
            // The learner is named before its own settings are set.
            (
                section_rank(key.split('.').next().unwrap_or("")),
                key != "learner.name",
            )
        });
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
            // A learner's own settings are a table within (`[learner.batch-ml]`);
            // the learner is named first, so that a program's settings are known.
            let mut flat: Vec<(String, &toml::Value)> = Vec::new();
            for (key, value) in entries {
                match value {
                    toml::Value::Table(inner) => {
                        flat.extend(
                            inner
                                .iter()
                                .map(|(k, v)| (format!("{section}.{key}.{k}"), v)),
                        );
                    }
                    v => flat.push((format!("{section}.{key}"), v)),
                }
            }
            flat.sort_by_key(|(full, _)| full != "learner.name");
            for (full, value) in flat {
                // Every learner setting but its name is a number.
                let kind = SETTINGS
                    .iter()
                    .find(|e| e.key == full)
                    .map(|e| e.kind)
                    .or_else(|| full.starts_with("learner.").then_some(Kind::Number));
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
        if let Some(entry) = SETTINGS.iter().find(|e| e.key == key) {
            (entry.set)(self, value).map_err(bad)?;
        } else if let Some(name) = key.strip_prefix("learner.") {
            match name.split_once('.') {
                None => {
                    let shared = scasm::declaration::shared(name).ok_or_else(|| unknown(key))?;
                    let v = shared
                        .setting(&self.learner)
                        .check(number(value).map_err(bad)?)
                        .map_err(bad)?;
                    (shared.set)(&mut self.learner, v);
                }
                Some((learner, own)) => {
                    let v = number(value).map_err(bad)?;
                    self.set_own(learner, own, v).map_err(bad)?;
                }
            }
        } else {
            return Err(unknown(key));
        }
        // Catch range errors at the door, naming the key.
        self.learner.validate().map_err(|e| bad(e.to_string()))?;
        self.sim.validate().map_err(|e| bad(e.to_string()))?;
        // A setting may also make a scheduled change impossible (a trial
        // shorter than it, say).
        self.worlds()?;
        Ok(())
    }

    /// Sets `learner.<learner>.<key>`: a setting that learner declares, in
    /// its range.
    fn set_own(&mut self, learner: &str, key: &str, value: f64) -> Result<(), String> {
        let found = crate::learners::registry::named(learner).ok_or_else(|| {
            format!(
                "no learner is called `{learner}`; known: {} (a program's settings follow \
                 learner.name=exec:... or --learner exec:...)",
                crate::learners::registry::names()
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })?;
        let settings = found.settings();
        let setting = settings.iter().find(|s| s.key == key).ok_or_else(|| {
            let keys: Vec<&str> = settings.iter().map(|s| s.key.as_str()).collect();
            format!(
                "learner `{learner}` has no setting `{key}`; its settings: {}",
                if keys.is_empty() {
                    "none of its own (it reads the shared learner.* ones)".into()
                } else {
                    keys.join(", ")
                }
            )
        })?;
        let v = setting.check(value)?;
        self.learner_own
            .insert(format!("learner.{learner}.{key}"), v);
        Ok(())
    }

    /// The values of `learner`'s own settings in this scenario: each as set,
    /// or its default.
    pub fn own_settings(&self, learner: &crate::learners::registry::Learner) -> Values {
        Values(
            learner
                .settings()
                .into_iter()
                .map(|s| {
                    let full = format!("learner.{}.{}", learner.name(), s.key);
                    let v = self.learner_own.get(&full).copied().unwrap_or(s.default);
                    (s.key, v)
                })
                .collect(),
        )
    }

    fn set_robot_file(&mut self, value: &str) -> Result<(), String> {
        let robot = RobotFile::load(value).map_err(|e| format!("{value}: {e}"))?;
        // Its gait was checked within the legs' reach as it was read.
        let sim = robot.sim_config();
        // The paper's experiment at the robot's scale: its commands, trial
        // length and the learner's time constants scale too.
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
        Ok(())
    }

    fn set_urdf(&mut self, value: &str) -> Result<(), String> {
        let (text, description) = read_urdf(Path::new(value)).map_err(|e| e.to_string())?;
        // A robot that cannot walk the gait is refused here, naming its
        // file, rather than in every trial.
        quadsim::walk::WalkEngine::check_feasible(&self.sim.walk, &description.legs)
            .map_err(|e| format!("{value}: {e}"))?;
        self.description = description;
        self.urdf_text = text;
        self.urdf_path = Some(PathBuf::from(value));
        self.robot_file = None;
        Ok(())
    }

    fn set_duration(&mut self, value: &str) -> Result<(), String> {
        let d = number(value)?;
        if !(d > 0.0 && d <= MAX_DURATION_S) {
            return Err(format!(
                "{d} s must be in (0, {MAX_DURATION_S}]: a trial keeps every 50 ms frame in memory"
            ));
        }
        if let Some(&(_, end)) = self.blank.intervals().last() {
            if end > d {
                return Err(format!(
                    "{d} s ends before camera.blank_s's interval ending at {end} s"
                ));
            }
        }
        self.duration_s = d;
        Ok(())
    }

    /// The value of a setting, as a scenario file writes it.
    pub fn get(&self, key: &str) -> Option<toml::Value> {
        if let Some(entry) = SETTINGS.iter().find(|e| e.key == key) {
            return Some((entry.get)(self));
        }
        let name = key.strip_prefix("learner.")?;
        match name.split_once('.') {
            None => {
                let s = scasm::declaration::shared(name)?;
                let v = (s.get)(&self.learner);
                Some(match s.kind {
                    scasm::declaration::Kind::Count => toml::Value::Integer(v as i64),
                    scasm::declaration::Kind::Number => toml::Value::Float(v),
                })
            }
            Some((learner, own)) => {
                let learner = crate::learners::registry::named(learner)?;
                let s = learner.settings().into_iter().find(|s| s.key == own)?;
                let v = self.learner_own.get(key).copied().unwrap_or(s.default);
                Some(match s.kind {
                    scasm::declaration::Kind::Count => toml::Value::Integer(v as i64),
                    scasm::declaration::Kind::Number => toml::Value::Float(v),
                })
            }
        }
    }

    /// The keys a run records: every setting, the scenario's learner's own
    /// settings, and any other learner's set.
    pub fn recorded_keys(&self) -> Vec<String> {
        let mut keys: Vec<String> = setting_keys().collect();
        if let Ok(learner) = crate::learners::registry::resolve(&self.learner_name) {
            for s in learner.settings() {
                keys.push(format!("learner.{}.{}", learner.name(), s.key));
            }
        }
        for k in self.learner_own.keys() {
            if !keys.contains(k) {
                keys.push(k.clone());
            }
        }
        keys
    }

    /// Every setting as a scenario file (TOML): what a run records as its
    /// `config.toml`, and what `--config` reads back to the same scenario. The
    /// shipped robot's `robot.urdf` is left out (it is the default).
    pub fn to_toml(&self) -> String {
        let mut table = toml::Table::new();
        for key in self.recorded_keys() {
            let Some(value) = self.get(&key) else {
                continue;
            };
            if (key == "robot.urdf" && self.urdf_path.is_none())
                || (key == "robot.file" && self.robot_file.is_none())
            {
                continue;
            }
            // `learner.batch-ml.gamma` is `[learner.batch-ml] gamma = ...`.
            let path: Vec<&str> = key.split('.').collect();
            insert_at(&mut table, &path, value);
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

/// Puts `value` at `path` (`["learner", "batch-ml", "gamma"]`) in nested tables.
fn insert_at(table: &mut toml::Table, path: &[&str], value: toml::Value) {
    match path {
        [] => {}
        [last] => {
            table.insert((*last).into(), value);
        }
        [first, rest @ ..] => {
            let entry = table
                .entry(*first)
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            if let toml::Value::Table(inner) = entry {
                insert_at(inner, rest, value);
            }
        }
    }
}

/// The error for a key no setting has.
fn unknown(key: &str) -> SettingError {
    SettingError::UnknownKey {
        key: key.into(),
        known: format!(
            "{}, and learner.<name>.<key> (--learner list)",
            setting_keys().collect::<Vec<_>>().join(", ")
        ),
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
