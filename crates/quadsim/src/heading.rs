//! Keeping the robot facing its line: a yaw-rate sensor (as a gyro on the torso
//! would give) integrated into a heading estimate, and a small steering correction
//! back towards the heading the robot started with. It never sees the true pose.

/// Settings of the heading keeper.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeadingConfig {
    /// Steering (difference of step lengths, m) per radian of heading error.
    pub gain_m_per_rad: f64,
    /// Largest steering correction, m.
    pub max_steer_m: f64,
}

impl Default for HeadingConfig {
    fn default() -> Self {
        Self {
            gain_m_per_rad: 0.2,
            max_steer_m: 0.02,
        }
    }
}

/// The heading estimate and the correction it asks for.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HeadingKeeper {
    estimate_rad: f64,
}

impl HeadingKeeper {
    /// Integrates a yaw-rate reading over `dt_s` (as an inertial unit does, at its
    /// own rate, however often the walk engine asks).
    pub fn integrate(&mut self, yaw_rate_rad_s: f64, dt_s: f64) {
        self.estimate_rad += yaw_rate_rad_s * dt_s;
    }

    /// The steering correction (positive: turn left) that brings the heading back
    /// to zero.
    pub fn steer(&self, config: &HeadingConfig) -> f64 {
        (-config.gain_m_per_rad * self.estimate_rad).clamp(-config.max_steer_m, config.max_steer_m)
    }

    /// The robot's own estimate of its heading, rad (0 = facing the beacon at the start).
    pub fn estimate_rad(&self) -> f64 {
        self.estimate_rad
    }
}
