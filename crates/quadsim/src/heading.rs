//! Keeping the robot facing the beacon, from what the robot itself senses: its
//! inertial unit's attitude (the gyro's rate vector integrated, as an attitude
//! filter does) gives its heading, and the beacon's bearing in the camera, when a
//! frame shows it, says which way to turn to keep the beacon centred. Without a
//! bearing it holds the heading it started with. It never sees the true pose.

use rapier3d::math::{Rotation, Vector};

/// Settings of the heading keeper.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeadingConfig {
    /// Turning (difference of step lengths, m) per radian of heading error.
    pub gain_m_per_rad: f64,
    /// Largest turning correction, m.
    pub max_steer_m: f64,
    /// How far past the beacon the robot aims, per radian that the beacon's
    /// direction (heading plus bearing) strays from the line it started on:
    /// walking along that aim brings it back to its line, forwards and
    /// backwards alike. 0 is a pure pursuit of the beacon, which keeps the angle
    /// off the line, so any sideways creep adds up.
    pub line_gain: f64,
}

impl Default for HeadingConfig {
    /// A gain of 0.4 m/rad made the fast backwards walk weave and its speed
    /// vary by 10-15 mm/s from second to second; 0.2 holds the line as well.
    fn default() -> Self {
        Self {
            gain_m_per_rad: 0.2,
            max_steer_m: 0.02,
            line_gain: 1.0,
        }
    }
}

/// The robot's attitude estimate and the latest bearing of the beacon.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeadingKeeper {
    attitude: Rotation,
    bearing_rad: Option<f64>,
}

impl Default for HeadingKeeper {
    fn default() -> Self {
        Self {
            attitude: Rotation::IDENTITY,
            bearing_rad: None,
        }
    }
}

impl HeadingKeeper {
    /// Integrates the gyro's rate vector (rad/s, body frame) over `dt_s`.
    /// Integrating only a yaw rate drifts from the true heading as the trotting
    /// torso rolls and pitches; the full attitude does not.
    pub fn integrate(&mut self, body_rate: [f64; 3], dt_s: f64) {
        let w = Vector::new(
            body_rate[0] as f32,
            body_rate[1] as f32,
            body_rate[2] as f32,
        );
        let rate = w.length();
        if rate > 0.0 {
            let step = Rotation::from_axis_angle(w / rate, rate * dt_s as f32);
            self.attitude = (self.attitude * step).normalize();
        }
    }

    /// Takes the beacon's bearing in the latest frame (rad, left positive), or
    /// `None` when the frame did not show it.
    pub fn observe_bearing(&mut self, bearing_rad: Option<f64>) {
        self.bearing_rad = bearing_rad;
    }

    /// The robot's own estimate of its heading, rad (0 = facing the beacon at the
    /// start).
    pub fn estimate_rad(&self) -> f64 {
        let f = self.attitude * Vector::X;
        f64::from(f.y.atan2(f.x))
    }

    /// The turning correction (positive: left) for a walk in direction
    /// `walking` (the command's sign): it keeps the beacon near the centre of
    /// the image, aimed a little to the side that steers the robot back onto
    /// its starting line. Without a bearing it holds the starting heading.
    pub fn steer(&self, config: &HeadingConfig, walking: f64) -> f64 {
        let error = match self.bearing_rad {
            Some(bearing) => {
                let off_line = self.estimate_rad() + bearing;
                bearing + config.line_gain * walking.signum() * off_line
            }
            None => -self.estimate_rad(),
        };
        (config.gain_m_per_rad * error).clamp(-config.max_steer_m, config.max_steer_m)
    }
}
