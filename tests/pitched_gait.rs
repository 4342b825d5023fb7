//! The walk's pitch keeper (`walk.pitch_gain`): on a training trial's own
//! commands, the open-loop walk falls into a pitched, slow trot after a fast
//! reversal, and the kept walk does not.
//!
//! Development seed 105 at the defaults: at 132.5 s the command goes from
//! -298 (the fastest walk backwards) to +216, and then stays at 190-216 until
//! 144 s, where the stopwatch has the robot at 163-188 mm/s. The open-loop
//! walk (gain 0, the default) pitches by about 6 degrees there and walks at
//! about 55 mm/s for 12 s; with the pitch keeper at 0.3 the same commands,
//! replayed open loop from the start, walk at the stopwatch's speeds.

use quadsim::QuadrupedSim;
use testbed::trial::{TrialConfig, TrialRunner};
use testbed::{experiment, metrics};

mod common;

const SEED: u64 = 105;
/// The stretch after the reversal, s (the walk has 1.5 s to change over).
const AFTER_S: (f64, f64) = (134.0, 144.0);

/// Mean velocity towards the beacon over `AFTER_S`, mm/s, from the distance
/// at each frame's end (`x[k]` at `(k + 1) * dt`).
fn mean_velocity(x_mm: &[f64], dt_s: f64) -> f64 {
    let at = |t: f64| x_mm[(t / dt_s).round() as usize - 1];
    (at(AFTER_S.0) - at(AFTER_S.1)) / (AFTER_S.1 - AFTER_S.0)
}

#[test]
fn the_pitch_keeper_keeps_the_trot_out_of_the_pitched_slow_mode() {
    let (scenario, models) = common::paper_reference();
    let config = TrialConfig {
        duration_s: AFTER_S.1 + 1.0,
        seed: SEED,
        behaviour: experiment::behaviour_for(scenario, models),
        judge_every_s: 5.0,
        blank: Default::default(),
        changes: Vec::new(),
    };
    let mut trial = TrialRunner::new(&scenario.description, scenario.sim, config).expect("a trial");
    let (mut commands, mut open_loop) = (Vec::new(), Vec::new());
    while !trial.finished() {
        let frame = trial.step_frame().expect("a frame");
        commands.push(frame.command);
        open_loop.push(frame.truth.x_mm);
    }
    let dt_s = scenario.sim.camera.frame_period_s;
    let commanded: Vec<f64> =
        commands[(AFTER_S.0 / dt_s) as usize..(AFTER_S.1 / dt_s) as usize].to_vec();
    assert!(
        commanded.iter().all(|&c| (185.0..=220.0).contains(&c)),
        "the case is a fast walk forwards after the reversal: {commanded:?}"
    );
    let table: Vec<(f64, f64)> = models
        .action
        .iter()
        .map(|m| (m.command, m.velocity_mm_s))
        .collect();
    let stopwatch = |c: f64| metrics::interpolate(&table, c).expect("a measured model").0;
    let expected = commanded.iter().map(|&c| stopwatch(c)).sum::<f64>() / commanded.len() as f64;

    let slow = mean_velocity(&open_loop, dt_s);
    assert!(
        slow < 0.6 * expected,
        "the open-loop walk no longer falls into the pitched trot here ({slow:.0} mm/s \
         against the stopwatch's {expected:.0}): the test needs another case"
    );

    let mut kept_config = scenario.sim;
    kept_config.walk.pitch_gain = 0.3;
    let mut sim = QuadrupedSim::new(&scenario.description, kept_config).expect("a robot");
    let mut kept = Vec::new();
    for &command in &commands {
        sim.set_command(command).expect("a command");
        loop {
            sim.step();
            if sim.take_frame().is_some() {
                break;
            }
        }
        kept.push(1000.0 * sim.distance_along_line_m());
    }
    let v = mean_velocity(&kept, dt_s);
    assert!(
        (v - expected).abs() < 0.1 * expected,
        "with the pitch keeper the walk is at {v:.0} mm/s against the stopwatch's \
         {expected:.0} (open loop: {slow:.0})"
    );
}
