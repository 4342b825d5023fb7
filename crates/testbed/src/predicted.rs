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
        Prediction::of(reference, t_s, (action, sensor), None, posterior).learned
    }
}

/// Which of the two models is judged.
#[derive(Debug, Clone, Copy)]
enum Model {
    Action,
    Sensor,
}

impl Model {
    /// The measured points this model is judged at.
    fn judged(self, world: &Reference) -> &[(f64, f64)] {
        match self {
            Self::Action => &world.action,
            Self::Sensor => &world.sensor,
        }
    }

    /// The metric's error of `model` against the measured points, and the
    /// scale it finds (the learner's units to the world's).
    fn error(self, model: &Polynomial, judged: &[(f64, f64)]) -> (f64, f64) {
        match self {
            Self::Action => {
                let e = metrics::action_error(model, judged);
                (e.rmse, e.scale)
            }
            Self::Sensor => {
                let e = metrics::sensor_error(model, judged);
                (e.rmse, e.scale)
            }
        }
    }

    /// The truth `draw` stands for at `judged`'s commands or readings, in
    /// the draw's units (`None` where a sensor draw has no table there).
    fn truth(self, draw: &scasm::Draw, judged: &[(f64, f64)]) -> Option<Vec<(f64, f64)>> {
        match self {
            Self::Action => Some(
                judged
                    .iter()
                    .map(|&(c, _)| (c, draw.action.eval(c)))
                    .collect(),
            ),
            Self::Sensor => judged
                .iter()
                .map(|&(_, obs)| metrics::interpolate(&draw.sensor, obs).map(|(x, _)| (x, obs)))
                .collect(),
        }
    }

    /// One model judged by every draw: the learned model's band, the start's
    /// (if given) and the share of draws by which the learned one is nearer
    /// the truth. Each draw's errors are in the draws' units and put in the
    /// world's by the scale the metric finds for the learned model.
    fn judge(
        self,
        world: &Reference,
        learned: Option<Polynomial>,
        start: Option<Option<Polynomial>>,
        posterior: &Posterior,
    ) -> (Option<Band>, Option<Band>, Option<f64>) {
        let Some(learned) = learned else {
            return (None, None, None);
        };
        let judged = self.judged(world);
        let to_world = self.error(&learned, judged).1.abs();
        let start = start.flatten();
        // Per draw: the learned model's error and the start's (NaN where the
        // draw has no truth to judge by).
        let pairs: Vec<(f64, f64)> = posterior
            .draws
            .iter()
            .map(|draw| match self.truth(draw, judged) {
                Some(truth) => (
                    to_world * self.error(&learned, &truth).0,
                    start.map_or(f64::NAN, |s| to_world * self.error(&s, &truth).0),
                ),
                None => (f64::NAN, f64::NAN),
            })
            .collect();
        let band = Band::of(pairs.iter().map(|p| p.0).collect());
        let Some(_) = start else {
            return (band, None, None);
        };
        let start_band = Band::of(pairs.iter().map(|p| p.1).collect());
        let wins = pairs.iter().filter(|(l, s)| metrics::above(*s, *l)).count();
        let share = wins as f64 / posterior.draws.len().max(1) as f64;
        (band, start_band, Some(share))
    }
}

/// What a learner's posterior says at the end of a trial: its predicted
/// errors, the start's by the same draws, and how likely it is that each
/// learned model is nearer the truth than the start's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prediction {
    /// The learned models' predicted errors.
    pub learned: Predicted,
    /// The uncalibrated start's (A0 and the section IV sensor model), by the
    /// learner's draws, if the start rode along.
    pub start: Option<Predicted>,
    /// The share of draws by which each learned model (`(action, sensor)`)
    /// is nearer the truth than the start's.
    pub better_than_start: (Option<f64>, Option<f64>),
}

impl Prediction {
    /// From the learner's `posterior` at `t_s`: its models `learned`, and the
    /// start's `start` if it rode along. The start's errors are put in the
    /// world's units by the learned models' scale, whatever the start's
    /// own units (the draws are in the learner's).
    pub fn of(
        reference: &Reference,
        t_s: f64,
        learned: (Option<Polynomial>, Option<Polynomial>),
        start: Option<(Option<Polynomial>, Option<Polynomial>)>,
        posterior: &Posterior,
    ) -> Self {
        let world = reference.at(t_s);
        let (action, action_start, action_share) =
            Model::Action.judge(world, learned.0, start.map(|s| s.0), posterior);
        let (sensor, sensor_start, sensor_share) =
            Model::Sensor.judge(world, learned.1, start.map(|s| s.1), posterior);
        Self {
            learned: Predicted { action, sensor },
            start: start.map(|_| Predicted {
                action: action_start,
                sensor: sensor_start,
            }),
            better_than_start: (action_share, sensor_share),
        }
    }
}

#[cfg(test)]
mod tests {
    use scasm::Draw;

    use super::*;

    fn truth_velocity(c: f64) -> f64 {
        0.8 * c + 4e-4 * c * c
    }

    /// A world with the pinhole camera `obs = 38400 / d`, and a posterior
    /// whose every draw is that truth (in the world's units).
    fn world() -> (Reference, Posterior) {
        let reference = Reference {
            action: (-15..=15)
                .map(|k| 20.0 * f64::from(k))
                .map(|c| (c, truth_velocity(c)))
                .collect(),
            sensor: (0..13)
                .map(|k| 1200.0 + 200.0 * f64::from(k))
                .map(|d| (d, 38_400.0 / d))
                .collect(),
            changes: Vec::new(),
        };
        let mut sensor: Vec<(f64, f64)> = (0..=280)
            .map(|k| 1000.0 + 10.0 * f64::from(k))
            .map(|x| (38_400.0 / x, x))
            .collect();
        sensor.sort_by(|p, q| p.0.total_cmp(&q.0));
        let draw = Draw {
            action: Polynomial::new(&[0.0, 0.8, 4e-4]).expect("finite"),
            sensor,
        };
        (
            reference,
            Posterior {
                draws: vec![draw; 20],
            },
        )
    }

    #[test]
    fn the_start_is_judged_by_the_learners_draws_and_the_learned_models_found_better() {
        let (reference, posterior) = world();
        let readings: Vec<(f64, f64)> = reference.sensor.iter().map(|&(d, o)| (o, d)).collect();
        let learned = (
            Polynomial::new(&[0.0, 0.8, 4e-4]),
            metrics::best_polynomial(&readings, 3),
        );
        let start = (
            Some(Polynomial::identity()),
            metrics::best_polynomial(&readings, 1),
        );
        let p = Prediction::of(&reference, 150.0, learned, Some(start), &posterior);
        // The draws are the truth, so the predicted errors are the measured ones.
        let a = p.learned.action.expect("a band");
        assert!(a.median.abs() < 1e-9 && a.high.abs() < 1e-9);
        let s = p.learned.sensor.expect("a band");
        let measured = metrics::sensor_error(&learned.1.expect("cubic"), &reference.sensor).rmse;
        assert!(
            (s.median - measured).abs() < 0.05 * measured,
            "{s:?} against {measured}"
        );
        let start_predicted = p.start.expect("the start rode along");
        let a0 = metrics::action_error(&Polynomial::identity(), &reference.action).rmse;
        let a0_predicted = start_predicted.action.expect("a band").median;
        assert!(
            (a0_predicted - a0).abs() < 1e-6 * a0,
            "{a0_predicted} against {a0}"
        );
        assert_eq!(p.better_than_start, (Some(1.0), Some(1.0)));
        // Judged the other way round, the start is never the better.
        let swapped = Prediction::of(&reference, 150.0, start, Some(learned), &posterior);
        assert_eq!(swapped.better_than_start, (Some(0.0), Some(0.0)));
    }
}
