//! The rapier patch change by change (`vendor/PATCH.md`), each beside the
//! upstream code it replaces, on the ERS-7's multibody (18 coordinates)
//! walking at command 300:
//!
//! - changes 1 and 2: the body jacobians and both mass matrices, assembled on
//!   each link's own columns, against upstream's dense assembly (kept in the
//!   patched crate as `update_*_dense`; both end with the same factoring);
//! - change 5: factoring the mass matrix with the Coriolis terms, `MassLu`
//!   against nalgebra's `LU::new` on a copy (upstream's every step);
//! - change 4: one solve with it (a constraint row's `M^-1 J`), `MassLu`'s
//!   against `LU::solve_mut`;
//! - the tree dynamics: the plain mass matrix factored as `L^T D L` along the
//!   tree, and a solve with those factors.
//!
//! The whole step, with either dynamics, is `cargo bench --bench
//! physics_step` (in the root package); upstream rapier3d's whole step is in
//! the book (Speed).

use std::hint::black_box;

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use quadsim::{ERS7_URDF, MultibodyDynamics, QuadrupedSim, RobotDescription, SimConfig};
use rapier3d::dynamics::MassLu;
use rapier3d::na::{DMatrix, DVector, LU};

/// The robot with rapier's own dynamics (whose mass matrices upstream also
/// computes), settled and walking at full speed.
fn walking() -> QuadrupedSim {
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("the shipped URDF");
    let config = SimConfig {
        multibody: MultibodyDynamics::Rapier,
        ..SimConfig::default()
    };
    let mut sim = QuadrupedSim::new(&d, config).expect("a world");
    sim.advance(0.5);
    sim.set_command(300.0).expect("finite");
    sim.advance(2.0);
    sim
}

fn bench(c: &mut Criterion) {
    let sim = walking();
    let mb = sim.multibody().expect("the robot is one multibody");
    let bodies = &sim.world().bodies;
    let dt = sim.config().dt_s as f32;
    let mut group = c.benchmark_group("rapier patch (ERS-7 walking, 18 coordinates)");

    for (name, dense) in [
        ("1-2 jacobians and mass matrices: upstream's dense", true),
        (
            "1-2 jacobians and mass matrices: the patch's, link columns",
            false,
        ),
    ] {
        group.bench_function(name, |b| {
            b.iter_batched(
                || mb.clone(),
                |mut m| {
                    m.assemble_mass_matrices(dt, bodies, dense);
                    black_box(m)
                },
                BatchSize::SmallInput,
            )
        });
    }

    let mut assembled = mb.clone();
    assembled.assemble_mass_matrices(dt, bodies, false);
    let (plain, with_coriolis) = assembled.mass_matrices();
    let (plain, with_coriolis): (DMatrix<f32>, DMatrix<f32>) =
        (plain.clone(), with_coriolis.clone());
    let n = with_coriolis.nrows();

    group.bench_function("5 factor: upstream's LU::new on a copy", |b| {
        b.iter(|| black_box(LU::new(black_box(&with_coriolis).clone())))
    });
    let mut lu = MassLu::empty();
    group.bench_function("5 factor: the patch's MassLu, storage kept", |b| {
        b.iter(|| {
            lu.factor(black_box(&with_coriolis), n);
            black_box(lu.dim())
        })
    });

    let rhs = DVector::from_fn(n, |i, _| 1.0 / (1.0 + i as f32));
    let upstream = LU::new(with_coriolis.clone());
    lu.factor(&with_coriolis, n);
    group.bench_function("4 solve: upstream's LU::solve_mut", |b| {
        b.iter_batched(
            || rhs.clone(),
            |mut x| {
                upstream.solve_mut(&mut x);
                black_box(x)
            },
            BatchSize::SmallInput,
        )
    });
    group.bench_function("4 solve: the patch's, raw storage", |b| {
        b.iter_batched(
            || rhs.clone(),
            |mut x| {
                lu.solve_mut(&mut x);
                black_box(x)
            },
            BatchSize::SmallInput,
        )
    });

    let mut tree = MassLu::empty();
    group.bench_function("tree: factor the plain mass matrix as L^T D L", |b| {
        b.iter(|| {
            tree.factor_tree(black_box(&plain), n);
            black_box(tree.dim())
        })
    });
    tree.factor_tree(&plain, n);
    group.bench_function("tree: solve with the L^T D L factors", |b| {
        b.iter_batched(
            || rhs.clone(),
            |mut x| {
                tree.solve_mut(&mut x);
                black_box(x)
            },
            BatchSize::SmallInput,
        )
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
