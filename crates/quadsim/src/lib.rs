//! # quadsim: an Aibo-class quadruped that walks in rapier3d
//!
//! The robot of Stronger & Stone's section II: a 1.6 kg quadruped described by a
//! URDF, simulated as a rapier multibody whose twelve leg joints are driven by
//! torque- and speed-limited servos. A walk command sets the gait parameters by
//! the paper's Eq. 1; the walk engine turns them into foot loci and joint angles;
//! the robot moves only because its feet push on the floor. Its true
//! command-to-velocity response comes out of the physics, not from a formula.
//!
//! This crate knows nothing of learning. It offers ground truth (pose, distance
//! along the line of approach) for testbeds and tests; a learner must never see it.
#![warn(missing_docs)]

pub mod beacon;
pub mod cadence;
pub mod camera;
pub mod checks;
pub mod config;
pub mod description;
pub mod discover;
pub mod error;
pub mod files;
pub mod fold;
pub mod gait;
pub mod heading;
pub mod ik;
pub mod joint_dynamics;
mod leg_chain;
pub mod legs;
pub mod mesh;
pub mod mjcf;
mod pose;
pub mod robot_file;
pub mod scale;
pub mod scene;
pub mod servo;
pub mod sim;
pub mod stance;
mod urdf_tree;
mod urdf_xml;
pub mod vision;
pub mod walk;

pub use config::{MultibodyDynamics, SimConfig};
pub use description::{LEG_NAMES, RobotDescription};
pub use error::{RobotError, SimConfigError, SimError};
pub use robot_file::RobotFile;
pub use scale::RobotScale;
pub use sim::{BLOW_UP_ENERGY, QuadrupedSim, TorsoState};
pub use vision::{CameraConfig, Frame, NoReading};

/// The default robot description shipped in `assets/ers7.urdf`.
pub const ERS7_URDF: &str = include_str!("../../../assets/ers7.urdf");
