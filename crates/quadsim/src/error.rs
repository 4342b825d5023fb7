//! Typed errors of the simulator: what is wrong, and where.

/// A robot description that cannot be used, with what is wrong in it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RobotError {
    /// The file could not be read.
    #[error("cannot read robot description {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// A number of the URDF that no physical robot has (see
    /// [`crate::checks`]).
    #[error("URDF {element}: {reason}")]
    BadValue {
        /// The element: `link `NAME`` or `joint `NAME``.
        element: String,
        /// The value, and what it must be.
        reason: String,
    },
    /// An MJCF element that cannot be read (see [`crate::mjcf`]).
    #[error("MJCF {at}: {reason}")]
    Mjcf {
        /// The element and where it is written: `<geom> at go2.xml line 40`.
        at: String,
        /// What is wrong.
        reason: String,
    },
    /// The text is not valid URDF.
    #[error("malformed URDF: {reason}")]
    Parse {
        /// The parser's message.
        reason: String,
    },
    /// A link the robot needs is not there.
    #[error("URDF has no link named `{link}`")]
    MissingLink {
        /// The link's name.
        link: String,
    },
    /// A joint the robot needs is not there.
    #[error("URDF has no joint named `{joint}`")]
    MissingJoint {
        /// The joint's name.
        joint: String,
    },
    /// Two links share a name.
    #[error("URDF defines link `{link}` more than once")]
    DuplicateLink {
        /// The link's name.
        link: String,
    },
    /// A joint names a link that does not exist.
    #[error("joint `{joint}` refers to link `{link}`, which does not exist")]
    DanglingJoint {
        /// The joint's name.
        joint: String,
        /// The missing link.
        link: String,
    },
    /// A link has two parents, or the links do not form one tree rooted at the torso.
    #[error("link `{link}` is not in one tree: {reason}")]
    NotATree {
        /// The link's name.
        link: String,
        /// What is wrong.
        reason: &'static str,
    },
    /// A joint connects the wrong links or has the wrong type or axis.
    #[error("joint `{joint}`: {reason}")]
    BadJoint {
        /// The joint's name.
        joint: String,
        /// What is wrong.
        reason: String,
    },
    /// A link's mass or inertia is not positive and finite.
    #[error("link `{link}` has an invalid mass or inertia: {reason}")]
    BadInertia {
        /// The link's name.
        link: String,
        /// What is wrong.
        reason: String,
    },
    /// A link's mesh collision shape cannot be loaded: rather than have it
    /// dropped, and the link collide as nothing, the robot is refused.
    #[error(
        "link `{link}` has a mesh collision shape ({file}) that {reason}; rather than drop \
         it, the robot is refused: put the file there, or give the link box, cylinder, capsule \
         or sphere collision shapes"
    )]
    MeshCollision {
        /// The link's name.
        link: String,
        /// The mesh's file, as the URDF names it.
        file: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A bare URDF's legs could not be found from its tree.
    #[error("the legs cannot be found from the URDF: {reason}")]
    LegsNotFound {
        /// What was found instead.
        reason: String,
    },
    /// A leg's lower segment has no foot at its end.
    #[error(
        "link `{link}` needs a foot: a sphere collision on it or on a link fixed to it, or a \
         link fixed below it with a collision shape"
    )]
    MissingFoot {
        /// The link's name.
        link: String,
    },
    /// The camera frame is not fixed to the head.
    #[error("the `camera` link must be fixed directly to `head`")]
    CameraNotOnHead,
    /// A robot file cannot be read or used.
    #[error("robot file {file}: {reason}")]
    RobotFile {
        /// The file.
        file: String,
        /// What is wrong.
        reason: String,
    },
    /// The camera's mount cannot be used.
    #[error("camera: {reason}")]
    BadCamera {
        /// What is wrong.
        reason: String,
    },
    /// The gait asks a leg for a foot position it cannot reach.
    #[error(
        "leg `{leg}` cannot walk the gait: at command {command_mm_s} mm/s its foot must reach \
         {target_m:?} m from the hip, beyond a thigh of {thigh_m} m and a shank of {shank_m} m"
    )]
    GaitOutOfReach {
        /// The leg (`fl`, `fr`, `hl`, `hr`).
        leg: &'static str,
        /// The walk command, mm/s.
        command_mm_s: f64,
        /// The foot target relative to the hip, m.
        target_m: [f64; 3],
        /// The leg's upper segment, m.
        thigh_m: f64,
        /// The leg's lower segment, m.
        shank_m: f64,
    },
    /// The gait asks a joint for an angle outside its URDF limits.
    #[error(
        "joint `{joint}` cannot walk the gait: at command {command_mm_s} mm/s it must reach \
         {angle_rad:.3} rad, outside its limits [{lower_rad}, {upper_rad}] rad"
    )]
    GaitOutOfLimits {
        /// The joint's name.
        joint: String,
        /// The walk command, mm/s.
        command_mm_s: f64,
        /// The angle the gait needs, rad.
        angle_rad: f64,
        /// The joint's lower limit, rad.
        lower_rad: f64,
        /// The joint's upper limit, rad.
        upper_rad: f64,
    },
}

/// A simulation setting out of range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimConfigError {
    /// A value is outside its valid range.
    #[error("{key} must be {expected}, got {value}")]
    OutOfRange {
        /// The setting's name.
        key: &'static str,
        /// What it must be.
        expected: &'static str,
        /// The value given.
        value: f64,
    },
    /// A setting was changed during a run that cannot change once the world
    /// is built.
    #[error(
        "{key} cannot change during a run; what can: world.friction, servo.torque_scale, \
         servo.speed_scale, beacon.height_m, beacon.centre_m, beacon.radius_m, camera.noise_px"
    )]
    NotLive {
        /// The setting's name.
        key: &'static str,
    },
}

/// Why a simulation could not be built.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// A setting is out of range.
    #[error(transparent)]
    Config(#[from] SimConfigError),
    /// The robot description cannot be used.
    #[error(transparent)]
    Robot(#[from] RobotError),
}
