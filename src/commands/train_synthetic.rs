//! Trains SCASM in the synthetic closed loop with no physics: a point robot with
//! a made-up nonlinear action model and an ideal pinhole camera with Gaussian pixel
//! noise, under the paper's behaviour. It prints the learned models beside the
//! truth and the errors beside the paper's. A check of the learner on its own; the
//! robot's experiment is `train`.

use anyhow::{Result, ensure};
use clap::Parser;
use scasm::{CalibrationLearner, Polynomial, Scasm, ScasmConfig};
use testbed::metrics;
use testbed::synthetic::{self, SyntheticTrialConfig};

/// Train SCASM in the synthetic closed loop (no physics).
#[derive(Debug, Parser)]
pub struct Args {
    /// Number of trials (seeds 0..N).
    #[arg(long, default_value_t = 15)]
    trials: u64,
    /// Trial length, s.
    #[arg(long, default_value_t = 150.0)]
    duration: f64,
    /// Reading noise, px (standard deviation).
    #[arg(long, default_value_t = 1.0)]
    noise_px: f64,
    /// Forgetting factor gamma.
    #[arg(long, default_value_t = ScasmConfig::default().gamma)]
    gamma: f64,
    /// Pull beta.
    #[arg(long, default_value_t = ScasmConfig::default().beta)]
    beta: f64,
    /// Ramp-up t_start, s.
    #[arg(long, default_value_t = ScasmConfig::default().t_start_s)]
    t_start: f64,
    /// Readings averaged per point of the sensor fit (1: the paper's algorithm).
    #[arg(long, default_value_t = ScasmConfig::default().sensor_window)]
    sensor_window: usize,
}

fn mean_std(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    (
        m,
        (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / n).sqrt(),
    )
}

/// Runs the command with its parsed flags.
pub fn main(args: Args) -> Result<()> {
    ensure!(args.trials > 0, "--trials must be at least 1");
    ensure!(
        args.duration > 0.0 && args.duration.is_finite(),
        "--duration must be > 0"
    );
    ensure!(
        args.noise_px >= 0.0 && args.noise_px.is_finite(),
        "--noise-px must be >= 0"
    );
    let params = ScasmConfig {
        gamma: args.gamma,
        beta: args.beta,
        t_start_s: args.t_start,
        sensor_window: args.sensor_window,
        ..Default::default()
    }
    .validate()?;
    let config = SyntheticTrialConfig {
        duration_s: args.duration,
        noise_px: args.noise_px,
        ..Default::default()
    };

    println!(
        "SCASM, synthetic closed loop (point robot, no physics): {} trials of {} s, noise {} px",
        args.trials, args.duration, args.noise_px
    );
    let started = std::time::Instant::now();
    let (mut action, mut sensor, mut consistency) = (Vec::new(), Vec::new(), Vec::new());
    let mut last = None;
    for seed in 0..args.trials {
        let mut learner = Scasm::new(params, scasm::Mode::Simultaneous)?;
        let out = synthetic::run_trial(&mut learner, &config, seed)?;
        let (Some(a), Some(s), Some(c)) = (out.action_error, out.sensor_error, out.consistency)
        else {
            println!("  seed {seed:2}: no models learned");
            continue;
        };
        println!(
            "  seed {seed:2}: action {:6.1} mm/s   sensor {:6.1} mm   consistency {:.3}",
            a.rmse, s.rmse, c
        );
        action.push(a.rmse);
        sensor.push(s.rmse);
        consistency.push(c);
        last = Some((learner, a, s));
    }
    let wall = started.elapsed().as_secs_f64();
    ensure!(!action.is_empty(), "no trial learned both models");

    let measured_a = synthetic::measured_action();
    let measured_s = synthetic::measured_sensor();
    let obs_to_d: Vec<(f64, f64)> = measured_s.iter().map(|&(d, o)| (o, d)).collect();
    let a0 = metrics::action_error(&Polynomial::identity(), &measured_a);
    let best_a = metrics::best_polynomial_rmse(&measured_a, 4).unwrap_or(f64::NAN);
    let best_s = metrics::best_polynomial_rmse(&obs_to_d, 3).unwrap_or(f64::NAN);
    let (am, asd) = mean_std(&action);
    let (sm, ssd) = mean_std(&sensor);
    let (cm, csd) = mean_std(&consistency);

    println!();
    println!(
        "{:<13} {:>22} {:>22} {:>16}",
        "figure", "ours (mean +- std)", "paper (Aibo ERS-7)", "best poly / A0"
    );
    println!(
        "{:<13} {:>15.1} +- {:>4.1} {:>22} {:>16}",
        "action mm/s",
        am,
        asd,
        "29.6",
        format!("{best_a:.1} / {:.1}", a0.rmse)
    );
    println!(
        "{:<13} {:>15.1} +- {:>4.1} {:>22} {:>16}",
        "sensor mm",
        sm,
        ssd,
        "70.4 +- 13.9",
        format!("{best_s:.1}")
    );
    println!(
        "{:<13} {:>15.3} +- {:>4.3} {:>22}",
        "consistency", cm, csd, "0.08 +- 0.06"
    );

    if let Some((learner, a, s)) = last {
        println!(
            "\nLast trial's models, mapped into true units by the best scale (A) and affine map (S):"
        );
        println!("  {:>8} {:>12} {:>12}", "command", "true mm/s", "learned");
        let model = learner.action_model().unwrap_or_else(Polynomial::identity);
        for &(c, v) in measured_a.iter().step_by(5) {
            println!("  {:>8.0} {:>12.1} {:>12.1}", c, v, a.scale * model.eval(c));
        }
        println!("  {:>8} {:>12} {:>12}", "obs px", "true mm", "learned");
        let model = learner.sensor_model().unwrap_or_else(Polynomial::identity);
        for &(d, o) in measured_s.iter().step_by(2) {
            println!(
                "  {:>8.1} {:>12.0} {:>12.0}",
                o,
                d,
                s.offset + s.scale * model.eval(o)
            );
        }
    }
    println!(
        "\n{} trials in {:.2} s wall ({:.0}x real time)",
        action.len(),
        wall,
        action.len() as f64 * args.duration / wall
    );
    Ok(())
}
