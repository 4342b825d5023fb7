//! The gait's lag after a change of command, as the floor models it: the
//! body's velocity follows the steady response `A(C)` through a first-order
//! lag of time constant `tau`, from standing at the walk's start. Over a frame
//! of length `dt` under a command whose steady velocity is `a`, from the
//! velocity `v` at its start, the mean velocity is
//! `a + (v - a) tau (1 - e^(-dt / tau)) / dt` and the velocity at its end
//! `a + (v - a) e^(-dt / tau)`. Both are linear in the steady velocities, so
//! the lagged motion of a polynomial `A` is the same filter run over each of
//! its basis functions. `tau = 0` is no lag: every frame's mean velocity is
//! its command's steady one, to the bit.

use super::Sample;

/// The longest lag searched for, s.
const LONGEST_S: f64 = 1.0;

/// Each row's mean velocity over its frame (row `j`'s frame runs from row
/// `j - 1`'s end to its own; row 0's is taken to last as long as row 1's and
/// to start from standing), for the steady velocities `steady[j]` of the rows'
/// commands, through a lag of `tau_s`.
pub fn mean_velocities(rows: &[Sample], tau_s: f64, steady: &[f64]) -> Vec<f64> {
    let mut v = 0.0;
    (0..rows.len())
        .map(|j| {
            let dt = match j {
                0 => rows.get(1).map_or(0.0, |r| r.t_s - rows[0].t_s),
                _ => rows[j].t_s - rows[j - 1].t_s,
            };
            let a = steady[j];
            let (mean_share, end_share) = shares(tau_s, dt);
            let mean = a + (v - a) * mean_share;
            v = a + (v - a) * end_share;
            mean
        })
        .collect()
}

/// The shares of the start's departure from steady left in a frame's mean
/// velocity and at its end: `(tau (1 - e^(-dt/tau)) / dt, e^(-dt/tau))`,
/// both 0 without lag.
fn shares(tau_s: f64, dt: f64) -> (f64, f64) {
    if tau_s <= 0.0 || dt <= 0.0 {
        return (0.0, 0.0);
    }
    let end = (-dt / tau_s).exp();
    (tau_s * (1.0 - end) / dt, end)
}

/// The lag that best explains the true path's departures from the steady
/// response over the first `span` frames after each change of command (the
/// walk off from standing included): the `tau` in `[0, 1]` s whose lagged
/// motion leaves the least sum of squares of those windows' summed
/// departures. `departures(tau)` gives each row's departure under `tau`,
/// `windows` the first rows of the windows.
pub(super) fn fit(windows: &[usize], span: usize, departures: impl Fn(f64) -> Vec<f64>) -> f64 {
    let cost = |tau: f64| -> f64 {
        let d = departures(tau);
        windows
            .iter()
            .map(|&j| d[j..(j + span).min(d.len())].iter().sum::<f64>().powi(2))
            .sum()
    };
    // A grid of 10 ms steps, then golden section about its best point.
    let steps = 100;
    let grid = |i: usize| LONGEST_S * i as f64 / steps as f64;
    let best = (0..=steps)
        .map(|i| (grid(i), cost(grid(i))))
        .fold((0.0, f64::INFINITY), |b, p| if p.1 < b.1 { p } else { b });
    let (mut lo, mut hi) = (
        (best.0 - grid(1)).max(0.0),
        (best.0 + grid(1)).min(LONGEST_S),
    );
    let golden = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..40 {
        let (a, b) = (hi - golden * (hi - lo), lo + golden * (hi - lo));
        if cost(a) < cost(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    let tau = 0.5 * (lo + hi);
    if cost(tau) < best.1 { tau } else { best.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(n: usize) -> Vec<Sample> {
        (1..=n)
            .map(|k| Sample {
                t_s: 0.05 * k as f64,
                command: 0.0,
                obs_px: None,
                x_true_mm: 0.0,
            })
            .collect()
    }

    #[test]
    fn no_lag_is_the_steady_velocity_to_the_bit() {
        let steady = [100.0, 100.0, 250.5, -30.25];
        assert_eq!(mean_velocities(&rows(4), 0.0, &steady), steady.to_vec());
    }

    #[test]
    fn the_lag_is_a_first_order_step_response() {
        // From standing to 100 mm/s at t = 0, tau 0.2 s: the distance walked
        // by t is 100 (t - tau (1 - e^(-t/tau))).
        let (tau, n) = (0.2, 40);
        let r = rows(n);
        let means = mean_velocities(&r, tau, &vec![100.0; n]);
        let walked: f64 = means.iter().map(|v| v * 0.05).sum();
        let t: f64 = 0.05 * n as f64;
        let want = 100.0 * (t - tau * (1.0 - (-t / tau).exp()));
        assert!((walked - want).abs() < 1e-9, "{walked} {want}");
    }

    #[test]
    fn the_fit_finds_the_lag_that_made_the_departures() {
        // Departures of a path walked with a 0.23 s lag, seen through a
        // trial lag tau: the steady model's mean velocities minus the
        // lagged ones.
        let r = rows(200);
        let steady: Vec<f64> = (0..200)
            .map(|j| if j < 100 { 150.0 } else { -80.0 })
            .collect();
        let truth = mean_velocities(&r, 0.23, &steady);
        let departures = |tau: f64| {
            let model = mean_velocities(&r, tau, &steady);
            truth
                .iter()
                .zip(&model)
                .map(|(a, b)| 0.05 * (a - b))
                .collect::<Vec<f64>>()
        };
        let tau = fit(&[0, 100], 10, departures);
        assert!((tau - 0.23).abs() < 1e-6, "{tau}");
    }
}
