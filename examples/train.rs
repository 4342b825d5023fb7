//! The paper's experiment on the simulated robot: trials of SCASM learning the
//! robot's action and sensor models at once, judged by the paper's protocol
//! against the models measured by stopwatch and by standing at marked distances.
//!
//! Writes a run directory with summary.json, the measured models, per trial its
//! trace and learned models, the section IV and V demonstrations, the paper's
//! figures as PNG and SVG, and index.html showing them beside the results table.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Context, Result, bail, ensure};
use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};
use report::page::Page;
use scasm::Polynomial;
use testbed::demos::{Demos, run_demos};
use testbed::experiment;
use testbed::output;
use testbed::scenario::LearningMode;
use testbed::summary::{self, Aggregate, Figures, TrialStatus};
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

fn write_models(path: &Path, action: Option<Polynomial>, sensor: Option<Polynomial>) -> Result<()> {
    let models = serde_json::json!({
        "action": action.map(|p| p.coeffs().to_vec()),
        "sensor": sensor.map(|p| p.coeffs().to_vec()),
    });
    std::fs::write(path, serde_json::to_string_pretty(&models)?)?;
    Ok(())
}

fn write_trial(dir: &Path, outcome: &TrialOutcome) -> Result<()> {
    let dir = dir.join(format!("trial-{}", outcome.seed));
    std::fs::create_dir_all(&dir)?;
    output::write_trace(&dir.join("trace.csv"), &outcome.trace)?;
    output::write_errors_over_time(&dir.join("errors_over_time.csv"), &outcome.over_time)?;
    write_models(
        &dir.join("models.json"),
        outcome.action_model,
        outcome.sensor_model,
    )
}

fn write_demos(dir: &Path, demos: &Demos) -> Result<()> {
    let dir = dir.join("demos");
    std::fs::create_dir_all(&dir)?;
    for (name, run) in [
        ("constant_walk", &demos.constant_walk),
        ("sensor_from_a0", &demos.sensor_from_a0),
        ("action_from_rough_sensor", &demos.action_from_rough_sensor),
    ] {
        output::write_trace(&dir.join(format!("{name}.csv")), &run.trace)?;
        write_models(&dir.join(format!("{name}.json")), run.action, run.sensor)?;
    }
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
    let models = testbed::reference::measured_models(&scenario, Some(&args.cache))?;
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
    let results = experiment::run_trials(&scenario, &models, &seeds, &|_, outcome| {
        if let Some(e) = outcome.and_then(|o| write_trial(&out, o).err()) {
            if let Ok(mut v) = write_errors.lock() {
                v.push(e.to_string());
            }
        }
        bar.inc(1);
    });
    bar.finish();
    if let Some(e) = write_errors.lock().ok().and_then(|v| v.first().cloned()) {
        bail!("writing a trial's files: {e}");
    }

    // Every trial gets a status; only the ok ones enter the means and figures,
    // and the others are counted and named wherever the means are shown.
    let best = summary::best_possible(&models.reference(), &scenario.learner);
    let per_trial: Vec<(u64, TrialStatus, Figures)> = results
        .iter()
        .map(|(seed, r)| match r {
            Ok((o, _)) => (*seed, TrialStatus::of(o), Figures::of(o, best)),
            Err(e) => (
                *seed,
                TrialStatus::Error(e.to_string()),
                Figures::filled(f64::NAN),
            ),
        })
        .collect();
    let aggregate = Aggregate::of(&per_trial);
    let (mean, std, paper) = (aggregate.mean, aggregate.std, Figures::paper());
    let trials: Vec<serde_json::Value> = per_trial
        .iter()
        .map(|(seed, status, f)| {
            let mut v = serde_json::to_value(f).unwrap_or_default();
            v["seed"] = (*seed).into();
            v["status"] = status.to_string().into();
            v
        })
        .collect();
    let summary = serde_json::json!({
        "trials": trials,
        "trials_ok": aggregate.ok(),
        "trials_failed": aggregate.failed_json(),
        "mean": mean,
        "std": std,
        "paper": paper,
        "reference": models.describe(),
    });
    std::fs::write(
        out.join("summary.json"),
        serde_json::to_string_pretty(&summary)?,
    )?;
    ensure!(
        aggregate.ok() > 0,
        "no trial finished ok: {}",
        aggregate.describe()
    );

    let (velocity_range, distance_range) =
        (models.velocity_range_mm_s(), models.distance_range_mm());
    let (header, rows) = results_table(&mean, &std, velocity_range, distance_range);
    println!();
    print_table(&header, &rows);
    println!("{}", aggregate.describe());
    println!("{}", models.describe());

    println!("\nRunning the section IV and V demonstrations (Figs. 2a, 2b, 3)...");
    let demos = run_demos(&scenario, &models, seeds[0])?;
    write_demos(&out, &demos)?;
    let outcomes: Vec<TrialOutcome> = results
        .into_iter()
        .zip(&per_trial)
        .filter(|(_, row)| row.1.is_ok())
        .filter_map(|((_, r), _)| r.ok().map(|(o, _)| o))
        .collect();
    let data = report::paper::RunData {
        measured: &models,
        trials: &outcomes,
        demos: &demos,
        best: (best.0, best.1),
        degrees: (
            scenario.learner.action_degree,
            scenario.learner.sensor_degree,
        ),
    };
    let figures = report::paper::write_figures(&out, &data)?;
    let page = Page {
        title: "SCASM on the simulated quadruped".into(),
        paragraphs: vec![
            format!(
                "{} trials of {} s (seeds {}..{}), learner {}, mode {:?}. Each figure links to its SVG.",
                per_trial.len(),
                scenario.duration_s,
                seeds[0],
                seeds[seeds.len() - 1] + 1,
                args.learner,
                scenario.mode
            ),
            format!(
                "{}; the means and figures are over the ok trials.",
                aggregate.describe()
            ),
            format!(
                "The {} (cache key {}).",
                models.describe(),
                scenario.reference_key()
            ),
        ],
        header,
        rows,
        figures: figures
            .iter()
            .map(|f| (f.stem.to_string(), caption(f.stem).to_string()))
            .collect(),
    };
    page.write(&out.join("index.html"))?;
    println!(
        "  {} figures (PNG and SVG) and index.html written",
        figures.len()
    );

    println!(
        "\n{} trials, mean {:.0}x real time per trial; whole run {:.1} s wall; results in {}",
        per_trial.len(),
        mean.realtime_factor,
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}

/// The results beside the paper's, as rows of text (for the console and the page).
fn results_table(
    mean: &Figures,
    std: &Figures,
    velocity_range: f64,
    distance_range: f64,
) -> (Vec<String>, Vec<Vec<String>>) {
    let header = [
        "figure",
        "learned / best poly (ours / paper)",
        "ours (mean +- std)",
        "paper",
        "best poly (ours / paper)",
        "A0 (ours / paper)",
    ]
    .map(String::from)
    .to_vec();
    let paper = Figures::paper();
    let ours = |m: f64, s: f64, range: f64| {
        format!(
            "{m:.1} +- {s:.1} ({:.1} % of {range:.0})",
            100.0 * m / range
        )
    };
    let pair = |a: f64, b: f64| format!("{a:.1} / {b:.1}");
    let ratio = |a: f64, best_a: f64, b: f64, best_b: f64| {
        format!("{:.2}x / {:.2}x", a / best_a, b / best_b)
    };
    let rows = vec![
        vec![
            "action RMSE (mm/s)".into(),
            ratio(
                mean.action_rmse_mm_s,
                mean.action_best_rmse_mm_s,
                paper.action_rmse_mm_s,
                paper.action_best_rmse_mm_s,
            ),
            ours(mean.action_rmse_mm_s, std.action_rmse_mm_s, velocity_range),
            format!("{:.1} (4.9 % of 600)", paper.action_rmse_mm_s),
            pair(mean.action_best_rmse_mm_s, paper.action_best_rmse_mm_s),
            pair(mean.action_a0_rmse_mm_s, paper.action_a0_rmse_mm_s),
        ],
        vec![
            "sensor RMSE (mm)".into(),
            ratio(
                mean.sensor_rmse_mm,
                mean.sensor_best_rmse_mm,
                paper.sensor_rmse_mm,
                paper.sensor_best_rmse_mm,
            ),
            ours(mean.sensor_rmse_mm, std.sensor_rmse_mm, distance_range),
            format!("{:.1} +- 13.9 (2.9 % of 2400)", paper.sensor_rmse_mm),
            pair(mean.sensor_best_rmse_mm, paper.sensor_best_rmse_mm),
            "-".into(),
        ],
        vec![
            "consistency".into(),
            "-".into(),
            format!("{:.3} +- {:.3}", mean.consistency, std.consistency),
            format!("{:.2} +- 0.06", paper.consistency),
            "-".into(),
            "-".into(),
        ],
    ];
    (header, rows)
}

fn print_table(header: &[String], rows: &[Vec<String>]) {
    let widths: Vec<usize> = (0..header.len())
        .map(|c| {
            std::iter::once(header)
                .chain(rows.iter().map(Vec::as_slice))
                .map(|r| r.get(c).map_or(0, |s| s.chars().count()))
                .max()
                .unwrap_or(0)
        })
        .collect();
    for row in std::iter::once(header).chain(rows.iter().map(Vec::as_slice)) {
        let cells: Vec<String> = row
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(i, (c, &w))| {
                if i == 0 {
                    format!("{c:<w$}")
                } else {
                    format!("{c:>w$}")
                }
            })
            .collect();
        println!("{}", cells.join("  "));
    }
}

/// What each figure shows (the page's captions).
fn caption(stem: &str) -> &'static str {
    match stem {
        "fig2a" => {
            "Fig. 2a. Readings against time while walking forwards at one constant command, with the best-fit cubic of time on reading: a sensor model in seconds of this walk (section IV)."
        }
        "fig2b" => {
            "Fig. 2b. Readings against x_a dead-reckoned by the identity action model A0 over one cycle (+ forwards, x backwards), with the cubic fitted to all of them. A0 is wrong, so forwards and backwards disagree; the cubic still has the right shape."
        }
        "fig3" => {
            "Fig. 3. x_s = S(obs) by the rough S of Fig. 2a over one cycle, with the piecewise-linear path of the action model learned from it: slope A(C(t)), x(0) from the fit (section V)."
        }
        "fig6" => {
            "Fig. 6. x_s (+) and x_a (line) over the typical trial (median final sensor error) while both models learn: they come into agreement."
        }
        "fig7a" => {
            "Fig. 7a. Measured velocity per command (stopwatch protocol, +- 1 std) and the typical trial's learned action model after its best scale."
        }
        "fig7b" => {
            "Fig. 7b. Measured distance per reading (stand-and-read protocol) and the typical trial's learned sensor model after its best affine map."
        }
        "fig8" => {
            "Fig. 8. Errors of the learned models every 5 s, mean and std over the trials, with the best possible polynomial of each model's degree (dashed)."
        }
        _ => "",
    }
}
