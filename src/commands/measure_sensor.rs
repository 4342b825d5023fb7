//! Measures the simulated robot's true sensor model by the paper's protocol: the
//! robot stands at 1.2, 1.4, ..., 3.6 m from the beacon and takes 100 readings at
//! each, stepping in place at the command that does not creep (found from the
//! stopwatch protocol, cached like `train`'s reference). Each point is labelled
//! with the distance the robot actually held while reading. Prints the table and
//! writes `measured_sensor.csv`; `--save-frame` also writes a PNG of what the
//! camera sees at each distance.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, ensure};
use clap::Parser;
use quadsim::{QuadrupedSim, RobotDescription, SimConfig};
use testbed::{measure, output, reference};

/// Measure the beacon-height-to-distance curve of the simulated camera.
#[derive(Debug, Parser)]
pub struct Args {
    /// Directory for measured_sensor.csv (and frames).
    #[arg(long, default_value = ".")]
    out: PathBuf,
    /// Readings per distance.
    #[arg(long, default_value_t = 100)]
    readings: usize,
    /// Also save a PNG of the camera's view at each distance.
    #[arg(long)]
    save_frame: bool,
    /// Where measured reference models are cached (for the hold command).
    #[arg(long, default_value = "runs/.cache")]
    cache: PathBuf,
    #[command(flatten)]
    scenario: crate::ScenarioArgs,
}

fn save_frame(
    description: &RobotDescription,
    config: SimConfig,
    distance_m: f64,
    path: &Path,
) -> Result<()> {
    let mut sim = QuadrupedSim::new(
        description,
        SimConfig {
            start_distance_m: distance_m,
            ..config
        },
    )?;
    sim.advance(1.0);
    let intr = config.camera.intrinsics;
    // Each camera pixel as a 3 x 3 block, so a person can see it.
    let (big, size) = report::upscale_rgb(&sim.camera_image(), (intr.width_px, intr.height_px), 3);
    report::write_png(path, &big, size)?;
    Ok(())
}

/// Runs the command with its parsed flags.
pub fn main(args: Args) -> Result<()> {
    ensure!(args.readings > 0, "--readings must be at least 1");
    let scenario = args.scenario.scenario()?;
    crate::needs_rapier(&scenario, "measure_sensor")?;
    let (description, config) = (&scenario.description, scenario.sim);
    let distances = measure::paper_distances_m(scenario.scale());
    let started = std::time::Instant::now();
    // As measured, unchecked: this tool is where an unseen beacon is looked into.
    let action = reference::measured_world(&scenario.world(0)?, Some(&args.cache))?.action;
    let hold = measure::hold_command(&action);
    println!("stepping in place at command {hold:.1}, where the measured velocity is zero");
    let table = measure::measure_sensor(description, config, &distances, args.readings, hold)?;
    println!(
        "{:>10} {:>12} {:>9} {:>10} {:>8} {:>7}",
        "put at mm", "actual mm", "+- mm", "obs px", "std px", "missed"
    );
    for r in &table {
        println!(
            "{:>10.0} {:>12.1} {:>9.1} {:>10.2} {:>8.2} {:>7}",
            r.nominal_mm, r.distance_mm, r.distance_std_mm, r.obs_px, r.std_px, r.missed
        );
    }
    let worst = table.iter().map(|r| r.std_px).fold(0.0, f64::max);
    println!(
        "each point is labelled by the distance the robot actually held while reading \
         (ground truth at each reading, averaged); largest reading std {worst:.2} px (the paper's <= 1.1)"
    );
    println!("wall {:.1} s", started.elapsed().as_secs_f64());

    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    output::write_measured_sensor(&args.out, &table)?;
    let path = args.out.join("measured_sensor.csv");
    println!("wrote {}", path.display());
    if args.save_frame {
        for &d in &distances {
            let p = args.out.join(format!("frame-{:04.0}mm.png", 1000.0 * d));
            save_frame(description, config, d, &p)?;
            println!("wrote {}", p.display());
        }
    }
    Ok(())
}
