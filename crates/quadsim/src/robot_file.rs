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
//! ```

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::description::{CameraMount, RobotDescription, RobotMap};
use crate::error::RobotError;

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
    /// The checked robot.
    pub description: RobotDescription,
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
        Self::build(&label, None, text, file, urdf_text.to_string())
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
        let text = std::fs::read_to_string(path).map_err(|e| RobotError::RobotFile {
            file: label.clone(),
            reason: format!("cannot read it: {e}"),
        })?;
        let file = parse(&label, &text)?;
        let urdf_path = path
            .parent()
            .unwrap_or_else(|| Path::new(""))
            .join(&file.urdf);
        let urdf_text = std::fs::read_to_string(&urdf_path).map_err(|e| RobotError::RobotFile {
            file: label.clone(),
            reason: format!("cannot read its URDF {}: {e}", urdf_path.display()),
        })?;
        Self::build(&label, Some(path.to_path_buf()), &text, file, urdf_text)
    }

    fn build(
        label: &str,
        path: Option<PathBuf>,
        text: &str,
        file: FileToml,
        urdf_text: String,
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
        let description = RobotDescription::from_urdf_str_with(&urdf_text, &map).map_err(|e| {
            RobotError::RobotFile {
                file: format!("{label} (URDF {})", file.urdf.display()),
                reason: e.to_string(),
            }
        })?;
        Ok(Self {
            name: file.name,
            path,
            text: text.to_string(),
            urdf_text,
            description,
        })
    }
}

fn parse(label: &str, text: &str) -> Result<FileToml, RobotError> {
    toml::from_str(text).map_err(|e| RobotError::RobotFile {
        file: label.to_string(),
        reason: e.to_string(),
    })
}
