//! One training trial on the simulated robot: the paper's behaviour drives the
//! robot, the head camera reads the beacon at 20 Hz, and a calibration learner is
//! fed the command in force over each frame and each reading, and nothing else.
//! Ground truth is recorded beside it for judging, never shown to the learner.

use quadsim::{QuadrupedSim, RobotDescription, SimConfig, SimError};
use rand::Rng;
use scasm::{CalibrationLearner, Event, EventError, Polynomial};

use crate::behaviour::{Behaviour, BehaviourConfig, Phase, TrainingBehaviour};
use crate::reference::{Judgement, Reference};
use crate::seeds::{self, Stream};

/// What went wrong in a trial.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TrialError {
    /// The world could not be built.
    #[error(transparent)]
    Sim(#[from] SimError),
    /// The learner refused an event (a bug in the host or the learner).
    #[error("the learner refused an event: {0}")]
    Learner(#[from] EventError),
    /// The learner could not be set up for this scenario.
    #[error("cannot set up the learner: {0}")]
    LearnerSetup(String),
}

/// Settings of one trial.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrialConfig {
    /// Trial length, s.
    pub duration_s: f64,
    /// The master seed (behaviour and reading noise get their own streams of it).
    pub seed: u64,
    /// The training behaviour.
    pub behaviour: BehaviourConfig,
    /// How often the learned models are judged during the trial, s (Fig. 8).
    pub judge_every_s: f64,
}

/// One row of a trial's trace: one camera frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TraceRow {
    /// Time at the end of the frame, s.
    pub t_s: f64,
    /// The command in force over the frame.
    pub command: f64,
    /// The reading, if the frame had one, px.
    pub obs_px: Option<f64>,
    /// Ground truth: distance to the beacon along the line, mm.
    pub x_true_mm: f64,
    /// The learner's dead-reckoned location.
    pub x_a: Option<f64>,
    /// The learner's location from the sensor model.
    pub x_s: Option<f64>,
}

/// A trial in progress: the robot, its world and its behaviour. The learner is
/// passed to each step, so it can be checkpointed and swapped mid-trial.
#[derive(Debug)]
pub struct TrialRunner {
    config: TrialConfig,
    sim: QuadrupedSim,
    behaviour: Box<dyn Behaviour>,
    frame: u64,
    fell: bool,
}

impl TrialRunner {
    /// Builds the world for a trial of the paper's training behaviour.
    pub fn new(
        description: &RobotDescription,
        sim_config: SimConfig,
        config: TrialConfig,
    ) -> Result<Self, TrialError> {
        let behaviour = TrainingBehaviour::new(
            config.behaviour,
            seeds::rng(config.seed, Stream::Behaviour),
            Phase::Forwards,
        );
        Self::with_behaviour(description, sim_config, config, Box::new(behaviour))
    }

    /// Builds the world for a trial of another behaviour (`config.behaviour` is
    /// then unused).
    pub fn with_behaviour(
        description: &RobotDescription,
        sim_config: SimConfig,
        config: TrialConfig,
        behaviour: Box<dyn Behaviour>,
    ) -> Result<Self, TrialError> {
        let mut sim_config = sim_config;
        sim_config.camera.noise_seed = seeds::rng(config.seed, Stream::SensorNoise).next_u64();
        let sim = QuadrupedSim::new(description, sim_config)?;
        Ok(Self {
            config,
            sim,
            behaviour,
            frame: 0,
            fell: false,
        })
    }

    /// The simulated robot and world (for viewers; learners never see it).
    pub fn sim(&self) -> &QuadrupedSim {
        &self.sim
    }

    /// The behaviour driving the robot.
    pub fn behaviour(&self) -> &dyn Behaviour {
        self.behaviour.as_ref()
    }

    /// Frames in the whole trial.
    pub fn total_frames(&self) -> u64 {
        (self.config.duration_s / self.frame_period_s()).round() as u64
    }

    fn frame_period_s(&self) -> f64 {
        self.sim.config().camera.frame_period_s
    }

    /// Whether every frame has run.
    pub fn finished(&self) -> bool {
        self.frame >= self.total_frames()
    }

    /// Whether the torso ever tipped (up-vector z <= 0.8).
    pub fn fell(&self) -> bool {
        self.fell
    }

    /// Runs one camera frame: the behaviour's command over it, the learner told
    /// of the command and then of the reading (if any).
    pub fn step_frame(
        &mut self,
        learner: &mut dyn CalibrationLearner,
    ) -> Result<TraceRow, TrialError> {
        let dt_s = self.frame_period_s();
        let t_s = self.frame as f64 * dt_s;
        let command = self.behaviour.command(t_s);
        self.sim.set_command(command).map_err(SimError::from)?;
        let frame = loop {
            self.sim.step();
            self.fell |= !self.sim.is_upright();
            if let Some(f) = self.sim.take_frame() {
                break f;
            }
        };
        learner.handle(Event::Command { t_s, dt_s, command })?;
        let t_end = t_s + dt_s;
        let obs_px = frame.obs_px.ok();
        if let Some(obs_px) = obs_px {
            learner.handle(Event::Reading { t_s: t_end, obs_px })?;
        }
        self.behaviour.observe(t_end, obs_px);
        self.frame += 1;
        Ok(TraceRow {
            t_s: t_end,
            command,
            obs_px,
            x_true_mm: 1000.0 * self.sim.distance_along_line_m(),
            x_a: learner.x_a(),
            x_s: learner.x_s(),
        })
    }
}

/// A finished trial.
#[derive(Debug, Clone, PartialEq)]
pub struct TrialOutcome {
    /// The master seed.
    pub seed: u64,
    /// One row per frame.
    pub trace: Vec<TraceRow>,
    /// The models' errors every `judge_every_s` (Fig. 8).
    pub over_time: Vec<Judgement>,
    /// The learned action model at the end.
    pub action_model: Option<Polynomial>,
    /// The learned sensor model at the end.
    pub sensor_model: Option<Polynomial>,
    /// The final judgement.
    pub last: Judgement,
    /// Whether the robot tipped over at any point.
    pub fell: bool,
    /// Simulated seconds per wall-clock second.
    pub realtime_factor: f64,
}

/// Runs a whole trial with `learner`.
pub fn run_trial(
    description: &RobotDescription,
    sim_config: SimConfig,
    config: TrialConfig,
    learner: &mut dyn CalibrationLearner,
    reference: &Reference,
) -> Result<TrialOutcome, TrialError> {
    let started = std::time::Instant::now();
    let mut runner = TrialRunner::new(description, sim_config, config)?;
    let judge_every = (config.judge_every_s / runner.frame_period_s())
        .round()
        .max(1.0) as u64;
    let mut trace = Vec::with_capacity(runner.total_frames() as usize);
    let mut over_time = Vec::new();
    while !runner.finished() {
        let row = runner.step_frame(learner)?;
        if runner.frame % judge_every == 0 {
            over_time.push(reference.judge(row.t_s, learner));
        }
        trace.push(row);
    }
    let wall = started.elapsed().as_secs_f64();
    Ok(TrialOutcome {
        seed: config.seed,
        last: reference.judge(config.duration_s, learner),
        trace,
        over_time,
        action_model: learner.action_model(),
        sensor_model: learner.sensor_model(),
        fell: runner.fell(),
        realtime_factor: config.duration_s / wall.max(1e-9),
    })
}
