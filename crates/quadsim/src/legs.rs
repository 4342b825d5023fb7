//! What the simulator needs of a robot beyond its URDF's links: the four
//! legs (which joints form each, with their geometry once read) and the
//! camera's mount. A [`RobotMap`] names the joints (a robot file's job, see
//! [`crate::robot_file`]; a URDF alone follows the shipped robot's naming
//! convention); a [`LegDescription`] is one leg as the URDF describes it.

use urdf_rs::{JointType, Robot};

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
