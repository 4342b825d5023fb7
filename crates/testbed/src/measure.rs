//! Measuring the true models as the paper did (section VII), from the physics
//! alone: a stopwatch on the walking robot, and readings taken standing at
//! marked distances. These are the references the learned models are judged
//! against.

use quadsim::{QuadrupedSim, RobotDescription, RobotScale, SimConfig, SimError};
use rayon::prelude::*;

/// The stopwatch protocol's settings.
///
/// Each command is timed across `distance_m` five times in a row, after the gait
/// has settled at it. Half a metre is at least four gait cycles at every
/// command, so where in its cycle the gait is when the watch starts or stops
/// matters little: the timings of a command agree within a few mm/s. Forwards
/// commands start far from the beacon and backwards ones near it, so that the
/// whole walk (about 3.3 m at the fastest) stays in sight of the beacon.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StopwatchConfig {
    /// Standing still before the command is given, s.
    pub stand_s: f64,
    /// Walking at the command before the first timing starts, s.
    pub settle_s: f64,
    /// The distance each timing covers, m.
    pub distance_m: f64,
    /// Timings per command.
    pub repeats: usize,
    /// A timing that has not covered the distance by then ends with the distance
    /// covered so far, s (for commands that barely move the robot).
    pub max_timing_s: f64,
    /// Where a forwards (or zero) command starts, m from the beacon.
    pub forwards_start_m: f64,
    /// Where a backwards command starts, m from the beacon.
    pub backwards_start_m: f64,
}

impl Default for StopwatchConfig {
    fn default() -> Self {
        Self {
            stand_s: 1.0,
            settle_s: 3.0,
            distance_m: 0.5,
            repeats: 5,
            max_timing_s: 4.0,
            forwards_start_m: 4.2,
            backwards_start_m: 1.0,
        }
    }
}

impl StopwatchConfig {
    /// The protocol at the robot's scale: distances by `scale.length`, times by
    /// `scale.time()` (the defaults for the ERS-7).
    pub fn scaled(scale: RobotScale) -> Self {
        let (s, t) = (scale.length, scale.time());
        let d = Self::default();
        Self {
            stand_s: d.stand_s * t,
            settle_s: d.settle_s * t,
            distance_m: d.distance_m * s,
            repeats: d.repeats,
            max_timing_s: d.max_timing_s * t,
            forwards_start_m: d.forwards_start_m * s,
            backwards_start_m: d.backwards_start_m * s,
        }
    }
}

/// One command's measured velocity.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MeasuredVelocity {
    /// The walk command.
    pub command: f64,
    /// Mean forward velocity over the timings (towards the beacon positive), mm/s.
    pub velocity_mm_s: f64,
    /// Standard deviation over the timings, mm/s.
    pub std_mm_s: f64,
    /// Each timing's velocity, mm/s.
    pub timings_mm_s: Vec<f64>,
    /// Whether the robot stayed upright (torso up-vector z > 0.8) throughout.
    pub upright: bool,
    /// Whether the physics blew up while it was timed (see
    /// [`QuadrupedSim::blew_up_at_s`]). Absent, and so false, in the
    /// references of datasets written before it was measured.
    #[serde(default)]
    pub blew_up: bool,
}

impl MeasuredVelocity {
    /// The slowest timing (most negative), mm/s.
    pub fn min_mm_s(&self) -> f64 {
        self.timings_mm_s
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
    }

    /// The fastest timing, mm/s.
    pub fn max_mm_s(&self) -> f64 {
        self.timings_mm_s
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// Mean and population standard deviation.
fn mean_std(values: &[f64]) -> (f64, f64) {
    let n = values.len().max(1) as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    (mean, var.sqrt())
}

/// Times the robot at `command`: after standing and settling, it is timed `repeats`
/// times in a row across `distance_m` (or for `max_timing_s` if slower).
pub fn time_command(
    description: &RobotDescription,
    sim_config: SimConfig,
    stopwatch: &StopwatchConfig,
    command: f64,
) -> Result<MeasuredVelocity, SimError> {
    let start_distance_m = if command >= 0.0 {
        stopwatch.forwards_start_m
    } else {
        stopwatch.backwards_start_m
    };
    let mut sim = QuadrupedSim::new(
        description,
        SimConfig {
            start_distance_m,
            ..sim_config
        },
    )?;
    let dt = sim.config().dt_s;
    let mut upright = true;
    let run = |sim: &mut QuadrupedSim, seconds: f64, upright: &mut bool| {
        let n = (seconds / dt).round() as u64;
        for _ in 0..n {
            sim.step();
            *upright &= sim.is_upright();
        }
    };
    run(&mut sim, stopwatch.stand_s, &mut upright);
    sim.set_command(command)?;
    run(&mut sim, stopwatch.settle_s, &mut upright);
    let mut timings_mm_s = Vec::with_capacity(stopwatch.repeats);
    for _ in 0..stopwatch.repeats {
        let (start_d, start_t) = (sim.distance_along_line_m(), sim.time_s());
        loop {
            sim.step();
            upright &= sim.is_upright();
            let covered = start_d - sim.distance_along_line_m();
            let elapsed = sim.time_s() - start_t;
            if covered.abs() >= stopwatch.distance_m || elapsed >= stopwatch.max_timing_s {
                timings_mm_s.push(1000.0 * covered / elapsed);
                break;
            }
        }
    }
    let (velocity_mm_s, std_mm_s) = mean_std(&timings_mm_s);
    Ok(MeasuredVelocity {
        command,
        velocity_mm_s,
        std_mm_s,
        timings_mm_s,
        upright,
        blew_up: sim.blew_up_at_s().is_some(),
    })
}

/// The stand-and-read protocol's result at one distance.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MeasuredReading {
    /// Where the robot was put, mm from the beacon (torso centre, along the line).
    pub nominal_mm: f64,
    /// Where it actually was while it read: the ground-truth distance at each
    /// reading, averaged, mm. Stepping in place creeps a little, so this is the
    /// point's label, not the nominal distance.
    pub distance_mm: f64,
    /// Standard deviation of the distance over the readings, mm.
    pub distance_std_mm: f64,
    /// Mean of the readings, px.
    pub obs_px: f64,
    /// Their standard deviation, px.
    pub std_px: f64,
    /// Frames without a reading (they are not in the mean).
    pub missed: usize,
}

/// The paper's 13 distances, 1.2, 1.4, ..., 3.6 m, at the robot's scale
/// (`scale.length` times these).
pub fn paper_distances_m(scale: RobotScale) -> Vec<f64> {
    (0..13)
        .map(|k| (1.2 + 0.2 * f64::from(k)) * scale.length)
        .collect()
}

/// Stands the robot at `distance_m`, stepping in place with `hold_command`, and
/// averages `readings` camera readings after `settle_s`, each labelled with the
/// distance the robot had when it was taken. `noise_seed` seeds the camera's
/// noise, so that each distance gets its own noise rather than all sharing one
/// offset.
pub fn read_at(
    description: &RobotDescription,
    sim_config: SimConfig,
    distance_m: f64,
    readings: usize,
    settle_s: f64,
    noise_seed: u64,
    hold_command: f64,
) -> Result<MeasuredReading, SimError> {
    let mut config = SimConfig {
        start_distance_m: distance_m,
        ..sim_config
    };
    config.camera.noise_seed = noise_seed;
    let mut sim = QuadrupedSim::new(description, config)?;
    sim.set_command(hold_command)?;
    sim.advance(settle_s);
    let (mut obs, mut at_mm, mut missed) = (
        Vec::with_capacity(readings),
        Vec::with_capacity(readings),
        0,
    );
    // Bounded: a beacon that is never seen must not hang the protocol.
    let max_frames = 4 * readings;
    let mut frames = 0;
    while obs.len() < readings && frames < max_frames {
        sim.step();
        if let Some(f) = sim.take_frame() {
            frames += 1;
            match f.obs_px {
                Ok(o) => {
                    obs.push(o);
                    at_mm.push(1000.0 * sim.distance_along_line_m());
                }
                Err(_) => missed += 1,
            }
        }
    }
    let (obs_px, std_px) = mean_std(&obs);
    let (distance_mm, distance_std_mm) = mean_std(&at_mm);
    Ok(MeasuredReading {
        nominal_mm: 1000.0 * distance_m,
        distance_mm: if obs.is_empty() {
            f64::NAN
        } else {
            distance_mm
        },
        distance_std_mm,
        obs_px: if obs.is_empty() { f64::NAN } else { obs_px },
        std_px,
        missed,
    })
}

/// The stand-and-read protocol at every distance, in parallel, in the order
/// given; the camera noise at distance `k` is seeded `k`. The robot steps in
/// place with `hold_command` (see [`hold_command`]).
pub fn measure_sensor(
    description: &RobotDescription,
    sim_config: SimConfig,
    distances_m: &[f64],
    readings: usize,
    hold_command: f64,
) -> Result<Vec<MeasuredReading>, SimError> {
    distances_m
        .par_iter()
        .enumerate()
        .map(|(k, &d)| {
            read_at(
                description,
                sim_config,
                d,
                readings,
                1.0,
                k as u64,
                hold_command,
            )
        })
        .collect()
}

/// The command at which the robot steps in place without creeping: where the
/// measured velocity crosses zero (linear between the two commands around it),
/// or 0 if it never does. The idle gait (command 0) creeps forwards on most
/// robots; stepping in place with this command keeps the robot where it was put
/// while it reads, and keeps the head's bob, which spreads the quantised pixel
/// extent into a smooth mean.
pub fn hold_command(measured: &[MeasuredVelocity]) -> f64 {
    let crossing = measured.windows(2).find_map(|w| {
        let (a, b) = (&w[0], &w[1]);
        let crosses = a.velocity_mm_s <= 0.0 && b.velocity_mm_s > 0.0;
        crosses.then(|| {
            let f = -a.velocity_mm_s / (b.velocity_mm_s - a.velocity_mm_s);
            a.command + f * (b.command - a.command)
        })
    });
    crossing.unwrap_or(0.0)
}

/// Measures every command, in parallel, in the order given.
pub fn measure_action(
    description: &RobotDescription,
    sim_config: SimConfig,
    stopwatch: &StopwatchConfig,
    commands: &[f64],
) -> Result<Vec<MeasuredVelocity>, SimError> {
    commands
        .par_iter()
        .map(|&c| time_command(description, sim_config, stopwatch, c))
        .collect()
}
