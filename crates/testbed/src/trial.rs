//! One training trial, in two halves that never meet: the world (a training
//! behaviour drives the robot in any [`crate::world::World`], whose camera reads
//! the beacon at 20 Hz) records each frame, and a calibration learner is fed
//! each frame's command and reading, and nothing else. Ground truth is recorded
//! beside them for judging, never shown to a learner. A behaviour that never
//! looks at a learner records a world any number of learners can be fed,
//! live or replayed from disk; one that steers by the learner's models
//! records with a twin of the learner in the loop ([`record_steered`]).

use quadsim::{QuadrupedSim, RobotDescription, SimConfig, SimError};
use scasm::{CalibrationLearner, EventError, Polynomial};

use crate::behaviour::{Behaviour, BehaviourConfig};
pub use crate::blanks::Blanks;
use crate::floor::{Floor, Sample};
use crate::localiser::{Following, Learned, Localiser, LocaliserConfig, Tabulated};
use crate::predicted::{DRAWS, Prediction};
use crate::reference::{Judgement, Reference};
use crate::seeds::{self, Stream};
pub use crate::world::{FrameRecord, Truth};
use crate::world::{RapierWorld, World, WorldError};

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
    /// The learner failed during the trial (a program that crashed, broke
    /// the protocol or stopped answering): why.
    #[error("{0}")]
    LearnerFailed(String),
    /// The scenario's world changes cannot be made.
    #[error(transparent)]
    Setting(#[from] crate::scenario::SettingError),
    /// The trial's world could not be recorded.
    #[error("recording failed: {0}")]
    Recording(String),
    /// The learner failed at a frame of the trial (`source` says how).
    #[error("at {t_s:.2} s (frame {frame}): {source}")]
    At {
        /// The frame, counted from 0.
        frame: usize,
        /// The end of that frame, s into the trial.
        t_s: f64,
        /// What failed.
        source: Box<TrialError>,
    },
}

impl From<WorldError> for TrialError {
    fn from(e: WorldError) -> Self {
        match e {
            WorldError::Sim(e) => TrialError::Sim(e),
            other => TrialError::Recording(other.to_string()),
        }
    }
}

impl TrialError {
    /// The error itself, without where in the trial it happened.
    pub fn root(&self) -> &TrialError {
        match self {
            Self::At { source, .. } => source.root(),
            other => other,
        }
    }

    /// Where in the trial it happened, if known: the frame and its end, s.
    pub fn at(&self) -> Option<(usize, f64)> {
        match self {
            Self::At { frame, t_s, .. } => Some((*frame, *t_s)),
            _ => None,
        }
    }
}

/// Settings of one trial.
#[derive(Debug, Clone, PartialEq)]
pub struct TrialConfig {
    /// Trial length, s.
    pub duration_s: f64,
    /// The master seed (behaviour and reading noise get their own streams of it).
    pub seed: u64,
    /// The training behaviour.
    pub behaviour: BehaviourConfig,
    /// How often the learned models are judged during the trial, s (Fig. 8).
    pub judge_every_s: f64,
    /// When the camera sees no beacon (its readings blanked, as when the
    /// beacon is out of view).
    pub blank: Blanks,
    /// Changes of the world during the trial, in time order: from the first
    /// frame that starts at or after each time (s), the world's settings
    /// become these (see [`QuadrupedSim::change_world`]).
    pub changes: Vec<(f64, SimConfig)>,
}

/// Feeds one frame's events to a learner. This is the only way learners are
/// fed, live or replayed, so a replay is the live run, bit for bit.
pub fn feed(learner: &mut dyn CalibrationLearner, frame: &FrameRecord) -> Result<(), EventError> {
    frame.events().try_for_each(|e| learner.handle(e))
}

/// [`feed`], and then whether the learner can go on: a refused event, or a
/// learner that has failed (a program that died, say), ends the trial with
/// the reason. Queries may also find a learner failed: check
/// [`CalibrationLearner::failure`] after them (see [`learner_failed`]).
pub fn feed_checked(
    learner: &mut dyn CalibrationLearner,
    frame: &FrameRecord,
) -> Result<(), TrialError> {
    let fed = feed(learner, frame).err();
    match (learner_failed(learner), fed) {
        (Some(e), _) => Err(e),
        (None, Some(e)) => Err(TrialError::Learner(e)),
        (None, None) => Ok(()),
    }
}

/// The learner's failure, as a trial's error, if it has failed.
pub fn learner_failed(learner: &dyn CalibrationLearner) -> Option<TrialError> {
    learner
        .failure()
        .map(|why| TrialError::LearnerFailed(why.into()))
}

/// A trial's world as recorded: every frame, in order.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// The master seed.
    pub seed: u64,
    /// One record per camera frame.
    pub frames: Vec<FrameRecord>,
    /// Simulated seconds per wall-clock second while recording (NaN if not
    /// recorded live).
    pub realtime_factor: f64,
}

impl Recording {
    /// The frames recorded from `seed`, timed from `started`.
    fn timed(seed: u64, frames: Vec<FrameRecord>, started: std::time::Instant) -> Self {
        let simulated_s = frames.last().map_or(0.0, FrameRecord::end_s);
        Self {
            seed,
            frames,
            realtime_factor: simulated_s / started.elapsed().as_secs_f64().max(1e-9),
        }
    }

    /// Whether the robot tipped over at any point.
    pub fn fell(&self) -> bool {
        self.fell_at_s().is_some()
    }

    /// When the robot tipped over, s, if it did: the end of the first frame
    /// during which it was not upright throughout (to within a frame).
    pub fn fell_at_s(&self) -> Option<f64> {
        self.frames
            .iter()
            .find(|f| !f.truth.upright)
            .map(FrameRecord::end_s)
    }

    /// When the physics blew up, s, if it did: the end of the frame in
    /// which it did.
    pub fn blew_up_at_s(&self) -> Option<f64> {
        self.frames
            .iter()
            .find(|f| f.truth.blew_up)
            .map(FrameRecord::end_s)
    }
}

/// A trial in progress: a world ([`World`]) and the training behaviour
/// that drives it. It knows nothing of learners
/// ([`TrialRunner::step_frame_steered`] shows one to a behaviour that
/// steers by it); [`feed`] gives its frames to any number of them.
#[derive(Debug)]
pub struct TrialRunner<W: World = RapierWorld> {
    config: TrialConfig,
    world: W,
    behaviour: Box<dyn Behaviour>,
    frame: u64,
}

impl TrialRunner<RapierWorld> {
    /// Builds the robot's world in rapier for a trial of the training
    /// behaviour `config.behaviour` names (see [`crate::behaviour::registry`]).
    pub fn new(
        description: &RobotDescription,
        sim_config: SimConfig,
        config: TrialConfig,
    ) -> Result<Self, TrialError> {
        let world = RapierWorld::new(description, sim_config, config.seed, config.changes.clone())?;
        Self::in_world(world, config)
    }

    /// Builds the robot's world in rapier for a trial of another behaviour
    /// (`config.behaviour` is then unused).
    pub fn with_behaviour(
        description: &RobotDescription,
        sim_config: SimConfig,
        config: TrialConfig,
        behaviour: Box<dyn Behaviour>,
    ) -> Result<Self, TrialError> {
        let world = RapierWorld::new(description, sim_config, config.seed, config.changes.clone())?;
        Ok(Self::in_world_with(world, config, behaviour))
    }

    /// The simulated robot and world (for viewers; learners never see it).
    pub fn sim(&self) -> &QuadrupedSim {
        self.world.sim()
    }
}

impl<W: World> TrialRunner<W> {
    /// A trial in `world` of the training behaviour `config.behaviour` names
    /// (see [`crate::behaviour::registry`]). The world was built with
    /// `config`'s seed and changes ([`crate::world::build`]).
    pub fn in_world(world: W, config: TrialConfig) -> Result<Self, TrialError> {
        let behaviour = crate::behaviour::registry::build(
            config.behaviour,
            seeds::rng(config.seed, Stream::Behaviour),
        )
        .map_err(TrialError::Recording)?;
        Ok(Self::in_world_with(world, config, behaviour))
    }

    /// A trial in `world` of another behaviour (`config.behaviour` is then
    /// unused).
    pub fn in_world_with(world: W, config: TrialConfig, behaviour: Box<dyn Behaviour>) -> Self {
        Self {
            config,
            world,
            behaviour,
            frame: 0,
        }
    }

    /// The world the trial walks in.
    pub fn world(&self) -> &W {
        &self.world
    }

    /// The behaviour driving the robot.
    pub fn behaviour(&self) -> &dyn Behaviour {
        self.behaviour.as_ref()
    }

    /// Frames in the whole trial.
    pub fn total_frames(&self) -> u64 {
        (self.config.duration_s / self.world.frame_period_s()).round() as u64
    }

    /// Whether every frame has run.
    pub fn finished(&self) -> bool {
        self.frame >= self.total_frames()
    }

    /// Runs one camera frame: the behaviour's command over it, until the camera
    /// has taken its picture. A reading in a blanked interval is dropped here,
    /// whatever the world, as if the camera had not seen the beacon.
    pub fn step_frame(&mut self) -> Result<FrameRecord, TrialError> {
        let dt_s = self.world.frame_period_s();
        let t_s = self.frame as f64 * dt_s;
        let command = self.behaviour.command(t_s);
        let sensed = self.world.step_frame(t_s, command)?;
        let obs_px = sensed
            .obs_px
            .filter(|_| !self.config.blank.contains(t_s + dt_s));
        self.behaviour.observe(t_s + dt_s, obs_px);
        self.frame += 1;
        Ok(FrameRecord {
            t_s,
            dt_s,
            command,
            obs_px,
            truth: sensed.truth,
        })
    }

    /// [`step_frame`](Self::step_frame) with `learner` in the loop (for a
    /// behaviour that steers by the learner's models): the frame, then the
    /// learner fed it ([`feed_checked`]; a failure is the trial's, at that
    /// frame), then the behaviour shown the learner
    /// ([`Behaviour::consult`]).
    pub fn step_frame_steered(
        &mut self,
        learner: &mut dyn CalibrationLearner,
    ) -> Result<FrameRecord, TrialError> {
        let index = self.frame as usize;
        let frame = self.step_frame()?;
        feed_checked(learner, &frame).map_err(|e| TrialError::At {
            frame: index,
            t_s: frame.end_s(),
            source: Box::new(e),
        })?;
        self.behaviour.consult(frame.end_s(), learner);
        Ok(frame)
    }

    /// Runs frames until the trial's time is up or `stop` says so (it sees the
    /// behaviour after each frame), and returns them.
    pub fn record_until(
        &mut self,
        mut stop: impl FnMut(&dyn Behaviour) -> bool,
    ) -> Result<Vec<FrameRecord>, TrialError> {
        // Grown as it goes rather than reserved for the whole trial, so that a
        // long trial costs memory only as far as it runs.
        let mut frames = Vec::with_capacity(self.total_frames().min(1 << 16) as usize);
        while !self.finished() && !stop(self.behaviour.as_ref()) {
            frames.push(self.step_frame()?);
        }
        Ok(frames)
    }
}

/// Records a whole trial in `world` (built for `config`): the world only, no
/// learner.
pub fn record_in(world: impl World, config: TrialConfig) -> Result<Recording, TrialError> {
    let started = std::time::Instant::now();
    let seed = config.seed;
    let frames = TrialRunner::in_world(world, config)?.record_until(|_| false)?;
    Ok(Recording::timed(seed, frames, started))
}

/// Records a whole trial in `world` (built for `config`) whose behaviour
/// steers by `learner`'s models: after each frame the learner is fed it
/// ([`TrialRunner::step_frame_steered`]). The recording is the world's frames, as any;
/// the same learner fed them again learns the same, so a run judges a fresh
/// one over it like any recording. Its realtime factor counts the
/// learner's time too.
pub fn record_steered(
    world: impl World,
    config: TrialConfig,
    learner: &mut dyn CalibrationLearner,
) -> Result<Recording, TrialError> {
    let started = std::time::Instant::now();
    let seed = config.seed;
    let mut runner = TrialRunner::in_world(world, config)?;
    let mut frames = Vec::with_capacity(runner.total_frames().min(1 << 16) as usize);
    while !runner.finished() {
        frames.push(runner.step_frame_steered(learner)?);
    }
    Ok(Recording::timed(seed, frames, started))
}

/// Records a whole trial of the robot in rapier: the world only, no learner.
pub fn record(
    description: &RobotDescription,
    sim_config: SimConfig,
    config: TrialConfig,
) -> Result<Recording, TrialError> {
    let world = RapierWorld::new(description, sim_config, config.seed, config.changes.clone())?;
    record_in(world, config)
}

/// One row of a learner's trace: one camera frame.
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
    /// The localiser's estimate with the learner's current models, in their
    /// units (see [`crate::localiser`]).
    pub x_loc: Option<f64>,
    /// Its standard deviation.
    pub x_loc_std: Option<f64>,
    /// The localiser's estimate with the measured (true) models, mm.
    pub x_loc_true_mm: Option<f64>,
    /// The localiser's estimate with the identity action model A0 and the
    /// sensor model learned from it (section IV), in A0's units.
    pub x_loc_a0: Option<f64>,
    /// The localiser's estimate with the best polynomials of the learner's
    /// degrees through the measured models (the model class's floor), mm.
    pub x_loc_best_mm: Option<f64>,
    /// Whether the learner, by its check on itself, was reporting older
    /// models in place of its own (`None`: it has no such check).
    pub falling_back: Option<bool>,
}

impl TraceRow {
    /// The row of `frame` once `learner` has been fed it.
    pub fn of(frame: &FrameRecord, learner: &dyn CalibrationLearner) -> Self {
        Self {
            t_s: frame.end_s(),
            command: frame.command,
            obs_px: frame.obs_px,
            x_true_mm: frame.truth.x_mm,
            x_a: learner.x_a(),
            x_s: learner.x_s(),
            x_loc: None,
            x_loc_std: None,
            x_loc_true_mm: None,
            x_loc_a0: None,
            x_loc_best_mm: None,
            falling_back: learner.falling_back(),
        }
    }
}

/// A learner's run over a recorded trial.
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
    /// The final judgement of the uncalibrated start it is compared with
    /// (A0 and the sensor model learned from it on the same frames, section
    /// IV), if it rode along (see [`Comparators::a0_baseline`]).
    pub start: Option<Judgement>,
    /// The learner's predicted errors of its final models, from its
    /// posterior, the start's by the same, if it reports one (see
    /// [`Prediction`]).
    pub predicted: Option<Prediction>,
    /// When the robot was first seen tipped over, s, if it was.
    pub fell_at_s: Option<f64>,
    /// When the physics blew up, s, if it did.
    pub blew_up_at_s: Option<f64>,
    /// Simulated seconds per wall-clock second of the recording's physics.
    pub realtime_factor: f64,
    /// Wall-clock seconds spent in the learner over the trial: its events and
    /// the queries of its models (what the simulation took is apart, in
    /// `realtime_factor`).
    pub learner_wall_s: f64,
    /// When the world changed during the trial, s (see [`Reference::at`]).
    pub world_changes_s: Vec<f64>,
    /// Ground truth: the largest distance the torso went off the line of
    /// approach over the trial, mm.
    pub off_line_max_mm: f64,
    /// The trial's information floor at the learner's degrees (see
    /// [`crate::floor`]), if the learner's degrees were given and the world
    /// did not change.
    pub floor: Option<Floor>,
}

/// What the localisers with the learner's models are compared with, beyond
/// the measured models (see [`learn`]).
#[derive(Default)]
pub struct Comparators<'a> {
    /// A learner of S from the identity action model A0, fed the same frames:
    /// a filter with A0 and its S.
    pub a0_baseline: Option<&'a mut dyn CalibrationLearner>,
    /// The learner's degrees `(action, sensor)`: a filter with the best
    /// polynomials of these degrees through the measured models.
    pub best_degrees: Option<(usize, usize)>,
}

impl std::fmt::Debug for Comparators<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Comparators")
            .field("a0_baseline", &self.a0_baseline.is_some())
            .field("best_degrees", &self.best_degrees)
            .finish()
    }
}

/// Runs `learner` over a recorded trial (no physics): feeds it every frame,
/// judges its models every `judge_every_s` and at the end. Localisers ride
/// along (see [`TraceRow`]): with the learner's models, with the measured
/// ones, and with those of `comparators`.
pub fn learn(
    recording: &Recording,
    learner: &mut dyn CalibrationLearner,
    comparators: Comparators<'_>,
    reference: &Reference,
    judge_every_s: f64,
) -> Result<TrialOutcome, TrialError> {
    let Comparators {
        mut a0_baseline,
        best_degrees,
    } = comparators;
    let frames = &recording.frames;
    let frame_s = frames.first().map_or(0.05, |f| f.dt_s);
    let judge_every = (judge_every_s / frame_s).round().max(1.0) as usize;
    let mut trace = Vec::with_capacity(frames.len());
    let mut over_time = Vec::new();
    // Two localisers ride along: one with the learner's models as they are at
    // each frame, one with the measured models (the bound).
    let config = LocaliserConfig {
        top_command: frames.iter().map(|f| f.command.abs()).fold(0.0, f64::max),
        ..LocaliserConfig::default()
    };
    let (mut with_learned, mut with_true, mut with_a0, mut with_best) = (
        Following::new(config),
        Localiser::new(config),
        Following::new(config),
        Localiser::new(config),
    );
    // The measured models of each world, which may change mid-trial: from
    // when, and the models.
    let true_models: Vec<(f64, Tabulated)> = reference
        .worlds()
        .map(|(at_s, r)| (at_s, Tabulated::new(&r.action, &r.sensor)))
        .collect();
    // The best polynomials of the learner's degrees through each world's
    // measured models, in mm (the location is the distance to the beacon,
    // which walking towards it shortens).
    let best_models: Vec<(f64, Learned)> = best_degrees
        .into_iter()
        .flat_map(|(da, ds)| {
            reference.worlds().filter_map(move |(at_s, r)| {
                let towards: Vec<(f64, f64)> = r.action.iter().map(|&(c, v)| (c, -v)).collect();
                let located: Vec<(f64, f64)> = r.sensor.iter().map(|&(d, o)| (o, d)).collect();
                let action = crate::metrics::best_polynomial(&towards, da)?;
                let sensor = crate::metrics::best_polynomial(&located, ds)?;
                Some((at_s, Learned { action, sensor }))
            })
        })
        .collect();
    let mut learner_wall = std::time::Duration::ZERO;
    for (k, f) in frames.iter().enumerate() {
        // The learner's own time: its events, and its models' first query
        // after them (a program answers it; later queries are the answer kept).
        let at = |e: TrialError| TrialError::At {
            frame: k,
            t_s: f.end_s(),
            source: Box::new(e),
        };
        let started = std::time::Instant::now();
        feed_checked(learner, f).map_err(at)?;
        let mut row = TraceRow::of(f, learner);
        let models = (learner.action_model(), learner.sensor_model());
        learner_wall += started.elapsed();
        let t_s = f.end_s();
        if (k + 1) % judge_every == 0 {
            over_time.push(reference.judge(t_s, learner));
        }
        if let (Some(action), Some(sensor)) = models {
            let models = Learned { action, sensor };
            if let Some(b) = with_learned.step(models, f.command, f.dt_s, f.obs_px) {
                (row.x_loc, row.x_loc_std) = (Some(b.x), Some(b.std));
            }
        }
        // The frame's motion is in the world in force over it.
        let world = true_models.iter().rfind(|(at_s, _)| *at_s <= f.t_s + 1e-9);
        row.x_loc_true_mm = world
            .and_then(|(_, models)| with_true.step(models, f.command, f.dt_s, f.obs_px))
            .map(|b| b.x);
        row.x_loc_best_mm = best_models
            .iter()
            .rfind(|(at_s, _)| *at_s <= f.t_s + 1e-9)
            .and_then(|(_, models)| with_best.step(models, f.command, f.dt_s, f.obs_px))
            .map(|b| b.x);
        if let Some(baseline) = a0_baseline.as_deref_mut() {
            feed(baseline, f).map_err(|e| at(e.into()))?;
            if let Some(sensor) = baseline.sensor_model() {
                let models = Learned {
                    action: Polynomial::identity(),
                    sensor,
                };
                row.x_loc_a0 = with_a0
                    .step(models, f.command, f.dt_s, f.obs_px)
                    .map(|b| b.x);
            }
        }
        if let Some(e) = learner_failed(learner) {
            return Err(at(e));
        }
        trace.push(row);
    }
    let end_s = frames.last().map_or(0.0, FrameRecord::end_s);
    let samples: Vec<Sample> = trace
        .iter()
        .map(|r| Sample {
            t_s: r.t_s,
            command: r.command,
            obs_px: r.obs_px,
            x_true_mm: r.x_true_mm,
        })
        .collect();
    let floor = best_degrees.and_then(|degrees| Floor::of(&samples, reference, degrees));
    let started = std::time::Instant::now();
    let posterior = learner.posterior(DRAWS);
    learner_wall += started.elapsed();
    // A learner that fails when asked for its posterior (a program that
    // lies or dies then) fails its trial, at the end.
    if let Some(e) = learner_failed(learner) {
        return Err(TrialError::At {
            frame: frames.len().saturating_sub(1),
            t_s: end_s,
            source: Box::new(e),
        });
    }
    let start = a0_baseline.map(|b| reference.judge(end_s, b));
    let predicted = posterior.map(|p| {
        Prediction::of(
            reference,
            end_s,
            (learner.action_model(), learner.sensor_model()),
            start.map(|s| (s.action_model, s.sensor_model)),
            &p,
        )
    });
    Ok(TrialOutcome {
        predicted,
        floor,
        seed: recording.seed,
        last: reference.judge(end_s, learner),
        start,
        trace,
        over_time,
        action_model: learner.action_model(),
        sensor_model: learner.sensor_model(),
        fell_at_s: recording.fell_at_s(),
        blew_up_at_s: recording.blew_up_at_s(),
        realtime_factor: recording.realtime_factor,
        learner_wall_s: learner_wall.as_secs_f64(),
        world_changes_s: reference.changes.iter().map(|c| c.0).collect(),
        off_line_max_mm: frames
            .iter()
            .map(|f| f.truth.lateral_mm.abs())
            .fold(0.0, f64::max),
    })
}

/// Records a whole trial and runs `learner` over it.
pub fn run_trial(
    description: &RobotDescription,
    sim_config: SimConfig,
    config: TrialConfig,
    learner: &mut dyn CalibrationLearner,
    reference: &Reference,
) -> Result<TrialOutcome, TrialError> {
    let judge_every_s = config.judge_every_s;
    let recording = record(description, sim_config, config)?;
    learn(
        &recording,
        learner,
        Comparators::default(),
        reference,
        judge_every_s,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(k: u32, upright: bool) -> FrameRecord {
        frame_of(k, upright, false)
    }

    fn frame_of(k: u32, upright: bool, blew_up: bool) -> FrameRecord {
        FrameRecord {
            t_s: 0.05 * f64::from(k),
            dt_s: 0.05,
            command: 0.0,
            obs_px: Some(40.0),
            truth: Truth {
                x_mm: 2000.0,
                lateral_mm: 0.0,
                yaw_rad: 0.0,
                upright,
                blew_up,
            },
        }
    }

    #[test]
    fn a_fall_is_dated_by_the_end_of_the_frame_it_happened_in() {
        let recording = |fallen_from: u32| Recording {
            seed: 0,
            frames: (0..10).map(|k| frame(k, k < fallen_from)).collect(),
            realtime_factor: f64::NAN,
        };
        let upright = recording(10);
        assert_eq!((upright.fell(), upright.fell_at_s()), (false, None));
        let fell = recording(4);
        assert!(fell.fell());
        // Frame 4 runs from 0.20 to 0.25 s.
        let at = fell.fell_at_s().expect("fell");
        assert!((at - 0.25).abs() < 1e-12, "{at}");
        assert_eq!(fell.blew_up_at_s(), None, "a fall is not a blow-up");
    }

    #[test]
    fn a_blow_up_is_dated_by_the_end_of_the_frame_it_happened_in() {
        // Blown up in frame 6 (0.30 to 0.35 s), thrown over in frame 7.
        let recording = Recording {
            seed: 0,
            frames: (0..10).map(|k| frame_of(k, k < 7, k >= 6)).collect(),
            realtime_factor: f64::NAN,
        };
        let at = recording.blew_up_at_s().expect("blew up");
        assert!((at - 0.35).abs() < 1e-12, "{at}");
        assert!((recording.fell_at_s().expect("fell") - 0.40).abs() < 1e-12);
    }
}
