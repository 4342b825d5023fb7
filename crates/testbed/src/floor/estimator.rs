//! Estimators of the floor's own model, which the floor is checked against by
//! Monte Carlo (`tests/information_floor.rs`).
//!
//! - [`maximum_likelihood`]: the models that maximise the likelihood of the
//!   readings with the path integrated out (the efficient estimator: at the
//!   noise levels of real trials its error attains the floor).
//! - [`joint_maximum_likelihood`]: the models and the path that maximise
//!   their joint likelihood. It treats every location as a parameter, so at
//!   real process noise it is biased (the Neyman-Scott problem: as many
//!   nuisance parameters as frames) and does worse than the floor; kept to
//!   show that (the test asserts it).
//!
//! The path is integrated out by Laplace's method. For fixed models the
//! negative log likelihood of path and readings is a sum of squares whose
//! Hessian in the path is tridiagonal, `H`; the readings' likelihood is then
//! `-log p(y | theta) = min_x [1/2 r' W r + 1/2 sum log var] + 1/2 log det H`
//! (exact where the readings are linear in the path, as the process is).
//! It is minimised over the models by Newton's method, with the gradient by
//! forward differences and the Hessian by the marginal Fisher information.

use nalgebra::DVector;
use scasm::Polynomial;

use super::{Noise, Point, Problem, Sample};
use crate::reference::Reference;

/// Outer Newton iterations at most.
const MAX_NEWTON: usize = 40;

/// The path is at its most likely when no location moves by more than this
/// share of the largest distance in a Gauss-Newton step.
const PATH_TOLERANCE: f64 = 1e-10;

/// Finite-difference step of the gradient, in standard deviations of each
/// model coefficient.
const GRADIENT_STEP_SD: f64 = 1e-3;

/// The models `(action, sensor)` (raw polynomials) that maximise the
/// likelihood of the readings under the floor's model with the noises
/// given, the path integrated out; Newton's method from the truth. `None` if
/// the problem cannot be set up or a step fails.
pub fn maximum_likelihood(
    rows: &[Sample],
    reference: &Reference,
    degrees: (usize, usize),
    noise: Noise,
) -> Option<(Polynomial, Polynomial)> {
    Problem::new(rows, reference, degrees, Some(noise))?.maximum_likelihood()
}

impl Problem<'_> {
    /// The models the floor's likelihood fits when nothing is noisy: the
    /// true path held and the readings noise-free, the models at the most
    /// likely given them (Gauss-Newton in the models alone, from the best
    /// polynomials). The likelihood weighs each frame alike and fits
    /// readings in pixels where the metrics weigh the test commands and
    /// distances alike in mm/s and mm, so these are not the best polynomials.
    pub(super) fn likelihood_limit(&self) -> Option<(Polynomial, Polynomial)> {
        let clean: Vec<Sample> = self
            .rows
            .iter()
            .map(|r| Sample {
                obs_px: r.obs_px.map(|_| self.true_obs(r.x_true_mm)),
                ..*r
            })
            .collect();
        let degrees = (self.action_degree, self.sensor_degree);
        let problem = Problem::new(&clean, self.reference, degrees, Some(self.noise))?;
        let mut point = problem.truth();
        for _ in 0..20 {
            let normal = problem.normal_equations(&point);
            let step = normal
                .model
                .clone()
                .cholesky()?
                .solve(&(-&normal.gradient_model));
            point.add(&[], step.as_slice());
            let sd = normal.model.diagonal().map(|d| 1.0 / d.sqrt());
            if step.iter().zip(sd.iter()).all(|(s, d)| s.abs() < 1e-9 * d) {
                break;
            }
        }
        Some((problem.action(&point)?, problem.sensor(&point)?))
    }

    /// [`maximum_likelihood`] of this problem.
    fn maximum_likelihood(&self) -> Option<(Polynomial, Polynomial)> {
        let problem = self;
        let mut point = problem.truth();
        let mut value = problem.profile(&mut point)?;
        for _ in 0..MAX_NEWTON {
            let covariance = problem.model_covariance(&point)?;
            // Forward differences, less the bias of their curvature (half the
            // step times the Hessian's diagonal, here the information's).
            let information = covariance.clone().try_inverse()?;
            let gradient = DVector::from_iterator(
                point.model.len(),
                (0..point.model.len()).map(|k| {
                    let h = GRADIENT_STEP_SD * covariance[(k, k)].sqrt();
                    let mut moved = point.clone();
                    moved.model[k] += h;
                    problem.profile(&mut moved).map_or(f64::NAN, |up| {
                        (up - value) / h - 0.5 * h * information[(k, k)]
                    })
                }),
            );
            let step = -(&covariance * &gradient);
            // The Newton decrement: how far below `value` the quadratic model
            // says the minimum is.
            let decrement = -0.5 * gradient.dot(&step);
            if !decrement.is_finite() {
                return None;
            }
            if decrement < 1e-9 {
                break;
            }
            let mut scale = 1.0;
            loop {
                let mut trial = point.clone();
                for (m, d) in trial.model.iter_mut().zip(step.iter()) {
                    *m += scale * d;
                }
                match problem.profile(&mut trial) {
                    Some(v) if v <= value => {
                        (point, value) = (trial, v);
                        break;
                    }
                    _ if scale > 1e-3 => scale *= 0.5,
                    _ => return Some((problem.action(&point)?, problem.sensor(&point)?)),
                }
            }
        }
        Some((problem.action(&point)?, problem.sensor(&point)?))
    }
}

/// The models `(action, sensor)` of the joint maximum of the likelihood over
/// path and models (Gauss-Newton from the truth with the noises given).
/// Biased at real process noise; see the module's documentation.
pub fn joint_maximum_likelihood(
    rows: &[Sample],
    reference: &Reference,
    degrees: (usize, usize),
    noise: Noise,
) -> Option<(Polynomial, Polynomial)> {
    let problem = Problem::new(rows, reference, degrees, Some(noise))?;
    let mut point = problem.truth();
    for _ in 0..20 {
        let normal = problem.normal_equations(&point);
        let (path, model) = normal.eliminate()?.step(&normal);
        point.add(&path, model.as_slice());
        let largest = path
            .iter()
            .chain(model.iter())
            .fold(0.0, |m, d| f64::max(m, d.abs()));
        if largest < 1e-10 * (1.0 + point.path.iter().fold(0.0, |m, x| f64::max(m, x.abs()))) {
            break;
        }
    }
    Some((problem.action(&point)?, problem.sensor(&point)?))
}

impl Problem<'_> {
    /// The negative log likelihood of the readings at `point`'s models, the
    /// path integrated out (Laplace): the path is moved to its most likely
    /// given the models (Gauss-Newton, from where it is), and the value is
    /// `1/2 r' W r + 1/2 sum log var + 1/2 log det H` there, up to a
    /// constant. `None` if the path's Hessian is not positive definite.
    fn profile(&self, point: &mut Point) -> Option<f64> {
        let scale = 1.0 + point.path.iter().fold(0.0, |m, x| f64::max(m, x.abs()));
        for _ in 0..50 {
            let normal = self.normal_equations_in(point, 0);
            let factor = normal.path_factor()?;
            let step = factor.solve(normal.gradient_path.iter().map(|g| -g).collect());
            point.add(&step, &[]);
            if step.iter().fold(0.0, |m, d| f64::max(m, d.abs())) < PATH_TOLERANCE * scale {
                // The sum of squares after the step, by the quadratic model
                // `f + g' step / 2` (its error is of the step's fourth power).
                let after = normal.weighted_squares
                    + normal
                        .gradient_path
                        .iter()
                        .zip(&step)
                        .map(|(g, d)| g * d)
                        .sum::<f64>();
                return Some(0.5 * (after + normal.log_variances + factor.log_det));
            }
        }
        None
    }
}
