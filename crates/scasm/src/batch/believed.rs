//! An online learner that knows how sure it is. It learns online as ever;
//! what it believes the robot's true responses could be, given every event
//! it has seen, is the likelihood's (`batch-ml-lag`'s model: the path, a
//! lagged response to each command and a forward sensor model, with the
//! process and reading noises), by the Laplace approximation at its
//! maximum. The posterior over the truth depends on the data and the model
//! of them, not on which estimate is reported: judging the online models
//! against its draws counts both the noise and how far the online estimate
//! is from the likeliest one.
//!
//! The likelihood's solve starts from its own online learner's path and
//! models (and the readings' pinhole path), and its draws are put in the
//! online learner's units (the affine map that best takes the solved path
//! onto the learner's dead-reckoned path), the units of the models reported.
//!
//! With `keep_start`, it also moves each model off its start only as far
//! as that belief supports: every `every_s` of the trial it solves the
//! likelihood and asks its draws whether each learned model is nearer the
//! truth than the start's, by the paper's metric (blind to the models'
//! units). The action model's start is A0, the command taken as the speed (a
//! line through the origin), judged over the commands it walks; while fewer
//! than half the draws favour the learned model, it reports A0's line at
//! the scale that best fits the learned one. The sensor model's start is
//! section IV's, learned by dead reckoning with A0 (a second online learner
//! rides along for it), judged over the distances walked (each draw's own
//! table: evenly spaced locations over the path's range, and the readings
//! the draw says they give); while fewer than `sensor_below` of the draws
//! favour the learned model, it reports section IV's, by the affine map
//! that best fits the learned one at a draw's readings. The sensor's
//! verdict asks for more than the action's because it is blind where the
//! sensor models differ most, beyond the ends of the walk (a walk that
//! turns short of where its sensor model is used). Its own learning and
//! dead reckoning are untouched.

use std::vec;
use std::vec::Vec;

use crate::batch::{BatchMl, BatchMlConfig};
use crate::config::{ScasmConfig, SensorFit};
use crate::error::EventError;
use crate::learner::{CalibrationLearner, Event};
use crate::mode::Mode;
use crate::polynomial::Polynomial;
use crate::posterior::{Draw, Posterior};
use crate::scasm::Scasm;

/// Commands, evenly over the learner's command range, at which a draw
/// judges the learned action model against the start's (as many as the
/// paper's stopwatch commands).
const JUDGED_COMMANDS: usize = 31;

/// Draws a keep-start decision is made from.
const DECISION_DRAWS: usize = 200;

/// When an online learner keeps its start's models (see the module's
/// documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeepStart {
    /// How often the belief is solved for the decision, s of the trial.
    pub every_s: f64,
    /// The share of draws favouring the learned sensor model below which
    /// the start's is kept (the action model's is one half; 0: never).
    pub sensor_below: f64,
}

/// An online SCASM learner with the lagged likelihood's posterior (see the
/// module's documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Believed {
    learner: Scasm,
    /// Section IV's learner: the sensor model by dead reckoning with A0, fed
    /// the same events (the sensor model's start); only if its start may be
    /// kept.
    start: Option<Scasm>,
    /// The likelihood, fed every event the learner took; solved only when
    /// a belief is due.
    batch: BatchMl,
    /// The learner's dead-reckoned location at each frame boundary (the
    /// first at time 0): its units, which the posterior's draws are put in.
    path: Vec<f64>,
    keep_start: Option<KeepStart>,
    /// When the next keep-start decision is due, s.
    next_decision_s: f64,
    /// Whether the last decision kept the start's action model.
    keeping_action: bool,
    /// If the last decision kept the start's sensor model, the readings its
    /// units are mapped to the learned model's at (a draw's).
    keeping_sensor: Option<Vec<f64>>,
    /// Whether the likelihood refused an event the learner took (it checks
    /// events alike, so never expected): then it has no belief.
    lost: bool,
    /// How many frame boundaries the likelihood was last solved over.
    solved_over: usize,
}

impl Believed {
    /// `learner` (simultaneous), its posterior that of `batch-ml-lag`'s
    /// likelihood started from a learner with its settings, keeping its
    /// start's models as `keep_start` says (`None`: never).
    pub fn new(learner: Scasm, keep_start: Option<KeepStart>) -> Self {
        let start = keep_start.filter(|k| k.sensor_below > 0.0).map(|_| {
            Scasm::new(
                *learner.params(),
                Mode::SensorFromAction(Polynomial::identity()),
            )
            .expect("A0 is finite")
        });
        let likelihood = BatchMlConfig {
            online: ScasmConfig {
                sensor_fit: SensorFit::Corrected,
                ..learner.params().config()
            },
            // Solved when a belief is due, never on its own.
            solve_every_s: f64::MAX,
            ..BatchMlConfig::lagged()
        };
        let batch = BatchMl::new(
            likelihood
                .validate()
                .expect("batch-ml-lag's defaults with a valid learner's settings"),
        );
        Self {
            learner,
            start,
            batch,
            path: vec![0.0],
            next_decision_s: keep_start.map_or(f64::INFINITY, |k| k.every_s),
            keep_start,
            keeping_action: false,
            keeping_sensor: None,
            lost: false,
            solved_over: 0,
        }
    }

    /// Draws of the likelihood's posterior over the events so far, from
    /// `batch` solved over them (solved now unless `solved` says it was
    /// already), in the units of the learner's `path`.
    fn draws(batch: &mut BatchMl, solved: bool, draws: usize, path: &[f64]) -> Option<Vec<Draw>> {
        if !solved {
            batch.solve_now();
        }
        batch
            .posterior_in_units_of(draws, Some(path))
            .map(|p| p.draws)
    }

    /// Decides, from a fresh belief, whether to keep each model's start:
    /// the action model's while fewer than half the draws find the learned
    /// one nearer them than the start's, the sensor model's while fewer
    /// than `sensor_below` of them do.
    fn decide(&mut self) {
        let (Some(action), Some(sensor), false) = (
            self.learner.action_model(),
            self.learner.sensor_model(),
            self.lost,
        ) else {
            (self.keeping_action, self.keeping_sensor) = (false, None);
            return;
        };
        self.solved_over = self.path.len();
        let Some(draws) = Self::draws(&mut self.batch, false, DECISION_DRAWS, &self.path) else {
            return;
        };
        let scale = self.learner.params().command_scale();
        self.keeping_action = better_share(&action, &draws, scale).is_some_and(|s| s < 0.5);
        let below = self.keep_start.map_or(0.0, |k| k.sensor_below);
        self.keeping_sensor = self
            .start
            .as_ref()
            .and_then(Scasm::sensor_model)
            .and_then(|start| sensor_better_share(&sensor, &start, &draws))
            .is_some_and(|s| s < below)
            .then(|| draws[0].sensor.iter().map(|&(obs, _)| obs).collect());
    }
}

/// The share of `draws` by which the sensor model `learned` is nearer the
/// truth than `start` over the distances walked, by the paper's sensor
/// error: each draw judges at its own table's points (evenly spaced
/// locations over the path's range, and the readings it says they give);
/// `None` without draws.
fn sensor_better_share(learned: &Polynomial, start: &Polynomial, draws: &[Draw]) -> Option<f64> {
    let better = draws
        .iter()
        .filter(|d| {
            let (readings, truth): (Vec<f64>, Vec<f64>) = d.sensor.iter().copied().unzip();
            affine_error(learned, &readings, &truth).0 < affine_error(start, &readings, &truth).0
        })
        .count();
    (!draws.is_empty()).then(|| better as f64 / draws.len() as f64)
}

/// The paper's sensor error of `model` at `readings` against the locations
/// `truth`: the RMS difference after the affine map that best fits `model`
/// to `truth`, and that map (`(scale, offset)`).
fn affine_error(model: &Polynomial, readings: &[f64], truth: &[f64]) -> (f64, (f64, f64)) {
    let m: Vec<f64> = readings.iter().map(|&o| model.eval(o)).collect();
    let n = m.len() as f64;
    let (mean_m, mean_t) = (m.iter().sum::<f64>() / n, truth.iter().sum::<f64>() / n);
    let (mt, mm) = m
        .iter()
        .zip(truth)
        .fold((0.0, 0.0), |(mt, mm), (&mi, &ti)| {
            (
                mt + (mi - mean_m) * (ti - mean_t),
                mm + (mi - mean_m).powi(2),
            )
        });
    let scale = if mm > 0.0 { mt / mm } else { 0.0 };
    let offset = mean_t - scale * mean_m;
    let ss: f64 = m
        .iter()
        .zip(truth)
        .map(|(&mi, &ti)| (offset + scale * mi - ti).powi(2))
        .sum();
    (libm::sqrt(ss / n), (scale, offset))
}

/// `JUDGED_COMMANDS` commands evenly over `±scale`.
fn commands(scale: f64) -> impl Iterator<Item = f64> {
    (0..JUDGED_COMMANDS).map(move |i| scale * (2.0 * i as f64 / (JUDGED_COMMANDS - 1) as f64 - 1.0))
}

/// The share of `draws` by which `learned` is nearer the truth than the
/// start's line over the commands `±scale`, by the paper's action error;
/// `None` without draws.
fn better_share(learned: &Polynomial, draws: &[Draw], scale: f64) -> Option<f64> {
    let commands: Vec<f64> = commands(scale).collect();
    let line = Polynomial::identity();
    let better = draws
        .iter()
        .filter(|d| {
            scaled_error(learned, &d.action, &commands) < scaled_error(&line, &d.action, &commands)
        })
        .count();
    (!draws.is_empty()).then(|| better as f64 / draws.len() as f64)
}

/// The paper's action error of `model` against `truth` at `commands`: the
/// RMS difference after the scale that best fits `model` to `truth`.
fn scaled_error(model: &Polynomial, truth: &Polynomial, commands: &[f64]) -> f64 {
    let (tm, mm) = commands.iter().fold((0.0, 0.0), |(tm, mm), &c| {
        let (t, m) = (truth.eval(c), model.eval(c));
        (tm + t * m, mm + m * m)
    });
    let k = if mm > 0.0 { tm / mm } else { 0.0 };
    let ss: f64 = commands
        .iter()
        .map(|&c| (k * model.eval(c) - truth.eval(c)).powi(2))
        .sum();
    libm::sqrt(ss / commands.len() as f64)
}

/// The line through the origin nearest `model` over `±scale` (its scale
/// fitted at evenly spaced commands).
fn line_of(model: &Polynomial, scale: f64) -> Option<Polynomial> {
    let (cm, cc) = commands(scale).fold((0.0, 0.0), |(cm, cc), c| {
        (cm + c * model.eval(c), cc + c * c)
    });
    (cc > 0.0)
        .then(|| Polynomial::new(&[0.0, cm / cc]))
        .flatten()
}

impl CalibrationLearner for Believed {
    fn name(&self) -> &str {
        self.learner.name()
    }

    fn handle(&mut self, event: Event) -> Result<(), EventError> {
        self.learner.handle(event)?;
        // The learner took it; the batch learner's online learner checks
        // events alike, but should it not, the belief is no longer of the
        // events taken.
        let refused = self.batch.handle(event).is_err();
        let refused_start = self
            .start
            .as_mut()
            .is_some_and(|s| s.handle(event).is_err());
        self.lost |= refused || refused_start;
        let x = self.learner.x_a().unwrap_or(0.0);
        match event {
            Event::Command { .. } => self.path.push(x),
            Event::Reading { t_s, .. } => {
                if let Some(last) = self.path.last_mut() {
                    *last = x;
                }
                if let Some(k) = self.keep_start
                    && t_s >= self.next_decision_s - 1e-9
                {
                    while self.next_decision_s <= t_s + 1e-9 {
                        self.next_decision_s += k.every_s;
                    }
                    self.decide();
                }
            }
        }
        Ok(())
    }

    fn action_model(&self) -> Option<Polynomial> {
        let learned = self.learner.action_model()?;
        if self.keeping_action {
            line_of(&learned, self.learner.params().command_scale())
        } else {
            Some(learned)
        }
    }

    fn sensor_model(&self) -> Option<Polynomial> {
        let learned = self.learner.sensor_model()?;
        let start = self.keeping_sensor.as_ref().and_then(|judged| {
            let at: Vec<f64> = judged.iter().map(|&o| learned.eval(o)).collect();
            let start = self.start.as_ref()?.sensor_model()?;
            let (_, (scale, offset)) = affine_error(&start, judged, &at);
            Some(start.rescaled(scale, offset))
        });
        Some(start.unwrap_or(learned))
    }

    fn x_a(&self) -> Option<f64> {
        self.learner.x_a()
    }

    fn x_s(&self) -> Option<f64> {
        self.learner.x_s()
    }

    fn falling_back(&self) -> Option<bool> {
        self.learner.falling_back()
    }

    fn posterior(&self, draws: usize) -> Option<Posterior> {
        if self.lost {
            return None;
        }
        // A decision at the last reading has solved over every event.
        let solved = self.solved_over == self.path.len();
        let draws = Self::draws(&mut self.batch.clone(), solved, draws, &self.path)?;
        Some(Posterior { draws })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(c: &[f64]) -> Polynomial {
        Polynomial::new(c).expect("finite")
    }

    fn draw(action: Polynomial) -> Draw {
        Draw {
            action,
            sensor: vec![(10.0, 2.0), (20.0, 1.0)],
        }
    }

    #[test]
    fn the_action_error_is_the_papers_blind_to_scale() {
        let commands: Vec<f64> = commands(300.0).collect();
        let truth = poly(&[0.0, 0.8, 0.0, -2e-6]);
        assert!(scaled_error(&truth, &truth, &commands) < 1e-12);
        let twice = truth.rescaled(2.0, 0.0);
        assert!(scaled_error(&twice, &truth, &commands) < 1e-9);
        assert!(scaled_error(&Polynomial::identity(), &truth, &commands) > 1.0);
    }

    #[test]
    fn the_start_is_kept_only_where_the_draws_do_not_favour_the_learned_model() {
        let scale = 300.0;
        let curved = poly(&[0.0, 0.8, 0.0, -2e-6]);
        let learned = poly(&[0.0, 0.8, 1e-5, -2e-6]);
        // Draws of a curved truth favour the curved model learned.
        let draws: Vec<Draw> = (0..10)
            .map(|k| draw(curved.rescaled(1.0 + 0.01 * f64::from(k), 0.0)))
            .collect();
        assert_eq!(better_share(&learned, &draws, scale), Some(1.0));
        // Draws of a straight one favour the start's line.
        let lines: Vec<Draw> = (0..10)
            .map(|k| draw(poly(&[0.0, 0.7 + 0.01 * f64::from(k)])))
            .collect();
        assert_eq!(better_share(&learned, &lines, scale), Some(0.0));
        assert_eq!(better_share(&learned, &[], scale), None);
    }

    /// A draw whose sensor table is `truth` (a location per reading) at
    /// readings 20..=50 px.
    fn sensor_draw(truth: impl Fn(f64) -> f64) -> Draw {
        Draw {
            action: Polynomial::identity(),
            sensor: (20..=50).map(f64::from).map(|o| (o, truth(o))).collect(),
        }
    }

    #[test]
    fn the_sensor_start_is_kept_only_where_the_draws_do_not_favour_the_learned_model() {
        // The truth is a pinhole camera; the learned model is a curve near
        // it, the start a line (each in its own units: the error is blind to
        // them). The draws' tables span 20-50 px.
        let pinhole = |o: f64| 40.0 / o;
        let learned = poly(&[4.2, -0.13, 0.0012]);
        let start = poly(&[100.0, -2.0]);
        let near: Vec<Draw> = (0..10)
            .map(|k| sensor_draw(move |o| (1.0 + 0.01 * f64::from(k)) * pinhole(o)))
            .collect();
        assert_eq!(sensor_better_share(&learned, &start, &near), Some(1.0));
        // A straight truth favours the straight start.
        let straight: Vec<Draw> = (0..10)
            .map(|k| sensor_draw(move |o| 3.0 - (0.03 + 0.001 * f64::from(k)) * o))
            .collect();
        assert_eq!(sensor_better_share(&learned, &start, &straight), Some(0.0));
        assert_eq!(sensor_better_share(&learned, &start, &[]), None);
    }

    #[test]
    fn a_sensor_model_kept_is_the_starts_in_the_learned_ones_units() {
        let judged: Vec<f64> = (20..=50).map(f64::from).collect();
        let learned = poly(&[4.2, -0.13, 0.0012]);
        let start = poly(&[100.0, -2.0]);
        let at: Vec<f64> = judged.iter().map(|&o| learned.eval(o)).collect();
        let (_, (scale, offset)) = affine_error(&start, &judged, &at);
        let kept = start.rescaled(scale, offset);
        // As near the learned model as an affine map of the start can be...
        let (residual, (k, b)) = affine_error(&kept, &judged, &at);
        assert!((k - 1.0).abs() < 1e-9 && b.abs() < 1e-9, "{k} {b}");
        assert!(residual > 0.0);
        // ...and, by the metric, exactly the start.
        let truth: Vec<f64> = judged.iter().map(|o| 40.0 / o).collect();
        let (e_kept, _) = affine_error(&kept, &judged, &truth);
        let (e_start, _) = affine_error(&start, &judged, &truth);
        assert!((e_kept - e_start).abs() < 1e-12 * e_start.max(1.0));
    }

    #[test]
    fn the_line_kept_is_the_learned_models_own_scale() {
        let line = line_of(&poly(&[0.0, 0.8, 0.0, -2e-6]), 300.0).expect("a line");
        assert_eq!(line.degree(), 1);
        assert!(line.eval(0.0).abs() < 1e-12);
        // The same line fitted to itself.
        let again = line_of(&line, 300.0).expect("a line");
        assert!((again.eval(300.0) - line.eval(300.0)).abs() < 1e-9);
        // Near the learned model's slope over the range (0.8, less its cubic's pull).
        assert!((0.6..0.8).contains(&(line.eval(1.0))));
    }
}
