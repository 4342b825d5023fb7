//! Watch the robot learn: the paper's training trial running live, from the same
//! simulation and trial code as `train`, in a window (or headless, to a PNG).
//!
//! Needs the `viewer` feature:
//! `cargo run --release --features viewer --example view`
//! Keys: Escape or closing the window ends it.

mod dashboard;
mod scene;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow};
use clap::Parser;
use testbed::experiment;
use testbed::trial::{TrialConfig, TrialRunner};

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
    let models = experiment::measured_models(&scenario, Some(&args.cache))?;
    let reference = models.reference();
    let mut learner = experiment::learner_for(&scenario, &reference).map_err(|e| anyhow!(e))?;
    let config = TrialConfig {
        duration_s: args.seconds.unwrap_or(1e9),
        seed: args.seed,
        behaviour: experiment::behaviour_for(&models),
        judge_every_s: 5.0,
    };
    let mut runner = TrialRunner::new(&scenario.description, scenario.sim, config)?;

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
    let mut picture = Vec::new();
    let mut frame_buffer = vec![0u32; w * h];
    loop {
        if let Some(win) = &window {
            if !win.is_open() || win.is_key_down(minifb::Key::Escape) {
                break;
            }
        }
        // Catch the simulation up with the wall clock (at --speed), a bounded
        // number of frames at a time so the window stays responsive.
        let sim_due = if window.is_some() {
            started.elapsed().as_secs_f64() * args.speed
        } else {
            f64::INFINITY // headless: as fast as it goes
        };
        let mut stepped = 0;
        while !runner.finished()
            && last.is_none_or(|r: testbed::trial::TraceRow| r.t_s < sim_due)
            && stepped < 40
        {
            last = Some(runner.step_frame(&mut learner)?);
            stepped += 1;
        }
        let sim_t = last.map_or(0.0, |r| r.t_s);
        let moment = dashboard::Moment {
            runner: &runner,
            learner: &learner,
            models: &models,
            last,
            seed: args.seed,
            realtime: sim_t / started.elapsed().as_secs_f64().max(1e-9),
        };
        let headless_done = window.is_none() && runner.finished();
        if window.is_some() || headless_done {
            picture = dashboard::render(&moment).map_err(|e| anyhow!(e))?;
        }
        if let Some(win) = &mut window {
            for (px, c) in frame_buffer.iter_mut().zip(picture.chunks_exact(3)) {
                *px = u32::from(c[0]) << 16 | u32::from(c[1]) << 8 | u32::from(c[2]);
            }
            win.update_with_buffer(&frame_buffer, w, h)?;
        } else if runner.finished() {
            break;
        }
        if runner.finished() && window.is_some() {
            std::thread::sleep(Duration::from_millis(200));
            if args.seconds.is_some() {
                break;
            }
        }
    }
    if let Some(path) = &args.screenshot {
        if picture.is_empty() {
            let moment = dashboard::Moment {
                runner: &runner,
                learner: &learner,
                models: &models,
                last,
                seed: args.seed,
                realtime: 0.0,
            };
            picture = dashboard::render(&moment).map_err(|e| anyhow!(e))?;
        }
        save_png(path, &picture, dashboard::SIZE)?;
        println!("wrote {}", path.display());
    }
    println!(
        "{:.1} s simulated in {:.1} s",
        last.map_or(0.0, |r| r.t_s),
        started.elapsed().as_secs_f64()
    );
    window.take();
    Ok(())
}

fn save_png(path: &std::path::Path, rgb: &[u8], (w, h): (u32, u32)) -> Result<()> {
    let file =
        std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header()?.write_image_data(rgb)?;
    Ok(())
}
