//! The information floor against a Monte Carlo on the synthetic world: one
//! path (the paper's behaviour), many draws of the reading noise. The bound
//! is for a model that holds, so here the truth is in the model class: the
//! synthetic robot's response and camera replaced by the best polynomials of
//! the learner's degrees through them (a quartic A, a cubic S). The spread of
//! the efficient estimator's errors, in each metric as the metrics compute
//! it, matches the floor; and a learner does no better than the floor.

use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use rayon::prelude::*;
use scasm::{BatchMl, BatchMlConfig, CalibrationLearner, Event, EventError, Polynomial};
use testbed::floor::{self, Floor, Noise, Sample};
use testbed::metrics;
use testbed::reference::Reference;
use testbed::synthetic::{self, SyntheticTrialConfig};

/// Records the commands a trial gives; learns nothing.
#[derive(Default)]
struct Recorder {
    frames: Vec<(f64, f64, f64)>,
}

impl CalibrationLearner for Recorder {
    fn name(&self) -> &str {
        "recorder"
    }
    fn handle(&mut self, event: Event) -> Result<(), EventError> {
        if let Event::Command { t_s, dt_s, command } = event {
            self.frames.push((t_s, dt_s, command));
        }
        Ok(())
    }
    fn action_model(&self) -> Option<Polynomial> {
        None
    }
    fn sensor_model(&self) -> Option<Polynomial> {
        None
    }
    fn x_a(&self) -> Option<f64> {
        None
    }
    fn x_s(&self) -> Option<f64> {
        None
    }
}

/// The world: the synthetic world's models replaced by the best quartic A
/// and cubic S through them, so that the truth is in the model class.
struct World {
    action: Polynomial,
    sensor: Polynomial,
    reference: Reference,
}

impl World {
    fn new() -> Self {
        let action = metrics::best_polynomial(&synthetic::measured_action(), 4).expect("A");
        let by_obs: Vec<(f64, f64)> = synthetic::measured_sensor()
            .iter()
            .map(|&(d, o)| (o, d))
            .collect();
        let sensor = metrics::best_polynomial(&by_obs, 3).expect("S");
        let reference = Reference {
            action: synthetic::test_commands()
                .map(|c| (c, action.eval(c)))
                .collect(),
            sensor: synthetic::test_distances_mm()
                .map(|d| (d, reading(&sensor, d)))
                .collect(),
            changes: Vec::new(),
        };
        Self {
            action,
            sensor,
            reference,
        }
    }

    /// The paper's behaviour's frames (the synthetic trial's commands) and
    /// the true distance at each frame's end (readings unset).
    fn path(&self) -> Vec<Sample> {
        let config = SyntheticTrialConfig::default();
        let mut recorder = Recorder::default();
        synthetic::run_trial(&mut recorder, &config, 3).expect("trial");
        let mut x = config.start_distance_mm;
        recorder
            .frames
            .iter()
            .map(|&(t_s, dt_s, command)| {
                x -= self.action.eval(command) * dt_s;
                Sample {
                    t_s: t_s + dt_s,
                    command,
                    obs_px: None,
                    x_true_mm: x,
                }
            })
            .collect()
    }

    /// The path with a fresh draw of 1 px of reading noise.
    fn draw(&self, path: &[Sample], rng: &mut rand_chacha::ChaCha8Rng) -> Vec<Sample> {
        let noise = Normal::new(0.0, 1.0).expect("normal");
        path.iter()
            .map(|r| Sample {
                obs_px: Some(reading(&self.sensor, r.x_true_mm) + noise.sample(rng)),
                ..*r
            })
            .collect()
    }
}

/// The noise-free reading at distance `x` of a camera whose sensor model is
/// `sensor`: `S^-1(x)`, by bisection over the readings S is monotone on.
fn reading(sensor: &Polynomial, x: f64) -> f64 {
    let (mut lo, mut hi) = (12.0, 90.0);
    assert!(
        sensor.eval(lo) > x && sensor.eval(hi) < x,
        "{x} mm out of range"
    );
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if sensor.eval(mid) > x {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The metrics' error vectors (after their best maps) of a pair of models.
fn errors(action: &Polynomial, sensor: &Polynomial, reference: &Reference) -> (Vec<f64>, Vec<f64>) {
    let a = metrics::action_error(action, &reference.action);
    let s = metrics::sensor_error(sensor, &reference.sensor);
    (
        reference
            .action
            .iter()
            .map(|&(c, v)| a.scale * action.eval(c) - v)
            .collect(),
        reference
            .sensor
            .iter()
            .map(|&(d, o)| s.offset + s.scale * sensor.eval(o) - d)
            .collect(),
    )
}

/// Mean square spread of error vectors about their mean, per point, and the
/// mean square error itself.
fn spread_and_mean_square(draws: &[Vec<f64>]) -> (f64, f64) {
    let (n, k) = (draws.len() as f64, draws[0].len());
    let mean: Vec<f64> = (0..k)
        .map(|i| draws.iter().map(|d| d[i]).sum::<f64>() / n)
        .collect();
    let spread = draws
        .iter()
        .map(|d| {
            d.iter()
                .zip(&mean)
                .map(|(e, m)| (e - m).powi(2))
                .sum::<f64>()
        })
        .sum::<f64>()
        / (n * k as f64);
    let square = draws
        .iter()
        .map(|d| d.iter().map(|e| e * e).sum::<f64>())
        .sum::<f64>()
        / (n * k as f64);
    (spread, square)
}

#[test]
fn the_efficient_estimators_spread_is_the_floor_and_no_learner_beats_it() {
    let world = World::new();
    let (degrees, reference) = ((4, 3), &world.reference);
    let path = world.path();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(29);
    // The noises as the truth shows them: 1 px of reading noise (and the
    // error of interpolating this camera, no pinhole, between the 13
    // distances), and no process noise beyond that of interpolating the
    // stopwatch's curve. The bound takes the noises as drawn.
    let measured = Floor::of(&world.draw(&path, &mut rng), reference, degrees).expect("floor");
    assert!(
        (measured.noise.reading_px - 1.0).abs() < 0.15,
        "{:?}",
        measured.noise
    );
    assert!(measured.noise.steady_mm < 0.05, "{:?}", measured.noise);
    let noise = Noise {
        reading_px: 1.0,
        steady_mm: 0.01,
        changing_mm: 0.01,
        bob_mm: 0.0,
        lag_s: 0.0,
        steady_core_mm: 0.01,
    };
    let bound =
        Floor::with_noise(&world.draw(&path, &mut rng), reference, degrees, noise).expect("floor");
    // In the class, the floor is its variance alone.
    assert!(bound.action_rmse_mm_s - bound.action_sd_mm_s < 1e-6 * bound.action_rmse_mm_s);

    // The draws made in turn (the same draws on any machine), the fits side
    // by side.
    let draws: Vec<Vec<Sample>> = (0..150).map(|_| world.draw(&path, &mut rng)).collect();
    let (action, sensor): (Vec<Vec<f64>>, Vec<Vec<f64>>) = draws
        .par_iter()
        .map(|rows| {
            let (a, s) = floor::maximum_likelihood(rows, reference, degrees, noise).expect("ml");
            errors(&a, &s, reference)
        })
        .unzip();
    let (action_spread, action_square) = spread_and_mean_square(&action);
    let (sensor_spread, sensor_square) = spread_and_mean_square(&sensor);
    let ratio_a = action_square.sqrt() / bound.action_rmse_mm_s;
    let ratio_s = sensor_square.sqrt() / bound.sensor_rmse_mm;
    eprintln!(
        "floor: action {:.3} mm/s, sensor {:.3} mm; the ML estimator's RMS / floor: action \
         {ratio_a:.3}, sensor {ratio_s:.3} (spread alone: {:.3}, {:.3})",
        bound.action_rmse_mm_s,
        bound.sensor_rmse_mm,
        action_spread.sqrt() / bound.action_rmse_mm_s,
        sensor_spread.sqrt() / bound.sensor_rmse_mm,
    );
    assert!((0.9..1.1).contains(&ratio_a), "action {ratio_a}");
    assert!((0.9..1.1).contains(&ratio_s), "sensor {ratio_s}");

    // A learner that knows neither the noises nor the truth does no better
    // than the floor: batch-ml on more draws of the same path, fed as a
    // trial feeds it.
    let draws: Vec<Vec<Sample>> = (0..12).map(|_| world.draw(&path, &mut rng)).collect();
    let squares: Vec<(f64, f64)> = draws
        .par_iter()
        .map(|rows| {
            let mut learner = BatchMl::new(BatchMlConfig::default().validate().expect("valid"));
            let mut start = 0.0;
            for r in rows {
                learner
                    .handle(Event::Command {
                        t_s: start,
                        dt_s: r.t_s - start,
                        command: r.command,
                    })
                    .expect("command");
                learner
                    .handle(Event::Reading {
                        t_s: r.t_s,
                        obs_px: r.obs_px.expect("reading"),
                    })
                    .expect("reading");
                start = r.t_s;
            }
            let a = metrics::action_error(&learner.action_model().expect("A"), &reference.action);
            let s = metrics::sensor_error(&learner.sensor_model().expect("S"), &reference.sensor);
            (a.rmse * a.rmse, s.rmse * s.rmse)
        })
        .collect();
    let n = squares.len() as f64;
    // Summed in the draws' order, whatever the threads' order.
    let action_sq = squares.iter().map(|q| q.0).sum::<f64>() / n;
    let sensor_sq = squares.iter().map(|q| q.1).sum::<f64>() / n;
    eprintln!(
        "batch-ml's RMS over {n} draws: action {:.3} mm/s, sensor {:.3} mm",
        action_sq.sqrt(),
        sensor_sq.sqrt()
    );
    assert!(action_sq.sqrt() >= 0.9 * bound.action_rmse_mm_s);
    assert!(sensor_sq.sqrt() >= 0.9 * bound.sensor_rmse_mm);
}

/// The noises of real trials, with no bob: a typical one (the ERS-7: 0.94
/// px, 0.72 mm a steady frame, 3 mm a frame changing over beyond the gait's
/// lag of 0.17 s) and the noisiest process (4.7 and 10 mm, the top of the
/// ranges real trials show: 0.5-4.7 mm steady, 6-10 mm changing over with
/// no lag modelled).
const REAL: [(&str, Noise); 2] = [
    (
        "typical",
        Noise {
            reading_px: 0.94,
            steady_mm: 0.72,
            changing_mm: 3.0,
            bob_mm: 0.0,
            lag_s: 0.17,
            steady_core_mm: 0.72,
        },
    ),
    (
        "noisiest",
        Noise {
            reading_px: 0.94,
            steady_mm: 4.7,
            changing_mm: 10.0,
            bob_mm: 0.0,
            lag_s: 0.2,
            steady_core_mm: 4.7,
        },
    ),
];

impl World {
    /// A fresh draw of the path, walked through `noise`'s lag with its
    /// process noise (the frames within 0.5 s of a change of command at its
    /// changing level), and of its readings.
    fn noisy_draw(
        &self,
        frames: &[Sample],
        noise: Noise,
        rng: &mut rand_chacha::ChaCha8Rng,
    ) -> Vec<Sample> {
        let unit = Normal::new(0.0, 1.0).expect("normal");
        let changing = floor::changing_frames(frames);
        let steady: Vec<f64> = frames.iter().map(|r| self.action.eval(r.command)).collect();
        let means = floor::lag::mean_velocities(frames, noise.lag_s, &steady);
        let mut x = frames[0].x_true_mm;
        let mut t = frames[0].t_s;
        frames
            .iter()
            .zip(changing)
            .enumerate()
            .map(|(j, (r, change))| {
                if j > 0 {
                    let sd = if change {
                        noise.changing_mm
                    } else {
                        noise.steady_mm
                    };
                    x -= means[j] * (r.t_s - t) + sd * unit.sample(rng);
                }
                t = r.t_s;
                Sample {
                    x_true_mm: x,
                    obs_px: Some(reading(&self.sensor, x) + noise.reading_px * unit.sample(rng)),
                    ..*r
                }
            })
            .collect()
    }
}

/// The RMS over `draws` of the floor and of the two estimators' errors, in
/// each metric: `[floor, integrated, joint]` for the action, then the sensor.
fn rms_over_draws(world: &World, draws: &[Vec<Sample>], noise: Noise) -> [[f64; 3]; 2] {
    let (degrees, reference) = ((4, 3), &world.reference);
    let per_draw: Vec<[[f64; 3]; 2]> = draws
        .par_iter()
        .map(|rows| {
            let bound = Floor::with_noise(rows, reference, degrees, noise).expect("floor");
            let (a, s) = floor::maximum_likelihood(rows, reference, degrees, noise).expect("ml");
            let (ea, es) = errors(&a, &s, reference);
            let joint =
                floor::joint_maximum_likelihood(rows, reference, degrees, noise).expect("joint");
            let (ja, js) = errors(&joint.0, &joint.1, reference);
            let square = |v: &[f64]| v.iter().map(|e| e * e).sum::<f64>() / v.len() as f64;
            [
                [bound.action_rmse_mm_s.powi(2), square(&ea), square(&ja)],
                [bound.sensor_rmse_mm.powi(2), square(&es), square(&js)],
            ]
        })
        .collect();
    let n = per_draw.len() as f64;
    // Summed in the draws' order, whatever the threads' order.
    std::array::from_fn(|m| {
        std::array::from_fn(|i| (per_draw.iter().map(|d| d[m][i]).sum::<f64>() / n).sqrt())
    })
}

/// The floor's own world at the noise levels of real trials: the path drawn
/// afresh through the gait's lag with its process noise, each draw's floor
/// computed with the noises it was drawn with (and found from the truth as
/// a trial's are). Maximum likelihood with the path integrated out attains
/// the floor by RMS over the draws; jointly over path and models it does not
/// (biased by the frames' locations as nuisance parameters), most where the
/// process noise is largest.
#[test]
fn at_real_noise_levels_the_path_integrated_out_attains_the_floor() {
    let world = World::new();
    let frames = world.path();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(57);
    for (name, noise) in REAL {
        let draws: Vec<Vec<Sample>> = (0..150)
            .map(|_| world.noisy_draw(&frames, noise, &mut rng))
            .collect();
        // The floor finds the lag and the noises from the truth.
        let found = Floor::of(&draws[0], &world.reference, (4, 3))
            .expect("floor")
            .noise;
        assert!(
            (found.lag_s / noise.lag_s - 1.0).abs() < 0.1,
            "{name}: {found:?}"
        );
        assert!(
            (found.steady_mm / noise.steady_mm - 1.0).abs() < 0.2,
            "{name}: {found:?}"
        );
        let [action, sensor] = rms_over_draws(&world, &draws, noise);
        let ratio = |m: [f64; 3], i: usize| m[i] / m[0];
        eprintln!(
            "{name} noise, {} draws: floor RMS action {:.3} mm/s, sensor {:.3} mm; path integrated \
             out {:.3}x, {:.3}x; joint over path and models {:.3}x, {:.3}x",
            draws.len(),
            action[0],
            sensor[0],
            ratio(action, 1),
            ratio(sensor, 1),
            ratio(action, 2),
            ratio(sensor, 2),
        );
        for (metric, m) in [("action", action), ("sensor", sensor)] {
            let r = ratio(m, 1);
            assert!((0.9..1.1).contains(&r), "{name}: {metric} {r}");
        }
        if name == "noisiest" {
            assert!(
                ratio(action, 2) > 1.5,
                "the joint estimator's bias: {action:?}"
            );
        }
    }
}
