//! The robot of a URDF in rapier: the walk engine turns each command into
//! joint targets, the servos drive the legs, the feet push on the ground, and
//! the head camera reads the beacon at its frame rate.

use quadsim::{QuadrupedSim, RobotDescription, SimConfig, SimError};
use rand::Rng;

use super::{Sensed, Truth, World, WorldError};
use crate::seeds::{self, Stream};

/// The simulated robot in its world, with the changes of the world scheduled
/// for its trial.
#[derive(Debug)]
pub struct RapierWorld {
    sim: QuadrupedSim,
    /// From the first frame that starts at or after each time (s), the
    /// world's settings become these (see [`QuadrupedSim::change_world`]).
    changes: Vec<(f64, SimConfig)>,
    /// The next change to make.
    next_change: usize,
}

impl RapierWorld {
    /// The robot `description` in `sim`, its camera's noise seeded from the
    /// trial's master seed `seed`.
    pub fn new(
        description: &RobotDescription,
        sim: SimConfig,
        seed: u64,
        changes: Vec<(f64, SimConfig)>,
    ) -> Result<Self, SimError> {
        let mut sim = sim;
        sim.camera.noise_seed = seeds::rng(seed, Stream::SensorNoise).next_u64();
        Ok(Self {
            sim: QuadrupedSim::new(description, sim)?,
            changes,
            next_change: 0,
        })
    }

    /// The simulated robot and world (for viewers; learners never see it).
    pub fn sim(&self) -> &QuadrupedSim {
        &self.sim
    }
}

impl World for RapierWorld {
    fn frame_period_s(&self) -> f64 {
        self.sim.config().camera.frame_period_s
    }

    fn step_frame(&mut self, t_s: f64, command: f64) -> Result<Sensed, WorldError> {
        while let Some(&(at_s, world)) = self.changes.get(self.next_change) {
            if at_s > t_s + 1e-9 {
                break;
            }
            self.sim.change_world(world).map_err(SimError::from)?;
            self.next_change += 1;
        }
        self.sim.set_command(command).map_err(SimError::from)?;
        let mut upright = true;
        let frame = loop {
            self.sim.step();
            upright &= self.sim.is_upright();
            if let Some(f) = self.sim.take_frame() {
                break f;
            }
        };
        Ok(Sensed {
            obs_px: frame.obs_px.ok(),
            truth: Truth {
                x_mm: 1000.0 * self.sim.distance_along_line_m(),
                lateral_mm: 1000.0 * self.sim.lateral_offset_m(),
                yaw_rad: self.sim.torso().yaw_rad,
                upright,
                blew_up: self.sim.blew_up_at_s().is_some(),
            },
        })
    }
}
