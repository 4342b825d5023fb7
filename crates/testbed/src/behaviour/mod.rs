//! What the robot does while it learns: a training behaviour chooses each
//! walk command from what the robot has seen, as a learner would see it
//! (its own commands and the readings), never the ground truth. The
//! behaviours a run can name are declared in [`registry`]: the paper's
//! (section II, [`paper`]: random commands held for a while, turning round
//! when the beacon looks too big or too small) and one that chooses its
//! commands by an optimal design ([`design`]), and one that steers by the
//! learner's current models ([`explore`]). The constant walk of section IV
//! is here too.

pub mod design;
pub mod explore;
pub mod paper;
pub mod registry;

pub use paper::TrainingBehaviour;
pub use registry::{BEHAVIOURS, Declaration, resolve};

/// Settings of a training behaviour: which one, and what every one is told.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BehaviourConfig {
    /// The behaviour's name ([`registry`], `behaviour.name`).
    pub name: &'static str,
    /// The action model's degree, for a behaviour that designs its commands
    /// for it (the learner's `action_degree`).
    pub action_degree: usize,
    /// How many degrees richer than the action model the `design`
    /// behaviour's model is (`behaviour.design_extra_degree`, see
    /// [`design`]).
    pub design_extra_degree: usize,
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

impl BehaviourConfig {
    /// The paper's behaviour turning at these readings, with commands up to
    /// `max_command` held 3 s and the default learner's action degree.
    pub fn paper(max_command: f64, near_obs_px: f64, far_obs_px: f64) -> Self {
        Self {
            name: registry::DEFAULT,
            action_degree: scasm::ScasmConfig::default().action_degree,
            design_extra_degree: design::EXTRA_DEGREE,
            max_command,
            hold_s: 3.0,
            near_obs_px,
            far_obs_px,
            turn_median_of: TURN_MEDIAN_OF,
        }
    }
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
    /// Sees the learner after it has been fed the frame that ended at
    /// `t_s`: what it reports (its models, its locations, its posterior),
    /// never the ground truth. Called only for a behaviour declared
    /// [`Declaration::steered`], whose trial runs with its learner in the
    /// loop; the default ignores it.
    fn consult(&mut self, t_s: f64, learner: &dyn scasm::CalibrationLearner) {
        let _ = (t_s, learner);
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
