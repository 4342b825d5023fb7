//! Measures the simulated robot's true action model by the paper's stopwatch
//! protocol: every multiple of 20 in [-300, 300], each timed across a distance
//! five times. Prints the curve, the identity model's scaled error and the best
//! polynomials' errors, and writes `measured_action.csv`.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Parser;
use scasm::Polynomial;
use testbed::measure;
use testbed::{metrics, output};

/// Measure the true command-to-velocity curve of the simulated robot.
#[derive(Debug, Parser)]
pub struct Args {
    /// Directory for measured_action.csv.
    #[arg(long, default_value = ".")]
    out: PathBuf,
    #[command(flatten)]
    scenario: crate::ScenarioArgs,
}

/// Runs the command with its parsed flags.
pub fn main(args: Args) -> Result<()> {
    let scenario = args.scenario.scenario()?;
    crate::needs_rapier(&scenario, "measure_action")?;
    let (description, sim_config) = (&scenario.description, scenario.sim);
    let started = std::time::Instant::now();
    let commands = scenario.scale().paper_commands();
    let stopwatch = scenario.stopwatch();
    let measured = measure::measure_action(description, sim_config, &stopwatch, &commands)?;
    let wall = started.elapsed().as_secs_f64();

    println!(
        "{:>8} {:>14} {:>10} {:>10} {:>10} {:>8} {:>8}",
        "command", "velocity mm/s", "std mm/s", "min", "max", "upright", "blew up"
    );
    for m in &measured {
        println!(
            "{:>8.0} {:>14.1} {:>10.1} {:>10.1} {:>10.1} {:>8} {:>8}",
            m.command,
            m.velocity_mm_s,
            m.std_mm_s,
            m.min_mm_s(),
            m.max_mm_s(),
            m.upright,
            m.blew_up
        );
    }
    let points: Vec<(f64, f64)> = measured
        .iter()
        .map(|m| (m.command, m.velocity_mm_s))
        .collect();
    let range = points.iter().map(|p| p.1).fold(f64::MIN, f64::max)
        - points.iter().map(|p| p.1).fold(f64::MAX, f64::min);
    let a0 = metrics::action_error(&Polynomial::identity(), &points);
    let line = metrics::best_polynomial_rmse(&points, 1).unwrap_or(f64::NAN);
    let quartic = metrics::best_polynomial_rmse(&points, 4).unwrap_or(f64::NAN);
    let worst = measured.iter().map(|m| m.std_mm_s).fold(0.0, f64::max);
    let monotone = points.windows(2).all(|w| w[1].1 > w[0].1);
    println!(
        "\n{} timings of {:.2} m each after {:.1} s of walking at the command",
        stopwatch.repeats, stopwatch.distance_m, stopwatch.settle_s
    );
    println!(
        "largest std {worst:.1} mm/s (the paper's <= 7); velocity {} in the command",
        if monotone {
            "increases monotonically"
        } else {
            "is NOT monotone"
        }
    );
    println!("velocity range {range:.0} mm/s");
    println!(
        "identity model A0 after its best scale ({:.3}): RMSE {:.1} mm/s ({:.1} % of the range)",
        a0.scale,
        a0.rmse,
        100.0 * a0.rmse / range
    );
    println!("best line: RMSE {line:.1} mm/s; best quartic: RMSE {quartic:.1} mm/s");
    let g = &sim_config.walk.gait;
    println!(
        "gait periods: stepping in place {:.3} s, fast forwards {:.3} s, fast backwards {:.3} s",
        g.idle.period_s, g.fast_forwards.period_s, g.fast_backwards.period_s
    );
    println!(
        "wall {wall:.1} s for {} commands on {} threads",
        commands.len(),
        rayon::current_num_threads()
    );

    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    output::write_measured_action(&args.out, &measured)?;
    let path = args.out.join("measured_action.csv");
    println!("wrote {}", path.display());
    Ok(())
}
