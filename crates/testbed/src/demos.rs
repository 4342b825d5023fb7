//! The paper's illustrations of learning one model from the other (sections IV
//! and V) on the simulated robot: S from one constant walk (Fig. 2a), S from the
//! identity action model over one cycle of the behaviour (Fig. 2b), and A from
//! the constant walk's rough S over one cycle (Fig. 3).

use scasm::{CalibrationLearner, Mode, Polynomial, Scasm};

use crate::behaviour::{ConstantWalk, Phase};
use crate::experiment::behaviour_for;
use crate::reference::MeasuredModels;
use crate::scenario::Scenario;
use crate::trial::{TraceRow, TrialConfig, TrialError, TrialRunner};

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
    let behaviour = behaviour_for(models);
    let config = TrialConfig {
        duration_s: MAX_DEMO_S,
        seed,
        behaviour,
        judge_every_s: MAX_DEMO_S,
    };

    let far_m = models.sensor.last().map_or(3.6, |s| s.distance_mm / 1000.0);
    let mut walk_sim = scenario.sim;
    walk_sim.start_distance_m = far_m + CONSTANT_WALK_LEAD_M;
    let walk = ConstantWalk {
        command: CONSTANT_COMMAND,
        near_obs_px: behaviour.near_obs_px,
        arrived: false,
    };
    let mut runner =
        TrialRunner::with_behaviour(&scenario.description, walk_sim, config, Box::new(walk))?;
    let constant_walk = run_until(
        &mut runner,
        learner(Mode::SensorFromConstantAction)?,
        |phases| phases >= 1,
    )?;
    let rough_sensor = constant_walk
        .sensor
        .ok_or_else(|| TrialError::LearnerSetup("the constant walk saw too little".into()))?;

    let one_cycle = |phases: usize| phases >= 2;
    let mut runner = TrialRunner::new(&scenario.description, scenario.sim, config)?;
    let sensor_from_a0 = run_until(
        &mut runner,
        learner(Mode::SensorFromAction(Polynomial::identity()))?,
        one_cycle,
    )?;
    let mut runner = TrialRunner::new(&scenario.description, scenario.sim, config)?;
    let action_from_rough_sensor = run_until(
        &mut runner,
        learner(Mode::ActionFromSensor(rough_sensor))?,
        one_cycle,
    )?;
    Ok(Demos {
        constant_walk,
        sensor_from_a0,
        action_from_rough_sensor,
    })
}

/// Runs frames until `done(phase changes so far)` or the runner's time is up.
fn run_until(
    runner: &mut TrialRunner,
    mut learner: Scasm,
    done: impl Fn(usize) -> bool,
) -> Result<DemoRun, TrialError> {
    let mut trace = Vec::new();
    let mut phase: Phase = runner.behaviour().phase();
    let mut changes = 0;
    while !runner.finished() && !done(changes) {
        trace.push(runner.step_frame(&mut learner)?);
        let now = runner.behaviour().phase();
        changes += usize::from(now != phase);
        phase = now;
    }
    Ok(DemoRun {
        trace,
        action: learner.action_model(),
        sensor: learner.sensor_model(),
        action_start: learner.action_start(),
    })
}
