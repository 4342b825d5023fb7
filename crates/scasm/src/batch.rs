//! A batch maximum-likelihood learner, in the spirit of Stronger & Stone's
//! later EM work (ICRA 2008): estimate the robot's path `x(t)`, the action model
//! A and the forward sensor model `g` (reading as a function of location)
//! jointly from the whole trial so far, then fit the sensor model S (location
//! from reading) to the solved path against `g`'s noise-free readings.
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
//! Cost: each solve is O(N) in the frames N it covers, for a fixed number of
//! iterations. By default (no forgetting) N is the whole trial, so solving
//! every `solve_every_s` of a trial of T seconds costs O(T^2 / solve_every_s)
//! in all: 15 solves of up to 3000 frames take about 0.1 s for a 150 s trial.
//! With forgetting (`gamma` < 1) frames whose weight is below 1e-6 are left
//! out, which bounds N (about 13 800 frames at gamma 0.999) and makes the cost
//! O(T) after that.

use std::boxed::Box;
use std::string::ToString;
use std::vec;
use std::vec::Vec;

use crate::MAX_REGRESSORS;
use crate::config::{ScasmConfig, ScasmParams, SensorFit};
use crate::declaration::{BuildContext, Declaration, Kind, Setting};
use crate::error::{ConfigError, EventError};
use crate::learner::{CalibrationLearner, Event};
use crate::poly_fit::PolynomialFit;
use crate::polynomial::Polynomial;
use crate::scasm::{Mode, Scasm};

/// Frames whose weight falls below this are left out of a solve.
const MIN_WEIGHT: f64 = 1e-6;

/// How long after a change of command the gait counts as changing over, s:
/// such frames get a process noise of their own, so the robot's speeding up
/// or slowing down does not bend A (which is the steady walk's speed).
const TRANSIENT_S: f64 = 0.5;

/// Frames either side of a frame over which [`Start::pinhole`] takes a speed.
const PINHOLE_SPAN: usize = 10;

/// Process precisions (1 / variance) of steady and changing-over frames.
type Precisions = [f64; 2];

/// The batch learner's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields, default)
)]
pub struct BatchMlConfig {
    /// The online learner it starts from; its degrees and forward degree are
    /// the batch fit's too.
    pub online: ScasmConfig,
    /// Forgetting per frame, in (0, 1]: 1 (the default) weighs the whole trial
    /// alike, as a batch estimate does; below 1 it forgets like SCASM.
    pub gamma: f64,
    /// How often (s of the trial) the whole fit is solved again.
    pub solve_every_s: f64,
    /// Levenberg-Marquardt iterations per solve.
    pub iterations: usize,
    /// The process noise per frame, as a fraction of the typical (RMS) speed
    /// times the frame's length: how far the robot may stray from `A(C) dt`.
    pub process_noise: f64,
    /// How much larger (in standard deviation) the process noise is within
    /// half a second of a change of command, while the gait changes over.
    pub transient_noise: f64,
}

impl Default for BatchMlConfig {
    /// Chosen on the development seeds 100-114 of the default scenario (never
    /// the evaluation seeds): a process noise of an eighth of the typical
    /// speed, four times that while the gait changes over.
    fn default() -> Self {
        Self {
            online: ScasmConfig::default(),
            gamma: 1.0,
            solve_every_s: 10.0,
            iterations: 15,
            process_noise: 0.125,
            transient_noise: 4.0,
        }
    }
}

impl BatchMlConfig {
    /// Checks every value's range.
    pub fn validate(self) -> Result<BatchMlParams, ConfigError> {
        self.online.validate()?;
        if !(self.gamma > 0.0 && self.gamma <= 1.0) {
            return Err(ConfigError::Gamma { gamma: self.gamma });
        }
        if !(self.solve_every_s.is_finite() && self.solve_every_s > 0.0) {
            return Err(ConfigError::SolveEvery {
                solve_every_s: self.solve_every_s,
            });
        }
        if self.iterations == 0 {
            return Err(ConfigError::Iterations {
                iterations: self.iterations,
            });
        }
        for (name, value) in [
            ("process_noise", self.process_noise),
            ("transient_noise", self.transient_noise),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(ConfigError::BatchNoise { name, value });
            }
        }
        Ok(BatchMlParams(self))
    }
}

/// The batch learner as a host declares it (see [`crate::declaration`]): its
/// own settings are [`BatchMlConfig`]'s, the shared ones its online start's.
pub const BATCH_ML: Declaration = Declaration {
    name: "batch-ml",
    about: "maximum likelihood over the whole trial: path, A and the forward sensor model \
            jointly, started from scasm-eiv, its own last solution and the readings' pinhole path",
    shared: &[
        "gamma",
        "beta",
        "t_start",
        "sensor_degree",
        "action_degree",
        "sensor_window",
        "forward_degree",
    ],
    settings: batch_settings,
    one_sided: false,
    build: |c: &BuildContext| {
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
        }
        .validate()
        .map_err(|e| e.to_string())?;
        Ok(Box::new(BatchMl::new(params)))
    },
};

/// [`BATCH_ML`]'s own settings, with [`BatchMlConfig::default`]'s values.
fn batch_settings() -> Vec<Setting> {
    let d = BatchMlConfig::default();
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
    ]
}

/// Checked [`BatchMlConfig`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(try_from = "BatchMlConfig", into = "BatchMlConfig")
)]
pub struct BatchMlParams(BatchMlConfig);

impl TryFrom<BatchMlConfig> for BatchMlParams {
    type Error = ConfigError;
    fn try_from(config: BatchMlConfig) -> Result<Self, ConfigError> {
        config.validate()
    }
}

impl From<BatchMlParams> for BatchMlConfig {
    fn from(params: BatchMlParams) -> Self {
        params.0
    }
}

impl BatchMlParams {
    /// The values as a plain config.
    pub fn config(&self) -> BatchMlConfig {
        self.0
    }
}

/// One frame: the command over it and the online learner's location at its end.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct FrameData {
    dt_s: f64,
    command: f64,
    /// The online learner's `x_a` at the frame's end (the starting path).
    x_online: f64,
    /// The reading at the frame's end, if any.
    obs_px: Option<f64>,
}

/// The latest solution.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Solution {
    action: Polynomial,
    sensor: Polynomial,
    /// Dead reckoning from the solved path's end with the solved A.
    x_a: f64,
}

/// Where a solve starts: a location at every frame boundary so far (the first
/// at 0) and an action model.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Start {
    path: Vec<f64>,
    action: Polynomial,
}

impl Start {
    /// The online learner's dead reckoning and its action model.
    fn online(frames: &[FrameData], online: &Scasm) -> Option<Self> {
        online.sensor_model()?;
        Some(Self {
            path: online_path(frames),
            action: online.action_model()?,
        })
    }

    /// The pinhole camera's law, from the readings alone: a beacon of fixed
    /// height spans a number of pixels inversely proportional to its
    /// distance, so `1 / obs` (carried linearly across frames without a
    /// reading) is the path up to its units, whatever either model is. A is
    /// then the least-squares polynomial of degree `action_degree` through
    /// the path's speeds over [`PINHOLE_SPAN`] frames either side of each
    /// frame where the command held, which averages the readings' noise.
    fn pinhole(frames: &[FrameData], action_degree: usize) -> Option<Self> {
        let inverse: Vec<Option<f64>> = frames
            .iter()
            .map(|f| f.obs_px.filter(|o| *o > 0.0).map(|o| 1.0 / o))
            .collect();
        let first = inverse.iter().flatten().next().copied()?;
        let mut path = Vec::with_capacity(frames.len() + 1);
        path.push(first);
        let mut last = (0, first);
        for (j, x) in inverse.iter().enumerate() {
            let Some(&x) = x.as_ref() else { continue };
            // Boundaries last.0 + 1 ..= j + 1 run linearly from last.1 to x.
            let gap = j + 1 - last.0;
            for k in 1..=gap {
                path.push(last.1 + (x - last.1) * k as f64 / gap as f64);
            }
            last = (j + 1, x);
        }
        path.resize(frames.len() + 1, last.1);
        let mut fit = PolynomialFit::new(action_degree, 1.0);
        for b in PINHOLE_SPAN..frames.len().saturating_sub(PINHOLE_SPAN) {
            let held = &frames[b - PINHOLE_SPAN..b + PINHOLE_SPAN];
            if held.iter().all(|f| f.command == held[0].command) {
                let span_s: f64 = held.iter().map(|f| f.dt_s).sum();
                let speed = (path[b + PINHOLE_SPAN] - path[b - PINHOLE_SPAN]) / span_s;
                fit.add(held[0].command, speed);
            }
        }
        let action = fit.polynomial().filter(Polynomial::is_finite)?;
        // Units in which A's slope at a standstill is 1, as A0's is.
        let slope = action.coeffs().get(1).copied().unwrap_or(0.0);
        if !(slope.is_finite() && slope != 0.0) {
            return None;
        }
        let mut start = Self { path, action };
        start.rescale(1.0 / slope, 0.0);
        Some(start)
    }

    /// Puts this start in the units `scale x + offset`.
    fn rescale(&mut self, scale: f64, offset: f64) {
        self.action = self.action.rescaled(scale, 0.0);
        for x in &mut self.path {
            *x = scale * *x + offset;
        }
    }

    /// This (a solved path) carried over frames it has not seen yet by its
    /// own action model.
    fn extended(&self, frames: &[FrameData]) -> Self {
        let mut path = self.path.clone();
        for f in frames.iter().skip(path.len() - 1) {
            let last = path.last().copied().unwrap_or(0.0);
            path.push(last + self.action.eval(f.command) * f.dt_s);
        }
        Self {
            path,
            action: self.action,
        }
    }
}

/// The online learner's dead reckoning at every frame boundary (the first at 0).
fn online_path(frames: &[FrameData]) -> Vec<f64> {
    core::iter::once(0.0)
        .chain(frames.iter().map(|f| f.x_online))
        .collect()
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
        }
    }

    /// The settings in use.
    pub fn params(&self) -> &BatchMlParams {
        &self.params
    }

    /// Solves the whole fit now, with every event so far (a host may call this
    /// at the end of a trial; the learner also solves every `solve_every_s`).
    pub fn solve_now(&mut self) {
        let c = self.params.config();
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
            .filter_map(|start| solve(&self.frames, &c, start))
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

impl CalibrationLearner for BatchMl {
    fn name(&self) -> &str {
        "batch-ml"
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
}

/// The model's unknowns besides the path: A's coefficients (but the linear
/// one, which fixes the scale) and g's.
#[derive(Debug, Clone)]
struct Models {
    /// A in normalised commands `u = C / command_scale`: `A = sum a_i u^i`.
    a: [f64; MAX_REGRESSORS],
    /// g in normalised locations `z = (x - centre) / half_width`.
    g: [f64; MAX_REGRESSORS + 1],
}

/// The problem's fixed data.
struct Problem<'a> {
    frames: &'a [FrameData],
    /// Weight of each frame (forgetting), oldest first.
    weights: Vec<f64>,
    action_degree: usize,
    forward_degree: usize,
    command_scale: f64,
    centre: f64,
    half_width: f64,
    /// `1 / sigma_o^2`, readings.
    reading_precision: f64,
    /// Per frame: 1 within [`TRANSIENT_S`] of a change of command (the gait is
    /// changing over), else 0. Each class has its own process noise.
    class: Vec<usize>,
}

impl Problem<'_> {
    /// The free model parameters: a_0, a_2..a_d, then g_0..g_m.
    fn model_params(&self) -> usize {
        self.action_degree + self.forward_degree + 1
    }

    fn u(&self, j: usize) -> f64 {
        self.frames[j].command / self.command_scale
    }

    fn velocity(&self, m: &Models, j: usize) -> f64 {
        let u = self.u(j);
        (0..=self.action_degree)
            .rev()
            .fold(0.0, |acc, i| acc * u + m.a[i])
    }

    fn z(&self, x: f64) -> f64 {
        (x - self.centre) / self.half_width
    }

    fn g(&self, m: &Models, x: f64) -> (f64, f64) {
        let z = self.z(x);
        let (mut v, mut d) = (0.0, 0.0);
        for i in (0..=self.forward_degree).rev() {
            d = d * z + v;
            v = v * z + m.g[i];
        }
        (v, d / self.half_width)
    }

    /// The process precisions (steady, changing over): the process noise is a
    /// fraction of the typical speed per frame under `m`'s A, larger while
    /// the gait changes over.
    fn process_precisions(&self, m: &Models, config: &BatchMlConfig) -> Precisions {
        let mean_square = self
            .frames
            .iter()
            .enumerate()
            .map(|(j, f)| (f.dt_s * self.velocity(m, j)).powi(2))
            .sum::<f64>()
            / self.frames.len().max(1) as f64;
        let steady = (config.process_noise * mean_square.sqrt()).max(1e-9);
        [
            1.0 / (steady * steady),
            1.0 / (steady * config.transient_noise).powi(2),
        ]
    }

    /// Weighted sum of squares: process residuals at `process_precision`,
    /// reading residuals at the reading precision. `path[0]` is held.
    fn cost(&self, path: &[f64], m: &Models, process_precision: &Precisions) -> f64 {
        let mut c = 0.0;
        for (j, f) in self.frames.iter().enumerate() {
            let w = self.weights[j];
            let r = path[j + 1] - path[j] - f.dt_s * self.velocity(m, j);
            c += w * process_precision[self.class[j]] * r * r;
            if let Some(obs) = f.obs_px {
                let e = obs - self.g(m, path[j + 1]).0;
                c += w * self.reading_precision * e * e;
            }
        }
        c
    }

    /// The Gauss-Newton normal equations at (`path`, `m`): a tridiagonal path
    /// block bordered by the model parameters.
    fn normal_equations(
        &self,
        path: &[f64],
        m: &Models,
        process_precision: &Precisions,
    ) -> NormalEquations {
        let n = self.frames.len(); // free path unknowns: path[1..=n]
        let q = self.model_params();
        let da = self.action_degree;
        // Normal equations: tridiagonal path block (diag, off), border (n x q),
        // model block (q x q), and right-hand sides.
        let mut diag = vec![0.0; n];
        let mut off = vec![0.0; n.saturating_sub(1)];
        let mut border = vec![0.0; n * q];
        let mut model = vec![0.0; q * q];
        let mut rhs_x = vec![0.0; n];
        let mut rhs_p = vec![0.0; q];
        let mut jp = vec![0.0; q];
        for (j, f) in self.frames.iter().enumerate() {
            let w = self.weights[j] * process_precision[self.class[j]];
            // Process residual r = x_{j+1} - x_j - dt A(u): derivatives +1 on
            // path[j+1] (free index j), -1 on path[j] (free index j-1 if j > 0),
            // -dt u^i on a_i.
            let r = path[j + 1] - path[j] - f.dt_s * self.velocity(m, j);
            let u = self.u(j);
            jp.iter_mut().for_each(|v| *v = 0.0);
            let mut p = 1.0;
            for i in 0..=da {
                if let Some(k) = action_index(i) {
                    jp[k] = -f.dt_s * p;
                }
                p *= u;
            }
            // Accumulate J^T J and -J^T r for this row.
            diag[j] += w;
            rhs_x[j] -= w * r;
            if j > 0 {
                diag[j - 1] += w;
                off[j - 1] -= w;
                rhs_x[j - 1] += w * r;
            }
            for a in 0..q {
                if jp[a] == 0.0 {
                    continue;
                }
                border[j * q + a] += w * jp[a];
                if j > 0 {
                    border[(j - 1) * q + a] -= w * jp[a];
                }
                rhs_p[a] -= w * jp[a] * r;
                for b in 0..q {
                    model[a * q + b] += w * jp[a] * jp[b];
                }
            }
            // Reading residual e = obs - g(x_{j+1}): derivatives -g'(x) on
            // path[j+1], -z^i on g_i.
            if let Some(obs) = f.obs_px {
                let w = self.weights[j] * self.reading_precision;
                let x = path[j + 1];
                let (gv, gd) = self.g(m, x);
                let e = obs - gv;
                let z = self.z(x);
                jp.iter_mut().for_each(|v| *v = 0.0);
                let mut p = 1.0;
                for i in 0..=self.forward_degree {
                    jp[da + i] = -p;
                    p *= z;
                }
                let jx = -gd;
                diag[j] += w * jx * jx;
                rhs_x[j] -= w * jx * e;
                for a in da..q {
                    border[j * q + a] += w * jx * jp[a];
                    rhs_p[a] -= w * jp[a] * e;
                    for b in da..q {
                        model[a * q + b] += w * jp[a] * jp[b];
                    }
                }
            }
        }
        NormalEquations {
            diag,
            off,
            border,
            model,
            rhs_x,
            rhs_p,
        }
    }

    /// One Levenberg-Marquardt step from (`path`, `m`) with damping `lambda`:
    /// the proposed new path and models.
    fn step(
        &self,
        path: &[f64],
        m: &Models,
        process_precision: &Precisions,
        lambda: f64,
    ) -> Option<(Vec<f64>, Models)> {
        let n = self.frames.len();
        let q = self.model_params();
        let da = self.action_degree;
        let NormalEquations {
            mut diag,
            off,
            border,
            mut model,
            rhs_x,
            rhs_p,
        } = self.normal_equations(path, m, process_precision);
        // Damping (Marquardt: scaled by the diagonal).
        for d in &mut diag {
            *d *= 1.0 + lambda;
            *d += 1e-12;
        }
        for a in 0..q {
            model[a * q + a] = model[a * q + a] * (1.0 + lambda) + 1e-12;
        }
        // Schur complement on the path block: Y = T^-1 B, y = T^-1 r_x.
        let t = Tridiagonal::factor(&diag, &off)?;
        let mut y = rhs_x.clone();
        t.solve(&mut y);
        let mut cols = vec![0.0; n * q];
        let mut col = vec![0.0; n];
        for a in 0..q {
            for j in 0..n {
                col[j] = border[j * q + a];
            }
            t.solve(&mut col);
            for j in 0..n {
                cols[j * q + a] = col[j];
            }
        }
        let mut schur = model.clone();
        let mut reduced = rhs_p.clone();
        for a in 0..q {
            for j in 0..n {
                let b_ja = border[j * q + a];
                if b_ja == 0.0 {
                    continue;
                }
                reduced[a] -= b_ja * y[j];
                for b in 0..q {
                    schur[a * q + b] -= b_ja * cols[j * q + b];
                }
            }
        }
        let dp = solve_dense(&mut schur, &mut reduced, q)?;
        let mut new_path = path.to_vec();
        for j in 0..n {
            let dx = y[j] - (0..q).map(|a| cols[j * q + a] * dp[a]).sum::<f64>();
            new_path[j + 1] += dx;
        }
        let mut new = m.clone();
        for i in 0..=da {
            if let Some(k) = action_index(i) {
                new.a[i] += dp[k];
            }
        }
        for i in 0..=self.forward_degree {
            new.g[i] += dp[da + i];
        }
        let finite = new_path.iter().all(|v| v.is_finite())
            && new.a.iter().chain(&new.g).all(|v| v.is_finite());
        finite.then_some((new_path, new))
    }
}

/// Gauss-Newton normal equations: `[T B; B' D] [dx; dp] = [rx; rp]` with `T`
/// tridiagonal (`diag`, `off`), `B` the border (row-major, frames x params).
struct NormalEquations {
    diag: Vec<f64>,
    off: Vec<f64>,
    border: Vec<f64>,
    model: Vec<f64>,
    rhs_x: Vec<f64>,
    rhs_p: Vec<f64>,
}

/// Where A's coefficient `a_i` sits among the free parameters (`a_1` is held).
fn action_index(i: usize) -> Option<usize> {
    match i {
        0 => Some(0),
        1 => None,
        i => Some(i - 1),
    }
}

/// The reading noise's variance from the readings alone: consecutive frames'
/// second differences, whose spread is six times the noise's variance while
/// the path itself hardly curves in 50 ms (median-based, so turns do not count).
fn reading_variance(frames: &[FrameData]) -> Option<f64> {
    let mut d2: Vec<f64> = frames
        .windows(3)
        .filter_map(|w| Some(w[2].obs_px? - 2.0 * w[1].obs_px? + w[0].obs_px?))
        .map(f64::abs)
        .collect();
    if d2.len() < 10 {
        return None;
    }
    let mid = d2.len() / 2;
    let (_, median, _) = d2.select_nth_unstable_by(mid, f64::total_cmp);
    // For a Gaussian, median |d| = 0.6745 sigma_d and sigma_d^2 = 6 sigma^2.
    let sigma_d = *median / 0.674_489_75;
    let v = sigma_d * sigma_d / 6.0;
    (v > 0.0 && v.is_finite()).then_some(v)
}

/// Solves the whole fit from the online learner's state, or `None` if it has
/// no models yet or the fit fails.
/// A solve's outcome: the solution, its path and A (to start the next solve
/// from), and its cost.
struct Solved {
    solution: Solution,
    start: Start,
    cost: f64,
}

impl Solved {
    /// The same solution in units `scale x + offset`.
    fn rescale(&mut self, scale: f64, offset: f64) {
        let s = &mut self.solution;
        s.action = s.action.rescaled(scale, 0.0);
        s.sensor = s.sensor.rescaled(scale, offset);
        s.x_a = scale * s.x_a + offset;
        self.start.rescale(scale, offset);
    }
}

/// The affine map `(scale, offset)` that takes `path` onto `previous` where
/// both have locations: the same mean and spread, the sign of their
/// covariance (the reduced major axis; a least-squares fit would shrink the
/// units towards a point whenever the two paths disagree); `None` if it is not
/// defined.
fn units_map(path: &[f64], previous: &[f64]) -> Option<(f64, f64)> {
    let n = path.len().min(previous.len());
    if n < 2 {
        return None;
    }
    let (x, y) = (&path[..n], &previous[..n]);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / n as f64;
    let (mx, my) = (mean(x), mean(y));
    let (sxx, syy, sxy) = x
        .iter()
        .zip(y)
        .fold((0.0, 0.0, 0.0), |(xx, yy, xy), (a, b)| {
            let (dx, dy) = (a - mx, b - my);
            (xx + dx * dx, yy + dy * dy, xy + dx * dy)
        });
    let scale = sxy.signum() * (syy / sxx).sqrt();
    let offset = my - scale * mx;
    (scale.is_finite() && offset.is_finite() && scale != 0.0 && sxy != 0.0)
        .then_some((scale, offset))
}

fn solve(all_frames: &[FrameData], config: &BatchMlConfig, start: &Start) -> Option<Solved> {
    let oc = config.online;
    // Forgetting: frame j of n weighs gamma^(n-1-j); drop the negligible ones.
    let gamma = config.gamma;
    let keep = if gamma < 1.0 {
        ((MIN_WEIGHT.ln() / gamma.ln()).ceil() as usize).max(1)
    } else {
        usize::MAX
    };
    let first = all_frames.len().saturating_sub(keep);
    let frames = &all_frames[first..];
    let n = frames.len();
    if frames.iter().filter(|f| f.obs_px.is_some()).count() < 4 * (oc.forward_degree + 2) {
        return None;
    }
    let weights: Vec<f64> = (0..n)
        .map(|j| libm::pow(gamma, (n - 1 - j) as f64))
        .collect();
    let mut path: Vec<f64> = start.path.get(first..)?.to_vec();
    if path.len() != n + 1 {
        return None;
    }
    let (lo, hi) = path
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    if hi.partial_cmp(&lo) != Some(core::cmp::Ordering::Greater) {
        return None;
    }
    let mut since_change = f64::INFINITY;
    let class: Vec<usize> = frames
        .iter()
        .enumerate()
        .map(|(j, f)| {
            let changed = j == 0 || f.command != frames[j - 1].command;
            since_change = if changed {
                0.0
            } else {
                since_change + frames[j - 1].dt_s
            };
            usize::from(since_change < TRANSIENT_S)
        })
        .collect();
    let problem = Problem {
        frames,
        weights,
        action_degree: oc.action_degree,
        forward_degree: oc.forward_degree,
        command_scale: oc.command_scale,
        centre: 0.5 * (lo + hi),
        half_width: 0.5 * (hi - lo),
        reading_precision: 1.0 / reading_variance(frames)?,
        class,
    };
    let mut m = Models {
        a: [0.0; MAX_REGRESSORS],
        g: [0.0; MAX_REGRESSORS + 1],
    };
    let mut p = 1.0;
    for (i, c) in start
        .action
        .coeffs()
        .iter()
        .enumerate()
        .take(oc.action_degree + 1)
    {
        m.a[i] = c * p;
        p *= oc.command_scale;
    }
    m.g = initial_forward_model(&problem, &path)?;
    let precision = problem.process_precisions(&m, config);
    let mut cost = problem.cost(&path, &m, &precision);
    let mut lambda = 1e-3;
    for _ in 0..config.iterations {
        match problem.step(&path, &m, &precision, lambda) {
            Some((new_path, new_m)) => {
                let new_cost = problem.cost(&new_path, &new_m, &precision);
                if new_cost <= cost {
                    (path, m, cost) = (new_path, new_m, new_cost);
                    lambda = (lambda * 0.3).max(1e-9);
                } else {
                    lambda *= 10.0;
                }
            }
            None => lambda *= 10.0,
        }
    }
    // Models in raw units.
    let mut a_raw = [0.0; MAX_REGRESSORS];
    let mut scale = 1.0;
    for i in 0..=oc.action_degree {
        a_raw[i] = m.a[i] / scale;
        scale *= oc.command_scale;
    }
    let action = Polynomial::new(&a_raw[..=oc.action_degree]).filter(Polynomial::is_finite)?;
    // S: location regressed on the forward model's noise-free reading at each
    // reading's location, so the data's own spread sets where S is fitted (as
    // in the paper's fit) and the reading noise biases nothing.
    let mut sensor_fit = PolynomialFit::new(oc.sensor_degree, gamma);
    for (j, f) in frames.iter().enumerate() {
        if f.obs_px.is_some() {
            let x = path[j + 1];
            sensor_fit.add(problem.g(&m, x).0, x);
        }
    }
    let sensor = sensor_fit.polynomial()?;
    // The cost at the process noise of the solved models' own typical speed,
    // which makes it the same whatever the units of the start.
    let cost = problem.cost(&path, &m, &problem.process_precisions(&m, config));
    // Dead reckoning carries on from the solved path's end.
    let x_a = *path.last()?;
    let mut full_path = start.path[..first].to_vec();
    full_path.extend_from_slice(&path);
    Some(Solved {
        solution: Solution {
            action,
            sensor,
            x_a,
        },
        start: Start {
            path: full_path,
            action,
        },
        cost,
    })
}

/// g's least-squares coefficients with the path held (a linear fit).
fn initial_forward_model(problem: &Problem<'_>, path: &[f64]) -> Option<[f64; MAX_REGRESSORS + 1]> {
    let q = problem.forward_degree + 1;
    let mut normal = vec![0.0; q * q];
    let mut rhs = vec![0.0; q];
    let mut phi = [0.0; MAX_REGRESSORS + 1];
    for (j, f) in problem.frames.iter().enumerate() {
        let Some(obs) = f.obs_px else { continue };
        let z = problem.z(path[j + 1]);
        let mut p = 1.0;
        for v in phi.iter_mut().take(q) {
            *v = p;
            p *= z;
        }
        let w = problem.weights[j];
        for a in 0..q {
            rhs[a] += w * phi[a] * obs;
            for b in 0..q {
                normal[a * q + b] += w * phi[a] * phi[b];
            }
        }
    }
    let c = solve_dense(&mut normal, &mut rhs, q)?;
    let mut g = [0.0; MAX_REGRESSORS + 1];
    g[..q].copy_from_slice(&c[..q]);
    Some(g)
}

/// A factored symmetric positive definite tridiagonal matrix (LDL^T).
struct Tridiagonal {
    /// D.
    d: Vec<f64>,
    /// L's subdiagonal.
    l: Vec<f64>,
}

impl Tridiagonal {
    fn factor(diag: &[f64], off: &[f64]) -> Option<Self> {
        let n = diag.len();
        let mut d = vec![0.0; n];
        let mut l = vec![0.0; n.saturating_sub(1)];
        for i in 0..n {
            d[i] = diag[i]
                - if i > 0 {
                    l[i - 1] * l[i - 1] * d[i - 1]
                } else {
                    0.0
                };
            if d[i].is_nan() || d[i] <= 0.0 {
                return None;
            }
            if i + 1 < n {
                l[i] = off[i] / d[i];
            }
        }
        Some(Self { d, l })
    }

    fn solve(&self, b: &mut [f64]) {
        let n = b.len();
        for i in 1..n {
            b[i] -= self.l[i - 1] * b[i - 1];
        }
        for i in 0..n {
            b[i] /= self.d[i];
        }
        for i in (0..n.saturating_sub(1)).rev() {
            b[i] -= self.l[i] * b[i + 1];
        }
    }
}

/// Solves the dense `q x q` system `a x = b` (row-major) by Gaussian
/// elimination with partial pivoting; `None` if it is singular.
fn solve_dense(a: &mut [f64], b: &mut [f64], q: usize) -> Option<Vec<f64>> {
    for c in 0..q {
        let pivot = (c..q).max_by(|&i, &j| a[i * q + c].abs().total_cmp(&a[j * q + c].abs()))?;
        if a[pivot * q + c].is_nan() || a[pivot * q + c].abs() <= 1e-300 {
            return None;
        }
        if pivot != c {
            for k in 0..q {
                a.swap(c * q + k, pivot * q + k);
            }
            b.swap(c, pivot);
        }
        for r in c + 1..q {
            let f = a[r * q + c] / a[c * q + c];
            if f == 0.0 {
                continue;
            }
            for k in c..q {
                a[r * q + k] -= f * a[c * q + k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = vec![0.0; q];
    for r in (0..q).rev() {
        let tail: f64 = (r + 1..q).map(|k| a[r * q + k] * x[k]).sum();
        x[r] = (b[r] - tail) / a[r * q + r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tridiagonal_solve_matches_the_matrix() {
        let (diag, off) = (vec![4.0, 5.0, 6.0, 3.0], vec![1.0, -2.0, 0.5]);
        let t = Tridiagonal::factor(&diag, &off).expect("spd");
        let mut x = vec![1.0, 2.0, 3.0, 4.0];
        t.solve(&mut x);
        let mul = |i: usize| {
            diag[i] * x[i]
                + if i > 0 { off[i - 1] * x[i - 1] } else { 0.0 }
                + if i + 1 < 4 { off[i] * x[i + 1] } else { 0.0 }
        };
        for (i, want) in [1.0, 2.0, 3.0, 4.0].iter().enumerate() {
            assert!((mul(i) - want).abs() < 1e-12);
        }
    }

    /// 120 s of walking in a pinhole world (`obs = 38400 / d` plus
    /// `noise_px` of noise, a reading missed every seventh frame) at the nonlinear
    /// speed `v(C) = 1.2 C - 1e-3 C^2` towards the beacon, the command
    /// changing every 3 s: the frames and the true distance at each frame
    /// boundary.
    fn pinhole_world(noise_px: f64) -> (Vec<FrameData>, Vec<f64>) {
        use rand::{RngExt, SeedableRng};
        use rand_distr::{Distribution, Normal};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let noise = Normal::new(0.0, noise_px).expect("normal");
        let (mut d, mut command, dt) = (2400.0, 200.0, 0.05);
        let (mut frames, mut truth) = (Vec::new(), vec![d]);
        for k in 0..2400 {
            if k % 60 == 0 {
                let speed: f64 = rng.random_range(60.0..280.0);
                command = if d < 1800.0 { -speed } else { speed };
            }
            d -= (1.2 * command - 1e-3 * command * command) * dt;
            truth.push(d);
            frames.push(FrameData {
                dt_s: dt,
                command,
                x_online: 0.0,
                obs_px: (k % 7 != 0).then(|| 38_400.0 / d + noise.sample(&mut rng)),
            });
        }
        (frames, truth)
    }

    #[test]
    fn the_pinhole_start_is_the_path_and_the_speed_up_to_units() {
        for noise_px in [0.0, 0.8] {
            let (frames, truth) = pinhole_world(noise_px);
            let start = Start::pinhole(&frames, 3).expect("a start");
            assert_eq!(start.path.len(), truth.len());
            assert!((start.action.coeffs()[1] - 1.0).abs() < 1e-9);
            // Without noise the path is an affine image of the distance (the
            // units'); with it, each point is as noisy as its reading.
            let (scale, offset) = units_map(&start.path, &truth).expect("a map");
            let rms = (start
                .path
                .iter()
                .zip(&truth)
                .map(|(x, d)| (scale * x + offset - d).powi(2))
                .sum::<f64>()
                / truth.len() as f64)
                .sqrt();
            if noise_px == 0.0 {
                assert!(rms < 1.0, "path off by {rms:.2} mm");
            }
            // In those units A is the true speed, within 5 % of the top speed
            // (362 mm/s, at -250).
            for command in [-250.0, -100.0, 0.0, 100.0, 250.0] {
                let truth = -(1.2 * command - 1e-3 * command * command);
                let learned = scale * start.action.eval(command);
                assert!(
                    (learned - truth).abs() < 0.05 * 362.5,
                    "{noise_px} px, {command}: {learned:.1} against {truth:.1} mm/s"
                );
            }
        }
    }

    #[test]
    fn dense_solve_pivots() {
        let mut a = vec![0.0, 2.0, 1.0, 1.0];
        let mut b = vec![4.0, 3.0];
        let x = solve_dense(&mut a, &mut b, 2).expect("regular");
        assert!((x[0] - 1.0).abs() < 1e-12 && (x[1] - 2.0).abs() < 1e-12);
    }
}
