//! The robot's physics: one simulated second of walking at full speed (250
//! steps of 4 ms, controllers every other step, camera at 20 Hz), reported per
//! step too, and one second stepping in place near the beacon, where the
//! camera sees the band at its largest; each with every `physics.multibody`
//! (the default first). Each sample starts from the same fresh,
//! settled robot, so every sample times the same work (a robot left walking
//! for minutes would walk into the beacon).

use std::hint::black_box;

use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use quadsim::{ERS7_URDF, MultibodyDynamics, QuadrupedSim, RobotDescription, SimConfig};

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
    // Each of `physics.multibody`'s values, the default first.
    let mut dynamics = vec![MultibodyDynamics::default()];
    dynamics.extend(
        MultibodyDynamics::NAMES
            .iter()
            .filter_map(|n| MultibodyDynamics::parse(n).ok())
            .filter(|m| *m != MultibodyDynamics::default()),
    );
    for multibody in dynamics {
        let world = SimConfig {
            multibody,
            ..SimConfig::default()
        };
        let name = multibody.as_str();
        group.bench_function(
            format!("walking at command 300, 1 s of simulated time (per step: elements), multibody {name}"),
            |b| {
                b.iter_batched(
                    || settled(&d, world, 300.0),
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
            ..world
        };
        group.bench_function(
            format!(
                "stepping in place 1.2 m from the beacon, 1 s of simulated time, multibody {name}"
            ),
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
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
