//! Sweeps SCASM's hyper-parameters (or any other setting) over a grid, every
//! combination times every seed, through the same trial code as `train`.
//!
//! Results go to DIR/sweep.csv (one row per finished run, rewritten whole as each
//! run finishes) and DIR/sweep_summary.csv (mean and std per combination).
//! Running again into the same DIR skips finished runs. `--shard K/N` runs a
//! deterministic slice (for a batch scheduler's array job); `--merge DIR...`
//! combines shards' results.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail, ensure};
use clap::Parser;
use testbed::sweep::{self, Axis, Results};

/// Sweep settings over a grid of values and seeds.
#[derive(Debug, Parser)]
pub struct Args {
    /// Values of learner.gamma: a list a,b,c or a range start:step:stop.
    #[arg(long)]
    gamma: Option<String>,
    /// Values of learner.beta.
    #[arg(long)]
    beta: Option<String>,
    /// Values of learner.t_start, s.
    #[arg(long = "t-start")]
    t_start: Option<String>,
    /// Any other setting to sweep, as key=values (repeatable), e.g. camera.noise_px=0.5,1.
    #[arg(long = "axis", value_name = "KEY=VALUES")]
    axes: Vec<String>,
    /// Seeds as a range A..B (B excluded).
    #[arg(long, default_value = "0..5")]
    seeds: String,
    /// The learner for every run; `list` prints the available ones
    /// [learner.name].
    #[arg(long)]
    learner: Option<String>,
    /// Run only shard K of N (1-based), e.g. 3/8; `auto` takes K and N from
    /// the Slurm array task it runs in (SLURM_ARRAY_TASK_ID, _MIN, _COUNT).
    #[arg(long)]
    shard: Option<String>,
    /// Merge these sweeps' results into --out instead of running.
    #[arg(long, num_args = 1..)]
    merge: Vec<PathBuf>,
    /// Results directory.
    #[arg(long, default_value = "runs/sweep")]
    out: PathBuf,
    /// Where measured reference models are cached.
    #[arg(long, default_value = "runs/.cache")]
    cache: PathBuf,
    #[command(flatten)]
    scenario: crate::ScenarioArgs,
}

fn axes(args: &Args) -> Result<Vec<Axis>> {
    let mut axes = Vec::new();
    for (key, spec) in [
        ("learner.gamma", &args.gamma),
        ("learner.beta", &args.beta),
        ("learner.t_start", &args.t_start),
    ] {
        if let Some(spec) = spec {
            axes.push(Axis::parse(key, spec)?);
        }
    }
    for a in &args.axes {
        let (key, spec) = a
            .split_once('=')
            .context("--axis must look like key=values")?;
        axes.push(Axis::parse(key.trim(), spec)?);
    }
    ensure!(
        !axes.is_empty(),
        "nothing to sweep: give --gamma, --beta, --t-start or --axis"
    );
    Ok(axes)
}

/// Writes sweep.csv, sweep_summary.csv and the heatmaps.
fn write_outputs(results: &Results, dir: &Path) -> Result<()> {
    results.write(dir)?;
    results.write_summary(dir)?;
    let maps = report::heatmap::write_sweep_heatmaps(dir, results.keys(), &results.summary())?;
    for m in maps {
        println!("heatmap {}.png (and .svg)", m.display());
    }
    Ok(())
}

/// Runs the command with its parsed flags.
pub fn main(args: Args) -> Result<()> {
    if crate::list_learners_if_asked(args.learner.as_deref()) {
        return Ok(());
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;

    if !args.merge.is_empty() {
        let mut merged: Option<Results> = None;
        for dir in &args.merge {
            let r = Results::read(dir)?
                .with_context(|| format!("{} has no sweep.csv", dir.display()))?;
            match &mut merged {
                None => merged = Some(r),
                Some(m) => m.merge(r)?,
            }
        }
        let merged = merged.context("nothing to merge")?;
        write_outputs(&merged, &args.out)?;
        println!(
            "merged {} runs into {}",
            merged.rows().count(),
            args.out.display()
        );
        return Ok(());
    }

    let axes = axes(&args)?;
    let keys: Vec<String> = axes.iter().map(|a| a.key.clone()).collect();
    let (first, end) =
        testbed::scenario::parse_seeds(&args.seeds).map_err(|e| anyhow::anyhow!("--seeds: {e}"))?;
    let seeds: Vec<u64> = (first..end).collect();
    let base = args.scenario.scenario_with(
        &args
            .learner
            .iter()
            .map(|l| format!("learner.name={l}"))
            .collect::<Vec<_>>(),
    )?;
    // The base scenario, every setting; each run's own are the axes' values in
    // sweep.csv (the command line is in the file's header).
    testbed::output::write_config(
        &args.out,
        &base,
        &testbed::provenance::Provenance::current(),
    )?;
    let mut runs = sweep::runs(&axes, &seeds);
    let total = runs.len();
    if let Some(spec) = &args.shard {
        let (k, n) = sweep::parse_shard_spec(spec, |name| std::env::var(name).ok())?;
        runs = sweep::shard(runs, k, n);
        println!("shard {k}/{n}: {} of {total} runs", runs.len());
    }
    // Every run's scenario is checked before anything runs.
    let scenarios = runs
        .iter()
        .map(|r| r.scenario(&base))
        .collect::<Result<Vec<_>, _>>()?;

    let results = match Results::read(&args.out)? {
        Some(r) if r.keys() == keys.as_slice() => r,
        Some(r) => bail!(
            "{} holds a sweep over {:?}, not {:?}; use another --out",
            args.out.display(),
            r.keys(),
            keys
        ),
        None => Results::new(keys.clone()),
    };
    let todo: Vec<usize> = (0..runs.len())
        .filter(|&i| !results.has(&runs[i]))
        .collect();
    println!(
        "{} runs ({} combinations x {} seeds{}), {} already done, {} to run",
        runs.len(),
        total / seeds.len(),
        seeds.len(),
        if args.shard.is_some() {
            ", this shard"
        } else {
            ""
        },
        runs.len() - todo.len(),
        todo.len()
    );

    // One measurement per distinct robot and world; runs that share a world
    // (every run of a seed, when only the learner's settings vary) share one
    // recording: the physics runs once per world.
    let bar = crate::progress_bar(todo.len() as u64, "runs");
    let (results, velocity_range) = sweep::run_pending(
        results,
        (&runs, &scenarios, &todo),
        &args.cache,
        &args.out,
        &|s| println!("{s}"),
        &|| bar.inc(1),
    )?;
    bar.finish();
    write_outputs(&results, &args.out)?;
    let summary = report::sweep::describe(&results, velocity_range.unwrap_or(600.0), &base.learner);
    print!(
        "{}",
        report::table::wrap(&summary, report::table::CONSOLE_COLUMNS)
    );
    println!("results in {}", args.out.display());
    Ok(())
}
