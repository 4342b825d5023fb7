//! The frames before a windowed solve's window: their path held at the
//! previous solution's, so that each of their residuals is linear in the
//! models and the frames are summed once per solve into the quadratic forms
//! they add to the cost (a [`Quadratic`] per residual kind).

use std::vec;
use std::vec::Vec;

use crate::MAX_REGRESSORS;
use crate::batch::frames::FrameData;

/// `sum w (b - j . x)^2` as `b2 - 2 x . c + x' h x`: the sum of squares of
/// residuals linear in `x`.
#[derive(Debug, Clone)]
pub(crate) struct Quadratic {
    pub(crate) h: Vec<f64>,
    pub(crate) c: Vec<f64>,
    pub(crate) b2: f64,
}

impl Quadratic {
    fn new(n: usize) -> Self {
        Self {
            h: vec![0.0; n * n],
            c: vec![0.0; n],
            b2: 0.0,
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.c.len()
    }

    fn add(&mut self, w: f64, b: f64, j: &[f64]) {
        let n = self.len();
        for a in 0..n {
            self.c[a] += w * j[a] * b;
            for k in 0..n {
                self.h[a * n + k] += w * j[a] * j[k];
            }
        }
        self.b2 += w * b * b;
    }

    /// The sum of squares at `x`.
    pub(crate) fn cost(&self, x: &[f64]) -> f64 {
        let n = self.len();
        let mut s = self.b2;
        for a in 0..n {
            s -= 2.0 * x[a] * self.c[a];
            for k in 0..n {
                s += x[a] * self.h[a * n + k] * x[k];
            }
        }
        s
    }

    /// `c - h x`: minus half the gradient, the Gauss-Newton right-hand side.
    pub(crate) fn descent(&self, x: &[f64]) -> Vec<f64> {
        let n = self.len();
        (0..n)
            .map(|a| self.c[a] - (0..n).map(|k| self.h[a * n + k] * x[k]).sum::<f64>())
            .collect()
    }
}

/// The held frames' residuals as quadratic forms: the process residuals' in
/// A's free coefficients (one per noise class), the readings' in g's.
#[derive(Debug, Clone)]
pub(crate) struct Frozen {
    pub(crate) process: [Quadratic; 2],
    pub(crate) reading: Quadratic,
}

/// What the held frames' residuals depend on besides the models.
pub(crate) struct Held<'a> {
    pub(crate) frames: &'a [FrameData],
    /// The location at each of their boundaries (one more than frames).
    pub(crate) path: &'a [f64],
    pub(crate) weights: &'a [f64],
    pub(crate) class: &'a [usize],
    /// With the response lag: each frame's lagged displacement of each of
    /// A's basis functions (see [`crate::batch::lag`]), else `dt u^i`.
    pub(crate) lagged: Option<&'a [[f64; MAX_REGRESSORS]]>,
}

/// How the problem normalises commands and locations, and A's held linear
/// coefficient.
pub(crate) struct Normalisation {
    pub(crate) action_degree: usize,
    pub(crate) forward_degree: usize,
    pub(crate) command_scale: f64,
    pub(crate) centre: f64,
    pub(crate) half_width: f64,
    pub(crate) a1: f64,
}

impl Frozen {
    pub(crate) fn of(held: &Held<'_>, n: &Normalisation) -> Self {
        let da = n.action_degree;
        let mut process = [Quadratic::new(da), Quadratic::new(da)];
        let mut reading = Quadratic::new(n.forward_degree + 1);
        let mut j = [0.0; MAX_REGRESSORS + 1];
        for (k, f) in held.frames.iter().enumerate() {
            let w = held.weights[k];
            let u = f.command / n.command_scale;
            // Process: b = x_{k+1} - x_k - dt a_1 u, j_i = dt u^i (i != 1);
            // with the lag, the lagged displacements instead of dt u^i.
            let basis = |i: usize, p: f64| held.lagged.map_or(f.dt_s * p, |l| l[k][i]);
            let b = held.path[k + 1] - held.path[k] - n.a1 * basis(1, u);
            let mut p = 1.0;
            for i in 0..=da {
                if let Some(a) = action_index(i) {
                    j[a] = basis(i, p);
                }
                p *= u;
            }
            process[held.class[k]].add(w, b, &j[..da]);
            // Reading: b = obs, j_i = z^i.
            if let Some(obs) = f.obs_px {
                let z = (held.path[k + 1] - n.centre) / n.half_width;
                let mut p = 1.0;
                for v in j.iter_mut().take(n.forward_degree + 1) {
                    *v = p;
                    p *= z;
                }
                reading.add(w, obs, &j[..=n.forward_degree]);
            }
        }
        Self { process, reading }
    }
}

/// Where A's coefficient `a_i` sits among the free parameters (`a_1` is held).
pub(crate) fn action_index(i: usize) -> Option<usize> {
    match i {
        0 => Some(0),
        1 => None,
        i => Some(i - 1),
    }
}
