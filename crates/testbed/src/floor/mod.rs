//! The information floor of a trial: the Cramer-Rao bound on the paper's two
//! metrics, from what the trial recorded. It says how well an unbiased learner
//! of the given model degrees could have done with these commands, these
//! reading times and this much noise, and so how much of a learner's gap to
//! the best polynomials is the recording's and how much is the method's.
//! The derivation and its assumptions, each with its measured effect, are in
//! `book/src/design/information-floor.md`.
//!
//! The model is the one every learner here assumes, with the gait's lag:
//! over frame `j` the location moves by the frame's mean velocity when the
//! body's velocity follows `A(C)` through a first-order lag (`floor/lag.rs`), times
//! `dt_j`, plus white process noise; each reading is `S^-1(x) + ` white
//! reading noise. The unknowns are the location at every frame's end, A's
//! coefficients and S's (A polynomial of the learner's action degree in the
//! command, S of its sensor degree in the reading). The gauge the metrics
//! are blind to is fixed by holding the first location and A's linear
//! coefficient. The noises and the lag are measured from the trial's ground
//! truth (the floor is the testbed's judgement, like the metrics): the
//! readings' spread about the noise-free reading at the true distance, the
//! lag's time constant that best explains the path after each change of
//! command, and the true displacement's spread about the lagged steady
//! response's, apart for frames within [`CHANGING_OVER_S`] of a change. The
//! Fisher information at the truth (the true path, the best polynomials) is
//! a tridiagonal path block bordered by the model columns (`floor/arrow.rs`); its
//! inverse's model block, pushed through each metric linearised at the
//! truth, is the variance no unbiased learner can go below. The true models
//! are not polynomials, so the floor adds the model class's bias in
//! quadrature: `floor^2 = best^2 + variance` (the metric's floor, with the
//! best polynomial in the metric's loss), and `limit^2 + variance` (the
//! likelihood's floor, with the models the likelihood fits when nothing is
//! noisy). [`maximum_likelihood`] is the efficient estimator the floor is checked
//! against.

use nalgebra::DMatrix;
use scasm::Polynomial;

use crate::metrics;
use crate::reference::Reference;

mod arrow;
mod estimator;
pub mod lag;
use arrow::Normal;
pub use estimator::{joint_maximum_likelihood, maximum_likelihood};

/// How long after a change of command the gait counts as changing over, s:
/// such frames have a process noise of their own.
pub const CHANGING_OVER_S: f64 = 0.5;

/// The least process noise per frame assumed, mm: a world with none (the
/// synthetic one) would make the path block singular.
const MIN_PROCESS_MM: f64 = 1e-3;

/// One camera frame as the floor needs it: when it ended, the command over
/// it, its reading, and the true location at its end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// End of the frame, s.
    pub t_s: f64,
    /// The command in force over the frame.
    pub command: f64,
    /// The reading at its end, px, if any.
    pub obs_px: Option<f64>,
    /// Ground truth: distance to the beacon at its end, mm.
    pub x_true_mm: f64,
}

/// A trial's noises, as its ground truth shows them (see
/// `measured_noise` for how).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Noise {
    /// RMS of the readings about the noise-free reading at the true distance, px.
    pub reading_px: f64,
    /// RMS per frame of the true displacement about the steady response's
    /// (the measured action model's), frames in a steady walk, mm.
    pub steady_mm: f64,
    /// The same for frames within [`CHANGING_OVER_S`] of a change of command, mm.
    pub changing_mm: f64,
    /// RMS of the location's bob about its smooth walk, mm: white jitter
    /// that shakes each reading by `g'(x)` times as much.
    pub bob_mm: f64,
    /// The time constant of the gait's first-order lag after a change of
    /// command, s (0: none); the departures above are what it leaves.
    pub lag_s: f64,
    /// The steady process noise's Gaussian core, mm per frame: the scale of
    /// the summed departures by their median absolute value (1.4826 MAD),
    /// which the occasional stall, a heavy tail, does not move as it moves
    /// the RMS (`steady_mm`).
    pub steady_core_mm: f64,
}

/// A trial's information floor on the paper's two metrics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Floor {
    /// The action metric's floor, the *metric's floor*: `sqrt(best^2 +
    /// variance)`, with `best` the best polynomial in the metric's own loss.
    /// No learner of the degrees does better on average, mm/s.
    pub action_rmse_mm_s: f64,
    /// The sensor metric's floor, mm.
    pub sensor_rmse_mm: f64,
    /// The action metric's *likelihood's floor*: `sqrt(limit^2 +
    /// variance)`, with `limit` the error of the maximum-likelihood models
    /// of the floor's model on this trial's frames with noise-free readings,
    /// where the efficient estimator of that model converges, mm/s. NaN if
    /// that fit fails.
    pub action_likelihood_mm_s: f64,
    /// The sensor metric's likelihood's floor, mm.
    pub sensor_likelihood_mm: f64,
    /// The action metric's floor with the steady process noise at its
    /// Gaussian core ([`Noise::steady_core_mm`]) instead of its RMS: what the
    /// floor would be if the noise's heavy tails were known, roughly; the gap
    /// to [`Floor::action_rmse_mm_s`] is what assuming Gaussian noise costs
    /// the bound, mm/s.
    pub action_core_mm_s: f64,
    /// The same of the sensor metric, mm.
    pub sensor_core_mm: f64,
    /// The action metric's variance part alone (its square root), mm/s.
    pub action_sd_mm_s: f64,
    /// The sensor metric's variance part alone, mm.
    pub sensor_sd_mm: f64,
    /// The noises it was computed with.
    pub noise: Noise,
}

impl Floor {
    /// The floor of a trial whose frames (and their ground truth) are `rows`,
    /// judged against `reference` with the learner's `(action, sensor)`
    /// degrees; `None` if the world changed during the trial, or there is too
    /// little to compute it from.
    pub fn of(rows: &[Sample], reference: &Reference, degrees: (usize, usize)) -> Option<Self> {
        Problem::new(rows, reference, degrees, None)?.floor()
    }

    /// The same with the noises given instead of measured.
    pub fn with_noise(
        rows: &[Sample],
        reference: &Reference,
        degrees: (usize, usize),
        noise: Noise,
    ) -> Option<Self> {
        Problem::new(rows, reference, degrees, Some(noise))?.floor()
    }
}

/// The floor's estimation problem over one trial.
#[derive(Clone)]
struct Problem<'a> {
    rows: &'a [Sample],
    reference: &'a Reference,
    /// The measured action model, `(command, mm/s)`, by command.
    velocities: Table,
    /// The measured sensor model as `(distance, 1 / reading)`, by distance.
    inverse_readings: Table,
    action_degree: usize,
    sensor_degree: usize,
    a_star: Polynomial,
    s_star: Polynomial,
    /// `S*'`.
    s_star_slope: Polynomial,
    command_scale: f64,
    obs_centre: f64,
    obs_half: f64,
    /// The location's change per unit of `velocity x dt` (-1 for a distance
    /// that shrinks as the robot walks forwards).
    direction: f64,
    /// Per row: whether its frame is within [`CHANGING_OVER_S`] of a change.
    changing: Vec<bool>,
    noise: Noise,
    /// Per row: the mean velocity over its frame of A* through the lag.
    star_means: Vec<f64>,
    /// Per free A coefficient `k`, per row: the same of its basis function.
    basis_means: Vec<Vec<f64>>,
}

/// A point of the problem: every location (the first held), and the
/// corrections to A's free coefficients (all but the linear) and to S's, in
/// normalised variables.
#[derive(Debug, Clone)]
struct Point {
    path: Vec<f64>,
    model: Vec<f64>,
}

impl Point {
    fn add(&mut self, path: &[f64], model: &[f64]) {
        for (x, d) in self.path[1..].iter_mut().zip(path) {
            *x += d;
        }
        for (m, d) in self.model.iter_mut().zip(model) {
            *m += d;
        }
    }
}

impl<'a> Problem<'a> {
    fn new(
        rows: &'a [Sample],
        reference: &'a Reference,
        (action_degree, sensor_degree): (usize, usize),
        noise: Option<Noise>,
    ) -> Option<Self> {
        if !reference.changes.is_empty() || rows.len() < 10 * (action_degree + sensor_degree + 2) {
            return None;
        }
        let by_obs: Vec<(f64, f64)> = reference.sensor.iter().map(|&(d, o)| (o, d)).collect();
        let a_star = metrics::best_polynomial(&reference.action, action_degree)?;
        let s_star = metrics::best_polynomial(&by_obs, sensor_degree)?;
        let command_scale = reference
            .action
            .iter()
            .fold(0.0, |m, &(c, _)| f64::max(m, c.abs()));
        let (lo, hi) = by_obs
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &(o, _)| {
                (lo.min(o), hi.max(o))
            });
        if !(command_scale > 0.0 && hi > lo) {
            return None;
        }
        let changing = changing_frames(rows);
        let mut problem = Self {
            rows,
            reference,
            velocities: Table::new(&reference.action),
            inverse_readings: Table::new(
                &reference
                    .sensor
                    .iter()
                    .map(|&(d, o)| (d, 1.0 / o))
                    .collect::<Vec<_>>(),
            ),
            action_degree,
            sensor_degree,
            a_star,
            s_star_slope: s_star.derivative(),
            s_star,
            command_scale,
            obs_centre: 0.5 * (lo + hi),
            obs_half: 0.5 * (hi - lo),
            direction: -1.0,
            changing,
            noise: Noise {
                reading_px: 1.0,
                steady_mm: 1.0,
                changing_mm: 1.0,
                bob_mm: 0.0,
                lag_s: 0.0,
                steady_core_mm: 1.0,
            },
            star_means: Vec::new(),
            basis_means: Vec::new(),
        };
        // Which way the location moves under a positive velocity, from the
        // truth itself.
        let moved: f64 = (1..rows.len())
            .map(|j| {
                (rows[j].x_true_mm - rows[j - 1].x_true_mm)
                    * problem.true_velocity(rows[j].command)
                    * problem.dt(j)
            })
            .sum();
        problem.direction = if moved < 0.0 { -1.0 } else { 1.0 };
        problem.noise = match noise {
            Some(n) => n,
            None => problem.measured_noise(problem.measured_lag())?,
        };
        let lag = problem.noise.lag_s;
        let commands: Vec<f64> = rows.iter().map(|r| r.command).collect();
        let star: Vec<f64> = commands.iter().map(|&c| problem.a_star.eval(c)).collect();
        problem.star_means = lag::mean_velocities(rows, lag, &star);
        problem.basis_means = (0..action_degree)
            .map(|k| {
                let u: Vec<f64> = commands
                    .iter()
                    .map(|&c| (c / command_scale).powi(Self::action_power(k)))
                    .collect();
                lag::mean_velocities(rows, lag, &u)
            })
            .collect();
        Some(problem)
    }

    fn dt(&self, j: usize) -> f64 {
        self.rows[j].t_s - self.rows[j - 1].t_s
    }

    /// The measured (steady) velocity at `command`, interpolated between the
    /// stopwatch's commands.
    fn true_velocity(&self, command: f64) -> f64 {
        self.velocities.at(command)
    }

    /// The noise-free reading at distance `x`: the measured readings,
    /// interpolated in `1 / obs` (linear in distance for a pinhole camera).
    fn true_obs(&self, x: f64) -> f64 {
        1.0 / self.inverse_readings.at(x)
    }

    /// The noises in the trial's ground truth. The torso's location bobs
    /// with each step about a smooth walk, so a frame's own displacement is
    /// mostly the bob: the process noise is measured over
    /// [`CHANGING_OVER_S`] of frames (the spread of the summed departures,
    /// per frame), where the bob has averaged out, and the bob itself (the
    /// one-frame excess) is counted with the readings it shakes.
    fn measured_noise(&self, lag_s: f64) -> Option<Noise> {
        let n = self.rows.len();
        let departure = self.departures(lag_s);
        let span = self.span();
        let (mut steady, mut changing, mut single) = (Vec::new(), Vec::new(), Vec::new());
        for j in 1..n.saturating_sub(span) {
            let window = j..j + span;
            let held = window
                .clone()
                .all(|i| self.rows[i].command == self.rows[j].command);
            if !held {
                continue;
            }
            let sum: f64 = departure[window.clone()].iter().sum();
            if window.clone().all(|i| !self.changing[i]) {
                steady.push(sum);
                single.push(departure[j]);
            } else if self.rows[j].command != self.rows[j - 1].command {
                changing.push(sum);
            }
        }
        let mean_square = |v: &[f64]| {
            (!v.is_empty()).then(|| v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64)
        };
        let per_frame =
            |v: &[f64]| mean_square(v).map(|m| (m / span as f64).sqrt().max(MIN_PROCESS_MM));
        let steady_mm = per_frame(&steady)?;
        let mut absolute: Vec<f64> = steady.iter().map(|x| x.abs()).collect();
        absolute.sort_by(f64::total_cmp);
        let core = 1.4826 * absolute[absolute.len() / 2] / (span as f64).sqrt();
        let bob = ((mean_square(&single)? - steady_mm * steady_mm) / 2.0)
            .max(0.0)
            .sqrt();
        let readings: Vec<f64> = self
            .rows
            .iter()
            .filter_map(|r| Some(r.obs_px? - self.true_obs(r.x_true_mm)))
            .collect();
        Some(Noise {
            reading_px: mean_square(&readings)?.sqrt().max(1e-9),
            steady_mm,
            changing_mm: per_frame(&changing).unwrap_or(steady_mm),
            bob_mm: bob,
            lag_s,
            steady_core_mm: core.clamp(MIN_PROCESS_MM, steady_mm),
        })
    }

    /// Frames in [`CHANGING_OVER_S`].
    fn span(&self) -> usize {
        let n = self.rows.len();
        let frame_s = (self.rows[n - 1].t_s - self.rows[0].t_s) / (n - 1) as f64;
        ((CHANGING_OVER_S / frame_s).round() as usize).max(1)
    }

    /// Per row: the true displacement over its frame less the steady
    /// response's through a lag of `lag_s` (0 for row 0, which has no frame
    /// before it).
    fn departures(&self, lag_s: f64) -> Vec<f64> {
        let steady: Vec<f64> = self
            .rows
            .iter()
            .map(|r| self.true_velocity(r.command))
            .collect();
        let means = lag::mean_velocities(self.rows, lag_s, &steady);
        (0..self.rows.len())
            .map(|j| match j {
                0 => 0.0,
                _ => {
                    self.rows[j].x_true_mm
                        - self.rows[j - 1].x_true_mm
                        - self.direction * self.dt(j) * means[j]
                }
            })
            .collect()
    }

    /// The gait's lag as the truth shows it: the time constant that best
    /// explains the departures over [`CHANGING_OVER_S`] after the walk off
    /// and after each change of command held that long ([`lag::fit`]).
    fn measured_lag(&self) -> f64 {
        let (n, span) = (self.rows.len(), self.span());
        let windows: Vec<usize> = (1..n.saturating_sub(span))
            .filter(|&j| j == 1 || self.rows[j].command != self.rows[j - 1].command)
            .filter(|&j| (j..j + span).all(|i| self.rows[i].command == self.rows[j].command))
            .collect();
        lag::fit(&windows, span, |tau| self.departures(tau))
    }

    /// Free model parameters: A's `action_degree` (all but the linear), then
    /// S's `sensor_degree + 1`.
    fn model_params(&self) -> usize {
        self.action_degree + self.sensor_degree + 1
    }

    /// The power of the command that A's free parameter `k` multiplies.
    fn action_power(k: usize) -> i32 {
        if k == 0 { 0 } else { k as i32 + 1 }
    }

    fn truth(&self) -> Point {
        Point {
            path: self.rows.iter().map(|r| r.x_true_mm).collect(),
            model: vec![0.0; self.model_params()],
        }
    }

    /// The mean velocity over row `j`'s frame of the A at `point`, through
    /// the lag.
    fn velocity(&self, point: &Point, j: usize) -> f64 {
        self.star_means[j]
            + (0..self.action_degree)
                .map(|k| point.model[k] * self.basis_means[k][j])
                .sum::<f64>()
    }

    fn w(&self, obs: f64) -> f64 {
        (obs - self.obs_centre) / self.obs_half
    }

    /// S and S' at `obs`.
    fn sensor_at(&self, point: &Point, obs: f64) -> (f64, f64) {
        let w = self.w(obs);
        let corrections = &point.model[self.action_degree..];
        let (mut v, mut d) = (self.s_star.eval(obs), self.s_star_slope.eval(obs));
        for (i, c) in corrections.iter().enumerate() {
            v += c * w.powi(i as i32);
            if i > 0 {
                d += c * i as f64 * w.powi(i as i32 - 1) / self.obs_half;
            }
        }
        (v, d)
    }

    /// The noise-free reading `S^-1(x)` by Newton's method from the true
    /// reading, and `S'` there; the true reading itself where that fails
    /// (S not monotone so far out).
    fn reading_at(&self, point: &Point, x: f64) -> (f64, f64) {
        let start = self.true_obs(x);
        let mut o = start;
        for _ in 0..30 {
            let (s, d) = self.sensor_at(point, o);
            if !(d.is_finite() && d != 0.0) {
                break;
            }
            let step = (s - x) / d;
            o -= step;
            if step.abs() < 1e-12 * o.abs().max(1.0) {
                return (o, self.sensor_at(point, o).1);
            }
        }
        (start, self.sensor_at(point, start).1)
    }

    /// Visits every residual row: its precision, residual and derivatives
    /// (free index, value). Free indices: locations 1.. first, then the model.
    fn visit_rows(&self, point: &Point, mut visit: impl FnMut(f64, f64, &[(usize, f64)])) {
        let free = self.rows.len() - 1;
        let q = self.model_params();
        let precision = |sd: f64| 1.0 / (sd * sd);
        let mut entries = Vec::with_capacity(q + 2);
        for (j, row) in self.rows.iter().enumerate() {
            if j > 0 {
                // Process: r = x_j - x_{j-1} - direction dt A(C_j).
                let dt = self.dt(j);
                let r = point.path[j]
                    - point.path[j - 1]
                    - self.direction * dt * self.velocity(point, j);
                entries.clear();
                entries.push((j - 1, 1.0));
                if j > 1 {
                    entries.push((j - 2, -1.0));
                }
                for k in 0..self.action_degree {
                    entries.push((free + k, -self.direction * dt * self.basis_means[k][j]));
                }
                let sd = if self.changing[j] {
                    self.noise.changing_mm
                } else {
                    self.noise.steady_mm
                };
                visit(precision(sd), r, &entries);
            }
            if let Some(obs) = row.obs_px {
                // Reading: e = obs - S^-1(x_j); d/dx = -1/S', d/ds_i = w^i/S'.
                let (o, slope) = self.reading_at(point, point.path[j]);
                let w = self.w(o);
                entries.clear();
                if j > 0 {
                    entries.push((j - 1, -1.0 / slope));
                }
                for i in 0..=self.sensor_degree {
                    entries.push((free + self.action_degree + i, w.powi(i as i32) / slope));
                }
                let shaken = self.noise.bob_mm / slope;
                let sd = self.noise.reading_px.hypot(shaken);
                visit(precision(sd), obs - o, &entries);
            }
        }
        debug_assert!(q == self.action_degree + self.sensor_degree + 1);
    }

    /// The Gauss-Newton normal equations at `point`: the Fisher information
    /// `J' W J`, the gradient `J' W r`, and the sum of squares' parts.
    fn normal_equations(&self, point: &Point) -> Normal {
        self.normal_equations_in(point, self.model_params())
    }

    /// The same with the first `q` model columns only (0: the path's
    /// equations alone, the models held).
    fn normal_equations_in(&self, point: &Point, q: usize) -> Normal {
        let mut normal = Normal::zeros(self.rows.len() - 1, q);
        self.visit_rows(point, |w, r, entries| normal.add(w, r, entries));
        normal
    }

    /// The covariance bound of the model corrections: the model block of the
    /// inverse Fisher information at `point` (the truth, for the floor).
    fn model_covariance(&self, point: &Point) -> Option<DMatrix<f64>> {
        let covariance = self.normal_equations(point).eliminate()?.model_covariance();
        covariance
            .iter()
            .all(|v| v.is_finite())
            .then_some(covariance)
    }

    fn floor(&self) -> Option<Floor> {
        let (action_var, sensor_var) = self.metric_variances()?;
        // The same bound with the steady process noise at its Gaussian core:
        // how much a likelihood that knew the tails could gain, at most.
        let core = Self {
            noise: Noise {
                steady_mm: self.noise.steady_core_mm,
                ..self.noise
            },
            ..self.clone()
        };
        let core_var = core.metric_variances().unwrap_or((f64::NAN, f64::NAN));
        let by_obs: Vec<(f64, f64)> = self.reference.sensor.iter().map(|&(d, o)| (o, d)).collect();
        let best_action =
            metrics::best_polynomial_rmse(&self.reference.action, self.action_degree)?;
        let best_sensor = metrics::best_polynomial_rmse(&by_obs, self.sensor_degree)?;
        let (limit_action, limit_sensor) =
            self.likelihood_limit()
                .map_or((f64::NAN, f64::NAN), |(a, s)| {
                    (
                        metrics::action_error(&a, &self.reference.action).rmse,
                        metrics::sensor_error(&s, &self.reference.sensor).rmse,
                    )
                });
        Some(Floor {
            action_rmse_mm_s: best_action.hypot(action_var.sqrt()),
            sensor_rmse_mm: best_sensor.hypot(sensor_var.sqrt()),
            action_likelihood_mm_s: limit_action.hypot(action_var.sqrt()),
            sensor_likelihood_mm: limit_sensor.hypot(sensor_var.sqrt()),
            action_core_mm_s: best_action.hypot(core_var.0.sqrt()),
            sensor_core_mm: best_sensor.hypot(core_var.1.sqrt()),
            action_sd_mm_s: action_var.sqrt(),
            sensor_sd_mm: sensor_var.sqrt(),
            noise: self.noise,
        })
    }

    /// The variance parts of the two metrics' floors: each metric linearised
    /// at the truth, pushed through the models' covariance bound.
    fn metric_variances(&self) -> Option<(f64, f64)> {
        let covariance = self.model_covariance(&self.truth())?;
        let da = self.action_degree;
        // Action metric: e = k A(c) - v after the best k; linearised at A*,
        // de = P dA with P the projection off A*'s values.
        let commands: Vec<f64> = self.reference.action.iter().map(|&(c, _)| c).collect();
        let a_values: Vec<f64> = commands.iter().map(|&c| self.a_star.eval(c)).collect();
        let action_basis = DMatrix::from_fn(commands.len(), da, |r, k| {
            (commands[r] / self.command_scale).powi(Self::action_power(k))
        });
        let action_var = metric_variance(
            &action_basis,
            &[a_values],
            &covariance.view((0, 0), (da, da)).into_owned(),
        );
        // Sensor metric: e = a + b S(obs) - d after the best a and b; de = P dS
        // with P the projection off the constants and S*'s values.
        let obs: Vec<f64> = self.reference.sensor.iter().map(|&(_, o)| o).collect();
        let s_values: Vec<f64> = obs.iter().map(|&o| self.s_star.eval(o)).collect();
        let sensor_basis = DMatrix::from_fn(obs.len(), self.sensor_degree + 1, |r, i| {
            self.w(obs[r]).powi(i as i32)
        });
        let sensor_var = metric_variance(
            &sensor_basis,
            &[vec![1.0; obs.len()], s_values],
            &covariance
                .view((da, da), (self.sensor_degree + 1, self.sensor_degree + 1))
                .into_owned(),
        );
        Some((action_var, sensor_var))
    }

    /// A at `point`, in raw units.
    fn action(&self, point: &Point) -> Option<Polynomial> {
        let mut c = self.a_star.coeffs().to_vec();
        c.resize(self.action_degree + 1, 0.0);
        for k in 0..self.action_degree {
            let p = Self::action_power(k);
            c[p as usize] += point.model[k] / self.command_scale.powi(p);
        }
        Polynomial::new(&c)
    }

    /// S at `point`, in raw units.
    fn sensor(&self, point: &Point) -> Option<Polynomial> {
        let correction = Polynomial::from_normalised(
            &point.model[self.action_degree..],
            self.obs_centre,
            self.obs_half,
        )?;
        let mut c = self.s_star.coeffs().to_vec();
        c.resize(self.sensor_degree + 1, 0.0);
        for (ci, di) in c.iter_mut().zip(correction.coeffs()) {
            *ci += di;
        }
        Polynomial::new(&c)
    }
}

/// The mean square of a metric's error vector `P basis dtheta` over its
/// points, for `dtheta` of `covariance`, with `P` the projection off the
/// span of `gauge` (the directions the metric's best map absorbs).
fn metric_variance(basis: &DMatrix<f64>, gauge: &[Vec<f64>], covariance: &DMatrix<f64>) -> f64 {
    let n = basis.nrows();
    let g = DMatrix::from_fn(n, gauge.len(), |r, c| gauge[c][r]);
    // P = I - G (G^T G)^-1 G^T.
    let projection = match (g.transpose() * &g).try_inverse() {
        Some(inv) => DMatrix::identity(n, n) - &g * inv * g.transpose(),
        None => DMatrix::identity(n, n),
    };
    let m = projection * basis;
    (&m * covariance * m.transpose()).trace() / n as f64
}

/// Points of a measured curve, sorted and without repeated abscissae, for
/// [`metrics::interpolate`] (extrapolated from the end segments).
#[derive(Clone)]
struct Table(Vec<(f64, f64)>);

impl Table {
    fn new(points: &[(f64, f64)]) -> Self {
        let mut sorted = points.to_vec();
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
        sorted.dedup_by(|a, b| a.0 == b.0);
        Self(sorted)
    }

    fn at(&self, x: f64) -> f64 {
        metrics::interpolate(&self.0, x).map_or(f64::NAN, |(y, _)| y)
    }
}

/// Per row: whether its frame starts within [`CHANGING_OVER_S`] of a change
/// of command. The walk off from standing, at the first frame's start, is a
/// change like any later one (counted as steady, it made the steady noise
/// about twice what a steady frame has).
pub fn changing_frames(rows: &[Sample]) -> Vec<bool> {
    let mut changed_at = match rows {
        [first, second, ..] => first.t_s - (second.t_s - first.t_s),
        _ => f64::NEG_INFINITY,
    };
    (0..rows.len())
        .map(|j| {
            if j > 0 && rows[j].command != rows[j - 1].command {
                changed_at = rows[j - 1].t_s;
            }
            j > 0 && rows[j - 1].t_s - changed_at < CHANGING_OVER_S - 1e-9
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_walk_off_from_standing_and_each_change_of_command_are_changing_over() {
        // 20 Hz frames: command 100 from the start, 200 from 2 s.
        let rows: Vec<Sample> = (1..=60)
            .map(|k| Sample {
                t_s: 0.05 * f64::from(k),
                command: if k <= 40 { 100.0 } else { 200.0 },
                obs_px: None,
                x_true_mm: 0.0,
            })
            .collect();
        let changing = changing_frames(&rows);
        let flagged: Vec<usize> = (0..rows.len()).filter(|&j| changing[j]).collect();
        // Frames starting in [0, 0.5) s and in [2.0, 2.5) s (row j spans
        // rows[j-1].t_s to rows[j].t_s; row 0 has no frame before it).
        let want: Vec<usize> = (1..10).chain(40..50).collect();
        assert_eq!(flagged, want);
    }
}
