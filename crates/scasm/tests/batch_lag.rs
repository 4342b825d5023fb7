//! `batch-ml-lag` in a world whose robot responds to a change of command
//! with a first-order lag: it learns the lag's time constant, and its A is
//! nearer the steady-state response than `batch-ml`'s, which averages each
//! change-over into A.

mod common;

use scasm::{BatchMl, BatchMlConfig, CalibrationLearner, Event};

const TAU_S: f64 = 0.15;

/// 150 s of the common world's robot, its speed lagging the command by a
/// first-order lag of `TAU_S`, commands changing every 2 s.
fn lagged_events() -> Vec<Event> {
    let dt = common::DT_S;
    let (mut x, mut v, mut dir, mut out) = (2400.0_f64, 0.0_f64, 1.0_f64, Vec::new());
    let mut lcg: u64 = 777;
    let mut next = || common::uniform(&mut lcg);
    let mut command = 0.0;
    for k in 0..3000 {
        if k % 40 == 0 {
            command = dir * (0.2 + 0.8 * next()) * 300.0;
        }
        let a = common::true_velocity(command);
        let e = (-dt / TAU_S).exp();
        x -= a * dt + (v - a) * TAU_S * (1.0 - e);
        v = a + (v - a) * e;
        let obs_px = 76_800.0 / x + (next() - 0.5) * 2.0;
        if (dir > 0.0 && x < 1200.0) || (dir < 0.0 && x > 3600.0) {
            dir = -dir;
        }
        let t_s = f64::from(k) * dt;
        common::push_frame(&mut out, t_s, command, obs_px);
    }
    out
}

#[test]
fn the_lag_is_learned_and_a_is_the_steady_response() {
    let events = lagged_events();
    let run = |config: BatchMlConfig| {
        let mut learner = BatchMl::new(config.validate().expect("valid"));
        common::feed(&mut learner, &events);
        let error = common::action_error(&learner.action_model().expect("A"));
        (error, learner.lag_time_constant_s())
    };
    let (plain, none) = run(BatchMlConfig::default());
    let (lagged, tau) = run(BatchMlConfig::lagged());
    let tau = tau.expect("a time constant");
    eprintln!("batch-ml {plain:.2} mm/s, batch-ml-lag {lagged:.2} mm/s, tau {tau:.3} s");
    assert!(none.is_none());
    assert!(
        (tau / TAU_S - 1.0).abs() < 0.2,
        "tau {tau} s, truth {TAU_S} s"
    );
    assert!(lagged < 0.6 * plain, "{lagged} against {plain}");
}
