//! Watch the robot learn in the Rerun viewer: the paper's training trial,
//! from the same simulation and trial code as `train`, streamed live to a
//! Rerun viewer (started if none is running; `pip install rerun-sdk==0.36.3`
//! gives the `rerun` command) or saved to a recording.
//!
//! Needs the `rerun` feature:
//! `cargo run --release --features rerun --example view`
//! `cargo run --release --features rerun --example view -- --seconds 60 --rerun trial.rrd`

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Result, anyhow};
use clap::Parser;
use report::rrd::{MODELS_EVERY_S, TrialLog};
use testbed::experiment;
use testbed::learners;
use testbed::trial::{self, TraceRow, TrialConfig, TrialRunner};

/// Show a training trial on the simulated quadruped, live, in Rerun.
#[derive(Debug, Parser)]
pub struct Args {
    /// The trial's seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Simulated seconds per wall-clock second (0: as fast as it runs).
    #[arg(long, default_value_t = 1.0)]
    speed: f64,
    /// Stop after this many simulated seconds (default: the scenario's trial).
    #[arg(long)]
    seconds: Option<f64>,
    /// Save to this recording (.rrd) instead of streaming to a viewer.
    #[arg(long, value_name = "FILE.rrd")]
    rerun: Option<PathBuf>,
    /// Where measured reference models are cached.
    #[arg(long, default_value = "runs/.cache")]
    cache: PathBuf,
    #[command(flatten)]
    scenario: crate::ScenarioArgs,
}

/// Runs the command with its parsed flags.
pub fn main(args: Args) -> Result<()> {
    anyhow::ensure!(
        args.speed.is_finite() && args.speed >= 0.0,
        "--speed must be 0 (as fast as it runs) or positive"
    );
    let scenario = args.scenario.scenario()?;
    crate::needs_rapier(&scenario, "view")?;
    println!("Measuring (or reading from the cache) the robot's true models...");
    let models = testbed::reference::measured_models(&scenario, Some(&args.cache))?;
    let reference = models.reference();
    let mut learner =
        learners::build(&scenario.learner_name, &scenario, &reference).map_err(|e| anyhow!(e))?;
    let config = TrialConfig {
        duration_s: args.seconds.unwrap_or(scenario.duration_s),
        ..experiment::trial_config(&scenario, &models, args.seed)?
    };
    let mut runner = TrialRunner::new(&scenario.description, scenario.sim, config)?;
    let mut log = match &args.rerun {
        Some(path) => TrialLog::save(path, &models)?,
        None => TrialLog::spawn(&models)?,
    };
    println!(
        "Trial {} ({} s, learner {}) {}...",
        args.seed,
        runner.total_frames() as f64 * scenario.sim.camera.frame_period_s,
        learners::display_name(&scenario.learner_name),
        args.rerun
            .as_ref()
            .map_or("streaming to the Rerun viewer".into(), |p| format!(
                "saving to {}",
                p.display()
            ))
    );
    let started = Instant::now();
    let mut next_judgement = MODELS_EVERY_S;
    let mut t_s = 0.0;
    while !runner.finished() {
        // The world steps one frame, then the learner is fed it: the same
        // feeding as every recorded run.
        let frame = runner.step_frame()?;
        trial::feed_checked(learner.as_mut(), &frame)?;
        t_s = frame.end_s();
        log.world_frame(runner.sim(), &frame)?;
        log.learner_row(&TraceRow::of(&frame, learner.as_ref()))?;
        if t_s + 1e-9 >= next_judgement {
            log.judgement(&reference.judge(t_s, learner.as_ref()))?;
            next_judgement += MODELS_EVERY_S;
        }
        if args.speed > 0.0 && args.rerun.is_none() {
            let due = Duration::from_secs_f64(t_s / args.speed);
            if let Some(wait) = due.checked_sub(started.elapsed()) {
                std::thread::sleep(wait);
            }
        }
    }
    log.judgement(&reference.judge(t_s, learner.as_ref()))?;
    log.finish()?;
    println!(
        "{t_s:.1} s simulated in {:.1} s",
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
