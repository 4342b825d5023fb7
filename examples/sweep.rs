//! Sweeps SCASM's hyper-parameters (or any other setting) over a grid, every
//! combination times every seed, through the same trial code as `train`.
//!
//! Results go to DIR/sweep.csv (one row per finished run, rewritten whole as each
//! run finishes) and DIR/sweep_summary.csv (mean and std per combination).
//! Running again into the same DIR skips finished runs. `--shard K/N` runs a
//! deterministic slice (for a batch scheduler's array job); `--merge DIR...`
//! combines shards' results.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Context, Result, bail, ensure};
use clap::Parser;
use testbed::experiment;
use testbed::reference::MeasuredModels;
use testbed::summary::{self, Figures};
use testbed::sweep::{self, Axis, CombinationSummary, Results, Row};

/// Sweep settings over a grid of values and seeds.
#[derive(Debug, Parser)]
struct Args {
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
    scenario: scasm_testbed::ScenarioArgs,
}

fn parse_seeds(spec: &str) -> Result<Vec<u64>> {
    let (a, b) = spec
        .split_once("..")
        .context("--seeds must look like A..B")?;
    let (a, b): (u64, u64) = (a.trim().parse()?, b.trim().parse()?);
    ensure!(a < b, "--seeds {spec} is empty");
    Ok((a..b).collect())
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

/// The combination with the lowest sum of relative errors (action over the
/// velocity range, sensor over the 2.4 m distance range), among those whose
/// every run finished ok if there are any such.
fn best(results: &Results, velocity_range: f64) -> Option<CombinationSummary> {
    let score = |m: &Figures| m.action_rmse_mm_s / velocity_range + m.sensor_rmse_mm / 2400.0;
    results
        .summary()
        .into_iter()
        .filter(|g| g.runs_ok > 0 && score(&g.mean).is_finite())
        .min_by(|a, b| {
            (a.runs_failed > 0)
                .cmp(&(b.runs_failed > 0))
                .then(score(&a.mean).total_cmp(&score(&b.mean)))
        })
}

fn report(results: &Results, velocity_range: f64) {
    let Some(g) = best(results, velocity_range) else {
        println!("no combination finished with both models learned");
        return;
    };
    let failed: Vec<String> = results
        .rows()
        .filter(|r| !r.status.is_ok())
        .map(|r| format!("{} ({})", r.run.key(), r.status))
        .collect();
    if !failed.is_empty() {
        println!(
            "\n{} runs did not finish ok and are not in any mean: {}",
            failed.len(),
            failed.join("; ")
        );
    }
    let worse: Vec<String> = results
        .rows()
        .filter(|r| r.status.is_ok() && r.figures.worse_than_start())
        .map(|r| r.run.key())
        .collect();
    if !worse.is_empty() {
        println!(
            "\n{} runs ended worse than their uncalibrated start (in the means): {}",
            worse.len(),
            worse.join("; ")
        );
    }
    let named: Vec<String> = g.settings.iter().map(|(k, v)| format!("{k}={v}")).collect();
    println!(
        "\nbest combination (lowest sum of relative errors; {} runs ok, {} failed, {} worse than \
         their start): {}",
        g.runs_ok,
        g.runs_failed,
        g.runs_worse_than_start,
        named.join(", ")
    );
    let [median, _, p90] = &g.quantiles;
    println!(
        "  action {:.1} mm/s (median {:.1}, p90 {:.1}), sensor {:.1} mm (median {:.1}, p90 {:.1}), \
         consistency {:.3}",
        g.mean.action_rmse_mm_s,
        median.action_rmse_mm_s,
        p90.action_rmse_mm_s,
        g.mean.sensor_rmse_mm,
        median.sensor_rmse_mm,
        p90.sensor_rmse_mm,
        g.mean.consistency
    );
    let paper = [
        ("learner.gamma", 0.999),
        ("learner.beta", 1.0 / 30.0),
        ("learner.t_start", 20.0),
    ];
    let is_paper = |g: &CombinationSummary| {
        g.settings.iter().all(|(k, v)| {
            paper.iter().find(|p| p.0 == k).is_none_or(|p| {
                v.parse::<f64>()
                    .is_ok_and(|x| (x - p.1).abs() <= 1e-3 * p.1)
            })
        })
    };
    print!(
        "paper's constants, the first values it tried (learner.gamma=0.999, learner.beta=0.0333, learner.t_start=20)"
    );
    match results
        .summary()
        .into_iter()
        .find(|g| is_paper(g) && g.runs_ok > 0)
    {
        Some(g) => println!(
            " ({} runs ok, {} failed):\n  action {:.1} mm/s, sensor {:.1} mm, consistency {:.3}",
            g.runs_ok,
            g.runs_failed,
            g.mean.action_rmse_mm_s,
            g.mean.sensor_rmse_mm,
            g.mean.consistency
        ),
        None => println!(": not in this sweep"),
    }
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

fn main() -> Result<()> {
    let args = Args::parse();
    if scasm_testbed::list_learners_if_asked(args.learner.as_deref()) {
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
    let seeds = parse_seeds(&args.seeds)?;
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

    let mut results = match Results::read(&args.out)? {
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

    // One measurement per distinct robot-and-world, before the runs share them.
    let mut references: BTreeMap<String, MeasuredModels> = BTreeMap::new();
    for &i in &todo {
        let key = scenarios[i].reference_key();
        if let std::collections::btree_map::Entry::Vacant(slot) = references.entry(key) {
            println!("measuring the reference models for {}...", slot.key());
            slot.insert(testbed::reference::measured_models(
                &scenarios[i],
                Some(&args.cache),
            )?);
        }
    }

    // Runs that share a world (every run of a seed, when only the learner's
    // settings vary) share one recording: the physics runs once per world.
    let bar = scasm_testbed::progress_bar(todo.len() as u64, "runs");
    let jobs: Vec<experiment::Job<'_>> = todo
        .iter()
        .map(|&i| experiment::Job {
            scenario: &scenarios[i],
            models: &references[&scenarios[i].reference_key()],
            seed: runs[i].seed,
            learner: &scenarios[i].learner_name,
        })
        .collect();
    let worlds: std::collections::BTreeSet<String> = jobs
        .iter()
        .map(|j| experiment::world_key(j.scenario, j.seed))
        .collect();
    println!("{} distinct worlds to simulate", worlds.len());
    let shared = Mutex::new((results.clone(), None::<String>));
    experiment::run_jobs(&jobs, &|k, result| {
        let (i, job) = (todo[k], &jobs[k]);
        let best_possible = summary::best_possible(&job.models.reference(), &job.scenario.learner);
        let (_, status, figures) = summary::trial_row(
            job.seed,
            result.as_ref().map_err(|e| e.to_string()),
            best_possible,
        );
        if let Ok(mut guard) = shared.lock() {
            guard.0.insert(Row {
                run: runs[i].clone(),
                figures,
                status,
            });
            if let Err(e) = guard.0.write(&args.out) {
                guard.1.get_or_insert(e.to_string());
            }
        }
        bar.inc(1);
    });
    bar.finish();
    let (done, write_error) = shared.into_inner().unwrap_or_else(|p| p.into_inner());
    if let Some(e) = write_error {
        bail!("writing results: {e}");
    }
    results = done;
    write_outputs(&results, &args.out)?;
    let velocity_range = references
        .values()
        .next()
        .map_or(600.0, MeasuredModels::velocity_range_mm_s);
    report(&results, velocity_range);
    println!("results in {}", args.out.display());
    Ok(())
}
