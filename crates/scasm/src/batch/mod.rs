//! A batch maximum-likelihood learner, in the spirit of Stronger & Stone's
//! later EM work (ICRA 2008): estimate the robot's path `x(t)`, the action model
//! A and the forward sensor model `g` (reading as a function of location)
//! jointly from the whole trial so far, then fit the sensor model S (location
//! from reading) to `g`'s noise-free readings at evenly spaced locations over
//! the solved path's range (`sensor_even`; or at the path's own locations).
//!
//! The model: over frame `j` the location moves by `A(C_j) dt_j` plus process
//! noise (the gait's transients, slips and turns), and each reading is
//! `g(x) + noise` at the frame's end. With Gaussian noises the negative log
//! likelihood is a weighted sum of squares of process and reading residuals,
//! minimised here by Levenberg-Marquardt. The unknowns are one location per
//! frame boundary and the two models' coefficients; the normal equations are a
//! tridiagonal block (the path) bordered by a dozen model columns, solved by
//! its Schur complement in O(frames) time. The gauge (the path's origin and
//! scale) is fixed by holding the first location and A's linear coefficient at
//! their starting values; the evaluation is blind to both.
//!
//! The reading noise's variance is estimated from the readings themselves
//! (their second differences over consecutive frames, where the path is
//! smooth). The process noise is a fixed fraction of the typical speed, four
//! times larger just after a change of command, while the gait changes over:
//! re-estimating it by joint maximum a posteriori collapses it to zero (the
//! path is fitted to make its residuals small), and by EM with white noise it
//! grows until the path follows the readings' correlated head bob; both made
//! worse models on the development seeds. Each solve starts from up to three
//! places and keeps whichever ends with the lowest cost (the negative log
//! likelihood, which no choice of units changes): the path and models of an
//! online SCASM learner fed the same events (by default `scasm-eiv`, whose
//! models the batch learner reports until its first solve), the previous
//! solution carried forward by its own A, and the pinhole path `1 / obs` (a
//! camera sees an object of fixed height at a size inversely proportional to
//! its distance), which needs neither model. An online learner in a bad
//! spell then no longer drags a good solution with it, and a solve whose other
//! starts lie in a poor local minimum still finds the right shape. The
//! solution is then put in the units the host has seen: the previous
//! solution's, or before the first the online learner's (the affine map that
//! best takes its path onto that path), so that the learner's units do not
//! jump at every solve: the likelihood is blind to them, a localiser is not.
//!
//! `batch-ml-lag` (`lag`) models the gait's response to a change of
//! command: the speed relaxes from the old steady speed to `A(C)` with a
//! time constant it learns with the rest (see `lag`), so that A is the
//! steady-state response the stopwatch measures rather than an average that
//! includes each change-over.
//!
//! Cost: each solve is O(N) in the frames N it moves, for a fixed number of
//! iterations. Up to `window_s` (150 s) of trial a solve covers the whole
//! trial: 15 solves of up to 3000 frames take about 0.3 s for a 150 s trial.
//! Past it, a solve moves only the last `window_s` of path, started from the
//! previous solution: the path before is held at that solution's, which
//! makes each older frame's residuals linear in the models, so those frames
//! enter as a few fixed quadratic forms summed in one pass (no iterations).
//! Whenever the trial has grown by half since the last solve of the whole,
//! the whole is solved again (from the previous solution), so that the held
//! path does not keep the errors of the solve that held it; those solves
//! grow geometrically, so their sum stays proportional to the trial. A 1200
//! s trial costs about 6.5x a 150 s one (`cargo bench --bench
//! batch_ml_trial`), against 73x solving the whole every time, for the
//! same models (dev seeds 100-103: 5.0 mm/s and 23.9 mm either way). With
//! forgetting (`gamma` < 1) frames whose weight is below 1e-6 are left out
//! too.

mod belief;
mod believed;
mod config;
mod frames;
mod frozen;
mod lag;
mod linalg;
mod problem;
mod solve;

use std::boxed::Box;
use std::string::ToString;
use std::vec;
use std::vec::Vec;

use crate::batch::frames::{FrameData, Solution, Start, online_path};
use crate::batch::solve::{solve, units_map};
use crate::config::{ScasmConfig, ScasmParams, SensorFit};
use crate::declaration::{BuildContext, Declaration, Kind, Setting};
use crate::error::EventError;
use crate::learner::{CalibrationLearner, Event};
use crate::mode::Mode;
use crate::polynomial::Polynomial;
use crate::posterior::Posterior;
use crate::scasm::Scasm;

pub use believed::{Believed, KeepStart};
pub use config::{BatchMlConfig, BatchMlParams};

/// How much longer a trial past the window has grown since the last solve
/// of the whole trial when the whole is solved again.
const REFRESH: f64 = 1.5;

/// The degree of the action model a batch learner believes the truth to be
/// (the richest it takes; its forward sensor model is its own), against
/// which its posterior judges the models it reports (see
/// [`CalibrationLearner::posterior`]).
const BELIEF_ACTION_DEGREE: usize = crate::MAX_REGRESSORS - 1;

/// The shared settings the batch learners read (their online start's).
const BATCH_SHARED: &[&str] = &[
    "gamma",
    "beta",
    "t_start",
    "sensor_degree",
    "action_degree",
    "sensor_window",
    "forward_degree",
    "action_prior",
    "action_highpass",
    "action_robust",
];

/// The batch learner as a host declares it (see [`crate::declaration`]): its
/// own settings are [`BatchMlConfig`]'s, the shared ones its online start's.
pub const BATCH_ML: Declaration = Declaration {
    name: "batch-ml",
    about: "maximum likelihood over the whole trial: path, A and the forward sensor model \
            jointly, started from scasm-eiv, its own last solution and the readings' pinhole path",
    shared: BATCH_SHARED,
    settings: || batch_settings(BatchMlConfig::default()),
    one_sided: false,
    build: |c: &BuildContext| build(c, false),
};

/// `batch-ml` modelling the gait's response to a change of command: a
/// first-order lag whose time constant it learns, so that its A is the
/// steady-state response (see [`BatchMlConfig::lagged`]).
pub const BATCH_ML_LAG: Declaration = Declaration {
    name: "batch-ml-lag",
    about: "batch-ml with the response to a change of command modelled: the speed relaxes \
            to A(C) with a learned time constant, so A is the steady-state response",
    shared: BATCH_SHARED,
    settings: || batch_settings(BatchMlConfig::lagged()),
    one_sided: false,
    build: |c: &BuildContext| build(c, true),
};

/// A batch learner from a host's settings, the lag modelled or not.
fn build(c: &BuildContext, lag: bool) -> Result<Box<dyn CalibrationLearner + Send>, String> {
    let own = &c.own;
    let params = BatchMlConfig {
        online: ScasmConfig {
            sensor_fit: SensorFit::Corrected,
            ..c.shared
        },
        gamma: own.get("gamma"),
        solve_every_s: own.get("solve_every_s"),
        iterations: own.count("iterations"),
        process_noise: own.get("process_noise"),
        transient_noise: own.get("transient_noise"),
        window_s: own.get("window_s"),
        lag,
        sensor_even: own.count("sensor_even") == 1,
    }
    .validate()
    .map_err(|e| e.to_string())?;
    Ok(Box::new(BatchMl::new(params)))
}

/// A batch learner's own settings, with `d`'s values as defaults.
fn batch_settings(d: BatchMlConfig) -> Vec<Setting> {
    let positive = (0.0, true, f64::INFINITY);
    vec![
        Setting::new(
            "gamma",
            Kind::Number,
            d.gamma,
            (0.0, true, 1.0),
            "forgetting per frame of the batch fit (1: the whole trial weighs alike)",
        ),
        Setting::new(
            "solve_every_s",
            Kind::Number,
            d.solve_every_s,
            positive,
            "how often the whole fit is solved again, s of the trial",
        ),
        Setting::new(
            "iterations",
            Kind::Count,
            d.iterations as f64,
            (1.0, false, 1000.0),
            "Levenberg-Marquardt iterations per solve",
        ),
        Setting::new(
            "process_noise",
            Kind::Number,
            d.process_noise,
            positive,
            "process noise per frame, as a fraction of the typical speed times the frame's length",
        ),
        Setting::new(
            "transient_noise",
            Kind::Number,
            d.transient_noise,
            positive,
            "how much larger the process noise is within half a second of a change of command",
        ),
        Setting::new(
            "window_s",
            Kind::Number,
            d.window_s,
            positive,
            "how far back a solve moves the path, s: older frames are held at the last solution \
             (a solve then costs the window's, however long the trial; longer than the trial: \
             the whole trial)",
        ),
        Setting::new(
            "sensor_even",
            Kind::Count,
            f64::from(u8::from(d.sensor_even)),
            (0.0, false, 1.0),
            "1: S is fitted to the forward model at evenly spaced locations over the path's \
             range, alike at every distance walked; 0: at each reading's location, each \
             distance weighed by the time spent there",
        ),
    ]
}

/// The batch maximum-likelihood learner (see the module's documentation).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BatchMl {
    params: BatchMlParams,
    online: Scasm,
    frames: Vec<FrameData>,
    next_solve_s: f64,
    solution: Option<Solution>,
    /// The latest solution's path and action model, to start the next from.
    solved: Option<Start>,
    x_s: Option<f64>,
    /// How many frames the last solve of the whole trial covered.
    #[cfg_attr(feature = "serde", serde(default))]
    whole_frames: usize,
}

impl BatchMl {
    /// A learner with these settings.
    pub fn new(params: BatchMlParams) -> Self {
        let c = params.config();
        let online = Scasm::new(
            c.online
                .validate()
                .unwrap_or_else(|_| ScasmParams::default()),
            Mode::Simultaneous,
        )
        .unwrap_or_default();
        Self {
            params,
            online,
            frames: Vec::new(),
            next_solve_s: c.solve_every_s,
            solution: None,
            solved: None,
            x_s: None,
            whole_frames: 0,
        }
    }

    /// The settings in use.
    pub fn params(&self) -> &BatchMlParams {
        &self.params
    }

    /// The response lag's learned time constant, s, if the lag is modelled
    /// and solved for.
    pub fn lag_time_constant_s(&self) -> Option<f64> {
        self.solved
            .as_ref()
            .filter(|_| self.params.config().lag)
            .map(|s| s.tau_s)
    }

    /// Solves the whole fit now, with every event so far (a host may call this
    /// at the end of a trial; the learner also solves every `solve_every_s`).
    pub fn solve_now(&mut self) {
        let c = self.params.config();
        // Past the window, the previous solution carried forward is the start,
        // and the path before the window is held at it (its units with it);
        // whenever the trial has grown by REFRESH since the last solve of the
        // whole trial, the whole is solved again, so that the held path does
        // not keep the errors of the solve that held it. Those solves' costs
        // grow geometrically, so the sum stays proportional to the trial.
        let held = self.frames_before_window(c.window_s);
        if let (true, Some(previous)) = (held > 0, &self.solved) {
            let start = previous.extended(&self.frames);
            let n = self.frames.len();
            let whole = n as f64 >= REFRESH * self.whole_frames as f64;
            if let Some(s) = solve(
                &self.frames,
                &c,
                &start,
                if whole { 0 } else { held },
                false,
            ) {
                self.solution = Some(s.solution);
                self.solved = Some(s.start);
                if whole {
                    self.whole_frames = n;
                }
            }
            return;
        }
        self.whole_frames = self.frames.len();
        let online = Start::online(&self.frames, &self.online);
        // The pinhole start in the units of the online learner's path.
        let pinhole = Start::pinhole(&self.frames, c.online.action_degree).map(|mut p| {
            if let Some((scale, offset)) = online.as_ref().and_then(|o| units_map(&p.path, &o.path))
            {
                p.rescale(scale, offset);
            }
            p
        });
        let starts = [
            online,
            self.solved.as_ref().map(|s| s.extended(&self.frames)),
            pinhole,
        ];
        let best = starts
            .iter()
            .flatten()
            .filter_map(|start| solve(&self.frames, &c, start, 0, false))
            .min_by(|a, b| a.cost.total_cmp(&b.cost));
        if let Some(mut s) = best {
            // Into the units the host has seen so far: the previous
            // solution's, else the online learner's.
            let map = match &self.solved {
                Some(previous) => units_map(&s.start.path, &previous.path),
                None => self
                    .online
                    .sensor_model()
                    .and_then(|_| units_map(&s.start.path, &online_path(&self.frames))),
            };
            if let Some((scale, offset)) = map {
                s.rescale(scale, offset);
            }
            self.solution = Some(s.solution);
            self.solved = Some(s.start);
        }
    }
}

impl BatchMl {
    /// How many frames end at least `window_s` before the last one ends.
    fn frames_before_window(&self, window_s: f64) -> usize {
        let end_s: f64 = self.frames.iter().map(|f| f.dt_s).sum();
        let mut t = 0.0;
        self.frames
            .iter()
            .take_while(|f| {
                t += f.dt_s;
                t <= end_s - window_s + 1e-9
            })
            .count()
    }
}

impl CalibrationLearner for BatchMl {
    fn name(&self) -> &str {
        if self.params.config().lag {
            "batch-ml-lag"
        } else {
            "batch-ml"
        }
    }

    fn handle(&mut self, event: Event) -> Result<(), EventError> {
        // The online learner checks the event; a refused one changes nothing.
        self.online.handle(event)?;
        match event {
            Event::Command { dt_s, command, .. } => {
                self.frames.push(FrameData {
                    dt_s,
                    command,
                    x_online: self.online.x_a().unwrap_or(0.0),
                    obs_px: None,
                });
                if let Some(s) = &mut self.solution {
                    s.x_a += s.action.eval(command) * dt_s;
                }
            }
            Event::Reading { t_s, obs_px } => {
                let x_online = self.online.x_a().unwrap_or(0.0);
                if let Some(f) = self.frames.last_mut() {
                    f.obs_px = Some(obs_px);
                    f.x_online = x_online;
                }
                if t_s >= self.next_solve_s - 1e-9 {
                    let every = self.params.config().solve_every_s;
                    while self.next_solve_s <= t_s + 1e-9 {
                        self.next_solve_s += every;
                    }
                    self.solve_now();
                }
                self.x_s = self
                    .solution
                    .map(|s| s.sensor.eval(obs_px))
                    .filter(|x| x.is_finite());
            }
        }
        Ok(())
    }

    fn action_model(&self) -> Option<Polynomial> {
        self.solution
            .map(|s| s.action)
            .or_else(|| self.online.action_model())
    }

    fn sensor_model(&self) -> Option<Polynomial> {
        self.solution
            .map(|s| s.sensor)
            .or_else(|| self.online.sensor_model())
    }

    fn x_a(&self) -> Option<f64> {
        self.solution.map(|s| s.x_a).or_else(|| self.online.x_a())
    }

    fn x_s(&self) -> Option<f64> {
        if self.solution.is_some() {
            self.x_s
        } else {
            self.online.x_s()
        }
    }

    fn posterior(&self, draws: usize) -> Option<Posterior> {
        self.posterior_in_units_of(draws, None)
    }
}

impl BatchMl {
    /// The posterior's draws, in the units of `path` (a location at each
    /// frame boundary, the first at time 0) if one is given: the affine
    /// map that best takes the solved path onto it (see [`units_map`]).
    pub(crate) fn posterior_in_units_of(
        &self,
        draws: usize,
        path: Option<&[f64]>,
    ) -> Option<Posterior> {
        // Only the models of a solve have one (not the online learner's,
        // reported before the first). The truth is believed to be the
        // richest model the learner takes, fitted to the whole trial from
        // the latest solution (in its units: the same gauge is held).
        self.solution?;
        let c = self.params.config();
        let richer = BatchMlConfig {
            online: ScasmConfig {
                action_degree: c.online.action_degree.max(BELIEF_ACTION_DEGREE),
                ..c.online
            },
            ..c
        };
        let start = self.solved.as_ref()?.extended(&self.frames);
        let solved = solve(&self.frames, &richer, &start, 0, true)?;
        let mut draws = solved.belief?.draws(draws);
        if let Some(path) = path {
            let (scale, offset) = units_map(&start.path, path)?;
            for d in &mut draws {
                d.action = d.action.rescaled(scale, 0.0);
                for (_, x) in &mut d.sensor {
                    *x = scale * *x + offset;
                }
            }
        }
        Some(Posterior { draws })
    }
}
