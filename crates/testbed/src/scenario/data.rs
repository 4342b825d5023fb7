//! What a scenario is: everything a trial depends on besides its seed (robot,
//! world, camera, learner settings, trial length), the paper's scenario, and
//! the errors of settings that cannot be applied.

use std::collections::BTreeMap;

use quadsim::{RobotDescription, RobotScale, SimConfig, SimError};
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
    /// The robot file, as named (a shipped robot's name or a path), and its
    /// text (`None`: the default ERS-7).
    pub robot_file: Option<(String, String)>,
    /// The world, robot controllers and camera.
    pub sim: SimConfig,
    /// Which world the trials walk in (`trial.world`): the robot in rapier,
    /// or the synthetic point robot with `sim`'s camera and start.
    pub world: crate::world::WorldKind,
    /// The learner's name (see [`crate::learners`]).
    pub learner_name: String,
    /// The training behaviour's name (`behaviour.name`, see
    /// [`crate::behaviour::registry`]).
    pub behaviour_name: &'static str,
    /// The `design` behaviour's extra degree (`behaviour.design_extra_degree`).
    pub behaviour_design_extra_degree: usize,
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

impl Scenario {
    /// The paper's experiment on the shipped robot, with the default learner
    /// (the paper's constants and a sensor reading window of 5, which the
    /// paper does not have).
    pub fn paper() -> Result<Self, SimError> {
        let urdf_text = quadsim::ERS7_URDF.to_string();
        Ok(Self {
            description: RobotDescription::from_urdf_str(&urdf_text).map_err(SimError::from)?,
            urdf_text,
            robot_file: None,
            sim: SimConfig::default(),
            world: crate::world::WorldKind::Rapier,
            learner_name: crate::learners::registry::DEFAULT.into(),
            behaviour_name: crate::behaviour::registry::DEFAULT,
            behaviour_design_extra_degree: crate::behaviour::design::EXTRA_DEGREE,
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
