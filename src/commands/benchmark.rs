//! Every learner on every scenario of the suite (`assets/scenarios/suite/`) and
//! every seed, in parallel: each world is simulated once and fed to all the
//! learners. Writes DIR/leaderboard.csv (a row per learner, scenario and seed),
//! leaderboard.md and index.html (the summary table and a figure of the ratios
//! to the best possible polynomials), and each scenario's config-<name>.toml.
//!
//! `cargo run --release --example benchmark -- [--learners a,b] [--scenarios x,y]
//!  [--behaviours p,q] [--seeds A..B] [--out DIR]`

use std::path::PathBuf;

use anyhow::Result;
use clap::Parser;
use testbed::benchmark::{self, Benchmark};
use testbed::provenance::Provenance;
use testbed::{learners, output, scenario, sweep};

/// Benchmark learners across a suite of scenarios.
#[derive(Debug, Parser)]
pub struct Args {
    /// Learners, comma-separated (default: all; `list` prints them).
    #[arg(long, value_delimiter = ',')]
    learners: Vec<String>,
    /// Scenarios of the suite by name, comma-separated (default: all).
    #[arg(long, value_delimiter = ',')]
    scenarios: Vec<String>,
    /// Training behaviours, comma-separated: each scenario runs once per
    /// behaviour, named SCENARIO+BEHAVIOUR (default: each scenario's own;
    /// `list` prints them) [behaviour.name].
    #[arg(long, value_delimiter = ',')]
    behaviours: Vec<String>,
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
    /// Print the whole leaderboard (medians, tails, floors: about 250
    /// columns), as leaderboard.md and index.html hold it; by default a
    /// table that fits 100 columns.
    #[arg(long)]
    wide: bool,
}

/// Runs the command with its parsed flags.
pub fn main(args: Args) -> Result<()> {
    if args.learners.iter().any(|l| l == "list") {
        crate::list_learners_if_asked(Some("list"));
        return Ok(());
    }
    if args.behaviours.iter().any(|b| b == "list") {
        crate::list_behaviours_if_asked(Some("list"));
        return Ok(());
    }
    let specs: Vec<String> = if args.learners.is_empty() {
        learners::names().map(String::from).collect()
    } else {
        args.learners.clone()
    };
    let (first, end) =
        scenario::parse_seeds(&args.seeds).map_err(|e| anyhow::anyhow!("--seeds: {e}"))?;
    let settings: Vec<String> = args
        .robot
        .iter()
        .map(|r| format!("robot.file={r}"))
        .chain(args.set.iter().cloned())
        .collect();
    // The learners first: a program's own settings are known once it has
    // said hello.
    for spec in &specs {
        learners::resolve(spec).map_err(|e| anyhow::anyhow!("--learners: {e}"))?;
    }
    let suite = benchmark::load_suite(&args.suite, &args.scenarios, &settings)?;
    let suite = benchmark::with_behaviours(suite, &args.behaviours)?;
    let out = crate::create_run_dir(args.out.as_deref(), "benchmark")?;
    let made_by = Provenance::current();
    for s in &suite {
        let dir = out.join(format!("config-{}", s.name));
        std::fs::create_dir_all(&dir)?;
        output::write_config(&dir, &s.scenario, &made_by)?;
    }
    let started = std::time::Instant::now();
    let bench = Benchmark::new(suite, specs, (first..end).collect(), &args.cache, &|s| {
        println!("{s}")
    })
    .map_err(|e| anyhow::anyhow!(e))?;

    let mut entries = if args.merge.is_empty() {
        let (k, n) = match &args.shard {
            Some(spec) => sweep::parse_shard_spec(spec, |name| std::env::var(name).ok())?,
            None => (1, 1),
        };
        let worlds = bench.worlds(k, n);
        if args.shard.is_some() {
            println!(
                "shard {k}/{n}: {} of {} worlds",
                worlds.len(),
                bench.suite.len() * bench.seeds.len()
            );
        }
        println!(
            "{} learners x {} scenarios x {} seeds = {} trials ({} worlds to simulate) on {} threads",
            bench.learners.len(),
            bench.suite.len(),
            bench.seeds.len(),
            worlds.len() * bench.learners.len(),
            bench.simulations(&worlds),
            rayon::current_num_threads()
        );
        let bar = crate::progress_bar((worlds.len() * bench.learners.len()) as u64, "trials");
        let entries = bench.run(&worlds, &|| bar.inc(1));
        bar.finish();
        entries
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
        bench
            .check_merged(&merged)
            .map_err(|e| anyhow::anyhow!("--merge: {e}"))?;
        println!(
            "merged {} entries from {} directories",
            merged.len(),
            args.merge.len()
        );
        merged
    };
    bench.sort(&mut entries);
    benchmark::write_leaderboard_csv(&out.join("leaderboard.csv"), &entries)?;
    output::write_json(&out.join("summary.json"), &bench.summary_json(&entries))?;
    println!(
        "{}",
        report::leaderboard::write(&out, &bench, &entries, args.wide)?
    );
    println!(
        "\nwhole benchmark {:.0} s wall; results in {}",
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}
