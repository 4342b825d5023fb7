//! Runs a learner over recorded worlds, with no physics: any dataset a `train`
//! run wrote (its `trial-*` directories), or such a run directory whole. The
//! learner gets exactly the events it would have got live, so for the same
//! learner and settings the models are the live run's, bit for bit.
//!
//! `cargo run --release --example replay -- runs/train-X --learner batch-ml --out DIR`
//!
//! Writes DIR/config.toml, DIR/summary.json and, per dataset, DIR/trial-<seed>/
//! with the learner's trace.csv, errors_over_time.csv and models.json: the same
//! form as a `train` run.

use std::path::PathBuf;
use std::sync::Mutex;

use anyhow::{Context, Result, bail, ensure};
use clap::Parser;
use rayon::prelude::*;
use testbed::dataset::{self, Dataset};
use testbed::experiment;
use testbed::provenance::Provenance;
use testbed::scenario::Scenario;
use testbed::summary::RunSummary;
use testbed::{output, run_dir};

/// Replay recorded trials to a learner.
#[derive(Debug, Parser)]
pub struct Args {
    /// Datasets, or run directories holding trial-*/ datasets.
    #[arg(required_unless_present = "learner")]
    datasets: Vec<PathBuf>,
    /// The learner; `list` prints the available ones (default: the dataset's).
    #[arg(long)]
    learner: Option<String>,
    /// A learner setting as key=value on top of the dataset's (repeatable),
    /// e.g. learner.gamma=0.995.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Results directory (default: runs/replay-<unix time>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print the whole results table (about 230 columns), the measured
    /// models and the localisation table, as index.html and summary.json
    /// hold them; by default a headline that fits 100 columns.
    #[arg(long)]
    wide: bool,
    #[command(flatten)]
    rerun: crate::RerunArgs,
}

/// The scenario a dataset was recorded in, with `args`' learner settings on top.
fn scenario_of(dataset: &Dataset, args: &Args) -> Result<Scenario> {
    let mut scenario = Scenario::paper()?;
    scenario
        .apply_toml("dataset.json's scenario", &dataset.meta.scenario)
        .context("the dataset's scenario")?;
    for s in &args.set {
        ensure!(
            ["learner.", "exec."]
                .iter()
                .any(|p| s.trim_start().starts_with(p)),
            "`{s}`: a replay can change only learner settings (learner.*, exec.*); the world is \
             recorded"
        );
        scenario.set(s)?;
    }
    if let Some(name) = &args.learner {
        scenario.set(&format!("learner.name={name}"))?;
    }
    Ok(scenario)
}

/// Runs the command with its parsed flags.
pub fn main(args: Args) -> Result<()> {
    if crate::list_learners_if_asked(args.learner.as_deref()) {
        return Ok(());
    }
    args.rerun.check()?;
    let paths = dataset::find(&args.datasets)?;
    let datasets: Vec<Dataset> = paths
        .iter()
        .map(|p| dataset::read(p))
        .collect::<Result<_, _>>()?;
    let scenarios: Vec<Scenario> = datasets
        .iter()
        .map(|d| scenario_of(d, &args))
        .collect::<Result<_>>()?;
    let out = crate::create_run_dir(args.out.as_deref(), "replay")?;
    let made_by = Provenance::current();
    output::write_config(&out, &scenarios[0], &made_by)?;
    let learner = scenarios[0].learner_name.clone();
    println!(
        "Replaying {} recorded trials to learner {}...",
        datasets.len(),
        testbed::learners::display_name(&learner)
    );

    let started = std::time::Instant::now();
    let write_errors = Mutex::new(Vec::new());
    let results: Vec<_> = datasets
        .par_iter()
        .zip(&scenarios)
        .map(|(d, scenario)| {
            let run = experiment::learn_kept(
                scenario,
                &d.meta.reference,
                &d.recording,
                &learner,
                experiment::JUDGE_EVERY_S,
            );
            let dir = out.join(format!("trial-{}", d.meta.seed));
            let written =
                run_dir::write_learner_files(&dir, run.outcome.as_ref(), run.stderr.as_deref());
            if let Err(e) = written {
                if let Ok(mut v) = write_errors.lock() {
                    v.push(e.to_string());
                }
            }
            (d.meta.seed, run.outcome)
        })
        .collect();
    let wall_s = started.elapsed().as_secs_f64();
    if let Some(e) = write_errors.lock().ok().and_then(|v| v.first().cloned()) {
        bail!("writing a trial's files: {e}");
    }

    let models = &datasets[0].meta.reference;
    let run = RunSummary::of(
        results
            .iter()
            .map(|(seed, r)| (*seed, r.as_ref().map_err(|e| e.to_string()))),
        &scenarios[0],
        models,
    );
    output::write_json(&out.join("summary.json"), &run.json)?;
    let (rows, aggregate) = (&run.rows, &run.aggregate);
    print!(
        "{}",
        report::run::console(&run, models, &scenarios[0], args.wide)
    );
    let trials: Vec<crate::RunTrial> = datasets
        .iter()
        .zip(&scenarios)
        .zip(&results)
        .zip(rows)
        .filter_map(|(((d, scenario), (_, r)), row)| {
            Some(crate::RunTrial {
                scenario,
                models: &d.meta.reference,
                recording: &d.recording,
                outcome: r.as_ref().ok()?,
                row,
            })
        })
        .collect();
    args.rerun.write(&trials)?;
    println!(
        "learning took {wall_s:.2} s wall for {} trials ({:.0} s simulated) on {} threads\n\
         the learner {:.1} ms a trial (mean)\nresults in {}",
        rows.len(),
        datasets
            .iter()
            .filter_map(|d| d.recording.frames.last().map(|f| f.end_s()))
            .sum::<f64>(),
        rayon::current_num_threads(),
        1000.0 * aggregate.mean.learner_wall_s,
        out.display()
    );
    ensure!(
        aggregate.ok() > 0,
        "no trial finished ok: {}",
        aggregate.describe()
    );
    Ok(())
}
