//! A robot file: a URDF plus what the URDF cannot say (which joints form each
//! leg, where the camera sits), in TOML. `assets/robots/*.toml` are the shipped
//! robots; a file anywhere names its URDF relative to itself.
//!
//! ```toml
//! name = "trotter"
//! urdf = "trotter.urdf"            # relative to this file
//! [legs]                           # abduction, hip, knee
//! front_left = ["fl_hip_roll", "fl_hip_pitch", "fl_knee_pitch"]
//! front_right = ["fr_hip_roll", "fr_hip_pitch", "fr_knee_pitch"]
//! rear_left = ["hl_hip_roll", "hl_hip_pitch", "hl_knee_pitch"]
//! rear_right = ["hr_hip_roll", "hr_hip_pitch", "hr_knee_pitch"]
//! [camera]
//! parent = "trunk"                 # the link it is fixed to
//! xyz = [0.2, 0.0, 0.03]           # m, in the parent's frame
//! rpy = [0.0, 0.0, 0.0]            # rad (optional); optical axis +x, image up +z
//! [gait]                           # optional: the robot's own gait (see below)
//! v_max_mm_s = 520.0
//! [gait.fast_forwards]
//! period_s = 0.45
//! ```
//!
//! Without `[gait]`, a robot walks the ERS-7's gait scaled to its size
//! ([`crate::RobotScale`]), at the cadence the walk test finds
//! ([`crate::cadence`]). `[gait] cadence = F` quickens (F < 1) or slows the
//! scaled gait's periods and step lengths together, and skips the test; so
//! does any `period_s`. `[gait]` replaces any of the scaled values, in the
//! robot's own units: `v_max_mm_s` and `v_min_mm_s` (the commands Eq. 1's fast
//! walks stand for), and in `[gait.idle]`, `[gait.fast_forwards]` and
//! `[gait.fast_backwards]` any field of [`GaitParams`] (`step_length_m`,
//! `step_height_m`, `period_s`, `body_height_m`, `stance_width_m`,
//! `duty_factor`, `foot_offset_m`).

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::config::SimConfig;
use crate::description::RobotDescription;
use crate::error::RobotError;
use crate::gait::{GaitParams, GaitTable};
use crate::legs::{CameraMount, RobotMap};

/// The shipped robots: name, robot file, URDF file name and URDF text.
const SHIPPED: [(&str, &str, &str); 2] = [
    (
        "ers7",
        include_str!("../../../assets/robots/ers7.toml"),
        include_str!("../../../assets/ers7.urdf"),
    ),
    (
        "trotter",
        include_str!("../../../assets/robots/trotter.toml"),
        include_str!("../../../assets/robots/trotter.urdf"),
    ),
];

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileToml {
    name: String,
    urdf: PathBuf,
    legs: LegsToml,
    camera: CameraToml,
    #[serde(default)]
    gait: GaitOverrides,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct LegsToml {
    front_left: [String; 3],
    front_right: [String; 3],
    rear_left: [String; 3],
    rear_right: [String; 3],
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraToml {
    parent: String,
    xyz: [f64; 3],
    #[serde(default)]
    rpy: [f64; 3],
}

/// A robot file's `[gait]`: values that replace the scaled ERS-7 gait's, in
/// the robot's own units (absent: keep the scaled value).
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaitOverrides {
    /// The scaled gait's periods and step lengths times this
    /// ([`crate::cadence::quicken`]) before any value below replaces them;
    /// absent, and with no `period_s` given, the walk test finds it
    /// ([`crate::cadence::fit`]).
    pub cadence: Option<f64>,
    /// Eq. 1's `v_max`, mm/s (> 0).
    pub v_max_mm_s: Option<f64>,
    /// Eq. 1's `v_min`, mm/s (< 0).
    pub v_min_mm_s: Option<f64>,
    /// `p_i`'s fields.
    #[serde(default)]
    pub idle: ParamOverrides,
    /// `p_f`'s fields.
    #[serde(default)]
    pub fast_forwards: ParamOverrides,
    /// `p_b`'s fields.
    #[serde(default)]
    pub fast_backwards: ParamOverrides,
}

/// Replacements for some of a [`GaitParams`]' fields.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)] // each is the `GaitParams` field of the same name
pub struct ParamOverrides {
    pub step_length_m: Option<f64>,
    pub step_height_m: Option<f64>,
    pub period_s: Option<f64>,
    pub body_height_m: Option<f64>,
    pub stance_width_m: Option<f64>,
    pub duty_factor: Option<f64>,
    pub foot_offset_m: Option<f64>,
}

impl ParamOverrides {
    fn apply(&self, p: &mut GaitParams) {
        let set = |slot: &mut f64, value: Option<f64>| *slot = value.unwrap_or(*slot);
        set(&mut p.step_length_m, self.step_length_m);
        set(&mut p.step_height_m, self.step_height_m);
        set(&mut p.period_s, self.period_s);
        set(&mut p.body_height_m, self.body_height_m);
        set(&mut p.stance_width_m, self.stance_width_m);
        set(&mut p.duty_factor, self.duty_factor);
        set(&mut p.foot_offset_m, self.foot_offset_m);
    }
}

impl GaitOverrides {
    /// `table` with these values in place.
    pub fn apply(&self, table: GaitTable) -> GaitTable {
        let mut t = crate::cadence::quicken(table, self.cadence.unwrap_or(1.0));
        t.v_max_mm_s = self.v_max_mm_s.unwrap_or(t.v_max_mm_s);
        t.v_min_mm_s = self.v_min_mm_s.unwrap_or(t.v_min_mm_s);
        self.idle.apply(&mut t.idle);
        self.fast_forwards.apply(&mut t.fast_forwards);
        self.fast_backwards.apply(&mut t.fast_backwards);
        t
    }
}

/// One check of a gait's value: its key, the value, whether it is allowed,
/// and what to say if not.
type Rule = (String, f64, fn(f64) -> bool, &'static str);

/// What is wrong with a gait, as `(key, reason)`: every value finite, the
/// periods, heights and `v_max` positive, `v_min` negative, the duty factors
/// in (0, 1), the step heights not negative, and the fast walks' steps
/// forwards and backwards.
fn check_gait(t: &GaitTable) -> Result<(), (String, &'static str)> {
    const ANY: fn(f64) -> bool = |_| true;
    const POSITIVE: fn(f64) -> bool = |v| v > 0.0;
    const NEGATIVE: fn(f64) -> bool = |v| v < 0.0;
    let mut rules: Vec<Rule> = vec![
        (
            "v_max_mm_s".into(),
            t.v_max_mm_s,
            POSITIVE,
            "must be positive",
        ),
        (
            "v_min_mm_s".into(),
            t.v_min_mm_s,
            NEGATIVE,
            "must be negative",
        ),
    ];
    for (walk, p, step, step_reason) in [
        ("idle", &t.idle, ANY, ""),
        (
            "fast_forwards",
            &t.fast_forwards,
            POSITIVE,
            "must be positive (a step forwards)",
        ),
        (
            "fast_backwards",
            &t.fast_backwards,
            NEGATIVE,
            "must be negative (a step backwards)",
        ),
    ] {
        let key = |field: &str| format!("{walk}.{field}");
        rules.extend([
            (key("step_length_m"), p.step_length_m, step, step_reason),
            (key("period_s"), p.period_s, POSITIVE, "must be positive"),
            (
                key("body_height_m"),
                p.body_height_m,
                POSITIVE,
                "must be positive",
            ),
            (
                key("step_height_m"),
                p.step_height_m,
                |v| v >= 0.0,
                "must not be negative",
            ),
            (
                key("duty_factor"),
                p.duty_factor,
                |v| v > 0.0 && v < 1.0,
                "must be in (0, 1)",
            ),
            (key("stance_width_m"), p.stance_width_m, ANY, ""),
            (key("foot_offset_m"), p.foot_offset_m, ANY, ""),
        ]);
    }
    for (key, value, ok, reason) in rules {
        if !value.is_finite() {
            return Err((key, "must be a finite number"));
        }
        if !ok(value) {
            return Err((key, reason));
        }
    }
    Ok(())
}

/// A robot read from a robot file and its URDF.
#[derive(Debug, Clone)]
pub struct RobotFile {
    /// The robot's name (the file's `name`).
    pub name: String,
    /// Where the robot file was read from (`None`: a shipped robot).
    pub path: Option<PathBuf>,
    /// The robot file's text.
    pub text: String,
    /// The URDF's text.
    pub urdf_text: String,
    /// The folder its mesh file names are relative to.
    pub urdf_dir: PathBuf,
    /// The checked robot.
    pub description: RobotDescription,
    /// The file's `[gait]`, with the cadence the walk test found if the file
    /// gave none.
    pub gait: GaitOverrides,
    /// What the walk test found, if it ran (see [`crate::cadence`]).
    pub cadence_fit: Option<crate::cadence::Cadence>,
}

impl RobotFile {
    /// The names of the shipped robots (`assets/robots/<name>.toml`).
    pub fn shipped_names() -> impl Iterator<Item = &'static str> {
        SHIPPED.iter().map(|(name, ..)| *name)
    }

    /// A shipped robot by name.
    pub fn shipped(name: &str) -> Result<Self, RobotError> {
        let (_, text, urdf_text) =
            SHIPPED
                .iter()
                .find(|(n, ..)| *n == name)
                .ok_or_else(|| RobotError::RobotFile {
                    file: format!("{name} (a shipped robot)"),
                    reason: format!(
                        "no such robot; shipped: {}",
                        Self::shipped_names().collect::<Vec<_>>().join(", ")
                    ),
                })?;
        let label = format!("assets/robots/{name}.toml");
        let file = parse(&label, text)?;
        Self::build(
            &label,
            None,
            text,
            file,
            urdf_text.to_string(),
            BesideUrdf::default(),
        )
    }

    /// A shipped robot's name, or a robot file's path.
    pub fn load(name_or_path: &str) -> Result<Self, RobotError> {
        if Self::shipped_names().any(|n| n == name_or_path) {
            Self::shipped(name_or_path)
        } else {
            Self::from_file(Path::new(name_or_path))
        }
    }

    /// Reads a robot file and the URDF it names (relative to the file).
    pub fn from_file(path: &Path) -> Result<Self, RobotError> {
        let label = path.display().to_string();
        let text = crate::files::read_text(
            path,
            crate::files::SETTINGS_LIMIT.max(crate::files::URDF_LIMIT),
        )
        .map_err(|e| RobotError::RobotFile {
            file: label.clone(),
            reason: e.to_string(),
        })?;
        if text.trim_start().starts_with('<') {
            let (urdf_text, beside) = urdf_text_of(path, text)?;
            return Self::from_bare_urdf(path, urdf_text, beside);
        }
        let file = parse(&label, &text)?;
        let urdf_path = path
            .parent()
            .unwrap_or_else(|| Path::new(""))
            .join(&file.urdf);
        let urdf_text =
            crate::files::read_text(&urdf_path, crate::files::URDF_LIMIT).map_err(|e| {
                RobotError::RobotFile {
                    file: label.clone(),
                    reason: format!("its URDF: {e}"),
                }
            })?;
        let (urdf_text, beside) = urdf_text_of(&urdf_path, urdf_text)?;
        Self::build(
            &label,
            Some(path.to_path_buf()),
            &text,
            file,
            urdf_text,
            beside,
        )
    }

    /// A bare URDF as a robot: its legs and camera found from its tree
    /// ([`crate::discover`]), the scaled default gait. Its robot file is the
    /// one that says what was found (see [`RobotFile::text`]).
    fn from_bare_urdf(
        path: &Path,
        urdf_text: String,
        beside: BesideUrdf,
    ) -> Result<Self, RobotError> {
        let label = path.display().to_string();
        let in_file = |e: RobotError| RobotError::RobotFile {
            file: label.clone(),
            reason: e.to_string(),
        };
        let (urdf, _) = crate::urdf_tree::parse(&urdf_text).map_err(in_file)?;
        let map = crate::discover::discover(&urdf).map_err(in_file)?;
        // Checked here, where the user's URDF is named: the robot file below
        // is the project's own writing, and TOML has no NaN to write.
        let camera = &map.camera;
        if camera.xyz.iter().chain(&camera.rpy).any(|v| !v.is_finite()) {
            return Err(in_file(RobotError::BadCamera {
                reason: format!(
                    "its camera joint's origin {:?} {:?} is not finite",
                    camera.xyz, camera.rpy
                ),
            }));
        }
        let file_name = path
            .file_name()
            .map_or_else(|| label.clone(), |n| n.to_string_lossy().into_owned());
        let [fl, fr, hl, hr] = map.legs.clone();
        let text = format!(
            "# Found from the URDF's tree (no robot file was given).\nname = {name:?}\nurdf = \
             {file_name:?}\n\n[legs]\nfront_left = {fl:?}\nfront_right = {fr:?}\nrear_left = \
             {hl:?}\nrear_right = {hr:?}\n\n[camera]\nparent = {parent:?}\nxyz = {xyz:?}\nrpy = \
             {rpy:?}\n",
            name = urdf.name,
            parent = map.camera.parent,
            xyz = map.camera.xyz,
            rpy = map.camera.rpy,
        );
        let file = parse(&label, &text)?;
        let mut robot = Self::build(
            &label,
            Some(path.to_path_buf()),
            &text,
            file,
            urdf_text,
            beside,
        )?;
        if let Some(fit) = &robot.cadence_fit {
            robot.text.push_str(&format!(
                "\n[gait]\n# Found by the walk test (quadsim::cadence).\n{}cadence = {:?}\n",
                fit.rejected
                    .iter()
                    .map(|(f, why)| format!("# cadence {f:?}: {why}\n"))
                    .collect::<String>(),
                fit.factor
            ));
        }
        Ok(robot)
    }

    fn build(
        label: &str,
        path: Option<PathBuf>,
        text: &str,
        file: FileToml,
        urdf_text: String,
        beside: BesideUrdf,
    ) -> Result<Self, RobotError> {
        let map = RobotMap {
            legs: [
                file.legs.front_left,
                file.legs.front_right,
                file.legs.rear_left,
                file.legs.rear_right,
            ],
            camera: CameraMount {
                parent: file.camera.parent,
                xyz: file.camera.xyz,
                rpy: file.camera.rpy,
            },
        };
        let urdf_dir = path
            .as_deref()
            .and_then(Path::parent)
            .unwrap_or_else(|| Path::new(""))
            .join(file.urdf.parent().unwrap_or_else(|| Path::new("")));
        let mut description = RobotDescription::from_urdf_str_in(&urdf_text, &map, &urdf_dir)
            .map_err(|e| RobotError::RobotFile {
                file: format!("{label} (URDF {})", file.urdf.display()),
                reason: e.to_string(),
            })?;
        let mut gait = file.gait;
        beside.apply(&mut description, &mut gait);
        Self {
            name: file.name,
            path,
            text: text.to_string(),
            urdf_text,
            urdf_dir,
            description,
            gait,
            cadence_fit: None,
        }
        .checked(label)?
        .with_cadence(label)
    }

    /// Whether the walk test chooses this robot's cadence: its file gives
    /// neither a cadence nor any period, and the robot is not the ERS-7's
    /// size and mass (whose gait the defaults are).
    fn needs_cadence_fit(&self) -> bool {
        let g = &self.gait;
        let periods = [g.idle, g.fast_forwards, g.fast_backwards].map(|p| p.period_s);
        g.cadence.is_none()
            && periods.iter().all(Option::is_none)
            && crate::RobotScale::of(&self.description) != crate::RobotScale::ONE
    }

    /// `self` with the cadence the walk test finds, if it chooses it
    /// ([`Self::needs_cadence_fit`]); an error listing every cadence's
    /// failure if none walks.
    fn with_cadence(mut self, label: &str) -> Result<Self, RobotError> {
        if !self.needs_cadence_fit() {
            return Ok(self);
        }
        let bad = |reason: String| RobotError::RobotFile {
            file: label.to_string(),
            reason,
        };
        let fitted = crate::cadence::fit(&self.description, |factor| {
            let mut file = self.clone();
            file.gait.cadence = Some(factor);
            file.sim_config()
        })
        .map_err(|e| bad(format!("the walk test could not run: {e}")))?;
        match fitted {
            Ok(cadence) => {
                self.gait.cadence = Some(cadence.factor);
                self.cadence_fit = Some(cadence);
                self.checked(label)
            }
            Err(failures) => Err(bad(format!(
                "the gait scaled from the ERS-7's does not walk this robot at any cadence tried \
                 ({}); give its own gait (periods and step lengths) under [gait] in a robot file",
                failures
                    .iter()
                    .map(|(f, why)| format!("cadence {f}: {why}"))
                    .collect::<Vec<_>>()
                    .join("; ")
            ))),
        }
    }

    /// The URDF as text for a copy written elsewhere: its mesh file names
    /// made absolute (see [`crate::mesh::with_absolute_meshes`]).
    pub fn urdf_text_elsewhere(&self) -> Result<String, RobotError> {
        let urdf = crate::mesh::with_absolute_meshes(&self.description.urdf, &self.urdf_dir);
        urdf_rs::write_to_string(&urdf).map_err(|e| RobotError::Parse {
            reason: e.to_string(),
        })
    }

    /// The robot's settings: the defaults scaled to its size
    /// ([`SimConfig::for_robot`]), then its `[gait]`.
    pub fn sim_config(&self) -> SimConfig {
        let mut config = SimConfig::for_robot(&self.description);
        config.walk.gait = self.gait.apply(config.walk.gait);
        config
    }

    /// `self` if its gait is valid and within the legs' reach and joint limits.
    fn checked(self, label: &str) -> Result<Self, RobotError> {
        let bad = |reason: String| RobotError::RobotFile {
            file: label.to_string(),
            reason,
        };
        if let Some(c) = self.gait.cadence {
            // Below 0.1 a stride takes ten times the scaled gait's: no walk.
            if !(0.1..=2.0).contains(&c) {
                return Err(bad(format!("gait.cadence must be in [0.1, 2], got {c}")));
            }
        }
        let config = self.sim_config();
        check_gait(&config.walk.gait)
            .map_err(|(key, reason)| bad(format!("gait.{key} {reason}")))?;
        crate::walk::WalkEngine::check_feasible(&config.walk, &self.description.legs)
            .map_err(|e| bad(format!("its gait: {e}")))?;
        Ok(self)
    }
}

/// What reading a model file into URDF found that URDF cannot say.
#[derive(Default)]
struct BesideUrdf {
    /// What was left out, a line each (see [`RobotDescription::notes`]).
    notes: Vec<String>,
    /// The joints' armature (see [`RobotDescription::armature`]).
    armature: std::collections::BTreeMap<String, f64>,
    /// The joints' standing angles (see [`crate::mjcf::Mjcf::standing`]).
    standing: std::collections::BTreeMap<String, f64>,
}

impl BesideUrdf {
    /// Gives `description`, read from the URDF, what the model file said
    /// beside it, and `gait` the standing pose's stance where it gives none.
    fn apply(self, description: &mut RobotDescription, gait: &mut GaitOverrides) {
        description.notes.splice(0..0, self.notes);
        description.armature = self.armature;
        if self.standing.is_empty() {
            return;
        }
        let Some(stance) = crate::stance::Stance::at(description, &self.standing) else {
            description.notes.push(
                "the keyframe's pose does not put every foot below its hip: the robot stands in \
                 its gait's own pose"
                    .into(),
            );
            return;
        };
        let mut used = false;
        for p in [
            &mut gait.idle,
            &mut gait.fast_forwards,
            &mut gait.fast_backwards,
        ] {
            used |= p.body_height_m.is_none() || p.stance_width_m.is_none();
            p.body_height_m.get_or_insert(stance.body_height_m);
            p.stance_width_m.get_or_insert(stance.stance_width_m);
        }
        if used {
            description.notes.push(format!(
                "the gait stands as the keyframe does: feet {:.4} m below the hips and {:.4} m \
                 outwards (body_height_m, stance_width_m; a robot file's [gait] can say otherwise)",
                stance.body_height_m, stance.stance_width_m
            ));
        }
    }
}

/// A robot's model file's text as URDF: URDF as it is, MJCF read into URDF
/// (see [`crate::mjcf`]) with what URDF cannot say.
fn urdf_text_of(path: &Path, text: String) -> Result<(String, BesideUrdf), RobotError> {
    if !crate::mjcf::is_mjcf(&text) {
        return Ok((text, BesideUrdf::default()));
    }
    let in_file = |e: RobotError| RobotError::RobotFile {
        file: path.display().to_string(),
        reason: e.to_string(),
    };
    let model = crate::mjcf::read(path).map_err(in_file)?;
    let urdf = urdf_rs::write_to_string(&model.urdf).map_err(|e| {
        in_file(RobotError::Parse {
            reason: e.to_string(),
        })
    })?;
    Ok((
        urdf,
        BesideUrdf {
            notes: model.notes,
            armature: model.armature,
            standing: model.standing,
        },
    ))
}

fn parse(label: &str, text: &str) -> Result<FileToml, RobotError> {
    toml::from_str(text).map_err(|e| RobotError::RobotFile {
        file: label.to_string(),
        reason: e.to_string(),
    })
}
