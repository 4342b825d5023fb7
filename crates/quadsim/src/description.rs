//! Reading and checking a robot's URDF: the parts the simulator relies on are
//! all there and consistent, or the error says which is not. The legs and
//! camera are named by a [`RobotMap`] (see [`crate::legs`]); each leg's chain
//! is read by `leg_chain.rs`.

use std::collections::BTreeMap;
use std::path::Path;

use urdf_rs::Robot;

use crate::error::RobotError;
use crate::leg_chain::check_leg;
pub use crate::legs::{CameraMount, LEG_NAMES, LegDescription, RobotMap};
use crate::urdf_tree::{check_tree, floating_base, moving_without_mass, parse};

/// A checked robot description.
#[derive(Debug, Clone)]
pub struct RobotDescription {
    /// The parsed URDF.
    pub urdf: Robot,
    /// The root link (the torso).
    pub root_link: String,
    /// The legs, in [`LEG_NAMES`] order.
    pub legs: Vec<LegDescription>,
    /// The camera's mount.
    pub camera: CameraMount,
    /// Sum of all link masses, kg.
    pub total_mass_kg: f64,
    /// The mesh collision shapes, loaded (see [`crate::mesh`]).
    pub meshes: Vec<crate::mesh::MeshCollision>,
    /// What reading the URDF left out, a line each: elements the simulator
    /// does not use (`<gazebo>`, `<transmission>`, ...) and a floating
    /// base's frame (see `urdf_xml.rs` and `urdf_tree.rs`), for a warning
    /// where the robot is named.
    pub notes: Vec<String>,
    /// Each joint's armature, the rotor inertia its gear reflects onto it
    /// (kg m^2), by joint name, where the model file gives one (MJCF's
    /// `armature`; URDF has no place for it). The simulator adds it to the
    /// joint's inertia, as MuJoCo does; its damping and dry friction are the
    /// URDF's `<dynamics>`.
    pub armature: BTreeMap<String, f64>,
}

impl RobotDescription {
    /// Reads and checks a URDF file.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self, RobotError> {
        let path = path.as_ref();
        let text = crate::files::read_text(path, crate::files::URDF_LIMIT).map_err(|e| {
            RobotError::Parse {
                reason: e.to_string(),
            }
        })?;
        let (urdf, notes) = parse(&text)?;
        let map = RobotMap::conventional(&urdf)?;
        Self::checked(
            urdf,
            &map,
            path.parent().unwrap_or_else(|| Path::new("")),
            notes,
        )
    }

    /// Parses and checks URDF text that follows the shipped robot's naming
    /// convention (see [`RobotMap::conventional`]).
    pub fn from_urdf_str(text: &str) -> Result<Self, RobotError> {
        let (urdf, notes) = parse(text)?;
        let map = RobotMap::conventional(&urdf)?;
        Self::checked(urdf, &map, Path::new(""), notes)
    }

    /// Parses and checks URDF text with the legs and camera `map` names.
    pub fn from_urdf_str_with(text: &str, map: &RobotMap) -> Result<Self, RobotError> {
        Self::from_urdf_str_in(text, map, Path::new(""))
    }

    /// Parses and checks URDF text with the legs and camera `map` names, its
    /// meshes' file names relative to `dir`.
    pub fn from_urdf_str_in(text: &str, map: &RobotMap, dir: &Path) -> Result<Self, RobotError> {
        let (urdf, notes) = parse(text)?;
        Self::checked(urdf, map, dir, notes)
    }

    /// Checks a parsed URDF with the legs and camera `map` names (its
    /// meshes' file names relative to the current directory).
    pub fn from_urdf(urdf: Robot, map: &RobotMap) -> Result<Self, RobotError> {
        Self::from_urdf_in(urdf, map, Path::new(""))
    }

    /// Checks a parsed URDF with the legs and camera `map` names, its
    /// meshes' file names relative to `dir`.
    pub fn from_urdf_in(urdf: Robot, map: &RobotMap, dir: &Path) -> Result<Self, RobotError> {
        let (urdf, note) = floating_base(urdf)?;
        Self::checked(urdf, map, dir, note.into_iter().collect())
    }

    /// Checks a URDF read with `notes` (see [`RobotDescription::notes`]).
    fn checked(
        urdf: Robot,
        map: &RobotMap,
        dir: &Path,
        notes: Vec<String>,
    ) -> Result<Self, RobotError> {
        crate::checks::values(&urdf)?;
        crate::checks::rigid_inertia(&urdf)?;
        let root_link = check_tree(&urdf)?;
        let urdf = crate::fold::fold_degenerate_links(&urdf);
        let mut total_mass_kg = 0.0;
        for link in &urdf.links {
            let m = link.inertial.mass.value;
            let i = &link.inertial.inertia;
            // A link with no <inertial> (urdf-rs reads mass 0) carries no
            // mass: a frame, or shapes riding on the body it is fixed to. A
            // body that moves must have mass somewhere in it.
            let massless = m == 0.0 && [i.ixx, i.iyy, i.izz].iter().all(|v| *v == 0.0);
            if massless {
                if let Some(j) = moving_without_mass(&urdf, &link.name) {
                    return Err(RobotError::BadInertia {
                        link: link.name.clone(),
                        reason: format!(
                            "it moves (joint `{j}`) but neither it nor any link fixed to it has \
                             mass"
                        ),
                    });
                }
                continue;
            }
            if !(m.is_finite() && m > 0.0) {
                return Err(RobotError::BadInertia {
                    link: link.name.clone(),
                    reason: format!("mass {m} kg"),
                });
            }
            if !crate::fold::is_body_inertia(i) {
                // Mass on a fixed joint was folded into the body it rides on
                // above; this link's has nowhere to go.
                let [a, b, c] = crate::fold::principal_moments(i);
                let fixed = |j: &&urdf_rs::Joint| matches!(j.joint_type, urdf_rs::JointType::Fixed);
                let why = match urdf.joints.iter().find(|j| j.child.link == link.name) {
                    Some(j) if !fixed(&j) => format!("it moves (joint `{}`)", j.name),
                    _ => "no link fixed to it has a body's inertia to take its mass".into(),
                };
                return Err(RobotError::BadInertia {
                    link: link.name.clone(),
                    reason: format!(
                        "principal moments of inertia ({a:.3e}, {b:.3e}, {c:.3e}) kg m^2 from \
                         ixx {} ixy {} ixz {} iyy {} iyz {} izz {}: no rigid body's (each must be \
                         positive and the smallest over {:e} of the largest). Mass with such an \
                         inertia is folded into the link it is fixed to, but {why}",
                        i.ixx,
                        i.ixy,
                        i.ixz,
                        i.iyy,
                        i.iyz,
                        i.izz,
                        crate::fold::MIN_MOMENT_RATIO
                    ),
                });
            }
            total_mass_kg += m;
        }
        if !total_mass_kg.is_finite() || total_mass_kg <= 0.0 {
            return Err(RobotError::BadInertia {
                link: root_link,
                reason: "the robot has no mass".into(),
            });
        }
        // Every collision shape is simulated or the robot is refused: none
        // is dropped. (Loaded first: a foot may be a mesh.)
        let meshes = crate::mesh::load(&urdf, dir)?;
        let legs = LEG_NAMES
            .iter()
            .zip(&map.legs)
            .map(|(&name, joints)| check_leg(&urdf, &meshes, &root_link, name, joints))
            .collect::<Result<Vec<_>, _>>()?;
        crate::checks::legs(&legs)?;
        let camera = map.camera.clone();
        if !urdf.links.iter().any(|l| l.name == camera.parent) {
            return Err(RobotError::MissingLink {
                link: camera.parent,
            });
        }
        if camera.xyz.iter().chain(&camera.rpy).any(|v| !v.is_finite()) {
            return Err(RobotError::BadCamera {
                reason: format!("mount {:?} {:?} is not finite", camera.xyz, camera.rpy),
            });
        }
        Ok(Self {
            urdf,
            root_link,
            legs,
            camera,
            total_mass_kg,
            meshes,
            notes,
            armature: BTreeMap::new(),
        })
    }

    /// The length of a leg (thigh and shank), m: the robot's size for scaling.
    pub fn leg_length_m(&self) -> f64 {
        self.legs[0].thigh_m + self.legs[0].shank_m
    }
}
