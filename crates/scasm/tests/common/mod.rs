//! A deterministic event stream for the learner's own tests: a point robot under
//! a made-up nonlinear action model, seen by an ideal pinhole with pseudo-noise.

// Each test file uses what it needs of this module.
#![allow(dead_code)]

use scasm::{CalibrationLearner, Event, Polynomial};

pub const DT_S: f64 = 0.05;

/// Forward speed (mm/s) of the made-up robot.
pub fn true_velocity(c: f64) -> f64 {
    let u = c / 300.0;
    300.0 * u + 40.0 * u * u - 30.0 * u * u * u
}

/// The next number of a linear congruential stream, uniform in [0, 1).
pub fn uniform(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

/// The events of frames `from..to`: a command over each frame, then a reading.
/// Distance moves between 1.2 and 3.6 m with commands changing every 3 s.
pub fn events(from: u64, to: u64) -> Vec<Event> {
    let (mut x, mut dir, mut out) = (2400.0_f64, 1.0_f64, Vec::new());
    let mut lcg: u64 = 12345;
    let mut command = 0.0;
    for k in 0..to {
        if k % 60 == 0 {
            command = dir * uniform(&mut lcg) * 300.0;
        }
        let t_s = k as f64 * DT_S;
        x -= true_velocity(command) * DT_S;
        let noise = (uniform(&mut lcg) - 0.5) * 2.0;
        let obs_px = 76_800.0 / x + noise;
        if (dir > 0.0 && x < 1200.0) || (dir < 0.0 && x > 3600.0) {
            dir = -dir;
        }
        if k >= from {
            push_frame(&mut out, t_s, command, obs_px);
        }
    }
    out
}

pub fn feed(learner: &mut dyn CalibrationLearner, events: &[Event]) {
    for &e in events {
        learner.handle(e).expect("valid event");
    }
}

/// Appends one frame: `command` over `DT_S` from `t_s`, then a reading at its end.
pub fn push_frame(out: &mut Vec<Event>, t_s: f64, command: f64, obs_px: f64) {
    out.push(Event::Command {
        t_s,
        dt_s: DT_S,
        command,
    });
    out.push(Event::Reading {
        t_s: t_s + DT_S,
        obs_px,
    });
}

/// RMSE of `model` against the true (steady) response after the best scale,
/// mm/s, over commands -300..=300 in steps of 20.
pub fn action_error(model: &Polynomial) -> f64 {
    let commands: Vec<f64> = (-15..=15).map(|k| 20.0 * f64::from(k)).collect();
    let (pv, pp) = commands.iter().fold((0.0, 0.0), |(pv, pp), &c| {
        let p = model.eval(c);
        (pv + p * true_velocity(c), pp + p * p)
    });
    let k = pv / pp;
    let sum: f64 = commands
        .iter()
        .map(|&c| (k * model.eval(c) - true_velocity(c)).powi(2))
        .sum();
    (sum / commands.len() as f64).sqrt()
}
