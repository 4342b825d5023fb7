//! The paper's illustrations of learning one model from the other (sections IV
//! and V) on the simulated robot: S from one constant walk (Fig. 2a), S from the
//! identity action model over one cycle of the behaviour (Fig. 2b), and A from
//! the constant walk's rough S over one cycle (Fig. 3).

use scasm::{CalibrationLearner, Mode, Polynomial, Scasm};

use crate::behaviour::{ConstantWalk, Phase};
use crate::experiment::{behaviour_for, world_for};
use crate::reference::MeasuredModels;
use crate::reference::Reference;
use crate::scenario::Scenario;
use crate::trial::{self, FrameRecord, Recording, TraceRow, TrialConfig, TrialError, TrialRunner};
use crate::world::World;

/// The command of the constant walk (Fig. 2a).
pub const CONSTANT_COMMAND: f64 = 200.0;
/// How far behind the far end of the test range the constant walk starts, m.
const CONSTANT_WALK_LEAD_M: f64 = 0.1;
/// No demonstration runs longer than this, s.
const MAX_DEMO_S: f64 = 120.0;

/// One demonstration: its trace and the models at its end.
#[derive(Debug, Clone, PartialEq)]
pub struct DemoRun {
    /// One row per camera frame.
    pub trace: Vec<TraceRow>,
    /// The action model at the end (learned or given).
    pub action: Option<Polynomial>,
    /// The sensor model at the end (learned or given).
    pub sensor: Option<Polynomial>,
    /// The action fit's `x(0)` (learning A only).
    pub action_start: Option<f64>,
}

/// The three demonstrations.
#[derive(Debug, Clone, PartialEq)]
pub struct Demos {
    /// Fig. 2a: readings against time under [`CONSTANT_COMMAND`], S = the cubic
    /// of time on reading.
    pub constant_walk: DemoRun,
    /// Fig. 2b: S from the identity action model A0 over one cycle.
    pub sensor_from_a0: DemoRun,
    /// Fig. 3: A from the constant walk's S over one cycle.
    pub action_from_rough_sensor: DemoRun,
}

/// Runs the three demonstrations of `scenario` from `seed`.
pub fn run_demos(
    scenario: &Scenario,
    models: &MeasuredModels,
    seed: u64,
) -> Result<Demos, TrialError> {
    let params = scenario
        .learner
        .validate()
        .map_err(|e| TrialError::LearnerSetup(e.to_string()))?;
    let learner =
        |mode| Scasm::new(params, mode).map_err(|e| TrialError::LearnerSetup(e.to_string()));
    let behaviour = behaviour_for(scenario, models);
    let scale = scenario.scale();
    let config = TrialConfig {
        duration_s: MAX_DEMO_S,
        seed,
        behaviour,
        judge_every_s: MAX_DEMO_S,
        blank: Default::default(),
        changes: Vec::new(),
    };

    let far_m = models.sensor.last().map_or(3.6, |s| s.distance_mm / 1000.0);
    let mut walk_sim = scenario.sim;
    walk_sim.start_distance_m = far_m + CONSTANT_WALK_LEAD_M * scale.length;
    // The walk crosses the whole test range: it stops at the nearest measured
    // point's reading.
    let walk = ConstantWalk {
        command: CONSTANT_COMMAND * scale.speed(),
        near_obs_px: models
            .sensor
            .first()
            .map_or(behaviour.near_obs_px, |s| s.obs_px),
        arrived: false,
    };
    let reference = models.reference();
    let mut runner = TrialRunner::in_world_with(
        world_for(scenario, walk_sim, &config)?,
        config.clone(),
        Box::new(walk),
    );
    let walk_frames = record_phases(&mut runner, 1)?;
    let constant_walk = learn(
        walk_frames,
        seed,
        learner(Mode::SensorFromConstantAction)?,
        &reference,
    )?;
    let rough_sensor = constant_walk
        .sensor
        .ok_or_else(|| TrialError::LearnerSetup("the constant walk saw too little".into()))?;

    // One cycle of the training behaviour, recorded once and fed to both.
    let mut runner = TrialRunner::in_world(world_for(scenario, scenario.sim, &config)?, config)?;
    let cycle = record_phases(&mut runner, 2)?;
    let sensor_from_a0 = learn(
        cycle.clone(),
        seed,
        learner(Mode::SensorFromAction(Polynomial::identity()))?,
        &reference,
    )?;
    let action_from_rough_sensor = learn(
        cycle,
        seed,
        learner(Mode::ActionFromSensor(rough_sensor))?,
        &reference,
    )?;
    Ok(Demos {
        constant_walk,
        sensor_from_a0,
        action_from_rough_sensor,
    })
}

/// Records frames until the behaviour has changed phase `changes` times (or
/// the runner's time is up).
fn record_phases(
    runner: &mut TrialRunner<Box<dyn World>>,
    changes: usize,
) -> Result<Vec<FrameRecord>, TrialError> {
    let mut phase: Phase = runner.behaviour().phase();
    let mut seen = 0;
    runner.record_until(|b| {
        seen += usize::from(b.phase() != phase);
        phase = b.phase();
        seen >= changes
    })
}

/// Runs `learner` over the frames.
fn learn(
    frames: Vec<FrameRecord>,
    seed: u64,
    mut learner: Scasm,
    reference: &Reference,
) -> Result<DemoRun, TrialError> {
    let recording = Recording {
        seed,
        frames,
        realtime_factor: f64::NAN,
    };
    let outcome = trial::learn(
        &recording,
        &mut learner,
        trial::Comparators::default(),
        reference,
        MAX_DEMO_S,
    )?;
    Ok(DemoRun {
        trace: outcome.trace,
        action: learner.action_model(),
        sensor: learner.sensor_model(),
        action_start: learner.action_start(),
    })
}
