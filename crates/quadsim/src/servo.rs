//! Servos like the Aibo's: a position setpoint that may move no faster than the
//! joint-speed limit, tracked by a torque-limited PD motor in the physics.

/// Settings shared by all twelve leg servos. Each joint's torque and speed
/// limits are the URDF's (`<limit effort velocity>`), times the scales here.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoConfig {
    /// Proportional gain, N m / rad.
    pub kp_nm_per_rad: f64,
    /// Damping gain, N m s / rad.
    pub kd_nm_s_per_rad: f64,
    /// Each joint's torque limit is its URDF effort limit times this (below 1:
    /// weaker servos, such as a tired battery's).
    pub torque_scale: f64,
    /// Each joint's setpoint speed limit is its URDF velocity limit times this.
    pub speed_scale: f64,
    /// How often the servos take a new target, s (8 ms on the Aibo).
    pub command_period_s: f64,
}

impl Default for ServoConfig {
    fn default() -> Self {
        Self {
            kp_nm_per_rad: 12.0,
            kd_nm_s_per_rad: 0.15,
            torque_scale: 1.0,
            speed_scale: 1.0,
            command_period_s: 0.008,
        }
    }
}

/// The setpoints of a set of servos.
#[derive(Debug, Clone, PartialEq)]
pub struct ServoSetpoints {
    position_rad: Vec<f64>,
    velocity_rad_s: Vec<f64>,
}

impl ServoSetpoints {
    /// Setpoints starting at `initial` (rad), at rest.
    pub fn new(initial: Vec<f64>) -> Self {
        let n = initial.len();
        Self {
            position_rad: initial,
            velocity_rad_s: vec![0.0; n],
        }
    }

    /// Moves every setpoint towards its target over one command period, each no
    /// faster than its own speed limit (rad/s). A `None` target holds the
    /// setpoint where it is.
    pub fn track(&mut self, targets: &[Option<f64>], period_s: f64, max_speed_rad_s: &[f64]) {
        for (((p, v), t), max_speed) in self
            .position_rad
            .iter_mut()
            .zip(&mut self.velocity_rad_s)
            .zip(targets)
            .zip(max_speed_rad_s)
        {
            let max_step = max_speed * period_s;
            let step = t.map_or(0.0, |t| (t - *p).clamp(-max_step, max_step));
            *p += step;
            *v = step / period_s;
        }
    }

    /// Setpoint positions, rad.
    pub fn positions(&self) -> &[f64] {
        &self.position_rad
    }

    /// Setpoint velocities, rad/s.
    pub fn velocities(&self) -> &[f64] {
        &self.velocity_rad_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn setpoints_respect_the_speed_limit() {
        let mut s = ServoSetpoints::new(vec![0.0, 0.0]);
        s.track(&[Some(1.0), Some(-0.01)], 0.008, &[5.0, 5.0]);
        assert!((s.positions()[0] - 0.04).abs() < 1e-12);
        assert!((s.positions()[1] + 0.01).abs() < 1e-12);
        s.track(&[None, Some(-0.01)], 0.008, &[5.0, 5.0]);
        assert!((s.positions()[0] - 0.04).abs() < 1e-12 && s.velocities()[0] == 0.0);
    }
}
