//! The `explore` behaviour: the paper's walk (the same holds and turning
//! round) with each command chosen, when it is due, to teach the action
//! model the most given what the robot has walked so far and what the
//! learner's current models predict the command will get.
//!
//! The criterion is the `design` behaviour's, made sequential: the action
//! model's average prediction variance over the paper's 31 commands,
//! `trace(L M^-1)` (see [`super::design`]), where `M` sums `f(u) f(u)^T`
//! over the frames walked so far that taught something (a reading seen, and
//! past the transient after a change of command), `u` the command as a
//! fraction of the largest. Of the candidates (every 5 % of the largest, in
//! the phase's direction) it holds the one whose frames lower it most: `k`
//! frames at `u` lower it by `k f^T M^-1 L M^-1 f / (1 + k f^T M^-1 f)`
//! (Sherman and Morrison), a greedy step of sequential I-optimal design.
//!
//! The learner's models say what `k` is: a command is held `hold_s` unless
//! the robot turns round first, and the learner's action model (its speed at
//! the command), its location from the latest reading and its sensor model
//! (the locations of the turning readings) say when it would; the frames of
//! the transient after a change of command count for nothing. Without models
//! yet (or with models that cannot say) a command counts its whole hold. Like
//! the design, it is for a polynomial `behaviour.design_extra_degree` degrees
//! above the action model's. It draws no random numbers: the seed moves it
//! only through the readings and what the learner makes of them.
//!
//! Its cost: none in time, distance or turns beyond the paper's walk (the
//! same holds and turning readings); it asks the learner for its models once
//! a second of the trial, and a trial with it runs its learner in the loop
//! (its recording is that learner's own).

use nalgebra::{DMatrix, DVector};
use scasm::{CalibrationLearner, Polynomial};

use super::design::{basis, metric_matrix};
use super::{BehaviourConfig, Phase};

/// Seconds after a change of command whose frames count for nothing: the
/// gait's transient, which no learner's model but the lag's follows. Chosen
/// on development seeds 100-129 (the ERS-7, `scasm` and `batch-ml-lag`)
/// among 0.25, 0.5, 1, 1.5 and 2 s: 1 s gave both learners their best
/// figures at the end and `scasm` its earliest paper level (book:
/// Behaviours). It makes the explorer keep a command rather than change it
/// for a little more information.
pub const TRANSIENT_S: f64 = 1.0;
/// Candidate commands per direction: every 5 % of the largest, and zero.
const CANDIDATES: usize = 21;
/// How often the learner is asked for its models, s.
const CONSULT_EVERY_S: f64 = 1.0;
/// `M`'s start, `RIDGE I`, so that it is invertible before any frame.
const RIDGE: f64 = 1e-6;

/// What the learner last said, for predicting a hold.
#[derive(Debug, Clone, PartialEq)]
struct Models {
    action: Polynomial,
    sensor: Polynomial,
    x_s: f64,
}

/// The explorer's state: the information walked so far and the learner's
/// latest models.
#[derive(Debug, Clone, PartialEq)]
pub struct Explorer {
    degree: usize,
    l: DMatrix<f64>,
    m: DMatrix<f64>,
    models: Option<Models>,
    consulted_s: f64,
    /// When the command in force started, s.
    changed_s: f64,
    /// The end of the last frame observed, s.
    last_s: f64,
    /// The camera's frame interval, s, as the frames come.
    frame_s: f64,
}

impl Explorer {
    /// An explorer for a polynomial of `degree` that has walked nothing.
    pub fn new(degree: usize) -> Self {
        let n = degree + 1;
        Self {
            degree,
            l: metric_matrix(degree),
            m: DMatrix::identity(n, n) * RIDGE,
            models: None,
            consulted_s: f64::NEG_INFINITY,
            changed_s: 0.0,
            last_s: 0.0,
            frame_s: 0.05,
        }
    }

    /// The frame that ended at `t_s` was walked at `command` (of `max`),
    /// with a reading if `seen`.
    pub fn walked(&mut self, t_s: f64, command: f64, max: f64, seen: bool) {
        let started_s = self.last_s;
        self.last_s = t_s;
        if t_s > started_s {
            self.frame_s = t_s - started_s;
        }
        if seen && started_s >= self.changed_s + TRANSIENT_S - 1e-9 {
            let f = basis(command / max, self.degree);
            self.m += &f * f.transpose();
        }
    }

    /// A command starts at `t_s`; `changed` if it differs from the last.
    pub fn held(&mut self, t_s: f64, changed: bool) {
        if changed {
            self.changed_s = t_s;
        }
    }

    /// Takes the learner's models, once a second.
    pub fn consult(&mut self, t_s: f64, learner: &dyn CalibrationLearner) {
        if t_s < self.consulted_s + CONSULT_EVERY_S - 1e-9 {
            return;
        }
        self.consulted_s = t_s;
        self.models = match (
            learner.action_model(),
            learner.sensor_model(),
            learner.x_s(),
        ) {
            (Some(action), Some(sensor), Some(x_s))
                if action.is_finite() && sensor.is_finite() && x_s.is_finite() =>
            {
                Some(Models {
                    action,
                    sensor,
                    x_s,
                })
            }
            _ => None,
        };
    }

    /// How long a hold of `command` from `t_s` would last by the learner's
    /// models: `hold_s`, or less if they say the robot would reach the
    /// phase's turning reading first.
    fn predicted_hold_s(&self, command: f64, phase: Phase, config: &BehaviourConfig) -> f64 {
        let Some(m) = &self.models else {
            return config.hold_s;
        };
        let turn_obs = match phase {
            Phase::Forwards => config.near_obs_px,
            Phase::Backwards => config.far_obs_px,
        };
        let remaining = m.sensor.eval(turn_obs) - m.x_s;
        let speed = m.action.eval(command);
        let t = remaining / speed;
        if !t.is_finite() || t < 0.0 {
            // Not towards the turn by the models, or they cannot say.
            config.hold_s
        } else {
            t.min(config.hold_s)
        }
    }

    /// The magnitude (up to `config.max_command`) to hold next in `phase`,
    /// with `current` the command in force until now.
    pub fn choose(&self, phase: Phase, current: f64, config: &BehaviourConfig) -> f64 {
        let max = config.max_command;
        let sign = match phase {
            Phase::Forwards => 1.0,
            Phase::Backwards => -1.0,
        };
        let Some(mi) = self.m.clone().cholesky().map(|c| c.inverse()) else {
            return max;
        };
        let b = &mi * &self.l * &mi;
        let mut best = (f64::NEG_INFINITY, max);
        for k in 0..CANDIDATES {
            let magnitude = max * k as f64 / (CANDIDATES - 1) as f64;
            let command = sign * magnitude;
            let mut taught_s = self.predicted_hold_s(command, phase, config);
            if command != current {
                taught_s -= TRANSIENT_S;
            }
            let frames = (taught_s / self.frame_s).max(0.0);
            let f: DVector<f64> = basis(command / max, self.degree);
            let gain = frames * (f.transpose() * &b * &f)[(0, 0)]
                / (1.0 + frames * (f.transpose() * &mi * &f)[(0, 0)]);
            if gain > best.0 {
                best = (gain, magnitude);
            }
        }
        best.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config() -> BehaviourConfig {
        BehaviourConfig {
            name: "explore",
            ..BehaviourConfig::paper(300.0, 40.0, 10.0)
        }
    }

    /// Walks `seconds` at `command` in frames of 0.05 s from `t_s`.
    fn walk(e: &mut Explorer, t_s: f64, seconds: f64, command: f64) -> f64 {
        e.held(t_s, true);
        let frames = (seconds / 0.05).round() as usize;
        for i in 1..=frames {
            e.walked(t_s + i as f64 * 0.05, command, 300.0, true);
        }
        t_s + seconds
    }

    #[test]
    fn it_goes_where_it_has_not_been() {
        let c = config();
        let mut e = Explorer::new(8);
        // Having walked only at the largest command forwards, it does not
        // choose it again.
        let mut t = walk(&mut e, 0.0, 6.0, 300.0);
        let first = e.choose(Phase::Forwards, 300.0, &c);
        assert!(first < 300.0, "{first}");
        // Over many holds it spreads its commands over the range.
        let mut seen = vec![first];
        let mut command = first;
        for i in 0..30 {
            let phase = if i % 2 == 0 {
                Phase::Backwards
            } else {
                Phase::Forwards
            };
            let sign = if i % 2 == 0 { -1.0 } else { 1.0 };
            t = walk(&mut e, t, 3.0, command);
            command = sign * e.choose(phase, command, &c);
            seen.push(command.abs());
        }
        seen.sort_by(f64::total_cmp);
        seen.dedup();
        assert!(seen.len() >= 4, "{seen:?}");
    }

    #[test]
    fn a_hold_the_models_say_ends_at_the_turn_counts_only_until_it() {
        let c = config();
        let mut e = Explorer::new(4);
        // Location = 12 000 / reading (mm), speed = command (mm/s), 10 mm
        // before the near turn (at 300 mm): the fast commands would be cut
        // short; with no models every hold counts whole.
        assert_eq!(e.predicted_hold_s(300.0, Phase::Forwards, &c), 3.0);
        // Location 400 - 10 reading: the near turn (40 px) at 0, the far
        // one (10 px) at 300; speed minus the command; the robot at 10.
        e.models = Some(Models {
            action: Polynomial::new(&[0.0, -1.0]).expect("a line"),
            sensor: Polynomial::new(&[400.0, -10.0]).expect("a line"),
            x_s: 10.0,
        });
        let cut = e.predicted_hold_s(300.0, Phase::Forwards, &c);
        assert!((cut - 10.0 / 300.0).abs() < 1e-12, "{cut}");
        assert_eq!(e.predicted_hold_s(30.0, Phase::Forwards, &c), 1.0 / 3.0);
        let back = e.predicted_hold_s(-300.0, Phase::Backwards, &c);
        assert!((back - 290.0 / 300.0).abs() < 1e-12, "{back}");
        assert_eq!(e.predicted_hold_s(-30.0, Phase::Backwards, &c), 3.0);
        // A model that has the robot walk away from its turn cannot say.
        e.models = Some(Models {
            action: Polynomial::new(&[0.0, 1.0]).expect("a line"),
            sensor: Polynomial::new(&[400.0, -10.0]).expect("a line"),
            x_s: 10.0,
        });
        assert_eq!(e.predicted_hold_s(300.0, Phase::Forwards, &c), 3.0);
    }
}
