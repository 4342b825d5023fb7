//! The batch learner's units hold from one solve to the next. The likelihood
//! is blind to them (any affine map of the path fits as well), so each solve
//! could land in units of its own; a localiser holding a location in the old
//! units would then be thrown off at every solve.

mod common;

use scasm::{BatchMl, BatchMlConfig, CalibrationLearner, Polynomial};

/// Readings evenly spread over 20-64 px (1.2-3.6 m).
fn readings() -> impl Iterator<Item = f64> {
    (0..=22).map(|k| 20.0 + 2.0 * f64::from(k))
}

/// How far the locations of readings over 1.2-3.6 m move from `old`'s units
/// to `new`'s, under the affine map that best takes one to the other: the
/// largest move, as a fraction of the span of `old`'s locations (the units'
/// origin lies anywhere, so a change of scale counts by what it does there).
fn units_move(old: &Polynomial, new: &Polynomial) -> f64 {
    let pairs: Vec<(f64, f64)> = readings().map(|o| (old.eval(o), new.eval(o))).collect();
    let n = pairs.len() as f64;
    let mx = pairs.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pairs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pairs.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pairs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let scale = sxy / sxx;
    let offset = my - scale * mx;
    let (lo, hi) = pairs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.0), hi.max(p.0))
        });
    let largest = pairs
        .iter()
        .map(|p| (scale * p.0 + offset - p.0).abs())
        .fold(0.0, f64::max);
    largest / (hi - lo)
}

#[test]
fn every_solve_keeps_the_previous_solves_units() {
    let mut learner = BatchMl::new(BatchMlConfig::default().validate().expect("defaults"));
    let (mut previous, mut moves) = (None, Vec::new());
    // 300 s; the learner solves every 10 s, from its first solve on.
    for chunk in common::events(0, 6000).chunks(400) {
        common::feed(&mut learner, chunk);
        let sensor = learner.sensor_model().expect("a sensor model");
        if let Some(old) = previous.replace(sensor) {
            moves.push(units_move(&old, &sensor));
        }
    }
    // The first solve takes the units of the online learner's models, which
    // the host saw until then; after the first minute, each S is nearly the
    // previous one. No location moves by more than 4 % of the range (about
    // 100 mm of 2400).
    assert!(
        moves[0] < 0.04 && moves[3..].iter().all(|m| *m < 0.04),
        "units moved between solves: {moves:.3?}"
    );
}
