//! A scenario: everything a trial depends on besides its seed (robot, world,
//! camera, learner settings, trial length), built from defaults, a scenario file
//! and `key=value` settings, each checked at the door.

use std::path::Path;

use quadsim::{RobotDescription, SimConfig, SimError};
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
pub const SETTING_KEYS: [&str; 20] = [
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
    "servo.torque_scale",
    "servo.speed_scale",
    "world.start_distance_m",
    "beacon.height_m",
    "beacon.centre_m",
    "beacon.radius_m",
    "trial.duration",
];

impl Scenario {
    /// The paper's experiment on the shipped robot, with the default learner
    /// (the paper's constants and a sensor reading window of 5, which the
    /// paper does not have).
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

    /// [`Scenario::paper`] with the robot of `urdf` (default: the shipped one),
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
            "servo.torque_scale" => self.sim.servo.torque_scale = number()?,
            "servo.speed_scale" => self.sim.servo.speed_scale = number()?,
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
    /// controllers, camera and the protocols; not the learner).
    pub fn reference_key(&self) -> String {
        crate::reference::key(self)
    }
}
