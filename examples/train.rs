//! The paper's experiment on the simulated robot: trials of a calibration
//! learner (SCASM by default) learning the robot's action and sensor models at
//! once, judged by the paper's protocol against the models measured by
//! stopwatch and by standing at marked distances.
//!
//! Writes a run directory: config.toml (every setting, to run it again),
//! summary.json, the measured models, per trial its dataset (the recorded
//! world, replayable by `replay`) and its learner's trace and models, the
//! section IV and V demonstrations, the paper's figures as PNG and SVG, and
//! index.html showing them beside the results table.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Result, bail, ensure};
use clap::Parser;
use report::page::Page;
use scasm_testbed::{RerunArgs, RunTrial, ScenarioArgs, TrialArgs};
use testbed::dataset::{self, DatasetMeta};
use testbed::demos::{Demos, run_demos};
use testbed::experiment;
use testbed::output;
use testbed::provenance::Provenance;
use testbed::reference::{self, MeasuredModels};
use testbed::scenario::Scenario;
use testbed::summary::RunSummary;
use testbed::trial::{Recording, TrialOutcome};

/// Run calibration trials on the simulated quadruped (the paper's experiment).
#[derive(Debug, Parser)]
struct Args {
    #[command(flatten)]
    trials: TrialArgs,
    /// Run directory (default: runs/train-<unix time>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Where measured reference models are cached.
    #[arg(long, default_value = "runs/.cache")]
    cache: PathBuf,
    #[command(flatten)]
    scenario: ScenarioArgs,
    #[command(flatten)]
    rerun: RerunArgs,
}

/// A trial's directory: its dataset and its learner's files.
fn write_trial(
    out: &Path,
    scenario: &Scenario,
    models: &MeasuredModels,
    made_by: &Provenance,
    (recording, outcome): &(Recording, TrialOutcome),
) -> std::io::Result<()> {
    let dir = out.join(format!("trial-{}", recording.seed));
    dataset::write(
        &dir,
        recording,
        &DatasetMeta::new(scenario, models, recording, made_by),
    )?;
    output::write_learner_run(&dir, outcome)
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
        output::write_models(&dir.join(format!("{name}.json")), run.action, run.sensor)?;
    }
    Ok(())
}

fn main() -> Result<()> {
    let args = Args::parse();
    if scasm_testbed::list_learners_if_asked(args.trials.learner.as_deref())
        || scasm_testbed::list_settings_if_asked(&args.scenario.set)
    {
        return Ok(());
    }
    args.rerun.check()?;
    let scenario = args.scenario.scenario_with(&args.trials.settings())?;
    let seeds: Vec<u64> = (scenario.seeds.0..scenario.seeds.1).collect();
    let out = scasm_testbed::create_run_dir(args.out.as_deref(), "train")?;
    let made_by = Provenance::current();
    output::write_config(&out, &scenario, &made_by)?;
    let started = std::time::Instant::now();

    println!("Measuring the robot's true models (stopwatch and stand-and-read protocols)...");
    let models = reference::measured_models(&scenario, Some(&args.cache))?;
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
    for (i, changed) in models.changes.iter().enumerate() {
        let dir = out.join(format!("world-{}", i + 1));
        std::fs::create_dir_all(&dir)?;
        output::write_measured_action(&dir, &changed.models.action)?;
        output::write_measured_sensor(&dir, &changed.models.sensor)?;
    }

    println!(
        "Running {} trials of {:.0} s ({:?}, learner {}) on {} threads...",
        seeds.len(),
        scenario.duration_s,
        scenario.mode,
        scenario.learner_name,
        rayon::current_num_threads()
    );
    let bar = scasm_testbed::progress_bar(seeds.len() as u64, "trials");
    let write_errors = Mutex::new(Vec::new());
    let results = experiment::run_trials(&scenario, &models, &seeds, &|_, done| {
        if let Some(e) = done.and_then(|d| write_trial(&out, &scenario, &models, &made_by, d).err())
        {
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
    let run = RunSummary::of(
        results
            .iter()
            .map(|(seed, r)| (*seed, r.as_ref().map(|(_, o)| o).map_err(|e| e.to_string()))),
        &scenario,
        &models,
    );
    output::write_json(&out.join("summary.json"), &run.json)?;
    let (rows, best, aggregate) = (&run.rows, run.best, &run.aggregate);
    ensure!(
        aggregate.ok() > 0,
        "no trial finished ok: {}",
        aggregate.describe()
    );
    // The final figures are judged in the world as it ends.
    let (header, table) = report::table::results_table(aggregate, models.last());
    println!("\n{}", report::table::text(&header, &table));
    println!("{}", aggregate.describe());
    println!("{}", models.describe(&scenario.stopwatch()));
    println!("\n{}", aggregate.describe_localisation());
    if let Some(text) = aggregate.describe_recovery(&scenario.changes_text()) {
        println!("\n{text}");
    }

    let trials: Vec<RunTrial> = results
        .iter()
        .zip(rows)
        .filter_map(|((_, r), row)| {
            let (recording, outcome) = r.as_ref().ok()?;
            Some(RunTrial {
                scenario: &scenario,
                models: &models,
                recording,
                outcome,
                row,
            })
        })
        .collect();
    args.rerun.write(&trials)?;

    println!("\nRunning the section IV and V demonstrations (Figs. 2a, 2b, 3)...");
    let demos = run_demos(&scenario, &models, seeds[0])?;
    write_demos(&out, &demos)?;
    let outcomes: Vec<TrialOutcome> = results
        .into_iter()
        .zip(rows)
        .filter(|(_, row)| row.1.is_ok())
        .filter_map(|((_, r), _)| r.ok().map(|(_, o)| o))
        .collect();
    let data = report::paper::RunData {
        measured: models.last(),
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
        title: "Self-calibration on the simulated quadruped".into(),
        paragraphs: vec![
            format!(
                "{} trials of {:.0} s (seeds {}..{}), learner {}, mode {:?}. Each figure links to its SVG.",
                rows.len(),
                scenario.duration_s,
                scenario.seeds.0,
                scenario.seeds.1,
                scenario.learner_name,
                scenario.mode
            ),
            format!(
                "{}; the means and figures are over the ok trials.",
                aggregate.describe()
            ),
            format!(
                "The {} (cache key {}).",
                models.describe(&scenario.stopwatch()),
                scenario.reference_key()
            ),
            format!("Made by {}.", made_by.describe()),
        ],
        header,
        rows: table,
        figures: figures
            .iter()
            .map(|f| {
                (
                    f.stem.to_string(),
                    report::paper::caption(f.stem).to_string(),
                )
            })
            .collect(),
    };
    page.write(&out.join("index.html"))?;
    println!(
        "  {} figures (PNG and SVG) and index.html written",
        figures.len()
    );

    println!(
        "\n{} trials, mean {:.0}x real time per trial; whole run {:.1} s wall; results in {}",
        rows.len(),
        aggregate.mean.realtime_factor,
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}
