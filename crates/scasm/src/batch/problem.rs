//! The batch fit as a least-squares problem: the negative log likelihood of
//! the path, A and g given the frames, its Gauss-Newton normal equations (a
//! tridiagonal path block bordered by the model columns), and one
//! Levenberg-Marquardt step.

use std::vec;
use std::vec::Vec;

use crate::MAX_REGRESSORS;
use crate::batch::config::BatchMlConfig;
use crate::batch::frames::FrameData;
use crate::batch::frozen::{Frozen, Quadratic, action_index};
use crate::batch::lag::{self, Regressors, TAU_RANGE_S};
use crate::batch::linalg::{Tridiagonal, solve_dense};

/// Frames whose weight falls below this are left out of a solve.
pub(crate) const MIN_WEIGHT: f64 = 1e-6;

/// How long after a change of command the gait counts as changing over, s:
/// such frames get a process noise of their own, so the robot's speeding up
/// or slowing down does not bend A (which is the steady walk's speed).
pub(crate) const TRANSIENT_S: f64 = 0.5;

/// Process precisions (1 / variance) of steady and changing-over frames.
pub(crate) type Precisions = [f64; 2];

/// The model's unknowns besides the path: A's coefficients (but the linear
/// one, which fixes the scale) and g's.
#[derive(Debug, Clone)]
pub(crate) struct Models {
    /// A in normalised commands `u = C / command_scale`: `A = sum a_i u^i`.
    pub(crate) a: [f64; MAX_REGRESSORS],
    /// g in normalised locations `z = (x - centre) / half_width`.
    pub(crate) g: [f64; MAX_REGRESSORS + 1],
    /// `ln tau` of the response lag (see [`crate::batch::lag`]), if modelled.
    pub(crate) log_tau: f64,
}

/// The problem's fixed data.
pub(crate) struct Problem<'a> {
    pub(crate) frames: &'a [FrameData],
    /// Weight of each frame (forgetting), oldest first.
    pub(crate) weights: Vec<f64>,
    pub(crate) action_degree: usize,
    pub(crate) forward_degree: usize,
    pub(crate) command_scale: f64,
    pub(crate) centre: f64,
    pub(crate) half_width: f64,
    /// `1 / sigma_o^2`, readings.
    pub(crate) reading_precision: f64,
    /// Per frame: 1 within [`TRANSIENT_S`] of a change of command (the gait is
    /// changing over), else 0. Each class has its own process noise.
    pub(crate) class: Vec<usize>,
    /// The frames before the window of a windowed solve, path held.
    pub(crate) frozen: Option<Frozen>,
    /// If the response lag is modelled: every frame kept (the held ones and
    /// the window's), through which the lag runs, and where the window starts.
    pub(crate) lag: Option<(&'a [FrameData], usize)>,
}

impl Problem<'_> {
    /// The free model parameters: a_0, a_2..a_d, then g_0..g_m, then
    /// `ln tau` if the lag is modelled.
    pub(crate) fn model_params(&self) -> usize {
        self.action_degree + self.forward_degree + 1 + usize::from(self.lag.is_some())
    }

    /// The lag's regressors over the window at `m`'s `tau`, if modelled.
    pub(crate) fn lag_regressors(&self, m: &Models) -> Option<Regressors> {
        let (all, window) = self.lag?;
        let mut r = lag::regressors(
            all,
            self.command_scale,
            self.action_degree,
            libm::exp(m.log_tau),
        );
        r.psi.drain(..window);
        r.dpsi.drain(..window);
        Some(r)
    }

    /// The displacement over frame `j` under `m`: `dt A(u)`, or with the lag
    /// the lagged basis functions' (`lag` from [`Self::lag_regressors`]).
    fn displacement(&self, m: &Models, j: usize, lag: Option<&Regressors>) -> f64 {
        match lag {
            None => self.frames[j].dt_s * self.velocity(m, j),
            Some(r) => (0..=self.action_degree).map(|i| m.a[i] * r.psi[j][i]).sum(),
        }
    }

    pub(crate) fn u(&self, j: usize) -> f64 {
        self.frames[j].command / self.command_scale
    }

    pub(crate) fn velocity(&self, m: &Models, j: usize) -> f64 {
        let u = self.u(j);
        (0..=self.action_degree)
            .rev()
            .fold(0.0, |acc, i| acc * u + m.a[i])
    }

    pub(crate) fn z(&self, x: f64) -> f64 {
        (x - self.centre) / self.half_width
    }

    pub(crate) fn g(&self, m: &Models, x: f64) -> (f64, f64) {
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
    pub(crate) fn process_precisions(&self, m: &Models, config: &BatchMlConfig) -> Precisions {
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

    /// A's free coefficients (all but the linear), in order.
    fn free_action(&self, m: &Models) -> Vec<f64> {
        (0..=self.action_degree)
            .filter(|&i| action_index(i).is_some())
            .map(|i| m.a[i])
            .collect()
    }

    /// The held frames' share of the cost.
    fn frozen_cost(&self, m: &Models, process_precision: &Precisions) -> f64 {
        self.frozen.as_ref().map_or(0.0, |f| {
            let a = self.free_action(m);
            process_precision[0] * f.process[0].cost(&a)
                + process_precision[1] * f.process[1].cost(&a)
                + self.reading_precision * f.reading.cost(&m.g[..f.reading.len()])
        })
    }

    /// Weighted sum of squares: process residuals at `process_precision`,
    /// reading residuals at the reading precision. `path[0]` is held.
    pub(crate) fn cost(&self, path: &[f64], m: &Models, process_precision: &Precisions) -> f64 {
        let mut c = self.frozen_cost(m, process_precision);
        let lag = self.lag_regressors(m);
        for (j, f) in self.frames.iter().enumerate() {
            let w = self.weights[j];
            let r = path[j + 1] - path[j] - self.displacement(m, j, lag.as_ref());
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
    pub(crate) fn normal_equations(
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
        let lag = self.lag_regressors(m);
        for (j, f) in self.frames.iter().enumerate() {
            let w = self.weights[j] * process_precision[self.class[j]];
            // Process residual r = x_{j+1} - x_j - dt A(u): derivatives +1 on
            // path[j+1] (free index j), -1 on path[j] (free index j-1 if j > 0),
            // -dt u^i on a_i (with the lag: minus the lagged u^i's
            // displacement, and on ln tau minus its derivative).
            let r = path[j + 1] - path[j] - self.displacement(m, j, lag.as_ref());
            let u = self.u(j);
            jp.iter_mut().for_each(|v| *v = 0.0);
            let mut p = 1.0;
            for i in 0..=da {
                if let Some(k) = action_index(i) {
                    jp[k] = match &lag {
                        None => -f.dt_s * p,
                        Some(l) => -l.psi[j][i],
                    };
                }
                p *= u;
            }
            if let Some(l) = &lag {
                jp[q - 1] = -(0..=da).map(|i| m.a[i] * l.dpsi[j][i]).sum::<f64>();
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
        if let Some(frozen) = &self.frozen {
            // The held frames add to the model block and its right-hand side
            // only: A's free coefficients are 0..da, g's da..q.
            let a = self.free_action(m);
            for (class, quadratic) in frozen.process.iter().enumerate() {
                let w = process_precision[class];
                add_quadratic(&mut model, &mut rhs_p, q, 0, w, quadratic, &a);
            }
            let g = &m.g[..frozen.reading.len()];
            add_quadratic(
                &mut model,
                &mut rhs_p,
                q,
                da,
                self.reading_precision,
                &frozen.reading,
                g,
            );
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
    pub(crate) fn step(
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
        let Reduced {
            y,
            cols,
            mut schur,
            mut reduced,
        } = reduce(&diag, &off, &border, model, &rhs_x, rhs_p, q)?;
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
        if self.lag.is_some() {
            let (lo, hi) = TAU_RANGE_S;
            new.log_tau = (m.log_tau + dp[q - 1]).clamp(libm::log(lo), libm::log(hi));
        }
        let finite = new_path.iter().all(|v| v.is_finite())
            && new.a.iter().chain(&new.g).all(|v| v.is_finite())
            && new.log_tau.is_finite();
        finite.then_some((new_path, new))
    }
}

impl Problem<'_> {
    /// The covariance of the model parameters ([`Self::model_params`], in
    /// their order) at (`path`, `m`): the inverse of the Fisher information
    /// with the path eliminated (its Schur complement), row-major; `None`
    /// where it is singular.
    pub(crate) fn model_covariance(
        &self,
        path: &[f64],
        m: &Models,
        process_precision: &Precisions,
    ) -> Option<Vec<f64>> {
        let q = self.model_params();
        let ne = self.normal_equations(path, m, process_precision);
        let rhs_p = vec![0.0; q];
        let Reduced { schur, .. } =
            reduce(&ne.diag, &ne.off, &ne.border, ne.model, &ne.rhs_x, rhs_p, q)?;
        let mut covariance = vec![0.0; q * q];
        for c in 0..q {
            let mut unit = vec![0.0; q];
            unit[c] = 1.0;
            let column = solve_dense(&mut schur.clone(), &mut unit, q)?;
            for r in 0..q {
                covariance[r * q + c] = column[r];
            }
        }
        Some(covariance)
    }
}

/// The normal equations with the path eliminated: `y = T^-1 r_x`, the
/// columns `T^-1 B` (frames x params, row-major), the Schur complement
/// `D - B' T^-1 B` and its right-hand side `r_p - B' y`.
struct Reduced {
    y: Vec<f64>,
    cols: Vec<f64>,
    schur: Vec<f64>,
    reduced: Vec<f64>,
}

/// Eliminates the tridiagonal path block (`diag`, `off`) from normal
/// equations bordered by `q` model columns; `None` if it is not positive
/// definite.
fn reduce(
    diag: &[f64],
    off: &[f64],
    border: &[f64],
    model: Vec<f64>,
    rhs_x: &[f64],
    rhs_p: Vec<f64>,
    q: usize,
) -> Option<Reduced> {
    let n = diag.len();
    let t = Tridiagonal::factor(diag, off)?;
    let mut y = rhs_x.to_vec();
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
    let mut schur = model;
    let mut reduced = rhs_p;
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
    Some(Reduced {
        y,
        cols,
        schur,
        reduced,
    })
}

/// Adds `w` times a held block's quadratic form, over the parameters from
/// `at` on (now at `x`), to the model block and its right-hand side.
fn add_quadratic(
    model: &mut [f64],
    rhs: &mut [f64],
    q: usize,
    at: usize,
    w: f64,
    quadratic: &Quadratic,
    x: &[f64],
) {
    let n = quadratic.len();
    for (a, d) in quadratic.descent(x).iter().enumerate() {
        rhs[at + a] += w * d;
        for k in 0..n {
            model[(at + a) * q + at + k] += w * quadratic.h[a * n + k];
        }
    }
}

/// Gauss-Newton normal equations: `[T B; B' D] [dx; dp] = [rx; rp]` with `T`
/// tridiagonal (`diag`, `off`), `B` the border (row-major, frames x params).
pub(crate) struct NormalEquations {
    pub(crate) diag: Vec<f64>,
    pub(crate) off: Vec<f64>,
    pub(crate) border: Vec<f64>,
    pub(crate) model: Vec<f64>,
    pub(crate) rhs_x: Vec<f64>,
    pub(crate) rhs_p: Vec<f64>,
}

/// The reading noise's variance from the readings alone: consecutive frames'
/// second differences, whose spread is six times the noise's variance while
/// the path itself hardly curves in 50 ms (median-based, so turns do not count).
pub(crate) fn reading_variance(frames: &[FrameData]) -> Option<f64> {
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
