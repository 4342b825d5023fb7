//! Watch the robot learn: the paper's training trial running live, from the same
//! simulation and trial code as `train`, in a window (or headless, to a PNG).
//!
//! Needs the `viewer` feature:
//! `cargo run --release --features viewer --example view`
//! Keys: Escape or closing the window ends it.

mod dashboard;
mod scene;

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, anyhow};
use clap::Parser;
use scasm::CalibrationLearner;
use testbed::trial::{self, TraceRow, TrialConfig, TrialRunner};
use testbed::{experiment, learners};

/// Show a SCASM training trial on the simulated quadruped, live.
#[derive(Debug, Parser)]
struct Args {
    /// The trial's seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Simulated seconds per wall-clock second.
    #[arg(long, default_value_t = 1.0)]
    speed: f64,
    /// Stop after this many simulated seconds (default: run until closed).
    #[arg(long)]
    seconds: Option<f64>,
    /// Save the last picture shown as a PNG here.
    #[arg(long)]
    screenshot: Option<PathBuf>,
    /// Draw without opening a window (with --seconds and --screenshot).
    #[arg(long)]
    no_window: bool,
    /// Where measured reference models are cached.
    #[arg(long, default_value = "runs/.cache")]
    cache: PathBuf,
    #[command(flatten)]
    scenario: scasm_testbed::ScenarioArgs,
}

fn main() -> Result<()> {
    let args = Args::parse();
    anyhow::ensure!(
        args.speed.is_finite() && args.speed > 0.0,
        "--speed must be positive"
    );
    report::plot::register_font()?;
    let scenario = args.scenario.scenario()?;
    println!("Measuring (or reading from the cache) the robot's true models...");
    let models = testbed::reference::measured_models(&scenario, Some(&args.cache))?;
    let reference = models.reference();
    let mut learner =
        learners::build(&scenario.learner_name, &scenario, &reference).map_err(|e| anyhow!(e))?;
    let config = TrialConfig {
        duration_s: args.seconds.unwrap_or(1e9),
        ..experiment::trial_config(&scenario, &models, args.seed)?
    };
    let mut runner = TrialRunner::new(&scenario.description, scenario.sim, config)?;
    // The world steps one frame, then the learner is fed it: the same feeding
    // as every recorded run.
    let step =
        |runner: &mut TrialRunner, learner: &mut learners::BoxedLearner| -> Result<TraceRow> {
            let frame = runner.step_frame()?;
            trial::feed(learner.as_mut(), &frame)?;
            Ok(TraceRow::of(&frame, learner.as_ref()))
        };

    let (w, h) = (dashboard::SIZE.0 as usize, dashboard::SIZE.1 as usize);
    let mut window = if args.no_window {
        None
    } else {
        let mut win = minifb::Window::new(
            "SCASM testbed: the robot learning its action and sensor models",
            w,
            h,
            minifb::WindowOptions::default(),
        )
        .context("opening a window (is there a display? try --no-window)")?;
        win.set_target_fps(30);
        Some(win)
    };

    let started = Instant::now();
    let mut last = None;
    let draw = |runner: &TrialRunner, learner: &dyn CalibrationLearner, last: Option<TraceRow>| {
        let sim_t = last.map_or(0.0, |r| r.t_s);
        dashboard::render(&dashboard::Moment {
            runner,
            learner,
            models: &models,
            last,
            seed: args.seed,
            realtime: sim_t / started.elapsed().as_secs_f64().max(1e-9),
        })
        .map_err(|e| anyhow!(e))
    };
    if let Some(win) = &mut window {
        let mut frame_buffer = vec![0u32; w * h];
        while win.is_open() && !win.is_key_down(minifb::Key::Escape) {
            // Catch the simulation up with the wall clock (at --speed), a bounded
            // number of frames at a time so the window stays responsive.
            let sim_due = started.elapsed().as_secs_f64() * args.speed;
            for _ in 0..40 {
                if runner.finished() || last.is_some_and(|r: TraceRow| r.t_s >= sim_due) {
                    break;
                }
                last = Some(step(&mut runner, &mut learner)?);
            }
            let picture = draw(&runner, learner.as_ref(), last)?;
            for (px, c) in frame_buffer.iter_mut().zip(picture.chunks_exact(3)) {
                *px = u32::from(c[0]) << 16 | u32::from(c[1]) << 8 | u32::from(c[2]);
            }
            win.update_with_buffer(&frame_buffer, w, h)?;
            if runner.finished() && args.seconds.is_some() {
                break;
            }
        }
    } else {
        // Headless: as fast as it goes, drawn once at the end.
        while !runner.finished() {
            last = Some(step(&mut runner, &mut learner)?);
        }
    }
    if let Some(path) = &args.screenshot {
        let picture = draw(&runner, learner.as_ref(), last)?;
        report::write_png(path, &picture, dashboard::SIZE)?;
        println!("wrote {}", path.display());
    }
    println!(
        "{:.1} s simulated in {:.1} s",
        last.map_or(0.0, |r| r.t_s),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
