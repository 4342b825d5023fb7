//! Reading and checking a robot's URDF: the parts the simulator relies on are
//! all there and consistent, or the error says which is not. A [`RobotMap`]
//! says which joints form each leg and where the camera sits (a robot file's
//! job, see [`crate::robot_file`]); a URDF alone follows the shipped robot's
//! naming convention.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use urdf_rs::{Geometry, JointType, Robot};

use crate::error::RobotError;
use crate::ik::LegGeometry;

/// The four legs, in the order the simulator uses everywhere.
pub const LEG_NAMES: [&str; 4] = ["fl", "fr", "hl", "hr"];

/// What the URDF cannot say: which joints form each leg and where the camera is.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotMap {
    /// Each leg's joints (abduction, hip, knee), in [`LEG_NAMES`] order.
    pub legs: [[String; 3]; 4],
    /// The camera's mount.
    pub camera: CameraMount,
}

/// Where the camera sits: a link, and the camera frame in that link's frame
/// (optical axis +x, image up +z).
#[derive(Debug, Clone, PartialEq)]
pub struct CameraMount {
    /// The link the camera is fixed to.
    pub parent: String,
    /// Translation in the parent's frame, m.
    pub xyz: [f64; 3],
    /// Roll, pitch, yaw in the parent's frame, rad.
    pub rpy: [f64; 3],
}

impl RobotMap {
    /// The shipped robot's convention: joints `{fl,fr,hl,hr}_{abduction,hip,knee}`
    /// and a `camera` link fixed directly to `head`.
    pub fn conventional(urdf: &Robot) -> Result<Self, RobotError> {
        let legs = LEG_NAMES.map(|name| {
            [
                format!("{name}_abduction"),
                format!("{name}_hip"),
                format!("{name}_knee"),
            ]
        });
        if !urdf.links.iter().any(|l| l.name == "camera") {
            return Err(RobotError::MissingLink {
                link: "camera".into(),
            });
        }
        let j = urdf
            .joints
            .iter()
            .find(|j| j.child.link == "camera")
            .ok_or(RobotError::CameraNotOnHead)?;
        if j.parent.link != "head" || !matches!(j.joint_type, JointType::Fixed) {
            return Err(RobotError::CameraNotOnHead);
        }
        Ok(Self {
            legs,
            camera: CameraMount {
                parent: "head".into(),
                xyz: j.origin.xyz.0,
                rpy: j.origin.rpy.0,
            },
        })
    }
}

/// One leg as the URDF describes it.
#[derive(Debug, Clone, PartialEq)]
pub struct LegDescription {
    /// `fl`, `fr`, `hl` or `hr`.
    pub name: &'static str,
    /// The abduction joint's position in the torso frame, m.
    pub hip_in_torso_m: [f64; 3],
    /// The leg's plane's sideways offset from the abduction joint, m
    /// (positive: left; 0 when the hip, knee and foot sit on the abduction
    /// axis's plane): the hip's, knee's and foot's offsets along y summed.
    pub hip_offset_m: f64,
    /// The hip joint's position from the abduction joint, forwards and up,
    /// m (0 and 0 when it sits on the abduction axis or beside it).
    pub hip_at_m: [f64; 2],
    /// Hip to knee in the leg's plane, m.
    pub thigh_m: f64,
    /// Knee to foot centre in the leg's plane, m.
    pub shank_m: f64,
    /// The thigh's direction at the zero pose, from straight down, positive
    /// backwards (a rotation about +y), rad: 0 for a thigh that hangs down,
    /// pi/2 for one that points backwards.
    pub thigh_zero_rad: f64,
    /// The shank's angle to the thigh's line at the zero pose (about +y),
    /// rad: 0 for a straight leg.
    pub knee_zero_rad: f64,
    /// Radius of the spherical foot, m.
    pub foot_radius_m: f64,
    /// Joint names: abduction, hip, knee.
    pub joints: [String; 3],
    /// Joint limits `[lower, upper]`, rad, in the same order, about the
    /// canonical axes (abduction +x, hip and knee +y).
    pub limits_rad: [[f64; 2]; 3],
    /// Each joint's URDF axis against its canonical one: 1, or -1 for an
    /// axis that points the other way (an angle about the canonical axis is
    /// this times the joint's own).
    pub axis_signs: [f64; 3],
    /// Torque limits from the URDF, N m, in the same order (infinite for a
    /// continuous joint that gives none).
    pub effort_nm: [f64; 3],
    /// Joint speed limits from the URDF, rad/s, in the same order (infinite
    /// for a continuous joint that gives none).
    pub velocity_rad_s: [f64; 3],
}

impl LegDescription {
    /// The leg's geometry for inverse kinematics, with the knee bending `knee_sign`.
    pub fn geometry(&self, knee_sign: f64) -> LegGeometry {
        LegGeometry {
            thigh_m: self.thigh_m,
            shank_m: self.shank_m,
            hip_offset_m: self.hip_offset_m,
            knee_sign,
            hip_at_m: self.hip_at_m,
            thigh_zero_rad: self.thigh_zero_rad,
            knee_zero_rad: self.knee_zero_rad,
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

    /// Which way the knee bends from the straight leg: the way its URDF
    /// range allows if the range lies on one side of straight (a knee that
    /// is never straight), or mostly on one side (less than half as much
    /// room, up to half a turn, on the other), else front knees like elbows
    /// (-1) and hind knees like knees (+1).
    pub fn knee_sign(&self) -> f64 {
        let [lower, upper] = self.limits_rad[2].map(|v| v + self.knee_zero_rad);
        let half_turn = std::f64::consts::PI;
        let (forwards, backwards) = (upper.clamp(0.0, half_turn), (-lower).clamp(0.0, half_turn));
        if forwards < 0.5 * backwards {
            -1.0
        } else if backwards < 0.5 * forwards {
            1.0
        } else if self.is_front() {
            -1.0
        } else {
            1.0
        }
    }
}

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
        let urdf = parse(&text)?;
        let map = RobotMap::conventional(&urdf)?;
        Self::from_urdf_in(urdf, &map, path.parent().unwrap_or_else(|| Path::new("")))
    }

    /// Parses and checks URDF text that follows the shipped robot's naming
    /// convention (see [`RobotMap::conventional`]).
    pub fn from_urdf_str(text: &str) -> Result<Self, RobotError> {
        let urdf = parse(text)?;
        let map = RobotMap::conventional(&urdf)?;
        Self::from_urdf(urdf, &map)
    }

    /// Parses and checks URDF text with the legs and camera `map` names.
    pub fn from_urdf_str_with(text: &str, map: &RobotMap) -> Result<Self, RobotError> {
        Self::from_urdf(parse(text)?, map)
    }

    /// Parses and checks URDF text with the legs and camera `map` names, its
    /// meshes' file names relative to `dir`.
    pub fn from_urdf_str_in(text: &str, map: &RobotMap, dir: &Path) -> Result<Self, RobotError> {
        Self::from_urdf_in(parse(text)?, map, dir)
    }

    /// Checks a parsed URDF with the legs and camera `map` names (its
    /// meshes' file names relative to the current directory).
    pub fn from_urdf(urdf: Robot, map: &RobotMap) -> Result<Self, RobotError> {
        Self::from_urdf_in(urdf, map, Path::new(""))
    }

    /// Checks a parsed URDF with the legs and camera `map` names, its
    /// meshes' file names relative to `dir`.
    pub fn from_urdf_in(urdf: Robot, map: &RobotMap, dir: &Path) -> Result<Self, RobotError> {
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
        })
    }

    /// The length of a leg (thigh and shank), m: the robot's size for scaling.
    pub fn leg_length_m(&self) -> f64 {
        self.legs[0].thigh_m + self.legs[0].shank_m
    }
}

/// URDF text parsed (by urdf-rs, after its nesting is checked: see
/// [`crate::files::check_xml`]).
pub(crate) fn parse(text: &str) -> Result<Robot, RobotError> {
    crate::files::check_xml(text).map_err(|reason| RobotError::Parse { reason })?;
    urdf_rs::read_from_string(text).map_err(|e| RobotError::Parse {
        reason: e.to_string(),
    })
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

/// Every joint names existing links, every link but the root has exactly one
/// parent, and every link is reachable from the root (the first link without a
/// parent): returns the root.
pub(crate) fn check_tree(urdf: &Robot) -> Result<String, RobotError> {
    let names = link_names(urdf)?;
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
    let root = urdf
        .links
        .iter()
        .map(|l| l.name.as_str())
        .find(|l| !parent_of.contains_key(l))
        .ok_or_else(|| RobotError::NotATree {
            link: urdf
                .links
                .first()
                .map_or_else(String::new, |l| l.name.clone()),
            reason: "no link is without a parent, so there is no root",
        })?;
    for &link in &names {
        let (mut at, mut steps) = (link, 0);
        while at != root {
            at = parent_of
                .get(at)
                .copied()
                .ok_or_else(|| RobotError::NotATree {
                    link: link.into(),
                    reason: "it is not connected to the root (the first link without a parent)",
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
    Ok(root.to_string())
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

/// The fixed joints from link `from` down to link `to`, in that order (none
/// if they are the same link), or `None` if `to` is not `from` or fixed
/// below it.
fn fixed_path<'a>(urdf: &'a Robot, from: &str, to: &str) -> Option<Vec<&'a urdf_rs::Joint>> {
    let mut path = Vec::new();
    let mut at = to;
    while at != from {
        let j = urdf
            .joints
            .iter()
            .find(|j| j.child.link == at && matches!(j.joint_type, JointType::Fixed))?;
        path.push(j);
        at = &j.parent.link;
    }
    path.reverse();
    Some(path)
}

/// The link `name` and every link rigidly fixed to it: joined through fixed
/// joints only, up or down the tree (a camera's link, its housing, the body
/// it is bolted to), `name` first and the rest in URDF joint order.
pub(crate) fn rigidly_fixed(urdf: &Robot, name: &str) -> Vec<String> {
    let mut out = vec![name.to_string()];
    let mut k = 0;
    while k < out.len() {
        for j in urdf
            .joints
            .iter()
            .filter(|j| matches!(j.joint_type, JointType::Fixed))
        {
            let other = if j.parent.link == out[k] {
                &j.child.link
            } else if j.child.link == out[k] {
                &j.parent.link
            } else {
                continue;
            };
            if !out.contains(other) {
                out.push(other.clone());
            }
        }
        k += 1;
    }
    out
}

/// How far a joint's axis may be from its canonical direction (or its
/// opposite), component by component.
const AXIS_TOLERANCE: f64 = 1e-4;

fn check_leg(
    urdf: &Robot,
    meshes: &[crate::mesh::MeshCollision],
    root: &str,
    name: &'static str,
    names: &[String; 3],
) -> Result<LegDescription, RobotError> {
    let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let mut joints = Vec::with_capacity(3);
    let mut limits_rad = [[0.0; 2]; 3];
    let mut effort_nm = [0.0; 3];
    let mut velocity_rad_s = [0.0; 3];
    let mut axis_signs = [1.0; 3];
    // The zero pose, in the root's orientation: each joint's frame turned by
    // the origins' rotations so far, and the offsets from joint to joint.
    // The chain: root -> abduction -> hip -> knee, with links fixed between.
    let mut turn = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut abduction_at = [0.0; 3];
    let mut offsets = [[0.0; 3]; 2];
    let mut above = root.to_string();
    for (k, jn) in names.iter().enumerate() {
        let j = joint(urdf, jn)?;
        let continuous = matches!(j.joint_type, JointType::Continuous);
        if !matches!(j.joint_type, JointType::Revolute) && !continuous {
            return Err(bad_joint(
                jn,
                format!("must be revolute or continuous, is {:?}", j.joint_type),
            ));
        }
        let fixed = fixed_path(urdf, &above, &j.parent.link).ok_or_else(|| {
            bad_joint(
                jn,
                format!("its parent must be `{above}` or a link fixed to it"),
            )
        })?;
        // From the joint above (or the root) through the fixed links to this
        // joint, in the root's orientation.
        let mut from_above = [0.0; 3];
        for f in &fixed {
            let step = rotate(&turn, f.origin.xyz.0);
            from_above = [0, 1, 2].map(|i| from_above[i] + step[i]);
            turn = compose(&turn, &rpy_matrix(f.origin.rpy.0));
        }
        let own = rotate(&turn, j.origin.xyz.0);
        let at = if fixed.is_empty() {
            // As written (no sums: the ERS-7's geometry to the bit).
            if k == 0 { j.origin.xyz.0 } else { own }
        } else {
            [0, 1, 2].map(|i| from_above[i] + own[i])
        };
        if k == 0 {
            abduction_at = at;
        } else {
            offsets[k - 1] = at;
        }
        above.clone_from(&j.child.link);
        turn = compose(&turn, &rpy_matrix(j.origin.rpy.0));
        // An axis may point either way along its canonical one, in the root
        // link's frame (to within the rounding of angles written to a few
        // digits, as 1.5708 for a quarter turn: 1e-4).
        let axis = rotate(&turn, j.axis.xyz.0);
        let along = |sign: f64| {
            axis.iter()
                .zip(&axes[k])
                .all(|(a, b)| (a - sign * b).abs() <= AXIS_TOLERANCE)
        };
        let axis_sign = if along(1.0) {
            1.0
        } else if along(-1.0) {
            -1.0
        } else {
            return Err(bad_joint(
                jn,
                format!(
                    "axis must be {:?} or its opposite in the root link's frame, is {axis:?}",
                    axes[k]
                ),
            ));
        };
        // A continuous joint has no limits: the gait's own range is its range.
        // A revolute joint's range need not hold its zero (a knee that is
        // never straight): the gait is checked against it as the robot is read.
        let (lo, hi) = if continuous {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            (j.limit.lower, j.limit.upper)
        };
        let ranged = lo.is_finite() && hi.is_finite() && lo < hi;
        if !(continuous || ranged) {
            return Err(bad_joint(
                jn,
                format!("limits must be finite with lower < upper, are [{lo}, {hi}]"),
            ));
        }
        // A continuous joint's <limit> is optional: with none (urdf-rs reads
        // 0), its servo is limited in neither torque nor speed.
        let given = |v: f64| {
            if continuous && v == 0.0 {
                f64::INFINITY
            } else {
                v
            }
        };
        let (effort, velocity) = (given(j.limit.effort), given(j.limit.velocity));
        if effort.is_nan() || effort <= 0.0 || (effort.is_infinite() && !continuous) {
            return Err(bad_joint(
                jn,
                format!("effort must be > 0, is {}", j.limit.effort),
            ));
        }
        if velocity.is_nan() || velocity <= 0.0 || (velocity.is_infinite() && !continuous) {
            return Err(bad_joint(
                jn,
                format!("velocity limit must be > 0, is {}", j.limit.velocity),
            ));
        }
        // About the canonical axis, the range is the joint's, mirrored if
        // its axis points the other way.
        limits_rad[k] = if axis_sign > 0.0 {
            [lo, hi]
        } else {
            [-hi, -lo]
        };
        axis_signs[k] = axis_sign;
        effort_nm[k] = effort;
        velocity_rad_s[k] = velocity;
        joints.push(j);
    }
    let [hip, knee] = offsets;
    let shank_link = &joints[2].child.link;
    let shank = urdf
        .links
        .iter()
        .find(|l| &l.name == shank_link)
        .ok_or_else(|| RobotError::MissingLink {
            link: shank_link.clone(),
        })?;
    let (foot, foot_radius_m) = find_foot(urdf, shank, [0.0; 3], turn)
        .or_else(|| foot_link(urdf, meshes, shank, turn))
        .ok_or_else(|| RobotError::MissingFoot {
            link: shank_link.clone(),
        })?;
    // A direction in the leg's plane from straight down, positive backwards
    // (a plain zero, not -0, for a segment that hangs straight down).
    let from_down = |v: [f64; 3]| {
        let a = (-v[0]).atan2(-v[2]);
        if a == 0.0 { 0.0 } else { a }
    };
    let (thigh_m, shank_m) = (knee[0].hypot(knee[2]), foot[0].hypot(foot[2]));
    if !(thigh_m > 1e-6 && thigh_m.is_finite()) {
        return Err(bad_joint(
            &names[2],
            format!("must sit away from the hip's axis, sits at {knee:?} m from the hip"),
        ));
    }
    if !(shank_m > 1e-6 && shank_m.is_finite()) {
        return Err(RobotError::MissingFoot {
            link: shank_link.clone(),
        });
    }
    let thigh_zero_rad = from_down(knee);
    let knee_zero_rad = from_down(foot) - thigh_zero_rad;
    Ok(LegDescription {
        name,
        hip_in_torso_m: abduction_at,
        hip_offset_m: hip[1] + knee[1] + foot[1],
        hip_at_m: [hip[0], hip[2]],
        thigh_m,
        shank_m,
        thigh_zero_rad,
        knee_zero_rad,
        foot_radius_m,
        joints: names.clone(),
        limits_rad,
        axis_signs,
        effort_nm,
        velocity_rad_s,
    })
}

/// A 3 x 3 rotation matrix, row-major.
type Rotation = [[f64; 3]; 3];

/// URDF's roll-pitch-yaw (fixed axes x, y, z): `Rz(yaw) Ry(pitch) Rx(roll)`.
pub(crate) fn rpy_matrix([r, p, y]: [f64; 3]) -> Rotation {
    let (sr, cr, sp, cp, sy, cy) = (r.sin(), r.cos(), p.sin(), p.cos(), y.sin(), y.cos());
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

fn rotate(m: &Rotation, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

/// A URDF origin (`xyz`, and `rpy` about the fixed x, y and z axes:
/// `Rz(yaw) Ry(pitch) Rx(roll)`) as a rapier pose.
pub(crate) fn urdf_pose(xyz: [f64; 3], rpy: [f64; 3]) -> rapier3d::math::Pose {
    use rapier3d::math::{Pose, Real, Rotation, Vector};
    let [x, y, z] = xyz.map(|v| v as Real);
    let [roll, pitch, yaw] = rpy.map(|v| v as Real);
    Pose::from_parts(
        Vector::new(x, y, z),
        Rotation::from_euler(rapier3d::glamx::EulerRot::ZYX, yaw, pitch, roll),
    )
}

/// `v`, a point in a joint's child frame, in its parent's frame.
pub(crate) fn place(origin: &urdf_rs::Pose, v: [f64; 3]) -> [f64; 3] {
    let r = rotate(&rpy_matrix(origin.rpy.0), v);
    [0, 1, 2].map(|i| origin.xyz.0[i] + r[i])
}

fn compose(a: &Rotation, b: &Rotation) -> Rotation {
    [0, 1, 2].map(|i| [0, 1, 2].map(|k| (0..3).map(|j| a[i][j] * b[j][k]).sum()))
}

/// The foot: the first sphere collision on `link`, or on a link fixed to it
/// (a toe, as many published URDFs have), as its centre in the frame where
/// `link` sits at `at` turned by `turn`, and its radius.
fn find_foot(
    urdf: &Robot,
    link: &urdf_rs::Link,
    at: [f64; 3],
    turn: Rotation,
) -> Option<([f64; 3], f64)> {
    let place = |v: [f64; 3]| {
        let r = rotate(&turn, v);
        [at[0] + r[0], at[1] + r[1], at[2] + r[2]]
    };
    let own = link.collision.iter().find_map(|c| match c.geometry {
        Geometry::Sphere { radius } if radius > 0.0 => Some((place(c.origin.xyz.0), radius)),
        _ => None,
    });
    own.or_else(|| {
        urdf.joints
            .iter()
            .filter(|j| j.parent.link == link.name && matches!(j.joint_type, JointType::Fixed))
            .find_map(|j| {
                let child = urdf.links.iter().find(|l| l.name == j.child.link)?;
                let turn = compose(&turn, &rpy_matrix(j.origin.rpy.0));
                find_foot(urdf, child, place(j.origin.xyz.0), turn)
            })
    })
}

/// A foot that is not a sphere: the link fixed below `shank` (a toe or foot
/// link, as Unitree's Go2 and ODRI's Solo 12 have, with a mesh, box,
/// cylinder or capsule) whose shapes' centre is farthest from the knee,
/// taken as the sphere inside its shapes' bounds: centred on the bounds,
/// with half their smallest extent as radius (a ball's hull gives the ball).
/// In the frame where `shank` sits at the origin turned by `turn`.
fn foot_link(
    urdf: &Robot,
    meshes: &[crate::mesh::MeshCollision],
    shank: &urdf_rs::Link,
    turn: Rotation,
) -> Option<([f64; 3], f64)> {
    // Every link fixed below the shank, with where it sits and how it turns.
    let below: Vec<(usize, [f64; 3], Rotation)> = fixed_to(urdf, &shank.name)
        .into_iter()
        .skip(1)
        .map(|(k, at, own)| (k, rotate(&turn, at), compose(&turn, &own)))
        .collect();
    let mut best: Option<([f64; 3], f64, f64)> = None;
    for (k, at, turn) in below {
        let corners = shape_corners(&urdf.links[k], k, meshes);
        if corners.is_empty() {
            continue;
        }
        let placed: Vec<[f64; 3]> = corners
            .iter()
            .map(|&v| {
                let r = rotate(&turn, v);
                [at[0] + r[0], at[1] + r[1], at[2] + r[2]]
            })
            .collect();
        let lo = [0, 1, 2].map(|i| placed.iter().map(|p| p[i]).fold(f64::INFINITY, f64::min));
        let hi = [0, 1, 2].map(|i| {
            placed
                .iter()
                .map(|p| p[i])
                .fold(f64::NEG_INFINITY, f64::max)
        });
        let centre = [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i]));
        let radius = (0..3)
            .map(|i| 0.5 * (hi[i] - lo[i]))
            .fold(f64::INFINITY, f64::min);
        let reach = centre.iter().map(|v| v * v).sum::<f64>().sqrt();
        if radius > 0.0 && radius.is_finite() && best.is_none_or(|b| reach > b.2) {
            best = Some((centre, radius, reach));
        }
    }
    best.map(|(centre, radius, _)| (centre, radius))
}

/// The link `name` and every link fixed below it (by fixed joints, to any
/// depth): each link's index, with where its frame sits and how it turns in
/// `name`'s frame; `name` first, at the origin, unturned.
fn fixed_to(urdf: &Robot, name: &str) -> Vec<(usize, [f64; 3], Rotation)> {
    let Some(first) = urdf.links.iter().position(|l| l.name == name) else {
        return Vec::new();
    };
    let identity = rpy_matrix([0.0; 3]);
    let mut out = vec![(first, [0.0; 3], identity)];
    let mut frontier = vec![(name.to_string(), [0.0; 3], identity)];
    while let Some((name, at, turn)) = frontier.pop() {
        for j in urdf
            .joints
            .iter()
            .filter(|j| j.parent.link == name && matches!(j.joint_type, JointType::Fixed))
        {
            let Some(k) = urdf.links.iter().position(|l| l.name == j.child.link) else {
                continue;
            };
            let r = rotate(&turn, j.origin.xyz.0);
            let here = [at[0] + r[0], at[1] + r[1], at[2] + r[2]];
            let turned = compose(&turn, &rpy_matrix(j.origin.rpy.0));
            out.push((k, here, turned));
            frontier.push((j.child.link.clone(), here, turned));
        }
    }
    out
}

/// The corners of the boxes bounding each collision shape of `link` (index
/// `k`), in its frame: a box's own, a cylinder's or capsule's bounding box,
/// a mesh's hull's bounds.
fn shape_corners(
    link: &urdf_rs::Link,
    k: usize,
    meshes: &[crate::mesh::MeshCollision],
) -> Vec<[f64; 3]> {
    let box_corners = |half: [f64; 3], origin: &urdf_rs::Pose| -> Vec<[f64; 3]> {
        let turn = rpy_matrix(origin.rpy.0);
        (0..8)
            .map(|c| {
                let v = [0, 1, 2].map(|i| if c >> i & 1 == 1 { half[i] } else { -half[i] });
                let r = rotate(&turn, v);
                [0, 1, 2].map(|i| origin.xyz.0[i] + r[i])
            })
            .collect()
    };
    let mut out = Vec::new();
    for c in &link.collision {
        let half = match c.geometry {
            Geometry::Box { size } => size.0.map(|v| 0.5 * v),
            Geometry::Cylinder { radius, length } => [radius, radius, 0.5 * length],
            Geometry::Capsule { radius, length } => [radius, radius, 0.5 * length + radius],
            Geometry::Sphere { radius } => [radius; 3],
            Geometry::Mesh { .. } => continue,
        };
        out.extend(box_corners(half, &c.origin));
    }
    for m in meshes.iter().filter(|m| m.link == k) {
        for (shape, pose) in &m.parts {
            let aabb = shape.compute_aabb(pose);
            let (lo, hi) = (aabb.mins, aabb.maxs);
            let centre = urdf_rs::Pose {
                xyz: urdf_rs::Vec3([0, 1, 2].map(|i| 0.5 * f64::from(lo[i] + hi[i]))),
                rpy: urdf_rs::Vec3([0.0; 3]),
            };
            let half = [0, 1, 2].map(|i| 0.5 * f64::from(hi[i] - lo[i]));
            out.extend(box_corners(half, &centre));
        }
    }
    out
}

/// The joint that moves `link`, if `link` is moved by a joint (not fixed to
/// its parent) and neither it nor any link fixed below it has mass.
fn moving_without_mass(urdf: &Robot, link: &str) -> Option<String> {
    let joint = urdf.joints.iter().find(|j| j.child.link == link)?;
    if matches!(joint.joint_type, JointType::Fixed) {
        return None;
    }
    fn has_mass(urdf: &Robot, link: &str) -> bool {
        let own = urdf
            .links
            .iter()
            .any(|l| l.name == link && l.inertial.mass.value > 0.0);
        own || urdf.joints.iter().any(|j| {
            j.parent.link == link
                && matches!(j.joint_type, JointType::Fixed)
                && has_mass(urdf, &j.child.link)
        })
    }
    (!has_mass(urdf, link)).then(|| joint.name.clone())
}
