//! The paper's evaluation (section VII). Learned models live in their own units,
//! so each is judged after the best mapping into true units: a scale for the
//! action model (zero velocity is physical zero), an affine map for the sensor
//! model (its origin is arbitrary).

use nalgebra::{DMatrix, DVector};
use scasm::Polynomial;

/// A learned action model against a measured one, after the best scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScaledError {
    /// The scale `k` minimising `sum (k A(c) - v(c))^2`.
    pub scale: f64,
    /// RMSE of `k A(c) - v(c)` over the measured commands, in velocity units.
    pub rmse: f64,
}

/// A learned sensor model against a measured one, after the best affine map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AffineError {
    /// Offset `a` of the best `a + b S(obs)`.
    pub offset: f64,
    /// Scale `b` of the best `a + b S(obs)`.
    pub scale: f64,
    /// RMSE of `a + b S(obs) - d` over the measured distances, in distance units.
    pub rmse: f64,
}

/// Action error: `model` against measured `(command, velocity)` pairs.
pub fn action_error(model: &Polynomial, measured: &[(f64, f64)]) -> ScaledError {
    let predicted: Vec<f64> = measured.iter().map(|&(c, _)| model.eval(c)).collect();
    let (pv, pp) = measured
        .iter()
        .zip(&predicted)
        .fold((0.0, 0.0), |(pv, pp), (&(_, v), &p)| {
            (pv + p * v, pp + p * p)
        });
    let scale = if pp > 0.0 { pv / pp } else { 0.0 };
    let rmse = rms(measured
        .iter()
        .zip(&predicted)
        .map(|(&(_, v), &p)| scale * p - v));
    ScaledError { scale, rmse }
}

/// Whether error `a` is above error `b` by more than rounding: a model the
/// metric cannot tell from another (the start's line at another scale, to
/// which it is blind) has the other's error up to the last bits of the
/// sums, and is neither worse nor better than it.
pub fn above(a: f64, b: f64) -> bool {
    a > b * (1.0 + 1e-9)
}

/// Sensor error: `model` against measured `(distance, obs)` pairs.
pub fn sensor_error(model: &Polynomial, measured: &[(f64, f64)]) -> AffineError {
    let s: Vec<f64> = measured.iter().map(|&(_, o)| model.eval(o)).collect();
    let n = s.len() as f64;
    let mean_s = s.iter().sum::<f64>() / n;
    let mean_d = measured.iter().map(|&(d, _)| d).sum::<f64>() / n;
    let (sd, ss) = measured
        .iter()
        .zip(&s)
        .fold((0.0, 0.0), |(sd, ss), (&(d, _), &si)| {
            (
                sd + (si - mean_s) * (d - mean_d),
                ss + (si - mean_s).powi(2),
            )
        });
    let scale = if ss > 0.0 { sd / ss } else { 0.0 };
    let offset = mean_d - scale * mean_s;
    let rmse = rms(measured
        .iter()
        .zip(&s)
        .map(|(&(d, _), &si)| offset + scale * si - d));
    AffineError {
        offset,
        scale,
        rmse,
    }
}

/// Consistency of the two learned scales: `| |k / b| - 1 |` (0 is perfect).
pub fn consistency(action_scale: f64, sensor_scale: f64) -> f64 {
    ((action_scale / sensor_scale).abs() - 1.0).abs()
}

/// The least-squares polynomial of `degree` through `(x, y)` points: the best any
/// learned polynomial of that degree could do.
pub fn best_polynomial(points: &[(f64, f64)], degree: usize) -> Option<Polynomial> {
    let n = points.len();
    if n <= degree {
        return None;
    }
    // Fit on a normalised variable, then expand into raw powers.
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &(x, _)| {
            (lo.min(x), hi.max(x))
        });
    let centre = 0.5 * (lo + hi);
    let half = (0.5 * (hi - lo)).max(f64::MIN_POSITIVE);
    let m = DMatrix::from_fn(n, degree + 1, |i, j| {
        ((points[i].0 - centre) / half).powi(j as i32)
    });
    let y = DVector::from_iterator(n, points.iter().map(|&(_, y)| y));
    // Householder QR: nalgebra 0.35's SVD solve was seen to return a wrong
    // least-squares solution on tall systems.
    let qr = m.qr();
    let q = qr.r().solve_upper_triangular(&qr.q().tr_mul(&y))?;
    Polynomial::from_normalised(q.as_slice(), centre, half)
}

/// Location error of `(estimate, true distance mm)` pairs: the RMSE after the
/// best affine map from the estimate's units to mm (the sensor metric's
/// gauge), or `None` with fewer than three pairs.
pub fn location_rmse(pairs: &[(f64, f64)]) -> Option<f64> {
    if pairs.len() < 3 {
        return None;
    }
    best_polynomial_rmse(pairs, 1)
}

/// RMSE of the best `degree` polynomial through `(x, y)` points.
pub fn best_polynomial_rmse(points: &[(f64, f64)], degree: usize) -> Option<f64> {
    let p = best_polynomial(points, degree)?;
    Some(rms(points.iter().map(|&(x, y)| p.eval(x) - y)))
}

/// Linear interpolation in a table sorted by `x` (at least two points): the
/// value and the slope of the segment used; beyond the ends, along the end
/// segments.
pub fn interpolate(table: &[(f64, f64)], x: f64) -> Option<(f64, f64)> {
    if table.len() < 2 {
        return None;
    }
    let k = table
        .partition_point(|p| p.0 <= x)
        .clamp(1, table.len() - 1);
    let ((x0, y0), (x1, y1)) = (table[k - 1], table[k]);
    let slope = (y1 - y0) / (x1 - x0);
    Some((y0 + slope * (x - x0), slope)).filter(|(y, s)| y.is_finite() && s.is_finite())
}

fn rms(residuals: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = residuals.fold((0.0, 0usize), |(s, n), r| (s + r * r, n + 1));
    if n == 0 { 0.0 } else { (sum / n as f64).sqrt() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scaled_copy_has_zero_action_error() {
        let truth = |c: f64| 1.1 * c + 2e-4 * c * c;
        let measured: Vec<_> = (-15..=15)
            .map(|k| (20.0 * f64::from(k), truth(20.0 * f64::from(k))))
            .collect();
        let learned = Polynomial::new(&[0.0, -0.55, -1e-4]).expect("poly");
        let e = action_error(&learned, &measured);
        assert!((e.scale + 2.0).abs() < 1e-9 && e.rmse < 1e-9, "{e:?}");
    }

    #[test]
    fn an_affine_copy_has_zero_sensor_error() {
        let measured: Vec<_> = (0..13)
            .map(|k| {
                let d = 1200.0 + 200.0 * f64::from(k);
                (d, 38_400.0 / d)
            })
            .collect();
        // S in its own units: 3 - 0.5 * (true distance), expressed as a polynomial in obs
        // is not possible exactly; use the best cubic and check the error equals its residual.
        let best = best_polynomial(
            &measured.iter().map(|&(d, o)| (o, d)).collect::<Vec<_>>(),
            3,
        )
        .expect("fit");
        let own_units = Polynomial::new(
            &best
                .coeffs()
                .iter()
                .enumerate()
                .map(|(i, c)| if i == 0 { 3.0 - 0.5 * c } else { -0.5 * c })
                .collect::<Vec<_>>(),
        )
        .expect("poly");
        let e = sensor_error(&own_units, &measured);
        let residual = best_polynomial_rmse(
            &measured.iter().map(|&(d, o)| (o, d)).collect::<Vec<_>>(),
            3,
        )
        .expect("fit");
        assert!((e.rmse - residual).abs() < 1e-6, "{e:?} vs {residual}");
        assert!((e.scale + 2.0).abs() < 1e-9);
    }

    #[test]
    fn best_polynomial_reproduces_a_polynomial() {
        let pts: Vec<_> = (0..20)
            .map(|k| {
                let x = f64::from(k) * 3.0 - 10.0;
                (x, 2.0 - x + 0.25 * x * x * x)
            })
            .collect();
        assert!(best_polynomial_rmse(&pts, 3).expect("fit") < 1e-9);
        assert!(best_polynomial_rmse(&pts, 1).expect("fit") > 1.0);
    }

    #[test]
    fn consistency_ignores_sign() {
        assert!(consistency(-2.0, 2.0).abs() < 1e-15);
        assert!((consistency(1.1, -1.0) - 0.1).abs() < 1e-12);
    }
}
