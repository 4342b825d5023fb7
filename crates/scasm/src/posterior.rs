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

impl Draw {
    /// The location `obs_px` means by this draw's sensor table: linear
    /// between its points, the end segments extended; `None` if the table
    /// has fewer than two points or is degenerate there.
    pub fn location_at(&self, obs_px: f64) -> Option<f64> {
        let table = &self.sensor;
        if table.len() < 2 {
            return None;
        }
        let k = table
            .partition_point(|p| p.0 <= obs_px)
            .clamp(1, table.len() - 1);
        let ((o0, x0), (o1, x1)) = (table[k - 1], table[k]);
        let x = x0 + (x1 - x0) / (o1 - o0) * (obs_px - o0);
        x.is_finite().then_some(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_draw_reads_its_table_between_and_beyond_its_points() {
        let draw = Draw {
            action: Polynomial::identity(),
            sensor: vec![(10.0, 4.0), (20.0, 2.0), (40.0, 1.0)],
        };
        assert_eq!(draw.location_at(15.0), Some(3.0));
        assert_eq!(draw.location_at(30.0), Some(1.5));
        // The end segments extended.
        assert_eq!(draw.location_at(5.0), Some(5.0));
        assert_eq!(draw.location_at(60.0), Some(0.0));
        let short = Draw {
            sensor: vec![(10.0, 4.0)],
            ..draw
        };
        assert_eq!(short.location_at(10.0), None);
    }
}
