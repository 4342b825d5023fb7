//! Solving the batch fit from one start (Levenberg-Marquardt over the
//! [`Problem`]), and the affine map between two paths' units.

use std::vec;
use std::vec::Vec;

use crate::MAX_REGRESSORS;
use crate::batch::belief::Belief;
use crate::batch::config::BatchMlConfig;
use crate::batch::frames::{FrameData, Solution, Start};
use crate::batch::frozen::{Frozen, Held, Normalisation};
use crate::batch::lag;
use crate::batch::linalg::solve_dense;
use crate::batch::problem::{MIN_WEIGHT, Models, Problem, TRANSIENT_S, reading_variance};
use crate::poly_fit::PolynomialFit;
use crate::polynomial::Polynomial;
/// Locations at which S is fitted to the forward model, evenly spaced over
/// the path's range (many more than a cubic's coefficients).
const SENSOR_FIT_POINTS: usize = 64;

/// A solve's outcome: the solution, its path and A (to start the next solve
/// from), its cost, and its posterior (if asked for and the Fisher
/// information is regular).
pub(crate) struct Solved {
    pub(crate) solution: Solution,
    pub(crate) start: Start,
    pub(crate) cost: f64,
    pub(crate) belief: Option<Belief>,
}

impl Solved {
    /// The same solution in units `scale x + offset`.
    pub(crate) fn rescale(&mut self, scale: f64, offset: f64) {
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
pub(crate) fn units_map(path: &[f64], previous: &[f64]) -> Option<(f64, f64)> {
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

/// Solves the fit from `start` over `all_frames`, the first `held` of them
/// (a windowed solve's frames before its window) with their path held at
/// `start`'s, and with `belief` the solution's posterior; `None` if there is
/// too little to solve or the fit fails.
pub(crate) fn solve(
    all_frames: &[FrameData],
    config: &BatchMlConfig,
    start: &Start,
    held: usize,
    belief: bool,
) -> Option<Solved> {
    let oc = config.online;
    // Forgetting: frame j of n weighs gamma^(n-1-j); drop the negligible ones.
    let gamma = config.gamma;
    let keep = if gamma < 1.0 {
        ((MIN_WEIGHT.ln() / gamma.ln()).ceil() as usize).max(1)
    } else {
        usize::MAX
    };
    let first = all_frames.len().saturating_sub(keep);
    let window = held.max(first);
    let kept = &all_frames[first..];
    let n = kept.len();
    if kept.iter().filter(|f| f.obs_px.is_some()).count() < 4 * (oc.forward_degree + 2) {
        return None;
    }
    let mut weights: Vec<f64> = (0..n)
        .map(|j| libm::pow(gamma, (n - 1 - j) as f64))
        .collect();
    let kept_path = start.path.get(first..)?;
    if kept_path.len() != n + 1 || window >= all_frames.len() {
        return None;
    }
    let (lo, hi) = kept_path
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    if hi.partial_cmp(&lo) != Some(core::cmp::Ordering::Greater) {
        return None;
    }
    let mut since_change = f64::INFINITY;
    let mut class: Vec<usize> = kept
        .iter()
        .enumerate()
        .map(|(j, f)| {
            let changed = j == 0 || f.command != kept[j - 1].command;
            since_change = if changed {
                0.0
            } else {
                since_change + kept[j - 1].dt_s
            };
            usize::from(since_change < TRANSIENT_S)
        })
        .collect();
    // The held frames, then the window's (whose path is free but its first
    // location).
    let split = window - first;
    let (held_weights, held_class) = (weights[..split].to_vec(), class[..split].to_vec());
    weights.drain(..split);
    class.drain(..split);
    let frames = &all_frames[window..];
    let mut path: Vec<f64> = start.path[window..].to_vec();
    let mut problem = Problem {
        frames,
        weights,
        action_degree: oc.action_degree,
        forward_degree: oc.forward_degree,
        command_scale: oc.command_scale,
        centre: 0.5 * (lo + hi),
        half_width: 0.5 * (hi - lo),
        reading_precision: 1.0 / reading_variance(frames)?,
        class,
        frozen: None,
        lag: config.lag.then_some((kept, split)),
    };
    let mut m = Models {
        a: [0.0; MAX_REGRESSORS],
        g: [0.0; MAX_REGRESSORS + 1],
        log_tau: libm::log(start.tau_s),
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
    if split > 0 {
        // With the lag, the held frames' lagged regressors at the start's tau.
        let lagged = config.lag.then(|| {
            let r = lag::regressors(kept, oc.command_scale, oc.action_degree, start.tau_s);
            r.psi[..split].to_vec()
        });
        let held = Held {
            frames: &kept[..split],
            path: &kept_path[..=split],
            weights: &held_weights,
            class: &held_class,
            lagged: lagged.as_deref(),
        };
        let normalisation = Normalisation {
            action_degree: problem.action_degree,
            forward_degree: problem.forward_degree,
            command_scale: problem.command_scale,
            centre: problem.centre,
            half_width: problem.half_width,
            a1: m.a[1],
        };
        problem.frozen = Some(Frozen::of(&held, &normalisation));
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
    // S: location regressed on the forward model's noise-free reading, so
    // the reading noise biases nothing. With `sensor_even` (the default), at
    // evenly spaced locations over the range the path covers, so that S is
    // fitted alike at every distance the robot works at, as it is used and
    // judged; without, at each reading's location (the data's own spread,
    // as in the paper's fit, which weighs each distance by the time spent
    // there and piles the cubic's misfit onto the distances walked least).
    let mut sensor_fit = PolynomialFit::new(
        oc.sensor_degree,
        if config.sensor_even { 1.0 } else { gamma },
    );
    let (lo, hi) = kept_path[..=split]
        .iter()
        .chain(path.iter())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    if config.sensor_even {
        for k in 0..SENSOR_FIT_POINTS {
            let x = lo + (hi - lo) * k as f64 / (SENSOR_FIT_POINTS - 1) as f64;
            sensor_fit.add(problem.g(&m, x).0, x);
        }
    } else {
        let held_readings = kept[..split].iter().zip(&kept_path[1..=split]);
        for (f, &x) in held_readings.chain(frames.iter().zip(&path[1..])) {
            if f.obs_px.is_some() {
                sensor_fit.add(problem.g(&m, x).0, x);
            }
        }
    }
    let sensor = sensor_fit.polynomial()?;
    // The cost at the process noise of the solved models' own typical speed,
    // which makes it the same whatever the units of the start.
    let precision = problem.process_precisions(&m, config);
    let cost = problem.cost(&path, &m, &precision);
    let belief = belief
        .then(|| problem.model_covariance(&path, &m, &precision))
        .flatten()
        .and_then(|covariance| Belief::of(&problem, &m, &covariance, (lo, hi)));
    // Dead reckoning carries on from the solved path's end.
    let x_a = *path.last()?;
    let mut full_path = start.path[..window].to_vec();
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
            tau_s: libm::exp(m.log_tau),
        },
        cost,
        belief,
    })
}

/// g's least-squares coefficients with the path held (a linear fit), held
/// frames included.
pub(crate) fn initial_forward_model(
    problem: &Problem<'_>,
    path: &[f64],
) -> Option<[f64; MAX_REGRESSORS + 1]> {
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
    if let Some(frozen) = &problem.frozen {
        for a in 0..q {
            rhs[a] += frozen.reading.c[a];
            for b in 0..q {
                normal[a * q + b] += frozen.reading.h[a * q + b];
            }
        }
    }
    let c = solve_dense(&mut normal, &mut rhs, q)?;
    let mut g = [0.0; MAX_REGRESSORS + 1];
    g[..q].copy_from_slice(&c[..q]);
    Some(g)
}
