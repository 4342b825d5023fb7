//! A fingerprint of the robot's physics: steps the default robot through 24 s
//! at six walk commands and hashes every torso pose and camera reading, bit for
//! bit. A change meant to leave the physics alone (a faster code path, a
//! refactor) must print the same lines before and after it.
//!
//! `cargo run --release --example fingerprint [-- --multibody NAME]`
//!
//! (`--multibody`: `physics.multibody`, the default's if not given.)
//!
//! The expected lines are `tests/fixtures/fingerprint.txt` (the default,
//! `physics.multibody = tree`; with `--multibody rapier`:
//! `tests/fixtures/fingerprint-rapier.txt`), and `.ci/run`
//! fails on any difference: a change that alters the physics updates that
//! file in the same commit and says so.

use clap::Parser;
use quadsim::{ERS7_URDF, MultibodyDynamics, QuadrupedSim, RobotDescription, SimConfig};

/// Hash 24 s of the default robot's poses and readings, bit for bit.
#[derive(Debug, Parser)]
struct Args {
    /// How the multibody is stepped (`physics.multibody`: tree, rapier); the default's if not given.
    #[arg(long, value_parser = MultibodyDynamics::parse)]
    multibody: Option<MultibodyDynamics>,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Args = scasm_testbed::args::parse();
    let description = RobotDescription::from_urdf_str(ERS7_URDF)?;
    let mut config = SimConfig::default();
    if let Some(multibody) = args.multibody {
        config.multibody = multibody;
    }
    let mut sim = QuadrupedSim::new(&description, config)?;
    let mut hash = 0u64;
    for (k, command) in [0.0, 300.0, -200.0, 120.0, -300.0, 50.0]
        .into_iter()
        .enumerate()
    {
        sim.set_command(command)?;
        for _ in 0..40 {
            sim.advance(0.1);
            let torso = sim.torso();
            for v in torso.position_m.iter().chain(&torso.orientation) {
                mix(&mut hash, v.to_bits());
            }
            if let Some(Ok(px)) = sim.take_frame().map(|f| f.obs_px) {
                mix(&mut hash, px.to_bits());
            }
        }
        let [x, y, z] = sim.torso().position_m;
        println!(
            "{k} command {command:6.1}: torso at ({x:.6}, {y:.6}, {z:.6}) m, fingerprint {hash:016x}"
        );
    }
    Ok(())
}

/// Folds `bits` into `hash` (splitmix64's finaliser: every bit of the input
/// reaches every bit of the output).
fn mix(hash: &mut u64, bits: u64) {
    let mut z = (*hash ^ bits).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    *hash = z ^ (z >> 31);
}
