//! The one table of a scenario's settings: each key with its type, a line of
//! doc, and how it is written and read. The learners' settings (`learner.*`)
//! come from their declarations. `--set`, scenario files, a run's
//! `config.toml` and `--set list` all read this table.

use quadsim::{RobotFile, RobotScale};
use scasm::ScasmConfig;

use crate::scenario::data::{
    LearningMode, MAX_DURATION_S, PAPER_DURATION_S, Scenario, SettingError,
};

/// A setting's type, as a scenario file writes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    Number,
    Count,
    Text,
}

/// One setting of the scenario: its key, type and a line of doc, and how it
/// is written and read. [`SETTINGS`] and the learners' declarations are the
/// one table that `--set`, scenario files, a run's `config.toml` and
/// `--set list` all read.
pub(crate) struct Entry {
    pub(crate) key: &'static str,
    pub(crate) kind: Kind,
    pub(crate) doc: &'static str,
    /// The values it takes, in words; `None` for a setting of the world,
    /// whose range is the world's own check ([`quadsim::SimConfig::ranges`]).
    pub(crate) range: Option<&'static str>,
    pub(crate) set: fn(&mut Scenario, &str) -> Result<(), String>,
    pub(crate) get: fn(&Scenario) -> toml::Value,
}

pub(crate) fn number(value: &str) -> Result<f64, String> {
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
            range: None,
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
pub(crate) const SETTINGS: [Entry; 31] = [
    Entry {
        key: "robot.file",
        kind: Kind::Text,
        doc: "a robot file (a shipped robot's name or a path): its URDF, gait and scale",
        range: Some(
            "a shipped robot's name (ers7, trotter), or a robot file's, URDF's or MJCF's path",
        ),
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
        doc: "a URDF file, as robot.file takes it (kept for older scenario files)",
        range: Some("a URDF's path"),
        set: Scenario::set_robot_file,
        // Recorded as robot.file.
        get: |_| toml::Value::String(String::new()),
    },
    Entry {
        key: "trial.duration",
        kind: Kind::Number,
        doc: "trial length, s",
        range: Some("(0, 86400] s, and past the last camera.blank_s interval"),
        set: Scenario::set_duration,
        get: |s| toml::Value::Float(s.duration_s),
    },
    Entry {
        key: "trial.world",
        kind: Kind::Text,
        doc: "the world the trials walk in: the robot in rapier, or a point robot with no physics",
        range: Some("rapier, synthetic"),
        set: |s, v| {
            s.world = crate::world::WorldKind::parse(v)?;
            Ok(())
        },
        get: |s| toml::Value::String(s.world.name().into()),
    },
    Entry {
        key: "trial.seeds",
        kind: Kind::Text,
        doc: "the seeds of a run's trials, A..B (B excluded)",
        range: Some("A..B with A < B, at most 1,000,000 seeds"),
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
        range: Some("simultaneous, sensor-from-action, action-from-sensor"),
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
        range: Some("a built-in learner's name, or exec:COMMAND"),
        set: |s, v| {
            crate::learners::registry::resolve(v)?;
            s.learner_name = v.into();
            Ok(())
        },
        get: |s| toml::Value::String(s.learner_name.clone()),
    },
    Entry {
        key: "behaviour.name",
        kind: Kind::Text,
        doc: "the training behaviour: what chooses each walk command (--behaviour list)",
        range: Some("a behaviour's name"),
        set: |s, v| {
            s.behaviour_name = crate::behaviour::registry::resolve(v)?.name;
            Ok(())
        },
        get: |s| toml::Value::String(s.behaviour_name.into()),
    },
    Entry {
        key: "behaviour.design_extra_degree",
        kind: Kind::Count,
        doc: "the design behaviour's polynomial: this many degrees above the action model's",
        range: Some("0 to 8"),
        set: |s, v| {
            let n: usize = count(v)?;
            if n > crate::behaviour::design::MAX_EXTRA_DEGREE {
                return Err(format!(
                    "{n} is more than {}",
                    crate::behaviour::design::MAX_EXTRA_DEGREE
                ));
            }
            s.behaviour_design_extra_degree = n;
            Ok(())
        },
        get: |s| toml::Value::Integer(s.behaviour_design_extra_degree as i64),
    },
    Entry {
        key: "exec.answer_timeout_s",
        kind: Kind::Number,
        doc: "how long a learner program may take to answer, s",
        range: Some("(0, 3600] s"),
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
        range: None,
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
        range: None,
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
        range: Some("intervals A-B, comma-separated, within the trial"),
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
        "servo.kp",
        "the servos' stiffness, N m/rad (the robot's: the ERS-7's 12, scaled with its size)",
        servo.kp_nm_per_rad
    ),
    world_number!(
        "servo.kd",
        "the servos' damping, N m s/rad (the robot's: the ERS-7's 0.15, scaled with its size)",
        servo.kd_nm_s_per_rad
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
        "walk.command_slew",
        "how fast the walk engine's command in effect may follow a new command, (mm/s) per s",
        walk.command_slew_mm_s2
    ),
    world_number!(
        "walk.pitch_gain",
        "how much of the torso's pitch the legs take out (0: the walk is open loop)",
        walk.pitch_gain
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
    Entry {
        key: "physics.solver_iterations",
        kind: Kind::Count,
        doc: "the constraint solver's iterations a step (1; more, e.g. 4, if the physics blows up)",
        range: None,
        set: |s, v| {
            s.sim.solver_iterations = count::<usize>(v)?;
            Ok(())
        },
        get: |s| toml::Value::Integer(s.sim.solver_iterations.try_into().unwrap_or(i64::MAX)),
    },
    Entry {
        key: "physics.multibody",
        kind: Kind::Text,
        doc: "how the robot's multibody is stepped: tree (composite rigid bodies, factored along \
              the tree, Coriolis explicit), rapier (rapier's own, Coriolis semi-implicit)",
        range: Some("tree, rapier"),
        set: |s, v| {
            s.sim.multibody = quadsim::MultibodyDynamics::parse(v)?;
            Ok(())
        },
        get: |s| toml::Value::String(s.sim.multibody.as_str().into()),
    },
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

/// Every setting with its type, default, range and doc, as a Markdown table:
/// the book's reference page (`scripts/reference.sh`). A setting of the world
/// whose range the table does not state is checked only for being a finite
/// number here; the world checks it when it is built.
pub fn describe_settings_markdown() -> String {
    let defaults = Scenario::paper().ok();
    let mut out =
        String::from("| key | type | default | range | meaning |\n|---|---|---|---|---|\n");
    let row = |key: &str, kind: Kind, default: String, range: &str, doc: &str| {
        format!(
            "| `{key}` | {} | {} | {range} | {} |\n",
            kind_name(kind),
            if default.is_empty() {
                "-".into()
            } else {
                format!("`{default}`")
            },
            doc.replace('|', "\\|")
        )
    };
    for e in &SETTINGS {
        let value = defaults
            .as_ref()
            .map(e.get)
            .map_or_else(String::new, |v| v.to_string());
        let range = e.range.map(String::from).unwrap_or_else(|| {
            quadsim::SimConfig::default()
                .ranges()
                .iter()
                .find(|r| r.0 == e.key)
                .map_or_else(|| "any finite number".into(), |r| r.3.to_string())
        });
        out += &row(e.key, e.kind, value, &range, e.doc);
    }
    for s in &scasm::declaration::SHARED {
        let setting = s.setting(&ScasmConfig::default());
        let kind = if s.kind == scasm::declaration::Kind::Count {
            Kind::Count
        } else {
            Kind::Number
        };
        out += &row(
            &format!("learner.{}", s.key),
            kind,
            setting.default.to_string(),
            &setting.range(),
            s.doc,
        );
    }
    out += "| `learner.<name>.<key>` | - | - | - | each learner's own: see [Learners and their settings](learners.md) |\n";
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
    fn set_robot_file(&mut self, value: &str) -> Result<(), String> {
        let robot = RobotFile::load(value).map_err(|e| format!("{value}: {e}"))?;
        // What reading its URDF left out (elements the simulator does not
        // use, a ROS footprint frame): a line each, where the user sees it.
        for note in &robot.description.notes {
            eprintln!("warning: {value}: {note}");
        }
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
        self.robot_file = Some((value.into(), robot.text));
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
}

/// The error for a key no setting has.
pub(crate) fn unknown(key: &str) -> SettingError {
    SettingError::UnknownKey {
        key: key.into(),
        known: format!(
            "{}, and learner.<name>.<key> (--learner list)",
            setting_keys().collect::<Vec<_>>().join(", ")
        ),
    }
}

/// The robot of a URDF file.
/// The most seeds one run may take: a million trials of 150 s is some days of
/// a large cluster's time.
pub const MAX_SEEDS: u64 = 1_000_000;

/// Seeds written `A..B` (B excluded, at least one and at most `MAX_SEEDS`).
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
    if b - a > MAX_SEEDS {
        return Err(format!(
            "`{text}` holds {} seeds: a run takes at most {MAX_SEEDS} (split it into several)",
            b - a
        ));
    }
    Ok((a, b))
}
