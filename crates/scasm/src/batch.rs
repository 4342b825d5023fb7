//! A batch maximum-likelihood learner, in the spirit of Stronger & Stone's
//! later EM work (ICRA 2008): estimate the robot's path `x(t)`, the action model
//! A and the forward sensor model `g` (reading as a function of location)
//! jointly from the whole trial so far, then invert `g` into the sensor model S.
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
//! smooth); the process noise's variance by maximum likelihood given the rest,
//! alternating with the fit. Everything starts from an online SCASM learner fed
//! the same events (by default `scasm-fwd`), whose models the batch learner
//! reports until its first solve.
//!
//! Cost: each solve is O(N) in the frames it covers (forgetting, as gamma does
//! for SCASM, cuts off frames whose weight is below 1e-6, so N is bounded: about
//! 13 800 frames at gamma 0.999). Solving every `solve_every_s` of a trial of T
//! seconds costs O(T^2 / solve_every_s) in all until that bound, O(T) after.

use std::vec::Vec;

use crate::MAX_REGRESSORS;
use crate::config::{ScasmConfig, ScasmParams};
use crate::error::{ConfigError, EventError};
use crate::forward_fit::{invert, spread_range};
use crate::learner::{CalibrationLearner, Event};
use crate::polynomial::Polynomial;
use crate::scasm::{Mode, Scasm};

/// Frames whose weight falls below this are left out of a solve.
const MIN_WEIGHT: f64 = 1e-6;

/// The batch learner's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields, default)
)]
pub struct BatchMlConfig {
    /// The online learner it starts from; its degrees, forgetting and forward
    /// degree are the batch fit's too.
    pub online: ScasmConfig,
    /// How often (s of the trial) the whole fit is solved again.
    pub solve_every_s: f64,
    /// Levenberg-Marquardt iterations per round.
    pub iterations: usize,
    /// Rounds of (fit, then the process noise's variance from the fit).
    pub noise_rounds: usize,
}

impl Default for BatchMlConfig {
    fn default() -> Self {
        Self {
            online: ScasmConfig::default(),
            solve_every_s: 10.0,
            iterations: 8,
            noise_rounds: 3,
        }
    }
}

impl BatchMlConfig {
    /// Checks every value's range.
    pub fn validate(self) -> Result<BatchMlParams, ConfigError> {
        self.online.validate()?;
        if !(self.solve_every_s.is_finite() && self.solve_every_s > 0.0) {
            return Err(ConfigError::SolveEvery {
                solve_every_s: self.solve_every_s,
            });
        }
        if self.iterations == 0 || self.noise_rounds == 0 {
            return Err(ConfigError::Iterations {
                iterations: self.iterations,
                noise_rounds: self.noise_rounds,
            });
        }
        Ok(BatchMlParams(self))
    }
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

/// The batch maximum-likelihood learner (see the module's documentation).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BatchMl {
    params: BatchMlParams,
    online: Scasm,
    frames: Vec<FrameData>,
    next_solve_s: f64,
    solution: Option<Solution>,
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
        if let Some(s) = solve(&self.frames, &c, &self.online) {
            self.solution = Some(s);
        }
    }
}

impl CalibrationLearner for BatchMl {
    fn name(&self) -> &'static str {
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

    /// Weighted sum of squares: process residuals at `process_precision`,
    /// reading residuals at the reading precision. `path[0]` is held.
    fn cost(&self, path: &[f64], m: &Models, process_precision: f64) -> f64 {
        let mut c = 0.0;
        for (j, f) in self.frames.iter().enumerate() {
            let w = self.weights[j];
            let r = path[j + 1] - path[j] - f.dt_s * self.velocity(m, j);
            c += w * process_precision * r * r;
            if let Some(obs) = f.obs_px {
                let e = obs - self.g(m, path[j + 1]).0;
                c += w * self.reading_precision * e * e;
            }
        }
        c
    }

    /// The process residuals' weighted mean square (the ML variance given the
    /// rest).
    fn process_variance(&self, path: &[f64], m: &Models) -> f64 {
        let (mut s, mut w) = (0.0, 0.0);
        for (j, f) in self.frames.iter().enumerate() {
            let r = path[j + 1] - path[j] - f.dt_s * self.velocity(m, j);
            s += self.weights[j] * r * r;
            w += self.weights[j];
        }
        s / w.max(f64::MIN_POSITIVE)
    }

    /// One Levenberg-Marquardt step from (`path`, `m`) with damping `lambda`:
    /// the proposed new path and models.
    fn step(
        &self,
        path: &[f64],
        m: &Models,
        process_precision: f64,
        lambda: f64,
    ) -> Option<(Vec<f64>, Models)> {
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
            let w = self.weights[j] * process_precision;
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
fn solve(all_frames: &[FrameData], config: &BatchMlConfig, online: &Scasm) -> Option<Solution> {
    let oc = config.online;
    let a_online = online.action_model()?;
    online.sensor_model()?;
    // Forgetting: frame j of n weighs gamma^(n-1-j); drop the negligible ones.
    let gamma = oc.gamma;
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
    // The starting path: the online learner's x_a at every frame boundary.
    let start_x = if first > 0 {
        all_frames[first - 1].x_online
    } else {
        0.0
    };
    let mut path: Vec<f64> = core::iter::once(start_x)
        .chain(frames.iter().map(|f| f.x_online))
        .collect();
    let (lo, hi) = path
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    if hi.partial_cmp(&lo) != Some(core::cmp::Ordering::Greater) {
        return None;
    }
    let problem = Problem {
        frames,
        weights,
        action_degree: oc.action_degree,
        forward_degree: oc.forward_degree,
        command_scale: oc.command_scale,
        centre: 0.5 * (lo + hi),
        half_width: 0.5 * (hi - lo),
        reading_precision: 1.0 / reading_variance(frames)?,
    };
    let mut m = Models {
        a: [0.0; MAX_REGRESSORS],
        g: [0.0; MAX_REGRESSORS + 1],
    };
    let mut p = 1.0;
    for (i, c) in a_online
        .coeffs()
        .iter()
        .enumerate()
        .take(oc.action_degree + 1)
    {
        m.a[i] = c * p;
        p *= oc.command_scale;
    }
    m.g = initial_forward_model(&problem, &path)?;
    let mut process_variance = problem.process_variance(&path, &m).max(1e-9);
    for _ in 0..config.noise_rounds {
        let precision = 1.0 / process_variance;
        let mut cost = problem.cost(&path, &m, precision);
        let mut lambda = 1e-3;
        for _ in 0..config.iterations {
            match problem.step(&path, &m, precision, lambda) {
                Some((new_path, new_m)) => {
                    let new_cost = problem.cost(&new_path, &new_m, precision);
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
        process_variance = problem.process_variance(&path, &m).max(1e-9);
    }
    // Models in raw units.
    let mut a_raw = [0.0; MAX_REGRESSORS];
    let mut scale = 1.0;
    for i in 0..=oc.action_degree {
        a_raw[i] = m.a[i] / scale;
        scale *= oc.command_scale;
    }
    let action = Polynomial::new(&a_raw[..=oc.action_degree]).filter(Polynomial::is_finite)?;
    let (sw, sx, sxx) = problem
        .weights
        .iter()
        .zip(&path[1..])
        .fold((0.0, 0.0, 0.0), |(w, x, xx), (&wj, &xj)| {
            (w + wj, x + wj * xj, xx + wj * xj * xj)
        });
    let mean = sx / sw;
    let (lo, hi) = spread_range(mean, (sxx / sw - mean * mean).max(0.0).sqrt())?;
    let sensor = invert(|x| problem.g(&m, x).0, lo, hi, oc.sensor_degree)?;
    // Dead reckoning carries on from the solved path's end.
    let x_a = *path.last()?;
    Some(Solution {
        action,
        sensor,
        x_a,
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

    #[test]
    fn dense_solve_pivots() {
        let mut a = vec![0.0, 2.0, 1.0, 1.0];
        let mut b = vec![4.0, 3.0];
        let x = solve_dense(&mut a, &mut b, 2).expect("regular");
        assert!((x[0] - 1.0).abs() < 1e-12 && (x[1] - 2.0).abs() < 1e-12);
    }
}
