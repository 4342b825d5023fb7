//! The robot's physics: one simulated second of walking at full speed (250
//! steps of 4 ms, controllers every other step, camera at 20 Hz), reported per
//! step too, and one second stepping in place near the beacon, where the
//! camera sees the band at its largest. Each sample starts from the same fresh,
//! settled robot, so every sample times the same work (a robot left walking
//! for minutes would walk into the beacon).

use std::hint::black_box;

use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use quadsim::{ERS7_URDF, QuadrupedSim, RobotDescription, SimConfig};

const STEPS_PER_SECOND: u64 = 250;

fn settled(d: &RobotDescription, config: SimConfig, command: f64) -> QuadrupedSim {
    let mut sim = QuadrupedSim::new(d, config).expect("sim");
    sim.advance(0.5);
    sim.set_command(command).expect("finite");
    sim.advance(2.0);
    sim
}

fn bench(c: &mut Criterion) {
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let mut group = c.benchmark_group("robot");
    group.sample_size(20);
    group.throughput(Throughput::Elements(STEPS_PER_SECOND));
    group.bench_function(
        "walking at command 300, 1 s of simulated time (per step: elements)",
        |b| {
            b.iter_batched(
                || settled(&d, SimConfig::default(), 300.0),
                |mut sim| {
                    sim.advance(1.0);
                    black_box(sim.time_s())
                },
                BatchSize::LargeInput,
            )
        },
    );
    let near = SimConfig {
        start_distance_m: 1.2,
        ..SimConfig::default()
    };
    group.bench_function(
        "stepping in place 1.2 m from the beacon, 1 s of simulated time",
        |b| {
            b.iter_batched(
                || settled(&d, near, 0.0),
                |mut sim| {
                    sim.advance(1.0);
                    black_box(sim.take_frame())
                },
                BatchSize::LargeInput,
            )
        },
    );
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
