//! A joint's own dynamics as its model file gives them: viscous damping and
//! dry friction (URDF's `<dynamics damping friction>`, MJCF's `damping` and
//! `frictionloss`) and armature (MJCF's rotor inertia, see
//! [`RobotDescription::armature`]). The simulator applies them to the joint's
//! degree of freedom as MuJoCo does (damping and armature implicit on the
//! joint's diagonal, friction as a bounded constraint force), on top of its
//! own damping of every joint (`physics.joint_damping`). URDF's absent
//! `<dynamics>` and its zeros mean none, as in urdfdom.

use crate::description::RobotDescription;

/// A joint's damping (N m s/rad), dry friction (N m) and armature (kg m^2).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointDynamics {
    /// Viscous damping, N m s/rad (N s/m for a prismatic joint).
    pub damping: f64,
    /// Dry friction, the largest torque it resists with, N m (N).
    pub friction: f64,
    /// Rotor inertia reflected onto the joint, kg m^2 (kg).
    pub armature: f64,
}

impl JointDynamics {
    /// `joint`'s dynamics in `description`, or `None` if it has none.
    pub fn of(description: &RobotDescription, joint: &urdf_rs::Joint) -> Option<Self> {
        let d = joint.dynamics.as_ref();
        let found = Self {
            damping: d.map_or(0.0, |d| d.damping),
            friction: d.map_or(0.0, |d| d.friction),
            armature: description
                .armature
                .get(&joint.name)
                .copied()
                .unwrap_or(0.0),
        };
        (found != Self::default()).then_some(found)
    }
}
