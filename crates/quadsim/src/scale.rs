//! How the gait, the controllers and the world scale with the robot's size, so
//! that a robot of another size walks the same trot without hand-tuning.
//!
//! The rules are those of dynamic similarity (equal Froude numbers), relative to
//! the shipped ERS-7, for which every default was chosen. With `s` the ratio of
//! leg lengths (thigh plus shank) and `mu` the ratio of masses:
//!
//! - lengths scale by `s`: step length and height, body height, stance width,
//!   the feet's forward offset, the heading keeper's steering, the beacon, the
//!   start distance, and (in the testbed) the test range and the protocols'
//!   distances;
//! - times scale by `sqrt(s)`: gait periods and the start ramp (the walk
//!   engine's command slew, an acceleration, stays);
//! - speeds scale by `sqrt(s)`: Eq. 1's `v_max` and `v_min`, and the commands;
//! - servo gains scale as torques, `kp` by `mu s` (`m g L` per radian) and `kd`
//!   by `mu s sqrt(s)`, and so does the joints' viscous damping; torque and
//!   speed limits are the URDF's own.
//!
//! The camera is unchanged: a beacon `s` times larger seen from `s` times
//! farther fills the same pixels.

use std::sync::OnceLock;

use crate::config::SimConfig;
use crate::description::RobotDescription;

/// A robot's size relative to the shipped ERS-7.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotScale {
    /// Ratio of leg lengths (thigh plus shank).
    pub length: f64,
    /// Ratio of total masses.
    pub mass: f64,
}

impl RobotScale {
    /// The reference robot's own scale.
    pub const ONE: Self = Self {
        length: 1.0,
        mass: 1.0,
    };

    /// `description`'s size relative to the ERS-7's (exactly 1 for the ERS-7).
    pub fn of(description: &RobotDescription) -> Self {
        static REFERENCE: OnceLock<(f64, f64)> = OnceLock::new();
        let &(leg_m, mass_kg) = REFERENCE.get_or_init(|| {
            let ers7 = RobotDescription::from_urdf_str(crate::ERS7_URDF)
                .expect("the shipped ERS-7 URDF is valid");
            (ers7.leg_length_m(), ers7.total_mass_kg)
        });
        Self {
            length: description.leg_length_m() / leg_m,
            mass: description.total_mass_kg / mass_kg,
        }
    }

    /// How times scale: `sqrt(length)`.
    pub fn time(&self) -> f64 {
        self.length.sqrt()
    }

    /// How speeds (and walk commands) scale: `sqrt(length)`.
    pub fn speed(&self) -> f64 {
        self.length.sqrt()
    }

    /// The paper's 31 commands, every multiple of 20 in [-300, 300] mm/s, at
    /// this scale (`speed()` times these).
    pub fn paper_commands(&self) -> Vec<f64> {
        (-15..=15)
            .map(|k| 20.0 * f64::from(k) * self.speed())
            .collect()
    }

    /// `base` (settings chosen for the ERS-7) scaled to this robot.
    pub fn apply(&self, base: SimConfig) -> SimConfig {
        let (s, t, v, mu) = (self.length, self.time(), self.speed(), self.mass);
        let mut c = base;
        let g = &mut c.walk.gait;
        for p in [&mut g.idle, &mut g.fast_forwards, &mut g.fast_backwards] {
            p.step_length_m *= s;
            p.step_height_m *= s;
            p.body_height_m *= s;
            p.stance_width_m *= s;
            p.foot_offset_m *= s;
            p.period_s *= t;
        }
        g.v_max_mm_s *= v;
        g.v_min_mm_s *= v;
        c.walk.start_ramp_s *= t;
        c.servo.kp_nm_per_rad *= mu * s;
        c.servo.kd_nm_s_per_rad *= mu * s * t;
        c.joint_damping_nm_s_per_rad *= mu * s * t;
        c.heading.gain_m_per_rad *= s;
        c.heading.max_steer_m *= s;
        let b = &mut c.beacon;
        b.xy_m = b.xy_m.map(|x| x * s);
        b.radius_m *= s;
        b.band_centre_m *= s;
        b.band_height_m *= s;
        c.start_distance_m *= s;
        c
    }
}

impl SimConfig {
    /// The default settings scaled to `description`'s size (see [`RobotScale`]);
    /// the defaults themselves for the ERS-7.
    pub fn for_robot(description: &RobotDescription) -> Self {
        RobotScale::of(description).apply(Self::default())
    }
}
