//! # testbed: experiments that connect a robot to a calibration learner
//!
//! The robot side knows nothing of learning and the learner knows nothing of
//! physics; this crate connects them. It holds the paper's training behaviour
//! (section II), its evaluation protocol (section VII), the seeding scheme, and the
//! worlds a trial walks in ([`world`]): the robot in rapier, and a synthetic
//! point robot used to check a learner without physics.
#![warn(missing_docs)]

pub mod behaviour;
pub mod benchmark;
pub mod blanks;
pub mod dataset;
pub mod demos;
pub mod experiment;
pub mod floor;
pub mod learners;
pub mod localiser;
pub mod measure;
pub mod metrics;
pub mod output;
pub mod predicted;
pub mod provenance;
pub mod reference;
pub mod run_dir;
pub mod scenario;
pub mod seeds;
pub mod summary;
pub mod sweep;
pub mod synthetic;
pub mod trial;
pub mod world;
