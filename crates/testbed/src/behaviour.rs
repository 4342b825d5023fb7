//! What the robot does: the paper's training behaviour (section II), walking
//! towards the beacon and away from it with random commands held for a while and
//! turning round when the beacon looks too big or too small; and the constant
//! walk of section IV. Behaviours see only readings, as the robot would.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// Settings of the training behaviour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BehaviourConfig {
    /// Largest command magnitude (forwards phases pick in `[0, max]`, backwards in `[-max, 0]`).
    pub max_command: f64,
    /// How long each command is held, s.
    pub hold_s: f64,
    /// Turn to backwards when a reading is at least this big (too close), px.
    pub near_obs_px: f64,
    /// Turn to forwards when a reading is at most this small (too far), px.
    pub far_obs_px: f64,
    /// Turn on the median of this many latest readings (1: on each reading), so
    /// that one noisy reading does not turn the robot round early.
    pub turn_median_of: usize,
}

/// Readings in the turn-round median by default: a quarter second at 20 Hz.
pub const TURN_MEDIAN_OF: usize = 5;

/// Which way the robot is going.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Towards the beacon (positive commands).
    Forwards,
    /// Away from the beacon (negative commands).
    Backwards,
}

/// Chooses the robot's walk command from its readings.
pub trait Behaviour: std::fmt::Debug + Send {
    /// The command in force at `t_s`.
    fn command(&mut self, t_s: f64) -> f64;
    /// Takes a reading (if any) at `t_s`.
    fn observe(&mut self, t_s: f64, obs_px: Option<f64>);
    /// Which way the robot is going.
    fn phase(&self) -> Phase;
}

/// The behaviour's state: its phase, the command in force and until when.
#[derive(Debug, Clone)]
pub struct TrainingBehaviour {
    config: BehaviourConfig,
    rng: ChaCha8Rng,
    phase: Phase,
    command: f64,
    hold_until_s: f64,
    /// The latest readings since the last turn, oldest first.
    recent: std::collections::VecDeque<f64>,
}

impl TrainingBehaviour {
    /// Starts in `phase` with a fresh command at time 0.
    pub fn new(config: BehaviourConfig, rng: ChaCha8Rng, phase: Phase) -> Self {
        let mut b = Self {
            config,
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
        let magnitude = self.rng.random_range(0.0..=self.config.max_command);
        self.command = match self.phase {
            Phase::Forwards => magnitude,
            Phase::Backwards => -magnitude,
        };
        self.hold_until_s = t_s + self.config.hold_s;
    }
}

impl Behaviour for TrainingBehaviour {
    /// Turns round if the beacon looks too big or too small, which starts a new
    /// command at once.
    fn observe(&mut self, t_s: f64, obs_px: Option<f64>) {
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
}

/// One constant command towards the beacon until it looks as big as at the
/// nearest test distance, then standing (command 0, phase `Backwards`): the walk
/// of the paper's Fig. 2a.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstantWalk {
    /// The command walked with.
    pub command: f64,
    /// Stop when a reading is at least this big, px.
    pub near_obs_px: f64,
    /// Whether the walk has arrived.
    pub arrived: bool,
}

impl Behaviour for ConstantWalk {
    fn command(&mut self, _t_s: f64) -> f64 {
        if self.arrived { 0.0 } else { self.command }
    }

    fn observe(&mut self, _t_s: f64, obs_px: Option<f64>) {
        self.arrived |= obs_px.is_some_and(|o| o >= self.near_obs_px);
    }

    fn phase(&self) -> Phase {
        if self.arrived {
            Phase::Backwards
        } else {
            Phase::Forwards
        }
    }
}
