// The motion the upstream fixture records, shared word for word by
// `tools/upstream-fixture` (rapier3d as published) and
// `tests/upstream_fixture.rs` (the patched rapier3d), which `include!` it.

/// Physics steps of each phase: the ERS-7 standing, then walking at 300,
/// then at -200 (4 ms steps: 0.5 s, 1.2 s and 0.8 s).
pub const PHASES: [(f64, usize); 3] = [(0.0, 125), (300.0, 300), (-200.0, 200)];

/// The torso's pose after every physics step of [`PHASES`]: position (m) and
/// orientation (quaternion x, y, z, w).
pub fn torso_track() -> Vec<[f64; 7]> {
    use quadsim::{ERS7_URDF, MultibodyDynamics, QuadrupedSim, RobotDescription, SimConfig};
    let description = RobotDescription::from_urdf_str(ERS7_URDF).expect("the ERS-7 parses");
    // rapier's own dynamics, the one rapier3d as published has.
    let config = SimConfig {
        multibody: MultibodyDynamics::Rapier,
        ..SimConfig::default()
    };
    let mut sim = QuadrupedSim::new(&description, config).expect("builds");
    let mut out = Vec::new();
    for (command, steps) in PHASES {
        sim.set_command(command).expect("finite");
        for _ in 0..steps {
            sim.step();
            let t = sim.torso();
            let [x, y, z] = t.position_m;
            let [qx, qy, qz, qw] = t.orientation;
            out.push([x, y, z, qx, qy, qz, qw]);
        }
    }
    out
}
