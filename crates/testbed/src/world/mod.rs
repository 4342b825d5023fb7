//! What a trial needs of a world, whatever it is made of: walk one camera
//! frame under a command, and say what the camera read at its end and, kept
//! apart for judging, where the robot truly was. Three worlds have it:
//!
//! - [`RapierWorld`]: the robot of a URDF in rapier, its feet pushing on the
//!   ground, its head camera reading the beacon (the testbed's world);
//! - [`SyntheticWorld`]: a point robot on a line with a made-up nonlinear
//!   response and an ideal pinhole camera, no physics (a check of a learner
//!   on its own);
//! - [`Replayed`]: a recording, walked again: it answers the commands it
//!   recorded and refuses any other.
//!
//! A trial ([`crate::trial::TrialRunner`]) drives any of them with a training
//! behaviour, and everything after a recording (learners, judging, the
//! information floor, the run's files) is the same for all.

mod rapier;
mod replayed;
pub mod synthetic;

use quadsim::{RobotDescription, RobotScale, SimConfig, SimError};
use scasm::Event;

pub use rapier::RapierWorld;
pub use replayed::Replayed;
pub use synthetic::SyntheticWorld;

/// A world a trial can walk in, one camera frame at a time.
pub trait World: std::fmt::Debug + Send {
    /// The camera's frame interval, s: one [`World::step_frame`] each.
    fn frame_period_s(&self) -> f64;
    /// Walks the frame that starts at `t_s` with the walk command `command`
    /// in force over it, until the camera takes its picture at the frame's
    /// end.
    fn step_frame(&mut self, t_s: f64, command: f64) -> Result<Sensed, WorldError>;
}

impl World for Box<dyn World> {
    fn frame_period_s(&self) -> f64 {
        self.as_ref().frame_period_s()
    }

    fn step_frame(&mut self, t_s: f64, command: f64) -> Result<Sensed, WorldError> {
        self.as_mut().step_frame(t_s, command)
    }
}

/// What a world gives for one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensed {
    /// The camera's reading at the frame's end, px, if it saw the beacon.
    pub obs_px: Option<f64>,
    /// Ground truth at the frame's end (never shown to a learner).
    pub truth: Truth,
}

/// Why a world could not walk a frame.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum WorldError {
    /// The simulated world refused (a command or a change of the world).
    #[error(transparent)]
    Sim(#[from] SimError),
    /// A replayed recording was asked for a frame it does not hold.
    #[error("the recording cannot be walked again: {0}")]
    Departed(String),
    /// The world cannot be built as asked.
    #[error("{0}")]
    Unsupported(String),
}

/// Which world a scenario's trials walk in (setting `trial.world`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum WorldKind {
    /// The robot in rapier ([`RapierWorld`]): the default.
    #[default]
    Rapier,
    /// The point robot with no physics ([`SyntheticWorld`]).
    Synthetic,
}

impl WorldKind {
    /// Every kind, in the order a listing shows them.
    pub const ALL: [WorldKind; 2] = [WorldKind::Rapier, WorldKind::Synthetic];

    /// Its name, as `trial.world` takes it.
    pub fn name(self) -> &'static str {
        match self {
            WorldKind::Rapier => "rapier",
            WorldKind::Synthetic => "synthetic",
        }
    }

    /// The kind named `name`, or why there is none.
    pub fn parse(name: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|k| k.name()).collect();
                format!("no world `{name}`; the worlds are {}", names.join(", "))
            })
    }
}

/// Builds the world of `kind` for a trial from master seed `seed`: the robot
/// `description` in `sim` (rapier), or the point robot at the robot's `scale`
/// with `sim`'s camera and start (synthetic). `changes` are the world's
/// settings from each time on (rapier only: a point robot has nothing to
/// change).
pub fn build(
    kind: WorldKind,
    description: &RobotDescription,
    sim: SimConfig,
    scale: RobotScale,
    seed: u64,
    changes: Vec<(f64, SimConfig)>,
) -> Result<Box<dyn World>, WorldError> {
    Ok(match kind {
        WorldKind::Rapier => Box::new(RapierWorld::new(description, sim, seed, changes)?),
        WorldKind::Synthetic => {
            if !changes.is_empty() {
                return Err(WorldError::Unsupported(
                    "the synthetic world cannot change during a trial (a point robot has no \
                     friction, payload or gait to change): remove the scenario's [[change]]s"
                        .into(),
                ));
            }
            Box::new(SyntheticWorld::new(
                synthetic::SyntheticConfig::of(sim, scale),
                seed,
            ))
        }
    })
}

/// What the world records of one camera frame: what a learner may see (the
/// command in force over the frame and the reading at its end, if any) and,
/// kept apart, the ground truth at the frame's end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameRecord {
    /// Start of the frame, s.
    pub t_s: f64,
    /// Length of the frame, s.
    pub dt_s: f64,
    /// The command in force over the frame.
    pub command: f64,
    /// The reading at the frame's end, px, if the frame had one.
    pub obs_px: Option<f64>,
    /// Ground truth at the frame's end (never shown to a learner).
    pub truth: Truth,
}

/// Ground truth at one moment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Truth {
    /// Distance to the beacon along the line of approach, mm.
    pub x_mm: f64,
    /// Offset from the line of approach, mm (left positive).
    pub lateral_mm: f64,
    /// The torso's heading, rad (0 faces the beacon).
    pub yaw_rad: f64,
    /// Whether the torso was upright throughout the frame.
    pub upright: bool,
    /// Whether the physics had blown up by the frame's end (see
    /// [`quadsim::QuadrupedSim::blew_up_at_s`]).
    pub blew_up: bool,
}

impl Truth {
    /// A robot on its line, facing the beacon, upright, at `x_mm`.
    pub fn on_line(x_mm: f64) -> Self {
        Self {
            x_mm,
            lateral_mm: 0.0,
            yaw_rad: 0.0,
            upright: true,
            blew_up: false,
        }
    }
}

impl FrameRecord {
    /// End of the frame, s: when its reading was taken.
    pub fn end_s(&self) -> f64 {
        self.t_s + self.dt_s
    }

    /// The events a learner gets for this frame: the command over it, then its
    /// reading (if any).
    pub fn events(&self) -> impl Iterator<Item = Event> {
        let command = Event::Command {
            t_s: self.t_s,
            dt_s: self.dt_s,
            command: self.command,
        };
        let reading = self.obs_px.map(|obs_px| Event::Reading {
            t_s: self.end_s(),
            obs_px,
        });
        std::iter::once(command).chain(reading)
    }
}
