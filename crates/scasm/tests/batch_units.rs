//! The batch learner's units hold from one solve to the next. The likelihood
//! is blind to them (any affine map of the path fits as well), so each solve
//! could land in units of its own; a localiser holding a location in the old
//! units would then be thrown off at every solve.

mod common;

use scasm::{BatchMl, BatchMlConfig, CalibrationLearner, Polynomial};

/// The affine map `(scale, offset)` that best takes `old`'s locations to
/// `new`'s, at readings evenly spread over 20-64 px (1.2-3.6 m).
fn units_map(old: &Polynomial, new: &Polynomial) -> (f64, f64) {
    let pairs: Vec<(f64, f64)> = (0..=22)
        .map(|k| 20.0 + 2.0 * f64::from(k))
        .map(|o| (old.eval(o), new.eval(o)))
        .collect();
    let n = pairs.len() as f64;
    let mx = pairs.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pairs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pairs.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pairs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let scale = sxy / sxx;
    (scale, my - scale * mx)
}

#[test]
fn every_solve_keeps_the_previous_solves_units() {
    let mut learner = BatchMl::new(BatchMlConfig::default().validate().expect("defaults"));
    let (mut previous, mut maps) = (None, Vec::new());
    // 300 s; the learner solves every 10 s, from its first solve on.
    for chunk in common::events(0, 6000).chunks(400) {
        common::feed(&mut learner, chunk);
        let sensor = learner.sensor_model().expect("a sensor model");
        if let Some(old) = previous.replace(sensor) {
            maps.push(units_map(&old, &sensor));
        }
    }
    // After the first minute, each S is nearly the previous one: the units
    // hold (the range spans about 2400 units).
    for &(scale, offset) in &maps[3..] {
        let shift = (scale - 1.0) * 2400.0 + offset;
        assert!(
            (scale - 1.0).abs() < 0.04 && shift.abs() < 100.0,
            "units moved between solves: {maps:?}"
        );
    }
}
