//! How sure a solve is: the Laplace approximation of the posterior over the
//! models (a Gaussian at the solution, its covariance the inverse Fisher
//! information with the path eliminated), and draws from it as the
//! responses the robot could have: A with its coefficients drawn, and the
//! sensor response as the drawn forward model's inverse, tabulated over the
//! solved path's range. The sensor model S is a polynomial of lower order
//! fitted to the forward model, so judging S against these draws counts the
//! misfit of S's class as well as the noise; A's draws are of A's own class,
//! so a response A's degree cannot follow is not in them.

use std::vec::Vec;

use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};

use crate::MAX_REGRESSORS;
use crate::batch::frozen::action_index;
use crate::batch::linalg::cholesky;
use crate::batch::problem::{Models, Problem};
use crate::polynomial::Polynomial;
use crate::posterior::Draw;

/// Locations at which each draw's sensor response is tabulated.
const TABLE_POINTS: usize = 128;

/// A solve's posterior.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Belief {
    /// A's coefficients in normalised commands (the solve's).
    a: [f64; MAX_REGRESSORS],
    /// The forward model's, in normalised locations.
    g: [f64; MAX_REGRESSORS + 1],
    /// The lower Cholesky factor of the covariance of A's free coefficients
    /// and g's (in that order), row-major.
    factor: Vec<f64>,
    action_degree: usize,
    forward_degree: usize,
    command_scale: f64,
    centre: f64,
    half_width: f64,
    /// The solved path's range.
    range: (f64, f64),
}

impl Belief {
    /// The posterior of `problem`'s solution `m` over a path spanning
    /// `range`, with the models' covariance `covariance` (every model
    /// parameter's, the lag's last); `None` if it is not positive definite.
    pub(crate) fn of(
        problem: &Problem<'_>,
        m: &Models,
        covariance: &[f64],
        range: (f64, f64),
    ) -> Option<Self> {
        let q = problem.model_params();
        // A's free coefficients and g's lead; the lag's ln tau, if any, is
        // last and is marginalised by leaving it out.
        let k = problem.action_degree + problem.forward_degree + 1;
        let block: Vec<f64> = (0..k)
            .flat_map(|r| (0..k).map(move |c| (r, c)))
            .map(|(r, c)| covariance[r * q + c])
            .collect();
        Some(Self {
            a: m.a,
            g: m.g,
            factor: cholesky(&block, k)?,
            action_degree: problem.action_degree,
            forward_degree: problem.forward_degree,
            command_scale: problem.command_scale,
            centre: problem.centre,
            half_width: problem.half_width,
            range,
        })
    }

    /// `n` draws, the same every time (a fixed seed).
    pub(crate) fn draws(&self, n: usize) -> Vec<Draw> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0);
        let da = self.action_degree;
        let k = da + self.forward_degree + 1;
        (0..n)
            .filter_map(|_| {
                let z: Vec<f64> = (0..k).map(|_| StandardNormal.sample(&mut rng)).collect();
                let d = |r: usize| -> f64 { (0..=r).map(|c| self.factor[r * k + c] * z[c]).sum() };
                let mut raw = [0.0; MAX_REGRESSORS];
                let mut power = 1.0;
                for (i, v) in raw.iter_mut().enumerate().take(da + 1) {
                    let a = self.a[i] + action_index(i).map_or(0.0, d);
                    *v = a / power;
                    power *= self.command_scale;
                }
                let action = Polynomial::new(&raw[..=da])?;
                let g: Vec<f64> = (0..=self.forward_degree)
                    .map(|i| self.g[i] + d(da + i))
                    .collect();
                let (lo, hi) = self.range;
                let mut sensor: Vec<(f64, f64)> = (0..TABLE_POINTS)
                    .map(|p| {
                        let x = lo + (hi - lo) * p as f64 / (TABLE_POINTS - 1) as f64;
                        let z = (x - self.centre) / self.half_width;
                        let obs = g.iter().rev().fold(0.0, |acc, c| acc * z + c);
                        (obs, x)
                    })
                    .collect();
                sensor.sort_by(|p, q| p.0.total_cmp(&q.0));
                let finite = action.is_finite()
                    && sensor.iter().all(|(o, x)| o.is_finite() && x.is_finite());
                finite.then_some(Draw { action, sensor })
            })
            .collect()
    }
}
