//! Reading and checking the robot's URDF: the parts the simulator relies on are
//! all there and consistent, or the error says which is not.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use urdf_rs::{Geometry, JointType, Robot};

use crate::error::RobotError;
use crate::ik::LegGeometry;

/// The four legs, in the order the simulator uses everywhere.
pub const LEG_NAMES: [&str; 4] = ["fl", "fr", "hl", "hr"];

/// One leg as the URDF describes it.
#[derive(Debug, Clone, PartialEq)]
pub struct LegDescription {
    /// `fl`, `fr`, `hl` or `hr`.
    pub name: &'static str,
    /// The abduction joint's position in the torso frame, m.
    pub hip_in_torso_m: [f64; 3],
    /// Segment lengths (the knee direction is the gait's choice).
    pub thigh_m: f64,
    /// Knee to foot centre, m.
    pub shank_m: f64,
    /// Radius of the spherical foot, m.
    pub foot_radius_m: f64,
    /// Joint names: abduction, hip, knee.
    pub joints: [String; 3],
    /// Joint limits `[lower, upper]`, rad, in the same order.
    pub limits_rad: [[f64; 2]; 3],
    /// Torque limits from the URDF, N m, in the same order.
    pub effort_nm: [f64; 3],
    /// Joint speed limits from the URDF, rad/s, in the same order.
    pub velocity_rad_s: [f64; 3],
}

impl LegDescription {
    /// The leg's geometry for inverse kinematics, with the knee bending `knee_sign`.
    pub fn geometry(&self, knee_sign: f64) -> LegGeometry {
        LegGeometry {
            thigh_m: self.thigh_m,
            shank_m: self.shank_m,
            knee_sign,
        }
    }

    /// `+1` for a left leg, `-1` for a right one.
    pub fn side(&self) -> f64 {
        if self.hip_in_torso_m[1] >= 0.0 {
            1.0
        } else {
            -1.0
        }
    }

    /// Whether this is a front leg.
    pub fn is_front(&self) -> bool {
        self.hip_in_torso_m[0] > 0.0
    }
}

/// A checked robot description.
#[derive(Debug, Clone)]
pub struct RobotDescription {
    /// The parsed URDF.
    pub urdf: Robot,
    /// The legs, in [`LEG_NAMES`] order.
    pub legs: Vec<LegDescription>,
    /// The camera frame in the head link's frame: translation (m) and roll, pitch,
    /// yaw (rad).
    pub camera_in_head: ([f64; 3], [f64; 3]),
    /// Sum of all link masses, kg.
    pub total_mass_kg: f64,
}

impl RobotDescription {
    /// Reads and checks a URDF file.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self, RobotError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| RobotError::Io {
            path: path.display().to_string(),
            source,
        })?;
        Self::from_urdf_str(&text)
    }

    /// Parses and checks URDF text.
    pub fn from_urdf_str(text: &str) -> Result<Self, RobotError> {
        let urdf = urdf_rs::read_from_string(text).map_err(|e| RobotError::Parse {
            reason: e.to_string(),
        })?;
        check_tree(&urdf)?;
        let mut total_mass_kg = 0.0;
        for link in &urdf.links {
            let m = link.inertial.mass.value;
            let i = &link.inertial.inertia;
            let frame_only = link.collision.is_empty() && m == 0.0;
            if frame_only {
                continue;
            }
            if !(m.is_finite() && m > 0.0) {
                return Err(RobotError::BadInertia {
                    link: link.name.clone(),
                    reason: format!("mass {m} kg"),
                });
            }
            if ![i.ixx, i.iyy, i.izz]
                .iter()
                .all(|v| v.is_finite() && *v > 0.0)
            {
                return Err(RobotError::BadInertia {
                    link: link.name.clone(),
                    reason: format!("principal inertia ({}, {}, {})", i.ixx, i.iyy, i.izz),
                });
            }
            total_mass_kg += m;
        }
        let legs = LEG_NAMES
            .iter()
            .map(|&name| check_leg(&urdf, name))
            .collect::<Result<Vec<_>, _>>()?;
        let camera_in_head = check_camera(&urdf)?;
        Ok(Self {
            urdf,
            legs,
            camera_in_head,
            total_mass_kg,
        })
    }
}

fn link_names(urdf: &Robot) -> Result<HashSet<&str>, RobotError> {
    let mut names = HashSet::new();
    for l in &urdf.links {
        if !names.insert(l.name.as_str()) {
            return Err(RobotError::DuplicateLink {
                link: l.name.clone(),
            });
        }
    }
    Ok(names)
}

/// Every joint names existing links, every link but the torso has exactly one
/// parent, and every link is reachable from the torso.
fn check_tree(urdf: &Robot) -> Result<(), RobotError> {
    let names = link_names(urdf)?;
    for required in ["torso", "head", "camera"] {
        if !names.contains(required) {
            return Err(RobotError::MissingLink {
                link: required.into(),
            });
        }
    }
    let mut parent_of: HashMap<&str, &str> = HashMap::new();
    for j in &urdf.joints {
        for link in [&j.parent.link, &j.child.link] {
            if !names.contains(link.as_str()) {
                return Err(RobotError::DanglingJoint {
                    joint: j.name.clone(),
                    link: link.clone(),
                });
            }
        }
        if parent_of.insert(&j.child.link, &j.parent.link).is_some() {
            return Err(RobotError::NotATree {
                link: j.child.link.clone(),
                reason: "it is the child of more than one joint",
            });
        }
    }
    if parent_of.contains_key("torso") {
        return Err(RobotError::NotATree {
            link: "torso".into(),
            reason: "the root must not have a parent",
        });
    }
    for &link in &names {
        let (mut at, mut steps) = (link, 0);
        while at != "torso" {
            at = parent_of
                .get(at)
                .copied()
                .ok_or_else(|| RobotError::NotATree {
                    link: link.into(),
                    reason: "it is not connected to the torso",
                })?;
            steps += 1;
            if steps > names.len() {
                return Err(RobotError::NotATree {
                    link: link.into(),
                    reason: "its joints form a cycle",
                });
            }
        }
    }
    Ok(())
}

fn joint<'a>(urdf: &'a Robot, name: &str) -> Result<&'a urdf_rs::Joint, RobotError> {
    urdf.joints
        .iter()
        .find(|j| j.name == name)
        .ok_or_else(|| RobotError::MissingJoint { joint: name.into() })
}

fn bad_joint(joint: &str, reason: String) -> RobotError {
    RobotError::BadJoint {
        joint: joint.into(),
        reason,
    }
}

fn check_leg(urdf: &Robot, name: &'static str) -> Result<LegDescription, RobotError> {
    let names = [
        format!("{name}_abduction"),
        format!("{name}_hip"),
        format!("{name}_knee"),
    ];
    let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let mut joints = Vec::with_capacity(3);
    let mut limits_rad = [[0.0; 2]; 3];
    let mut effort_nm = [0.0; 3];
    let mut velocity_rad_s = [0.0; 3];
    for (k, jn) in names.iter().enumerate() {
        let j = joint(urdf, jn)?;
        if !matches!(j.joint_type, JointType::Revolute) {
            return Err(bad_joint(
                jn,
                format!("must be revolute, is {:?}", j.joint_type),
            ));
        }
        let axis = j.axis.xyz.0;
        if axis.iter().zip(&axes[k]).any(|(a, b)| (a - b).abs() > 1e-9) {
            return Err(bad_joint(
                jn,
                format!("axis must be {:?}, is {axis:?}", axes[k]),
            ));
        }
        let (lo, hi) = (j.limit.lower, j.limit.upper);
        if !(lo.is_finite() && hi.is_finite() && lo < 0.0 && hi > 0.0) {
            return Err(bad_joint(
                jn,
                format!("limits must satisfy lower < 0 < upper, are [{lo}, {hi}]"),
            ));
        }
        if !(j.limit.effort.is_finite() && j.limit.effort > 0.0) {
            return Err(bad_joint(
                jn,
                format!("effort must be > 0, is {}", j.limit.effort),
            ));
        }
        if !(j.limit.velocity.is_finite() && j.limit.velocity > 0.0) {
            return Err(bad_joint(
                jn,
                format!("velocity limit must be > 0, is {}", j.limit.velocity),
            ));
        }
        limits_rad[k] = [lo, hi];
        effort_nm[k] = j.limit.effort;
        velocity_rad_s[k] = j.limit.velocity;
        joints.push(j);
    }
    // The chain: torso -> abduction -> hip -> knee.
    if joints[0].parent.link != "torso" {
        return Err(bad_joint(&names[0], "its parent must be `torso`".into()));
    }
    for k in 1..3 {
        if joints[k].parent.link != joints[k - 1].child.link {
            return Err(bad_joint(
                &names[k],
                format!("its parent must be `{}`", joints[k - 1].child.link),
            ));
        }
    }
    let [hip_origin, knee_origin] = [&joints[1].origin, &joints[2].origin];
    if hip_origin.xyz.0.iter().any(|v| v.abs() > 1e-9) {
        return Err(bad_joint(
            &names[1],
            "must sit at the abduction joint".into(),
        ));
    }
    let knee = knee_origin.xyz.0;
    if knee[0].abs() > 1e-9 || knee[1].abs() > 1e-9 || knee[2] >= 0.0 {
        return Err(bad_joint(
            &names[2],
            "must sit straight below the hip".into(),
        ));
    }
    let shank_link = &joints[2].child.link;
    let shank = urdf
        .links
        .iter()
        .find(|l| &l.name == shank_link)
        .ok_or_else(|| RobotError::MissingLink {
            link: shank_link.clone(),
        })?;
    let foot = shank
        .collision
        .iter()
        .find_map(|c| match c.geometry {
            Geometry::Sphere { radius } if radius > 0.0 => Some((c.origin.xyz.0, radius)),
            _ => None,
        })
        .ok_or_else(|| RobotError::MissingFoot {
            link: shank_link.clone(),
        })?;
    if foot.0[0].abs() > 1e-9 || foot.0[1].abs() > 1e-9 || foot.0[2] >= 0.0 {
        return Err(RobotError::MissingFoot {
            link: shank_link.clone(),
        });
    }
    Ok(LegDescription {
        name,
        hip_in_torso_m: joints[0].origin.xyz.0,
        thigh_m: -knee[2],
        shank_m: -foot.0[2],
        foot_radius_m: foot.1,
        joints: names,
        limits_rad,
        effort_nm,
        velocity_rad_s,
    })
}

/// The camera's pose in the head frame, following fixed joints from the head.
fn check_camera(urdf: &Robot) -> Result<([f64; 3], [f64; 3]), RobotError> {
    let j = urdf
        .joints
        .iter()
        .find(|j| j.child.link == "camera")
        .ok_or(RobotError::CameraNotOnHead)?;
    if j.parent.link != "head" || !matches!(j.joint_type, JointType::Fixed) {
        return Err(RobotError::CameraNotOnHead);
    }
    Ok((j.origin.xyz.0, j.origin.rpy.0))
}
