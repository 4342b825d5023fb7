//! Measures the simulated robot's true sensor model by the paper's protocol: the
//! robot stands at 1.2, 1.4, ..., 3.6 m from the beacon and takes 100 readings at
//! each. Prints the table and writes `measured_sensor.csv`; `--save-frame` also
//! writes a PNG of what the camera sees at each distance.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, ensure};
use clap::Parser;
use quadsim::{QuadrupedSim, RobotDescription, SimConfig};
use testbed::{measure, output};

/// Measure the beacon-height-to-distance curve of the simulated camera.
#[derive(Debug, Parser)]
struct Args {
    /// Directory for measured_sensor.csv (and frames).
    #[arg(long, default_value = ".")]
    out: PathBuf,
    /// Readings per distance.
    #[arg(long, default_value_t = 100)]
    readings: usize,
    /// Also save a PNG of the camera's view at each distance.
    #[arg(long)]
    save_frame: bool,
    #[command(flatten)]
    scenario: scasm_testbed::ScenarioArgs,
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

fn main() -> Result<()> {
    let args = Args::parse();
    ensure!(args.readings > 0, "--readings must be at least 1");
    let scenario = args.scenario.scenario()?;
    let (description, config) = (&scenario.description, scenario.sim);
    let distances = measure::paper_distances_m();
    let started = std::time::Instant::now();
    let table = measure::measure_sensor(description, config, &distances, args.readings)?;
    println!(
        "{:>12} {:>10} {:>8} {:>7}",
        "distance mm", "obs px", "std px", "missed"
    );
    for r in &table {
        println!(
            "{:>12.0} {:>10.2} {:>8.2} {:>7}",
            r.distance_mm, r.obs_px, r.std_px, r.missed
        );
    }
    println!("wall {:.1} s", started.elapsed().as_secs_f64());

    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let rows: Vec<_> = table
        .iter()
        .map(|r| (r.distance_mm, r.obs_px, r.std_px))
        .collect();
    output::write_measured_sensor(&args.out, &rows)?;
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
