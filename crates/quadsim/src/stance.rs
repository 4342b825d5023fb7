//! A model's standing pose as the gait's stance: where the feet are, below
//! and outwards of the hips, at the joints' standing angles (an MJCF's
//! keyframe, [`crate::mjcf::Mjcf::standing`]), the mean over the four legs.
//! The gait then stands, and walks, at that height and width; its step
//! lengths, step height and the feet's forward offsets stay the scaled
//! gait's.

use std::collections::BTreeMap;

use crate::description::RobotDescription;
use crate::ik::{self, LegAngles};

/// The feet's place in the standing pose, relative to the hips.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stance {
    /// How far below its hip joint a foot's centre is, m (the gait's
    /// `body_height_m`).
    pub body_height_m: f64,
    /// How far outwards of its leg's plane, m (the gait's `stance_width_m`).
    pub stance_width_m: f64,
}

impl Stance {
    /// The stance at `angles` (rad, by joint name), or `None` if a leg's
    /// joint has none or a foot would not be below its hip.
    pub fn at(description: &RobotDescription, angles: &BTreeMap<String, f64>) -> Option<Self> {
        let mut sum = [0.0; 2];
        for leg in &description.legs {
            let [a, h, k] =
                [0, 1, 2].map(|i| angles.get(&leg.joints[i]).map(|v| leg.axis_signs[i] * v));
            let angles = LegAngles {
                abduction: a?,
                hip: h?,
                knee: k?,
            };
            let g = leg.geometry(leg.knee_sign());
            let p = ik::forward(&g, &angles);
            // The walk engine's target, inverted: the foot relative to the
            // hip joint (see `walk::Leg::target`).
            sum[0] += g.hip_at_m[1] - p[2];
            sum[1] += leg.side() * (p[1] - g.hip_offset_m);
        }
        let n = description.legs.len() as f64;
        let stance = Self {
            body_height_m: sum[0] / n,
            stance_width_m: sum[1] / n,
        };
        (stance.body_height_m > 0.0 && stance.stance_width_m.is_finite()).then_some(stance)
    }
}
