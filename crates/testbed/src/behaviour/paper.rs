//! The paper's training behaviour (section II): walking towards the beacon
//! and away from it with random commands, each held for a while, drawn
//! uniformly from `[0, max]` forwards and `[-max, 0]` backwards, turning
//! round when the beacon looks too big or too small. The same walk with its
//! command magnitudes drawn from a design instead ([`Draw::Design`]) is the
//! `design` behaviour ([`super::design`]); chosen by an explorer that sees
//! the learner's models ([`Draw::Explore`]), the `explore` behaviour
//! ([`super::explore`]).

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::{Behaviour, BehaviourConfig, Phase};

/// How a command's magnitude is drawn.
#[derive(Debug, Clone, PartialEq)]
pub enum Draw {
    /// Uniformly from `[0, max]` (the paper's).
    Uniform,
    /// From these fractions of `max`, each with its probability (summing
    /// to 1), in increasing order of fraction.
    Design(Vec<(f64, f64)>),
    /// Chosen by the explorer, from what the robot has walked and the
    /// learner's models (no random draw).
    Explore(Box<super::explore::Explorer>),
}

/// The behaviour's state: its phase, the command in force and until when.
#[derive(Debug, Clone)]
pub struct TrainingBehaviour {
    config: BehaviourConfig,
    draw: Draw,
    rng: ChaCha8Rng,
    phase: Phase,
    command: f64,
    hold_until_s: f64,
    /// The latest readings since the last turn, oldest first.
    recent: std::collections::VecDeque<f64>,
}

impl TrainingBehaviour {
    /// The paper's behaviour, starting in `phase` with a fresh command at
    /// time 0.
    pub fn new(config: BehaviourConfig, rng: ChaCha8Rng, phase: Phase) -> Self {
        Self::drawing(config, Draw::Uniform, rng, phase)
    }

    /// The walk with its magnitudes drawn by `draw`, starting in `phase`
    /// with a fresh command at time 0.
    pub fn drawing(config: BehaviourConfig, draw: Draw, rng: ChaCha8Rng, phase: Phase) -> Self {
        let mut b = Self {
            config,
            draw,
            rng,
            phase,
            command: 0.0,
            hold_until_s: 0.0,
            recent: std::collections::VecDeque::new(),
        };
        b.pick(0.0);
        b
    }

    fn pick(&mut self, t_s: f64) {
        let max = self.config.max_command;
        let magnitude = match &self.draw {
            Draw::Uniform => self.rng.random_range(0.0..=max),
            Draw::Design(support) => {
                let u: f64 = self.rng.random_range(0.0..1.0);
                let mut below = 0.0;
                let mut chosen = support.last().map_or(1.0, |s| s.0);
                for &(fraction, p) in support {
                    below += p;
                    if u < below {
                        chosen = fraction;
                        break;
                    }
                }
                chosen * max
            }
            Draw::Explore(explorer) => explorer.choose(self.phase, self.command, &self.config),
        };
        self.hold(magnitude, t_s);
    }

    /// Holds `magnitude` in the current phase's direction from `t_s`.
    fn hold(&mut self, magnitude: f64, t_s: f64) {
        let command = match self.phase {
            Phase::Forwards => magnitude,
            Phase::Backwards => -magnitude,
        };
        if let Draw::Explore(explorer) = &mut self.draw {
            explorer.held(t_s, command != self.command);
        }
        self.command = command;
        self.hold_until_s = t_s + self.config.hold_s;
    }
}

impl Behaviour for TrainingBehaviour {
    /// Turns round if the beacon looks too big or too small, which starts a new
    /// command at once.
    fn observe(&mut self, t_s: f64, obs_px: Option<f64>) {
        if let Draw::Explore(explorer) = &mut self.draw {
            explorer.walked(t_s, self.command, self.config.max_command, obs_px.is_some());
        }
        let Some(obs) = obs_px else { return };
        let n = self.config.turn_median_of.max(1);
        self.recent.push_back(obs);
        while self.recent.len() > n {
            self.recent.pop_front();
        }
        if self.recent.len() < n {
            return;
        }
        let mut sorted: Vec<f64> = self.recent.iter().copied().collect();
        sorted.sort_by(f64::total_cmp);
        let obs = sorted[n / 2];
        let turn = match self.phase {
            Phase::Forwards if obs >= self.config.near_obs_px => Some(Phase::Backwards),
            Phase::Backwards if obs <= self.config.far_obs_px => Some(Phase::Forwards),
            _ => None,
        };
        if let Some(phase) = turn {
            self.phase = phase;
            self.recent.clear();
            self.pick(t_s);
        }
    }

    /// A new command is drawn when the old one's time is up.
    fn command(&mut self, t_s: f64) -> f64 {
        if t_s >= self.hold_until_s {
            self.pick(t_s);
        }
        self.command
    }

    fn phase(&self) -> Phase {
        self.phase
    }

    fn consult(&mut self, t_s: f64, learner: &dyn scasm::CalibrationLearner) {
        if let Draw::Explore(explorer) = &mut self.draw {
            explorer.consult(t_s, learner);
        }
    }
}
