//! The gait's response lag, for `batch-ml-lag`: after a change of command
//! the robot's speed does not jump to the new steady speed `A(C)` but relaxes
//! to it from where it was, with a time constant `tau` (a first-order lag),
//! so that `A` stays the steady-state response the stopwatch measures. A
//! frame's displacement is then a linear filter of A's basis functions: the
//! process residual stays linear in A's coefficients, and only `tau` enters
//! nonlinearly (as `ln tau`, one more model parameter).

use std::vec;
use std::vec::Vec;

use crate::MAX_REGRESSORS;
use crate::batch::frames::FrameData;

/// The range `tau` is kept in, s.
pub(crate) const TAU_RANGE_S: (f64, f64) = (0.005, 2.0);

/// Per frame, the displacement of each of A's basis functions `u^i` over the
/// frame under the lag (`psi`), and its derivative in `ln tau` (`dpsi`).
pub(crate) struct Regressors {
    pub(crate) psi: Vec<[f64; MAX_REGRESSORS]>,
    pub(crate) dpsi: Vec<[f64; MAX_REGRESSORS]>,
}

/// The regressors of `frames` (a trial from a standstill, or the frames
/// kept of it) for A of `degree` in `u = C / command_scale`, at `tau`.
pub(crate) fn regressors(
    frames: &[FrameData],
    command_scale: f64,
    degree: usize,
    tau: f64,
) -> Regressors {
    let n = frames.len();
    let (mut psi, mut dpsi) = (
        vec![[0.0; MAX_REGRESSORS]; n],
        vec![[0.0; MAX_REGRESSORS]; n],
    );
    // Each basis function's lagged value and its derivative in ln tau, from
    // a standstill (u = 0: only the constant is 1).
    let (mut state, mut dstate) = ([0.0; MAX_REGRESSORS], [0.0; MAX_REGRESSORS]);
    state[0] = 1.0;
    for (j, f) in frames.iter().enumerate() {
        let u = f.command / command_scale;
        let dt = f.dt_s;
        let e = libm::exp(-dt / tau);
        let de = e * dt / tau;
        let k = tau * (1.0 - e);
        let dk = k - e * dt;
        let mut p = 1.0;
        for i in 0..=degree {
            let (s, ds) = (state[i], dstate[i]);
            psi[j][i] = p * dt + (s - p) * k;
            dpsi[j][i] = ds * k + (s - p) * dk;
            state[i] = p + (s - p) * e;
            dstate[i] = ds * e + (s - p) * de;
            p *= u;
        }
    }
    Regressors { psi, dpsi }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames() -> Vec<FrameData> {
        (0..40)
            .map(|j| FrameData {
                dt_s: 0.05,
                command: if j < 20 { 100.0 } else { -50.0 },
                x_online: 0.0,
                obs_px: None,
            })
            .collect()
    }

    #[test]
    fn a_held_command_reaches_its_steady_displacement_and_the_derivative_is_right() {
        let f = frames();
        let r = regressors(&f, 100.0, 2, 0.1);
        // Long after the change the lag has died out: dt u^i.
        for i in 0..=2 {
            let steady = 0.05 * (-0.5f64).powi(i as i32);
            assert!((r.psi[39][i] - steady).abs() < 1e-4 * 0.05, "{i}");
        }
        // Just after it the displacement is still near the old command's.
        assert!(r.psi[20][1] > 0.0);
        // d psi / d ln tau against a central difference.
        let h = 1e-6;
        let (up, down) = (
            regressors(&f, 100.0, 2, 0.1 * libm::exp(h)),
            regressors(&f, 100.0, 2, 0.1 * libm::exp(-h)),
        );
        for j in [0, 5, 20, 23] {
            for i in 0..=2 {
                let numeric = (up.psi[j][i] - down.psi[j][i]) / (2.0 * h);
                assert!((numeric - r.dpsi[j][i]).abs() < 1e-7, "{j} {i}");
            }
        }
    }
}
