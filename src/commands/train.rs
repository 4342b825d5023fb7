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

use std::path::PathBuf;
use std::sync::Mutex;

use crate::{RerunArgs, RunTrial, ScenarioArgs, TrialArgs};
use anyhow::{Result, bail, ensure};
use clap::Parser;
use testbed::demos::run_demos;
use testbed::provenance::Provenance;
use testbed::summary::RunSummary;
use testbed::trial::TrialOutcome;
use testbed::{experiment, learners, output, reference, run_dir};

/// Run calibration trials on the simulated quadruped (the paper's experiment).
#[derive(Debug, Parser)]
pub struct Args {
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
    /// Print the whole results table (about 230 columns), the measured
    /// models and the localisation table, as index.html and summary.json
    /// hold them; by default a headline that fits 100 columns.
    #[arg(long)]
    wide: bool,
    #[command(flatten)]
    rerun: RerunArgs,
}

/// Runs the command with its parsed flags.
pub fn main(args: Args) -> Result<()> {
    if crate::list_learners_if_asked(args.trials.learner.as_deref())
        || crate::list_behaviours_if_asked(args.trials.behaviour.as_deref())
        || crate::list_settings_if_asked(&args.scenario.set, args.trials.learner.as_deref())
    {
        return Ok(());
    }
    args.rerun.check()?;
    let scenario = args.scenario.scenario_with(&args.trials.settings())?;
    let seeds: Vec<u64> = (scenario.seeds.0..scenario.seeds.1).collect();
    let out = crate::create_run_dir(args.out.as_deref(), "train")?;
    let made_by = Provenance::current();
    output::write_config(&out, &scenario, &made_by)?;
    let started = std::time::Instant::now();

    println!(
        "{}",
        match scenario.world {
            testbed::world::WorldKind::Rapier =>
                "Measuring the robot's true models (stopwatch and stand-and-read protocols)...",
            testbed::world::WorldKind::Synthetic =>
                "The synthetic world's true models (its own, no measuring)...",
        }
    );
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
    run_dir::write_reference(&out, &models)?;

    println!(
        "Running {} trials of {:.0} s ({:?}, learner {}, behaviour {}) on {} threads...",
        seeds.len(),
        scenario.duration_s,
        scenario.mode,
        learners::display_name(&scenario.learner_name),
        scenario.behaviour_name,
        rayon::current_num_threads()
    );
    let bar = crate::progress_bar(seeds.len() as u64, "trials");
    let trials_started = std::time::Instant::now();
    let write_errors = Mutex::new(Vec::new());
    let results = experiment::run_trials(&scenario, &models, &seeds, &|trial| {
        if let Err(e) = run_dir::write_trial(&out, &scenario, &models, &made_by, trial) {
            if let Ok(mut v) = write_errors.lock() {
                v.push(e.to_string());
            }
        }
        bar.inc(1);
    });
    bar.finish();
    println!(
        "  {} trials in {:.2} s wall on {} threads",
        seeds.len(),
        trials_started.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
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
    let (rows, aggregate) = (&run.rows, &run.aggregate);
    ensure!(
        aggregate.ok() > 0,
        "no trial finished ok: {}",
        aggregate.describe()
    );
    print!(
        "{}",
        report::run::console(&run, &models, &scenario, args.wide)
    );

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
    run_dir::write_demos(&out, &demos)?;
    let outcomes: Vec<TrialOutcome> = results
        .into_iter()
        .zip(rows)
        .filter(|(_, row)| row.1.is_ok())
        .filter_map(|((_, r), _)| r.ok().map(|(_, o)| o))
        .collect();
    let figures =
        report::run::write_page(&out, &scenario, &models, &run, &outcomes, &demos, &made_by)?;
    println!("  {figures} figures (PNG and SVG) and index.html written");

    println!(
        "\n{} trials: the {} {:.0}x real time, the learner {:.1} ms a trial (means); \
         whole run {:.1} s wall",
        rows.len(),
        match scenario.world {
            testbed::world::WorldKind::Rapier => "physics",
            testbed::world::WorldKind::Synthetic => "synthetic world",
        },
        aggregate.mean.realtime_factor,
        1000.0 * aggregate.mean.learner_wall_s,
        started.elapsed().as_secs_f64(),
    );
    println!(
        "results in {0}: open {0}/index.html (every figure: summary.json, or --wide)",
        out.display()
    );
    Ok(())
}
