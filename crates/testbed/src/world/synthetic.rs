//! A world with no physics for checking a learner: a point robot on a line
//! whose true action model is a made-up, clearly nonlinear monotone curve and
//! whose camera is an ideal pinhole (`obs = k / distance`) with Gaussian pixel
//! noise. At another robot's scale its speeds and distances scale as that
//! robot's do ([`RobotScale`]).

use quadsim::{RobotScale, SimConfig};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use super::{Sensed, Truth, World, WorldError};
use crate::seeds::{self, Stream};

/// The synthetic robot's true forward speed (mm/s) under `command`, at the
/// ERS-7's scale: monotone, saturating forwards, slower backwards, and not a
/// polynomial.
pub fn true_velocity_mm_s(command: f64) -> f64 {
    let u = command / 300.0;
    330.0 * (1.3 * u).tanh() / 1.3_f64.tanh() + 25.0 * u * u
}

/// The synthetic camera's noise-free reading (px) of a 200 mm band at
/// `distance_mm` through a lens of focal length 384 px, at the ERS-7's scale.
pub fn true_obs_px(distance_mm: f64) -> f64 {
    SENSOR_K_PX_MM / distance_mm
}

const SENSOR_K_PX_MM: f64 = 384.0 * 200.0;

/// The synthetic world's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyntheticConfig {
    /// Camera frame interval, s.
    pub frame_period_s: f64,
    /// Standard deviation of the Gaussian reading noise, px.
    pub noise_px: f64,
    /// Where the robot starts, mm from the beacon.
    pub start_distance_mm: f64,
    /// The robot's size relative to the ERS-7: speeds scale by
    /// [`RobotScale::speed`], distances (and so the beacon) by its length.
    pub scale: RobotScale,
}

impl SyntheticConfig {
    /// The settings a scenario's `sim` gives: its camera's frame interval and
    /// noise (`camera.frame_period_s`, `camera.noise_px`) and its start
    /// (`world.start_distance_m`), at `scale`.
    pub fn of(sim: SimConfig, scale: RobotScale) -> Self {
        Self {
            frame_period_s: sim.camera.frame_period_s,
            noise_px: sim.camera.noise_px,
            start_distance_mm: 1000.0 * sim.start_distance_m,
            scale,
        }
    }

    /// The true forward speed under `command`, mm/s.
    pub fn velocity_mm_s(&self, command: f64) -> f64 {
        let speed = self.scale.speed();
        speed * true_velocity_mm_s(command / speed)
    }

    /// The noise-free reading at `distance_mm`, px.
    pub fn obs_px(&self, distance_mm: f64) -> f64 {
        true_obs_px(distance_mm / self.scale.length)
    }
}

/// The point robot in its world.
#[derive(Debug, Clone)]
pub struct SyntheticWorld {
    config: SyntheticConfig,
    distance_mm: f64,
    noise: Normal<f64>,
    rng: ChaCha8Rng,
}

impl SyntheticWorld {
    /// The world of `config`, its camera's noise drawn from the trial's
    /// master seed `seed`.
    pub fn new(config: SyntheticConfig, seed: u64) -> Self {
        Self {
            config,
            distance_mm: config.start_distance_mm,
            // `max` takes a NaN to 0; the scenario's settings bound the noise
            // (`camera.noise_px` in [0, 50]), so the deviation is valid.
            noise: Normal::new(0.0, config.noise_px.max(0.0)).unwrap_or_else(|_| unreachable!()),
            rng: seeds::rng(seed, Stream::SensorNoise),
        }
    }
}

impl World for SyntheticWorld {
    fn frame_period_s(&self) -> f64 {
        self.config.frame_period_s
    }

    fn step_frame(&mut self, _t_s: f64, command: f64) -> Result<Sensed, WorldError> {
        self.distance_mm -= self.config.velocity_mm_s(command) * self.config.frame_period_s;
        let obs_px = self.config.obs_px(self.distance_mm) + self.noise.sample(&mut self.rng);
        Ok(Sensed {
            obs_px: Some(obs_px),
            truth: Truth::on_line(self.distance_mm),
        })
    }
}
