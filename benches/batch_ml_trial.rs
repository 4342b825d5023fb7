//! `batch-ml` over a whole synthetic trial (no physics: the learner's cost
//! alone), 150 s and 1200 s long: how its cost grows with the trial.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use scasm::{BatchMl, BatchMlConfig};
use testbed::synthetic::{self, SyntheticTrialConfig};

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("batch-ml trial");
    group.sample_size(10);
    for duration_s in [150.0, 1200.0] {
        let config = SyntheticTrialConfig {
            duration_s,
            ..Default::default()
        };
        group.bench_function(format!("{duration_s:.0} s"), |b| {
            b.iter(|| {
                let mut learner =
                    BatchMl::new(BatchMlConfig::default().validate().expect("defaults"));
                synthetic::run_trial(&mut learner, black_box(&config), 1).expect("valid events")
            });
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
