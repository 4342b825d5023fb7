//! What the batch learner keeps of a trial (one [`FrameData`] per frame), its
//! latest solution, and where a solve starts: the online learner's path, a
//! previous solution carried forward, or the pinhole camera's path.

use std::vec::Vec;

use crate::learner::CalibrationLearner;
use crate::poly_fit::PolynomialFit;
use crate::polynomial::Polynomial;
use crate::scasm::Scasm;

/// Where `tau` starts before the first solve, s (chosen on the development
/// seeds; the solve moves it).
pub(crate) const INITIAL_TAU_S: f64 = 0.1;

/// Frames either side of a frame over which [`Start::pinhole`] takes a speed.
pub(crate) const PINHOLE_SPAN: usize = 10;

/// One frame: the command over it and the online learner's location at its end.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct FrameData {
    pub(crate) dt_s: f64,
    pub(crate) command: f64,
    /// The online learner's `x_a` at the frame's end (the starting path).
    pub(crate) x_online: f64,
    /// The reading at the frame's end, if any.
    pub(crate) obs_px: Option<f64>,
}

/// The latest solution.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Solution {
    pub(crate) action: Polynomial,
    pub(crate) sensor: Polynomial,
    /// Dead reckoning from the solved path's end with the solved A.
    pub(crate) x_a: f64,
}

/// Where a solve starts: a location at every frame boundary so far (the first
/// at 0) and an action model.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Start {
    pub(crate) path: Vec<f64>,
    pub(crate) action: Polynomial,
    /// The response lag's time constant, s (used only where it is modelled).
    #[cfg_attr(feature = "serde", serde(default = "initial_tau_s"))]
    pub(crate) tau_s: f64,
}

#[cfg(feature = "serde")]
fn initial_tau_s() -> f64 {
    INITIAL_TAU_S
}

impl Start {
    /// The online learner's dead reckoning and its action model.
    pub(crate) fn online(frames: &[FrameData], online: &Scasm) -> Option<Self> {
        online.sensor_model()?;
        Some(Self {
            path: online_path(frames),
            action: online.action_model()?,
            tau_s: INITIAL_TAU_S,
        })
    }

    /// The pinhole camera's law, from the readings alone: a beacon of fixed
    /// height spans a number of pixels inversely proportional to its
    /// distance, so `1 / obs` (carried linearly across frames without a
    /// reading) is the path up to its units, whatever either model is. A is
    /// then the least-squares polynomial of degree `action_degree` through
    /// the path's speeds over [`PINHOLE_SPAN`] frames either side of each
    /// frame where the command held, which averages the readings' noise.
    pub(crate) fn pinhole(frames: &[FrameData], action_degree: usize) -> Option<Self> {
        let inverse: Vec<Option<f64>> = frames
            .iter()
            .map(|f| f.obs_px.filter(|o| *o > 0.0).map(|o| 1.0 / o))
            .collect();
        let first = inverse.iter().flatten().next().copied()?;
        let mut path = Vec::with_capacity(frames.len() + 1);
        path.push(first);
        let mut last = (0, first);
        for (j, x) in inverse.iter().enumerate() {
            let Some(&x) = x.as_ref() else { continue };
            // Boundaries last.0 + 1 ..= j + 1 run linearly from last.1 to x.
            let gap = j + 1 - last.0;
            for k in 1..=gap {
                path.push(last.1 + (x - last.1) * k as f64 / gap as f64);
            }
            last = (j + 1, x);
        }
        path.resize(frames.len() + 1, last.1);
        let mut fit = PolynomialFit::new(action_degree, 1.0);
        for b in PINHOLE_SPAN..frames.len().saturating_sub(PINHOLE_SPAN) {
            let held = &frames[b - PINHOLE_SPAN..b + PINHOLE_SPAN];
            if held.iter().all(|f| f.command == held[0].command) {
                let span_s: f64 = held.iter().map(|f| f.dt_s).sum();
                let speed = (path[b + PINHOLE_SPAN] - path[b - PINHOLE_SPAN]) / span_s;
                fit.add(held[0].command, speed);
            }
        }
        let action = fit.polynomial().filter(Polynomial::is_finite)?;
        // Units in which A's slope at a standstill is 1, as A0's is.
        let slope = action.coeffs().get(1).copied().unwrap_or(0.0);
        if !(slope.is_finite() && slope != 0.0) {
            return None;
        }
        let mut start = Self {
            path,
            action,
            tau_s: INITIAL_TAU_S,
        };
        start.rescale(1.0 / slope, 0.0);
        Some(start)
    }

    /// Puts this start in the units `scale x + offset`.
    pub(crate) fn rescale(&mut self, scale: f64, offset: f64) {
        self.action = self.action.rescaled(scale, 0.0);
        for x in &mut self.path {
            *x = scale * *x + offset;
        }
    }

    /// This (a solved path) carried over frames it has not seen yet by its
    /// own action model.
    pub(crate) fn extended(&self, frames: &[FrameData]) -> Self {
        let mut path = self.path.clone();
        for f in frames.iter().skip(path.len() - 1) {
            let last = path.last().copied().unwrap_or(0.0);
            path.push(last + self.action.eval(f.command) * f.dt_s);
        }
        Self {
            path,
            action: self.action,
            tau_s: self.tau_s,
        }
    }
}

/// The online learner's dead reckoning at every frame boundary (the first at 0).
pub(crate) fn online_path(frames: &[FrameData]) -> Vec<f64> {
    core::iter::once(0.0)
        .chain(frames.iter().map(|f| f.x_online))
        .collect()
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::batch::solve::units_map;

    /// 120 s of walking in a pinhole world (`obs = 38400 / d` plus
    /// `noise_px` of noise, a reading missed every seventh frame) at the nonlinear
    /// speed `v(C) = 1.2 C - 1e-3 C^2` towards the beacon, the command
    /// changing every 3 s: the frames and the true distance at each frame
    /// boundary.
    fn pinhole_world(noise_px: f64) -> (Vec<FrameData>, Vec<f64>) {
        use rand::{RngExt, SeedableRng};
        use rand_distr::{Distribution, Normal};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let noise = Normal::new(0.0, noise_px).expect("normal");
        let (mut d, mut command, dt) = (2400.0, 200.0, 0.05);
        let (mut frames, mut truth) = (Vec::new(), vec![d]);
        for k in 0..2400 {
            if k % 60 == 0 {
                let speed: f64 = rng.random_range(60.0..280.0);
                command = if d < 1800.0 { -speed } else { speed };
            }
            d -= (1.2 * command - 1e-3 * command * command) * dt;
            truth.push(d);
            frames.push(FrameData {
                dt_s: dt,
                command,
                x_online: 0.0,
                obs_px: (k % 7 != 0).then(|| 38_400.0 / d + noise.sample(&mut rng)),
            });
        }
        (frames, truth)
    }

    #[test]
    fn the_pinhole_start_is_the_path_and_the_speed_up_to_units() {
        for noise_px in [0.0, 0.8] {
            let (frames, truth) = pinhole_world(noise_px);
            let start = Start::pinhole(&frames, 3).expect("a start");
            assert_eq!(start.path.len(), truth.len());
            assert!((start.action.coeffs()[1] - 1.0).abs() < 1e-9);
            // Without noise the path is an affine image of the distance (the
            // units'); with it, each point is as noisy as its reading.
            let (scale, offset) = units_map(&start.path, &truth).expect("a map");
            let rms = (start
                .path
                .iter()
                .zip(&truth)
                .map(|(x, d)| (scale * x + offset - d).powi(2))
                .sum::<f64>()
                / truth.len() as f64)
                .sqrt();
            if noise_px == 0.0 {
                assert!(rms < 1.0, "path off by {rms:.2} mm");
            }
            // In those units A is the true speed, within 5 % of the top speed
            // (362 mm/s, at -250).
            for command in [-250.0, -100.0, 0.0, 100.0, 250.0] {
                let truth = -(1.2 * command - 1e-3 * command * command);
                let learned = scale * start.action.eval(command);
                assert!(
                    (learned - truth).abs() < 0.05 * 362.5,
                    "{noise_px} px, {command}: {learned:.1} against {truth:.1} mm/s"
                );
            }
        }
    }
}
