//! One physics step of the robot alone (walking at full speed, controllers
//! included every other step), one second of simulated time, and one second
//! standing near the beacon, where the camera sees the band at its largest.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use quadsim::{ERS7_URDF, QuadrupedSim, RobotDescription, SimConfig};

fn walking_sim() -> QuadrupedSim {
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let mut sim = QuadrupedSim::new(&d, SimConfig::default()).expect("sim");
    sim.advance(0.5);
    sim.set_command(300.0).expect("finite");
    sim.advance(2.0);
    sim
}

fn bench(c: &mut Criterion) {
    let mut sim = walking_sim();
    c.bench_function("physics step (robot walking, dt 4 ms)", |b| {
        b.iter(|| {
            sim.step();
            black_box(sim.time_s())
        })
    });
    let mut group = c.benchmark_group("simulated second");
    group.sample_size(10);
    let mut sim = walking_sim();
    group.bench_function("robot walking, 1 s of simulated time", |b| {
        b.iter(|| {
            sim.advance(1.0);
            black_box(sim.time_s())
        })
    });
    // A fresh robot each time: left running, its idle creep would carry it ever
    // closer, and the band's image (and the camera's cost) would keep growing.
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let near = SimConfig {
        start_distance_m: 1.2,
        ..SimConfig::default()
    };
    group.bench_function(
        "robot stepping in place 1.2 m from the beacon, camera at 20 Hz",
        |b| {
            b.iter_batched(
                || {
                    let mut sim = QuadrupedSim::new(&d, near).expect("sim");
                    sim.advance(1.0);
                    sim
                },
                |mut sim| {
                    sim.advance(1.0);
                    black_box(sim.take_frame())
                },
                criterion::BatchSize::LargeInput,
            )
        },
    );
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
