//! Guards the patched rapier3d (vendor/rapier3d, see vendor/PATCH.md): the
//! body jacobians and mass matrices it computes on each link's own columns
//! equal upstream's dense code's, on the robot standing and walking fast forwards, backwards and
//! slowly: the jacobians and the plain mass matrix to the bit, the one with the Coriolis terms within
//! 1e-9 of the largest entry (rapier computes in f32, whose resolution for an
//! entry of 1 is 1.2e-7; the differences seen are at most 9.3e-10 of entries
//! up to 1.6, i.e. 5.8e-10 of the largest).

use quadsim::{ERS7_URDF, MultibodyDynamics, QuadrupedSim, RobotDescription, SimConfig};

/// The robot stepped by rapier's own dynamics, whose mass matrices upstream
/// computes too (the tree dynamics, the default, assembles only the upper
/// triangle of the plain one).
fn rapier_sim() -> QuadrupedSim {
    let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
    let config = SimConfig {
        multibody: MultibodyDynamics::Rapier,
        ..SimConfig::default()
    };
    QuadrupedSim::new(&d, config).expect("sim")
}

fn compare(sim: &QuadrupedSim, what: &str) {
    let mb = sim.multibody().expect("the robot is one multibody");
    let bodies = &sim.world().bodies;
    let dt = sim.config().dt_s as f32;
    let (mut sparse, mut dense) = (mb.clone(), mb.clone());
    sparse.assemble_mass_matrices(dt, bodies, false);
    dense.assemble_mass_matrices(dt, bodies, true);
    for link in 0..mb.num_links() {
        assert_eq!(
            sparse.body_jacobian(link),
            dense.body_jacobian(link),
            "{what}: body jacobian of link {link}"
        );
    }
    let (s, d) = (sparse.mass_matrices(), dense.mass_matrices());
    for (a, b, name) in [(s.0, d.0, "mass matrix"), (s.1, d.1, "with Coriolis")] {
        assert_eq!(a.shape(), b.shape());
        assert_eq!(a.nrows(), 18, "six root and twelve leg coordinates");
        let scale = b.iter().fold(0.0f64, |m, v| m.max(f64::from(v.abs())));
        let worst = a
            .iter()
            .zip(b.iter())
            .fold(0.0f64, |m, (x, y)| m.max(f64::from((x - y).abs())));
        eprintln!("{what}, {name}: largest difference {worst:e} of entries up to {scale:e}");
        for (x, y) in a.iter().zip(b.iter()) {
            // rapier3d computes in f32 (resolution 1.2e-7 of an entry): the two
            // assemblies sum the same terms in another order. The differences
            // seen are at most 9.3e-10 with entries up to 1.6; the bound is
            // 1e-9 of the largest entry, as the issue asks, far inside f32's
            // rounding of sums of that size.
            let diff = f64::from((x - y).abs());
            assert!(
                diff <= 1e-9 * scale,
                "{what}, {name}: {x} vs {y} (largest entry {scale})"
            );
        }
    }
}

#[test]
fn the_patched_mass_matrix_equals_upstreams() {
    let mut sim = rapier_sim();
    sim.advance(0.5);
    compare(&sim, "standing");
    for (command, what) in [(300.0, "forwards"), (-300.0, "backwards"), (120.0, "slow")] {
        sim.set_command(command).expect("finite");
        for k in 0..5 {
            sim.advance(0.37);
            compare(&sim, &format!("{what}, sample {k}"));
        }
    }
}

/// `physics.multibody = tree`: the mass matrix by composite rigid bodies is
/// upstream's `J^T M J` up to f32 rounding (another algorithm, other sums),
/// and the factors along the tree solve with it as a dense LU does.
fn compare_tree(sim: &QuadrupedSim, what: &str) {
    let mb = sim.multibody().expect("the robot is one multibody");
    let bodies = &sim.world().bodies;
    let dt = sim.config().dt_s as f32;
    let (mut tree, mut dense) = (mb.clone(), mb.clone());
    tree.set_dynamics(rapier3d::dynamics::MultibodyDynamics::Tree);
    tree.assemble_mass_matrices(dt, bodies, false);
    dense.assemble_mass_matrices(dt, bodies, true);
    // The body jacobians, by one shift per column where upstream's take two.
    for link in 0..mb.num_links() {
        let (jt, jd) = (tree.body_jacobian(link), dense.body_jacobian(link));
        let err = (jt - jd).amax();
        assert!(
            err <= 1e-6 * jd.amax().max(1.0),
            "{what}: body jacobian of link {link}: {err} off"
        );
    }
    let (t, d) = (tree.mass_matrices().0, dense.mass_matrices().0);
    // Each entry against its row's and column's scale, sqrt(M_ii M_jj) (the
    // leg's entries are 1e-6 of the torso's): f32 resolves 1.2e-7 of it, and
    // the two sum the same physics in other orders and forms.
    let mut worst = 0.0f32;
    for i in 0..d.nrows() {
        for j in 0..d.ncols() {
            let scale = (d[(i, i)] * d[(j, j)]).sqrt();
            worst = worst.max((t[(i, j)] - d[(i, j)]).abs() / scale);
        }
    }
    eprintln!("{what}: largest difference {worst:e} of an entry's scale");
    assert!(worst <= 1e-5, "{what}: {worst}");
    // The factors' solves against a dense LU of upstream's matrix, for a
    // unit right-hand side at each coordinate.
    let lu = d.clone().lu();
    for k in 0..d.nrows() {
        let mut b = nalgebra::DVector::<f32>::zeros(d.nrows());
        b[k] = 1.0;
        let want = lu.solve(&b).expect("the mass matrix is invertible");
        let mut got = b.clone();
        assert!(
            tree.inv_augmented_mass().solve_mut(&mut got),
            "{what}: solved"
        );
        let size = want.amax();
        let err = (got - &want).amax();
        assert!(
            err <= 1e-3 * size,
            "{what}, coordinate {k}: {err} of {size}"
        );
    }
}

#[test]
fn the_tree_mass_matrix_and_its_factors_equal_upstreams_up_to_rounding() {
    let mut sim = rapier_sim();
    sim.advance(0.5);
    compare_tree(&sim, "standing");
    for (command, what) in [(300.0, "forwards"), (-300.0, "backwards"), (120.0, "slow")] {
        sim.set_command(command).expect("finite");
        for k in 0..5 {
            sim.advance(0.37);
            compare_tree(&sim, &format!("{what}, sample {k}"));
        }
    }
}
