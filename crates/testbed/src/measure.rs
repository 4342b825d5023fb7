//! Measuring the true models as the paper did (section VII), from the physics
//! alone: a stopwatch on the walking robot, and (later) readings at marked
//! distances. These are the references the learned models are judged against.

use quadsim::{QuadrupedSim, RobotDescription, SimConfig, SimError};
use rayon::prelude::*;

/// The stopwatch protocol's settings.
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
}

impl Default for StopwatchConfig {
    fn default() -> Self {
        Self {
            stand_s: 1.0,
            settle_s: 2.0,
            distance_m: 0.25,
            repeats: 5,
            max_timing_s: 6.0,
        }
    }
}

/// One command's measured velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasuredVelocity {
    /// The walk command.
    pub command: f64,
    /// Mean forward velocity over the timings (towards the beacon positive), mm/s.
    pub velocity_mm_s: f64,
    /// Standard deviation over the timings, mm/s.
    pub std_mm_s: f64,
    /// Whether the robot stayed upright (torso up-vector z > 0.8) throughout.
    pub upright: bool,
}

/// Times the robot at `command`: after standing and settling, it is timed `repeats`
/// times across `distance_m` (or for `max_timing_s` if slower).
pub fn time_command(
    description: &RobotDescription,
    sim_config: SimConfig,
    stopwatch: &StopwatchConfig,
    command: f64,
) -> Result<MeasuredVelocity, SimError> {
    let mut sim = QuadrupedSim::new(description, sim_config)?;
    let dt = sim_config.dt_s;
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
    let mut velocities = Vec::with_capacity(stopwatch.repeats);
    for _ in 0..stopwatch.repeats {
        let (start_d, start_t) = (sim.distance_along_line_m(), sim.time_s());
        loop {
            sim.step();
            upright &= sim.is_upright();
            let covered = start_d - sim.distance_along_line_m();
            let elapsed = sim.time_s() - start_t;
            if covered.abs() >= stopwatch.distance_m || elapsed >= stopwatch.max_timing_s {
                velocities.push(1000.0 * covered / elapsed);
                break;
            }
        }
    }
    let n = velocities.len() as f64;
    let mean = velocities.iter().sum::<f64>() / n;
    let std = (velocities.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
    Ok(MeasuredVelocity {
        command,
        velocity_mm_s: mean,
        std_mm_s: std,
        upright,
    })
}

/// The stand-and-read protocol's result at one distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasuredReading {
    /// Distance from the beacon, mm (torso centre, along the line).
    pub distance_mm: f64,
    /// Mean of the readings, px.
    pub obs_px: f64,
    /// Their standard deviation, px.
    pub std_px: f64,
    /// Frames without a reading (they are not in the mean).
    pub missed: usize,
}

/// The paper's 13 distances: 1.2, 1.4, ..., 3.6 m.
pub fn paper_distances_m() -> Vec<f64> {
    (0..13).map(|k| 1.2 + 0.2 * f64::from(k)).collect()
}

/// Stands the robot (idle gait) at `distance_m` and averages `readings` camera
/// readings, after `settle_s` of standing.
pub fn read_at(
    description: &RobotDescription,
    sim_config: SimConfig,
    distance_m: f64,
    readings: usize,
    settle_s: f64,
) -> Result<MeasuredReading, SimError> {
    let config = SimConfig {
        start_distance_m: distance_m,
        ..sim_config
    };
    let mut sim = QuadrupedSim::new(description, config)?;
    sim.advance(settle_s);
    let (mut obs, mut missed) = (Vec::with_capacity(readings), 0);
    // Bounded: a beacon that is never seen must not hang the protocol.
    let max_frames = 4 * readings;
    let mut frames = 0;
    while obs.len() < readings && frames < max_frames {
        sim.step();
        if let Some(f) = sim.take_frame() {
            frames += 1;
            match f.obs_px {
                Ok(o) => obs.push(o),
                Err(_) => missed += 1,
            }
        }
    }
    let n = obs.len().max(1) as f64;
    let mean = obs.iter().sum::<f64>() / n;
    let std = (obs.iter().map(|o| (o - mean).powi(2)).sum::<f64>() / n).sqrt();
    Ok(MeasuredReading {
        distance_mm: 1000.0 * distance_m,
        obs_px: if obs.is_empty() { f64::NAN } else { mean },
        std_px: std,
        missed,
    })
}

/// The stand-and-read protocol at every distance, in parallel, in the order given.
pub fn measure_sensor(
    description: &RobotDescription,
    sim_config: SimConfig,
    distances_m: &[f64],
    readings: usize,
) -> Result<Vec<MeasuredReading>, SimError> {
    distances_m
        .par_iter()
        .map(|&d| read_at(description, sim_config, d, readings, 1.0))
        .collect()
}

/// The paper's 31 commands: every multiple of 20 in [-300, 300].
pub fn paper_commands() -> Vec<f64> {
    (-15..=15).map(|k| 20.0 * f64::from(k)).collect()
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
