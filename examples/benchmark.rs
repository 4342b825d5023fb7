//! Every learner on every scenario of the suite (`assets/scenarios/suite/`) and
//! every seed, in parallel: each world is simulated once and fed to all the
//! learners. Writes DIR/leaderboard.csv (a row per learner, scenario and seed),
//! leaderboard.md and index.html (the summary table and a figure of the ratios
//! to the best possible polynomials), and each scenario's config-<name>.toml.
//!
//! `cargo run --release --example benchmark -- [--learners a,b] [--scenarios x,y]
//!  [--seeds A..B] [--out DIR]`

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Mutex;

use anyhow::{Result, bail};
use clap::Parser;
use report::page::Page;
use testbed::benchmark::{self, Entry};
use testbed::experiment::{self, Job};
use testbed::learners;
use testbed::output;
use testbed::provenance::Provenance;
use testbed::reference::{self, MeasuredModels};
use testbed::scenario;
use testbed::summary;
use testbed::sweep;

/// Benchmark learners across a suite of scenarios.
#[derive(Debug, Parser)]
struct Args {
    /// Learners, comma-separated (default: all; `list` prints them).
    #[arg(long, value_delimiter = ',')]
    learners: Vec<String>,
    /// Scenarios of the suite by name, comma-separated (default: all).
    #[arg(long, value_delimiter = ',')]
    scenarios: Vec<String>,
    /// Seeds as a range A..B, B excluded.
    #[arg(long, default_value = "0..5")]
    seeds: String,
    /// A setting applied to every scenario as key=value (repeatable), e.g.
    /// trial.duration=60.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// The robot: a shipped robot's name or a robot file's path (default:
    /// ers7) [robot.file]. The suite's scenarios set some world values in
    /// metres for the ERS-7's scale.
    #[arg(long, value_name = "NAME_OR_PATH")]
    robot: Option<String>,
    /// The suite's directory.
    #[arg(long, default_value = benchmark::SUITE_DIR)]
    suite: PathBuf,
    /// Results directory (default: runs/benchmark-<unix time>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Where measured reference models are cached.
    #[arg(long, default_value = "runs/.cache")]
    cache: PathBuf,
    /// Run only shard K of N (1-based) of the (scenario, seed) worlds, e.g.
    /// 3/8; `auto` takes K and N from the Slurm array task it runs in.
    #[arg(long)]
    shard: Option<String>,
    /// Merge these benchmark directories' leaderboard.csv into --out instead
    /// of running (with the same --learners, --scenarios and --seeds).
    #[arg(long, num_args = 1..)]
    merge: Vec<PathBuf>,
}

fn main() -> Result<()> {
    let args = Args::parse();
    if args.learners.iter().any(|l| l == "list") {
        scasm_testbed::list_learners_if_asked(Some("list"));
        return Ok(());
    }
    // Each learner as named (a program is started here once, to read its
    // hello), and the name it reports under.
    let specs: Vec<String> = if args.learners.is_empty() {
        learners::names().map(String::from).collect()
    } else {
        args.learners.clone()
    };
    let learners: Vec<String> = specs
        .iter()
        .map(|spec| learners::resolve(spec).map(|l| l.name().to_string()))
        .collect::<Result<_, _>>()
        .map_err(|e| anyhow::anyhow!("--learners: {e}"))?;
    let (first, end) =
        scenario::parse_seeds(&args.seeds).map_err(|e| anyhow::anyhow!("--seeds: {e}"))?;
    let seeds: Vec<u64> = (first..end).collect();
    let settings: Vec<String> = args
        .robot
        .iter()
        .map(|r| format!("robot.file={r}"))
        .chain(args.set.iter().cloned())
        .collect();
    let suite = benchmark::load_suite(&args.suite, &args.scenarios, &settings)?;
    let out = scasm_testbed::create_run_dir(args.out.as_deref(), "benchmark")?;
    let made_by = Provenance::current();
    for s in &suite {
        let dir = out.join(format!("config-{}", s.name));
        std::fs::create_dir_all(&dir)?;
        output::write_config(&dir, &s.scenario, &made_by)?;
    }
    let started = std::time::Instant::now();

    // One reference per distinct robot and world.
    let mut references: BTreeMap<String, MeasuredModels> = BTreeMap::new();
    for s in &suite {
        let key = s.scenario.reference_key();
        if let std::collections::btree_map::Entry::Vacant(slot) = references.entry(key) {
            println!("reference models for {} ({})...", s.name, slot.key());
            slot.insert(reference::measured_models(&s.scenario, Some(&args.cache))?);
        }
    }
    let mut entries = if args.merge.is_empty() {
        run(&args, &suite, &references, &specs, &seeds)?
    } else {
        let parts = args
            .merge
            .iter()
            .map(|dir| {
                let path = dir.join("leaderboard.csv");
                benchmark::read_leaderboard_csv(&path).map(|e| (path.display().to_string(), e))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let merged = benchmark::merge_entries(parts)?;
        // Every merged entry must be one this benchmark's tables show.
        if let Some(e) = merged
            .iter()
            .find(|e| !suite.iter().any(|s| s.name == e.scenario) || !learners.contains(&e.learner))
        {
            bail!(
                "--merge: {} on {} seed {} is not among --learners {} and --scenarios {}; \
                 merge with the flags the shards ran with",
                e.learner,
                e.scenario,
                e.seed,
                learners.join(","),
                suite
                    .iter()
                    .map(|s| s.name.as_str())
                    .collect::<Vec<_>>()
                    .join(",")
            );
        }
        println!(
            "merged {} entries from {} directories",
            merged.len(),
            args.merge.len()
        );
        merged
    };
    let order = |e: &Entry| {
        (
            suite.iter().position(|s| s.name == e.scenario),
            learners.iter().position(|l| *l == e.learner),
            e.seed,
        )
    };
    entries.sort_by_key(order);
    benchmark::write_leaderboard_csv(&out.join("leaderboard.csv"), &entries)?;

    let names: Vec<String> = suite.iter().map(|s| s.name.clone()).collect();
    let cells = benchmark::cells(&entries, &learners, &names);
    let (header, rows) = benchmark::summary_table(&cells);
    println!("\n{}", report::table::text(&header, &rows));
    let ranges = |name: &str| {
        suite
            .iter()
            .find(|s| s.name == name)
            .map(|s| &references[&s.scenario.reference_key()])
            .map_or((f64::NAN, f64::NAN), |m| {
                (m.velocity_range_mm_s(), m.distance_range_mm())
            })
    };
    let misses = benchmark::below_paper(&cells, &ranges);
    let failed: Vec<String> = entries
        .iter()
        .filter(|e| !e.status.is_ok())
        .map(|e| {
            format!(
                "{} on {} seed {} ({})",
                e.learner, e.scenario, e.seed, e.status
            )
        })
        .collect();
    let mut notes = vec![format!(
        "{} learners x {} scenarios x seeds {}..{}, {} s trials; the figures are means over each \
         cell's ok trials (+- their std); ratios are to the best polynomial through the measured \
         model (quartic action, cubic sensor).",
        learners.len(),
        suite.len(),
        first,
        end,
        suite.first().map_or(f64::NAN, |s| s.scenario.duration_s)
    )];
    notes.push(if failed.is_empty() {
        "Every trial finished ok.".into()
    } else {
        format!("Trials not ok (not in any mean): {}.", failed.join("; "))
    });
    notes.push(if misses.is_empty() {
        "Every learner is at the paper's level (action <= 4.9 %, sensor <= 2.9 % of range, \
         consistency <= 0.08) on every scenario."
            .into()
    } else {
        format!("Below the paper's level: {}.", misses.join("; "))
    });
    for n in &notes[1..] {
        println!("{n}");
    }
    let markdown = format!(
        "{}\n\n{}",
        report::table::markdown(&header, &rows),
        notes.join("\n\n")
    );
    output::write_atomic(&out.join("leaderboard.md"), markdown.as_bytes())?;

    // The figures: each learner's median ratio to the best polynomial, and
    // its 10th to 90th percentile, per scenario.
    let figures = vec![
        (
            report::spread::save_ratios(
                &out,
                "leaderboard-action",
                "Action",
                &cells,
                &learners,
                &names,
                |c, f| c.action_ratio_of(f),
            )?,
            "Each learner's action error over the best quartic's per scenario: the median \
             (dot) and the 10th to 90th percentile (bar) over the seeds."
                .to_string(),
        ),
        (
            report::spread::save_ratios(
                &out,
                "leaderboard-sensor",
                "Sensor",
                &cells,
                &learners,
                &names,
                |c, f| c.sensor_ratio_of(f),
            )?,
            "Each learner's sensor error over the best cubic's per scenario: the median (dot) \
             and the 10th to 90th percentile (bar) over the seeds."
                .to_string(),
        ),
    ];
    Page {
        title: "Learners side by side".into(),
        paragraphs: notes,
        header,
        rows,
        figures,
    }
    .write(&out.join("index.html"))?;
    println!(
        "\nwhole benchmark {:.0} s wall; results in {}",
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}

/// Runs the benchmark's jobs (this shard's, with --shard) and returns their
/// entries.
fn run(
    args: &Args,
    suite: &[benchmark::SuiteScenario],
    references: &BTreeMap<String, MeasuredModels>,
    learners: &[String],
    seeds: &[u64],
) -> Result<Vec<Entry>> {
    let mut jobs: Vec<Job<'_>> = Vec::new();
    let worlds = match &args.shard {
        Some(spec) => {
            let (k, n) = sweep::parse_shard_spec(spec, |name| std::env::var(name).ok())?;
            let worlds = benchmark::shard_worlds(suite.len(), seeds, k, n);
            println!(
                "shard {k}/{n}: {} of {} worlds",
                worlds.len(),
                suite.len() * seeds.len()
            );
            worlds
        }
        None => benchmark::shard_worlds(suite.len(), seeds, 1, 1),
    };
    for &(i, seed) in &worlds {
        let s = &suite[i];
        let models = &references[&s.scenario.reference_key()];
        for l in learners {
            jobs.push(Job {
                scenario: &s.scenario,
                models,
                seed,
                learner: l,
            });
        }
    }
    println!(
        "{} learners x {} scenarios x {} seeds = {} trials ({} worlds to simulate) on {} threads",
        learners.len(),
        suite.len(),
        seeds.len(),
        jobs.len(),
        worlds.len(),
        rayon::current_num_threads()
    );
    let scenario_of = |job: &Job<'_>| {
        suite
            .iter()
            .find(|s| std::ptr::eq(&s.scenario, job.scenario))
            .map_or(String::new(), |s| s.name.clone())
    };
    let bar = scasm_testbed::progress_bar(jobs.len() as u64, "trials");
    let entries = Mutex::new(Vec::new());
    experiment::run_jobs(&jobs, &|i, result| {
        let job = &jobs[i];
        let best = summary::best_possible(&job.models.reference(), &job.scenario.learner);
        let (seed, status, figures) =
            summary::trial_row(job.seed, result.as_ref().map_err(|e| e.to_string()), best);
        if let Ok(mut v) = entries.lock() {
            v.push(Entry {
                learner: learners::display_name(job.learner),
                scenario: scenario_of(job),
                seed,
                status,
                figures,
            });
        }
        bar.inc(1);
    });
    bar.finish();
    Ok(entries.into_inner().unwrap_or_else(|p| p.into_inner()))
}
