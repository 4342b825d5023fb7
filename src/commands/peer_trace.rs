//! The robot's motion for a peer simulator, and this build's own step time on
//! it: the robot stands for 0.5 s and then walks at `--command` for the rest of
//! `--seconds`, towards the beacon but starting far enough from it that it
//! touches nothing but the floor (the peer's world has nothing else). Every physics step's servo targets go to DIR/targets.csv, and
//! what a peer needs to build the same robot goes to DIR/peer.json: the URDF,
//! the time step, the servo gains and torque limits, the joints in order, the
//! start, and this build's full step (servos, walk engine and 20 Hz camera
//! included) in microseconds, the best of `--repeats` runs, with its contact
//! points per step. Only the steps are timed: building the robot and its world
//! is not, as the peer's model compilation is not.
//!
//! `scripts/peer/compare.sh` runs this and then MuJoCo on the same targets;
//! `scripts/peer/response.sh` does so at each command, for the response.
//!
//! `cargo run --release --example peer_trace -- --robot trotter --out target/peer`

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Result, bail};
use clap::Parser;
use quadsim::{MultibodyDynamics, QuadrupedSim, RobotDescription, RobotFile, SimConfig};

/// Record a walk's servo targets for a peer simulator, and time this build on it.
#[derive(Debug, Parser)]
pub struct Args {
    /// A shipped robot's name or a robot file's path (default: the ERS-7).
    #[arg(long)]
    robot: Option<String>,
    /// The walk command after the first 0.5 s.
    #[arg(long, default_value_t = 300.0)]
    command: f64,
    /// Simulated seconds.
    #[arg(long, default_value_t = 10.0)]
    seconds: f64,
    /// Timed runs; the best is reported.
    #[arg(long, default_value_t = 5)]
    repeats: usize,
    /// Output directory.
    #[arg(long, default_value = "target/peer")]
    out: PathBuf,
}

/// The robot, its world, its URDF's text, and its MJCF file if it was read
/// from one (for the peer to load the file itself).
type Robot = (RobotDescription, SimConfig, String, Option<PathBuf>);

fn robot(name: Option<&str>) -> Result<Robot> {
    match name {
        None => Ok((
            RobotDescription::from_urdf_str(quadsim::ERS7_URDF)?,
            SimConfig::default(),
            quadsim::ERS7_URDF.to_string(),
            None,
        )),
        Some(name) => {
            let file = RobotFile::load(name)?;
            // Its meshes found from wherever the copy is read.
            let text = file.urdf_text_elsewhere()?;
            let mjcf = match &file.path {
                Some(p) if quadsim::mjcf::is_mjcf(&std::fs::read_to_string(p)?) => {
                    Some(std::path::absolute(p)?)
                }
                _ => None,
            };
            Ok((file.description.clone(), file.sim_config(), text, mjcf))
        }
    }
}

/// How far short of the beacon's axis the torso's walk ends, at least, m.
const SHORT_OF_THE_BEACON_M: f64 = 0.6;

/// `config` with the robot starting far enough from the beacon that its walk
/// ends short of it: the peer's world has only the floor, and a robot pushing
/// against the beacon's pole would not be the same motion (nor the same
/// work: an extra contact). How far the walk goes is measured by a first,
/// untimed walk from well beyond its reach; the distance is never less than
/// the configured one.
fn clear_of_the_beacon(d: &RobotDescription, config: SimConfig, args: &Args) -> Result<SimConfig> {
    let reach_m = 2.0 * args.command.abs() / 1000.0 * args.seconds;
    let far = SimConfig {
        start_distance_m: config.start_distance_m + reach_m + SHORT_OF_THE_BEACON_M,
        ..config
    };
    let (mut first_x, mut end_x) = (None, 0.0);
    run(d, far, args, |sim| {
        end_x = sim.torso().position_m[0];
        first_x.get_or_insert(end_x);
    })?;
    let travelled_m = (end_x - first_x.unwrap_or(end_x)).max(0.0);
    Ok(SimConfig {
        start_distance_m: config
            .start_distance_m
            .max(SHORT_OF_THE_BEACON_M + 1.2 * travelled_m),
        ..config
    })
}

/// Runs the motion from a fresh robot; calls `each` after every step.
/// Returns the wall time of the steps alone, s: building the robot and its
/// world is not timed, as the peer's model compilation is not.
fn run(
    d: &RobotDescription,
    config: SimConfig,
    args: &Args,
    mut each: impl FnMut(&QuadrupedSim),
) -> Result<f64> {
    let mut sim = QuadrupedSim::new(d, config)?;
    let steps = (args.seconds / config.dt_s).round() as usize;
    let stand = (0.5 / config.dt_s).round() as usize;
    let started = Instant::now();
    for k in 0..steps {
        if k == stand {
            sim.set_command(args.command)?;
        }
        sim.step();
        each(&sim);
    }
    Ok(started.elapsed().as_secs_f64())
}

/// Runs the command with its parsed flags.
pub fn main(args: Args) -> Result<()> {
    let (d, config, urdf_text, mjcf) = robot(args.robot.as_deref())?;
    let config = clear_of_the_beacon(&d, config, &args)?;
    std::fs::create_dir_all(&args.out)?;
    let urdf = args.out.join("robot.urdf");
    std::fs::write(&urdf, &urdf_text)?;
    let start = QuadrupedSim::new(&d, config)?;
    let (torso, first_targets) = (start.torso(), start.servo_targets());

    // The motion, recorded.
    let mut targets = std::io::BufWriter::new(std::fs::File::create(args.out.join("targets.csv"))?);
    let (mut contacts, mut steps, mut upright, mut end_x) = (0usize, 0usize, true, 0.0);
    let mut off_floor = 0;
    // Where the torso is halfway through the walk: the speed over the second
    // half is the gait's, its start from standing over.
    let total = (args.seconds / config.dt_s).round() as usize;
    let half = total - (total - (0.5 / config.dt_s).round() as usize) / 2;
    let mut half_x = 0.0;
    run(&d, config, &args, |sim| {
        end_x = sim.torso().position_m[0];
        if steps + 1 == half {
            half_x = end_x;
        }
        let row: Vec<String> = sim.servo_targets().iter().map(|t| t.to_string()).collect();
        let _ = writeln!(targets, "{}", row.join(","));
        contacts += sim.contact_points();
        off_floor += sim.contact_points_off_floor();
        steps += 1;
        upright &= sim.is_upright();
    })?;
    targets.flush()?;
    if off_floor > 0 {
        bail!(
            "the robot touched something besides the floor ({off_floor} contact points over the \
             walk, starting {:.2} m from the beacon): the peer's world has only the floor, so the \
             two would not simulate the same motion; try a shorter --seconds",
            config.start_distance_m
        );
    }

    // The same motion, timed, with each `physics.multibody` (the robot's own first).
    let mut timed = Vec::new();
    let mut order = vec![config.multibody];
    order.extend(
        MultibodyDynamics::NAMES
            .iter()
            .filter_map(|n| MultibodyDynamics::parse(n).ok())
            .filter(|m| *m != config.multibody),
    );
    for multibody in order {
        let config = SimConfig {
            multibody,
            ..config
        };
        let mut best = f64::INFINITY;
        for _ in 0..args.repeats.max(1) {
            best = best.min(run(&d, config, &args, |_| {})?);
        }
        timed.push((multibody.as_str(), 1e6 * best / steps as f64));
    }
    let us_per_step = timed[0].1;
    let joints: Vec<&str> = d
        .legs
        .iter()
        .flat_map(|l| l.joints.iter().map(String::as_str))
        .collect();
    // The servos' torque limits as the simulator reads them (none, written
    // null, for a continuous joint whose URDF gives none).
    let effort: Vec<Option<f64>> = d
        .legs
        .iter()
        .flat_map(|l| l.effort_nm)
        .map(|e| Some(e * config.servo.torque_scale).filter(|e| e.is_finite()))
        .collect();
    let peer = serde_json::json!({
        "urdf": "robot.urdf",
        "root_link": d.root_link,
        "dt_s": config.dt_s,
        "seconds": args.seconds,
        "command": args.command,
        "kp_nm_per_rad": config.servo.kp_nm_per_rad,
        "kd_nm_s_per_rad": config.servo.kd_nm_s_per_rad,
        "effort_nm": effort,
        "friction": config.friction,
        "joints": joints,
        "start_position_m": torso.position_m,
        "start_beacon_distance_m": config.start_distance_m,
        "start_orientation_xyzw": torso.orientation,
        "start_joints_rad": first_targets,
        "steps": steps,
        "upright": upright,
        "travelled_m": end_x - torso.position_m[0],
        "half_step": half,
        "second_half_mm_s": 1000.0 * (end_x - half_x) / ((steps - half) as f64 * config.dt_s),
        "mjcf": mjcf,
        "multibody": timed[0].0,
        "us_per_step": us_per_step,
        "us_per_step_by_multibody": timed.iter().cloned().collect::<std::collections::BTreeMap<_, _>>(),
        "contacts_per_step": contacts as f64 / steps as f64,
    });
    std::fs::write(
        args.out.join("peer.json"),
        serde_json::to_string_pretty(&peer)?,
    )?;
    for (name, us) in &timed[1..] {
        println!("this build with physics.multibody = {name}: {us:.1} us per full step");
    }
    println!(
        "this build ({}): {us_per_step:.1} us per full step (best of {}), {:.0}x real time, {:.2} \
         contact points per step, {steps} steps, upright {upright}, walked {:.2} m; motion in {}",
        timed[0].0,
        args.repeats,
        config.dt_s * 1e6 / us_per_step,
        contacts as f64 / steps as f64,
        end_x - torso.position_m[0],
        args.out.display()
    );
    Ok(())
}
