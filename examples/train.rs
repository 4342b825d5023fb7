//! The paper's experiment on the simulated robot: trials of SCASM learning the
//! robot's action and sensor models at once, judged by the paper's protocol
//! against the models measured by stopwatch and by standing at marked distances.
//!
//! Writes a run directory with summary.json, the measured models, and per trial
//! its trace and learned models.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Context, Result, bail, ensure};
use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};
use testbed::experiment::{self, Figures, LearningMode};
use testbed::output;
use testbed::trial::TrialOutcome;

/// Run SCASM training trials on the simulated quadruped.
#[derive(Debug, Parser)]
struct Args {
    /// Number of trials (seeds 0..N); ignored if --seeds is given.
    #[arg(long, default_value_t = 15)]
    trials: u64,
    /// Seeds as a range A..B (B excluded).
    #[arg(long)]
    seeds: Option<String>,
    /// Trial length, s.
    #[arg(long)]
    duration: Option<f64>,
    /// The learner (only `scasm` so far).
    #[arg(long, default_value = "scasm")]
    learner: String,
    /// What is learned from what.
    #[arg(long, value_enum, default_value = "simultaneous")]
    mode: Mode,
    /// Run directory (default: runs/train-<unix time>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Where measured reference models are cached.
    #[arg(long, default_value = "runs/.cache")]
    cache: PathBuf,
    #[command(flatten)]
    scenario: scasm_testbed::ScenarioArgs,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum Mode {
    Simultaneous,
    SensorFromAction,
    ActionFromSensor,
}

fn parse_seeds(args: &Args) -> Result<Vec<u64>> {
    match &args.seeds {
        None => Ok((0..args.trials).collect()),
        Some(s) => {
            let (a, b) = s.split_once("..").context("--seeds must look like A..B")?;
            let (a, b): (u64, u64) = (a.trim().parse()?, b.trim().parse()?);
            ensure!(a < b, "--seeds {s} is empty");
            Ok((a..b).collect())
        }
    }
}

fn opt(v: Option<f64>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

fn write_trial(dir: &Path, outcome: &TrialOutcome) -> Result<()> {
    let dir = dir.join(format!("trial-{}", outcome.seed));
    std::fs::create_dir_all(&dir)?;
    output::write_csv(
        &dir.join("trace.csv"),
        "t,command,obs,x_true_mm,x_a,x_s",
        outcome.trace.iter().map(|r| {
            format!(
                "{},{},{},{},{},{}",
                r.t_s,
                r.command,
                opt(r.obs_px),
                r.x_true_mm,
                opt(r.x_a),
                opt(r.x_s)
            )
        }),
    )?;
    output::write_csv(
        &dir.join("errors_over_time.csv"),
        "t,action_rmse_mm_s,sensor_rmse_mm,consistency",
        outcome.over_time.iter().map(|j| {
            format!(
                "{},{},{},{}",
                j.t_s,
                opt(j.action_rmse_mm_s),
                opt(j.sensor_rmse_mm),
                opt(j.consistency)
            )
        }),
    )?;
    let models = serde_json::json!({
        "action": outcome.action_model.map(|p| p.coeffs().to_vec()),
        "sensor": outcome.sensor_model.map(|p| p.coeffs().to_vec()),
    });
    std::fs::write(
        dir.join("models.json"),
        serde_json::to_string_pretty(&models)?,
    )?;
    Ok(())
}

fn main() -> Result<()> {
    let args = Args::parse();
    if args.learner != "scasm" {
        bail!("unknown learner `{}`; available: scasm", args.learner);
    }
    let seeds = parse_seeds(&args)?;
    let mut scenario = args.scenario.scenario()?;
    if let Some(d) = args.duration {
        scenario.set(&format!("trial.duration={d}"))?;
    }
    scenario.mode = match args.mode {
        Mode::Simultaneous => LearningMode::Simultaneous,
        Mode::SensorFromAction => LearningMode::SensorFromAction,
        Mode::ActionFromSensor => LearningMode::ActionFromSensor,
    };
    let out = args.out.clone().unwrap_or_else(|| {
        let t = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_secs())
            .unwrap_or(0);
        PathBuf::from(format!("runs/train-{t}"))
    });
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let started = std::time::Instant::now();

    println!("Measuring the robot's true models (stopwatch and stand-and-read protocols)...");
    let models = experiment::measured_models(&scenario, Some(&args.cache))?;
    println!(
        "  {} (cache key {})",
        if models.from_cache {
            "read from cache"
        } else {
            "measured"
        },
        scenario.reference_key()
    );
    output::write_measured_action(&out, &models.action)?;
    output::write_measured_sensor(&out, &models.sensor)?;

    println!(
        "Running {} trials of {} s ({:?}, learner {}) on {} threads...",
        seeds.len(),
        scenario.duration_s,
        scenario.mode,
        args.learner,
        rayon::current_num_threads()
    );
    let bar = ProgressBar::new(seeds.len() as u64).with_style(
        ProgressStyle::with_template(
            "  [{elapsed_precise}] {bar:40} {pos}/{len} trials, eta {eta}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let write_errors = Mutex::new(Vec::new());
    let results = experiment::run_trials(&scenario, &models, &seeds, &|o| {
        if let Err(e) = write_trial(&out, o) {
            if let Ok(mut v) = write_errors.lock() {
                v.push(e.to_string());
            }
        }
        bar.inc(1);
    })?;
    bar.finish();
    if let Some(e) = write_errors.lock().ok().and_then(|v| v.first().cloned()) {
        bail!("writing a trial's files: {e}");
    }

    let best = experiment::best_possible(&models.reference(), &scenario.learner);
    let figures: Vec<Figures> = results.iter().map(|(o, _)| Figures::of(o, best)).collect();
    let (mean, std, paper) = (
        Figures::mean(&figures),
        Figures::std(&figures),
        Figures::paper(),
    );
    let fell: Vec<u64> = results
        .iter()
        .filter(|(o, _)| o.fell)
        .map(|(o, _)| o.seed)
        .collect();
    let trials: Vec<serde_json::Value> = results
        .iter()
        .zip(&figures)
        .map(|((o, _), f)| {
            let mut v = serde_json::to_value(f).unwrap_or_default();
            v["seed"] = o.seed.into();
            v["fell"] = o.fell.into();
            v
        })
        .collect();
    let summary = serde_json::json!({ "trials": trials, "mean": mean, "std": std, "paper": paper });
    std::fs::write(
        out.join("summary.json"),
        serde_json::to_string_pretty(&summary)?,
    )?;

    let velocity_range = models.action.iter().map(|a| a.1).fold(f64::MIN, f64::max)
        - models.action.iter().map(|a| a.1).fold(f64::MAX, f64::min);
    let distance_range = 2400.0;
    println!();
    println!(
        "{:<14} {:>24} {:>16} {:>12} {:>10}",
        "figure", "ours (mean +- std)", "paper", "best poly", "A0"
    );
    println!(
        "{:<14} {:>14.1} +- {:>5.1} {:>16} {:>12.1} {:>10.1}",
        "action mm/s",
        mean.action_rmse_mm_s,
        std.action_rmse_mm_s,
        "29.6",
        mean.action_best_rmse_mm_s,
        mean.action_a0_rmse_mm_s
    );
    println!(
        "{:<14} {:>14.1} +- {:>5.1} {:>16} {:>12.1}",
        "sensor mm",
        mean.sensor_rmse_mm,
        std.sensor_rmse_mm,
        "70.4 +- 13.9",
        mean.sensor_best_rmse_mm
    );
    println!(
        "{:<14} {:>14.3} +- {:>5.3} {:>16}",
        "consistency", mean.consistency, std.consistency, "0.08 +- 0.06"
    );
    println!(
        "\naction error {:.1} % of the {:.0} mm/s velocity range (paper 4.9 %); sensor error {:.1} % of the {:.0} mm distance range (paper 2.9 %)",
        100.0 * mean.action_rmse_mm_s / velocity_range,
        velocity_range,
        100.0 * mean.sensor_rmse_mm / distance_range,
        distance_range
    );
    println!(
        "learned / best possible: action {:.2}x, sensor {:.2}x",
        mean.action_rmse_mm_s / mean.action_best_rmse_mm_s,
        mean.sensor_rmse_mm / mean.sensor_best_rmse_mm
    );
    if !fell.is_empty() {
        println!("the robot tipped over in trials {fell:?}");
    }
    println!(
        "\n{} trials, mean {:.0}x real time per trial; whole run {:.1} s wall; results in {}",
        results.len(),
        mean.realtime_factor,
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}
