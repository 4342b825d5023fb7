//! A learner's predicted error of its own models, from its posterior: each
//! model judged by the paper's metric against each of the learner's draws of
//! the robot's true responses, as if that draw were the truth. The spread of
//! those errors is what the learner expects its measured error to be; the
//! measured one is judged against the measured models as ever.
//!
//! The draws are in the learner's units. The metric is blind to units (a
//! scale for the action model, an affine map for the sensor model), so each
//! draw's error is in the learner's units and is put in the world's by the
//! scale the metric finds between the learner's model and the measured one:
//! a change of units, not information about the truth. The draws are
//! judged at the measured models' commands and readings, as the models are.

use scasm::{Polynomial, Posterior};

use crate::metrics;
use crate::reference::Reference;
use crate::summary::quantile::quantile;

/// How many posterior draws a trial's predicted error is from.
pub const DRAWS: usize = 200;

/// The share of draws a band leaves out, half each side: a 90 % band.
pub const BAND_TAIL: f64 = 0.05;

/// A predicted error: the median over the draws and a 90 % band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Band {
    /// The median of the draws' errors.
    pub median: f64,
    /// Their 5th percentile.
    pub low: f64,
    /// Their 95th percentile.
    pub high: f64,
}

impl Band {
    /// The band of `errors` (NaNs left out); `None` if there are none.
    fn of(mut errors: Vec<f64>) -> Option<Self> {
        errors.retain(|e| !e.is_nan());
        if errors.is_empty() {
            return None;
        }
        errors.sort_by(f64::total_cmp);
        Some(Self {
            median: quantile(&errors, 0.5),
            low: quantile(&errors, BAND_TAIL),
            high: quantile(&errors, 1.0 - BAND_TAIL),
        })
    }
}

/// A learner's predicted errors of its two models, in the metrics' units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Predicted {
    /// The action model's, mm/s.
    pub action: Option<Band>,
    /// The sensor model's, mm.
    pub sensor: Option<Band>,
}

impl Predicted {
    /// The predicted errors of `action` and `sensor` (a learner's models at
    /// `t_s`) from the learner's `posterior`, in the world `reference` has
    /// then.
    pub fn of(
        reference: &Reference,
        t_s: f64,
        action: Option<Polynomial>,
        sensor: Option<Polynomial>,
        posterior: &Posterior,
    ) -> Self {
        let world = reference.at(t_s);
        let action = action.and_then(|model| {
            // Learner's units to mm/s: the scale the metric finds.
            let to_world = metrics::action_error(&model, &world.action).scale.abs();
            let errors = posterior.draws.iter().map(|draw| {
                let truth: Vec<(f64, f64)> = world
                    .action
                    .iter()
                    .map(|&(c, _)| (c, draw.action.eval(c)))
                    .collect();
                to_world * metrics::action_error(&model, &truth).rmse
            });
            Band::of(errors.collect())
        });
        let sensor = sensor.and_then(|model| {
            let to_world = metrics::sensor_error(&model, &world.sensor).scale.abs();
            let errors = posterior.draws.iter().map(|draw| {
                let truth: Option<Vec<(f64, f64)>> = world
                    .sensor
                    .iter()
                    .map(|&(_, obs)| metrics::interpolate(&draw.sensor, obs).map(|(x, _)| (x, obs)))
                    .collect();
                truth.map_or(f64::NAN, |t| {
                    to_world * metrics::sensor_error(&model, &t).rmse
                })
            });
            Band::of(errors.collect())
        });
        Self { action, sensor }
    }
}
