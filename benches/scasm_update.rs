//! One SCASM time step (a command event) and one observation update (a reading
//! event), on a learner that is past its ramp-up, so both models are learning.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use scasm::{CalibrationLearner, Scasm};
use testbed::synthetic::{self, SyntheticTrialConfig};

fn warmed_up() -> Scasm {
    let mut learner = Scasm::default();
    let config = SyntheticTrialConfig {
        duration_s: 60.0,
        ..Default::default()
    };
    synthetic::run_trial(&mut learner, &config, 0).expect("valid events");
    learner
}

fn bench(c: &mut Criterion) {
    let learner = warmed_up();
    let t0 = learner.clock_s();
    c.bench_function("scasm time step (command event)", |b| {
        let mut l = learner.clone();
        let mut t = t0;
        b.iter(|| {
            l.handle(black_box(scasm::Event::Command {
                t_s: t,
                dt_s: 0.002,
                command: 150.0,
            }))
            .expect("valid");
            t += 0.002;
        });
    });
    c.bench_function("scasm observation update (reading event)", |b| {
        let mut l = learner.clone();
        let mut obs = 20.0;
        b.iter(|| {
            // Readings at the learner's clock; vary them so the fits keep working.
            obs = if obs > 60.0 { 20.0 } else { obs + 0.37 };
            l.handle(black_box(scasm::Event::Reading {
                t_s: t0,
                obs_px: obs,
            }))
            .expect("valid");
        });
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
