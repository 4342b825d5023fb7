//! The incremental fits against batch weighted least squares (Householder QR, nalgebra),
//! on random and on deliberately ill-conditioned data.

use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

use crate::action_fit::ActionFit;
use crate::poly_fit::PolynomialFit;
use crate::polynomial::Polynomial;

/// Batch weighted least squares `y ~ alpha + beta . v` with weights
/// `gamma^(n-1-k)`; returns the fitted values at the data points. Regressor
/// columns are standardised first (an affine change that leaves the fitted values
/// unchanged), so the reference itself is accurate.
fn batch_fitted_values(rows: &[Vec<f64>], y: &[f64], gamma: f64) -> Vec<f64> {
    let n = rows.len();
    let p = rows[0].len();
    let mut cols: Vec<(f64, f64)> = Vec::with_capacity(p);
    for j in 0..p {
        let mean = rows.iter().map(|r| r[j]).sum::<f64>() / n as f64;
        let var = rows.iter().map(|r| (r[j] - mean).powi(2)).sum::<f64>() / n as f64;
        cols.push((mean, var.sqrt().max(f64::MIN_POSITIVE)));
    }
    let design = |k: usize, j: usize| {
        if j == 0 {
            1.0
        } else {
            (rows[k][j - 1] - cols[j - 1].0) / cols[j - 1].1
        }
    };
    let w = |k: usize| gamma.powi((n - 1 - k) as i32).sqrt();
    let a = DMatrix::from_fn(n, p + 1, |k, j| w(k) * design(k, j));
    let b = DVector::from_fn(n, |k, _| w(k) * y[k]);
    let qr = a.qr();
    let qtb = qr.q().tr_mul(&b);
    let beta = qr.r().solve_upper_triangular(&qtb).expect("full rank");
    (0..n)
        .map(|k| (0..=p).map(|j| design(k, j) * beta[j]).sum())
        .collect()
}

fn assert_close(got: &[f64], want: &[f64], y: &[f64]) -> Result<(), TestCaseError> {
    let rms_y = (y.iter().map(|v| v * v).sum::<f64>() / y.len() as f64).sqrt();
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        let tol = 1e-9 * w.abs().max(rms_y);
        prop_assert!(
            (g - w).abs() <= tol,
            "point {k}: incremental {g} vs batch {w} (tolerance {tol})"
        );
    }
    Ok(())
}

/// Inputs `x` in a band `[centre - hw, centre + hw]`, targets from a random
/// polynomial plus noise. Narrow bands far from zero are the ill-conditioned ones.
fn poly_case() -> impl Strategy<Value = (usize, f64, Vec<(f64, f64)>)> {
    (1usize..=3, 0.9f64..=1.0, 5.0f64..150.0, 0.02f64..=1.0).prop_flat_map(
        |(degree, gamma, centre, rel_width)| {
            let hw = (centre * rel_width).max(2.0);
            (
                Just(degree),
                prop_oneof![Just(1.0), Just(gamma)],
                prop::collection::vec((-1.0f64..=1.0, -1.0f64..=1.0), 8..300).prop_map(
                    move |pts| {
                        pts.into_iter()
                            .map(|(u, e)| {
                                let x = centre + hw * u;
                                let y =
                                    3000.0 - 40.0 * x + 0.3 * x * x - 1e-3 * x * x * x + 50.0 * e;
                                (x, y)
                            })
                            .collect()
                    },
                ),
            )
        },
    )
}

fn fit_poly(degree: usize, gamma: f64, pts: &[(f64, f64)]) -> (PolynomialFit, Option<Polynomial>) {
    let mut fit = PolynomialFit::new(degree, gamma);
    for &(x, y) in pts {
        fit.add(x, y);
    }
    let p = fit.polynomial();
    (fit, p)
}

fn distinct(xs: impl Iterator<Item = f64>) -> usize {
    let mut v: Vec<f64> = xs.collect();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v.len()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Random and narrow-band data: incremental == batch, gamma < 1 and gamma = 1.
    #[test]
    fn polynomial_fit_equals_batch((degree, gamma, pts) in poly_case()) {
        let (_, p) = fit_poly(degree, gamma, &pts);
        let p = p.expect("enough distinct points");
        let rows: Vec<Vec<f64>> = pts.iter().map(|&(x, _)| (1..=degree).map(|j| x.powi(j as i32)).collect()).collect();
        let y: Vec<f64> = pts.iter().map(|&(_, y)| y).collect();
        let want = batch_fitted_values(&rows, &y, gamma);
        let got: Vec<f64> = pts.iter().map(|&(x, _)| p.eval(x)).collect();
        assert_close(&got, &want, &y)?;
    }

    /// Inputs that repeat a few values: a model only once they determine it.
    #[test]
    fn polynomial_fit_waits_for_enough_distinct_inputs(
        degree in 1usize..=5,
        values in prop::collection::vec(10.0f64..60.0, 1..=6),
        repeats in 1usize..20,
    ) {
        let pts: Vec<(f64, f64)> = (0..repeats).flat_map(|_| values.iter().map(|&x| (x, 5.0 * x))).collect();
        let (_, p) = fit_poly(degree, 0.999, &pts);
        let determined = distinct(values.iter().copied()) > degree;
        prop_assert_eq!(p.is_some(), determined);
    }

    /// Action fit on random walks: the learned A equals the batch one on the test commands.
    #[test]
    fn action_fit_equals_batch(
        degree in 1usize..=4,
        gamma in prop_oneof![Just(1.0), 0.95f64..1.0],
        segments in prop::collection::vec((-300.0f64..=300.0, 1usize..40), 8..60),
        dt in prop_oneof![Just(0.05), 0.001f64..0.1],
        noise in prop::collection::vec(-1.0f64..1.0, 2000),
    ) {
        check_action_fit(degree, gamma, &segments, dt, &noise, 0.0)?;
    }
}

/// Drives an ActionFit along `segments` (command, steps) with an observation after
/// each step of a made-up location, and compares its A (least squares: no
/// prior) with the batch solution.
fn check_action_fit(
    degree: usize,
    gamma: f64,
    segments: &[(f64, usize)],
    dt: f64,
    noise: &[f64],
    t0_s: f64,
) -> Result<(), TestCaseError> {
    prop_assume!(distinct(segments.iter().map(|s| s.0)) > degree + 1);
    let truth = |c: f64| 1.1 * c - 2e-4 * c * c + 4e-6 * c * c * c;
    let mut fit = ActionFit::new(degree, gamma, 300.0, 0.0);
    let mut v = vec![0.0; degree + 1];
    let (mut rows, mut y) = (Vec::new(), Vec::new());
    let mut x = 2000.0;
    // A lead-in at idle makes every V_0 = t large before data arrive.
    if t0_s > 0.0 {
        fit.integrate(0.0, t0_s);
        v[0] += t0_s;
    }
    let mut k = 0;
    for &(c, steps) in segments {
        for _ in 0..steps {
            fit.integrate(c, dt);
            for (i, vi) in v.iter_mut().enumerate() {
                *vi += c.powi(i as i32) * dt;
            }
            x += truth(c) * dt;
            let obs = x + 20.0 * noise[k % noise.len()];
            k += 1;
            fit.add(obs);
            rows.push(v.clone());
            y.push(obs);
        }
    }
    let (a, x0) = fit.model().expect("determined");
    // Fitted values at the data points from the raw-unit model and x(0).
    let got: Vec<f64> = rows
        .iter()
        .map(|r| {
            x0 + r
                .iter()
                .enumerate()
                .map(|(i, vi)| a.coeffs()[i] * vi)
                .sum::<f64>()
        })
        .collect();
    let want = batch_fitted_values(&rows, &y, gamma);
    assert_close(&got, &want, &y)
}

/// An hour of walking with raw commands up to 300: V_4 reaches ~3e13 and the
/// forgetting window is a small slice of it. The fit must still equal the batch.
#[test]
fn action_fit_after_an_hour_equals_batch() {
    let mut segments = Vec::new();
    let mut s: u64 = 7;
    for _ in 0..1200 {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let c = ((s >> 11) as f64 / (1u64 << 53) as f64) * 600.0 - 300.0;
        segments.push((c, 60)); // 3 s at 20 Hz
    }
    let noise: Vec<f64> = (0..997)
        .map(|k| ((k * 7919) % 997) as f64 / 498.5 - 1.0)
        .collect();
    for gamma in [0.999, 1.0] {
        check_action_fit(4, gamma, &segments, 0.05, &noise, 0.0).expect("hour-long fit");
    }
}

/// A long idle lead-in (V_0 = t ~ 1e4 s) before any variation: intercept and V_0
/// are then nearly collinear over the data.
#[test]
fn action_fit_after_a_long_idle_lead_in_equals_batch() {
    let segments: Vec<(f64, usize)> = (0..40)
        .map(|k| (f64::from(k % 9) * 70.0 - 280.0, 20))
        .collect();
    let noise: Vec<f64> = (0..101).map(|k| f64::from(k % 13) / 6.5 - 1.0).collect();
    check_action_fit(4, 0.999, &segments, 0.05, &noise, 10_000.0).expect("lead-in fit");
}
