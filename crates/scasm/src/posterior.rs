//! What a learner believes the robot's true responses could be: draws from
//! its posterior, which a host turns into the learner's predicted error of
//! each model by judging the reported models against each draw as if it
//! were the truth (see [`crate::CalibrationLearner::posterior`]).

use std::vec::Vec;

use crate::polynomial::Polynomial;

/// Draws from a learner's posterior over the robot's true responses, in the
/// units of its reported models.
#[derive(Debug, Clone, PartialEq)]
pub struct Posterior {
    /// The draws, as many as the host asked for (or none, if the learner
    /// has no posterior yet).
    pub draws: Vec<Draw>,
}

/// One draw: a response the robot could have, given what the learner has seen.
#[derive(Debug, Clone, PartialEq)]
pub struct Draw {
    /// The action response: command -> location units per second.
    pub action: Polynomial,
    /// The sensor response as a table of `(reading px, location)`, sorted by
    /// reading, over the readings of the locations the robot was at: the
    /// location a reading means (a host interpolates between the points and
    /// extends the end segments).
    pub sensor: Vec<(f64, f64)>,
}
