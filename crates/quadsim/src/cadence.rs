//! The scaled gait's cadence fitted to a robot that cannot walk it.
//!
//! Dynamic similarity scales the ERS-7's gait to another robot's size, but it
//! does not make a position-controlled trot stable on it: a trot rocks about
//! its support diagonals when the cycle is slow for the body, and the ERS-7's
//! own gait sits close to that edge (its cycle 1.4 times slower rocks it by
//! 0.1 rad). A robot with its mass elsewhere may be past the edge at the
//! scaled cadence: the Unitree A1, scaled, rocks by 0.14 rad and walks
//! backwards at a forward command.
//!
//! The walk test ([`check_walk`]): from standing, the robot walks each of the
//! paper's 31 commands (every 20 mm/s from -300 to 300, at its speed scale,
//! as the stopwatch times them), and passes if it stays upright, its
//! torso's tilt (from vertical) has a root mean square of at most
//! [`MAX_RMS_TILT_RAD`] in each walk, and its velocities increase with the
//! command. [`fit`] tries the cadence factors of [`FACTORS`] in turn, each
//! multiplying the gait's periods and step lengths (so the speeds Eq. 1's
//! commands stand for are kept, and only the cadence quickens), and keeps the
//! first that passes, the scaled gait itself first.

use crate::config::SimConfig;
use crate::description::RobotDescription;
use crate::error::SimError;
use crate::gait::GaitTable;
use crate::scale::RobotScale;
use crate::sim::QuadrupedSim;

/// The cadence factors tried, in order: the scaled gait, then ever quicker.
pub const FACTORS: [f64; 6] = [1.0, 0.9, 0.8, 0.7, 0.6, 0.5];

/// The most a walk may rock: the root mean square of the torso's tilt from
/// vertical over a walk, rad (about 6 degrees; the ERS-7's own gait rocks
/// by at most 0.07, walking backwards at full speed).
pub const MAX_RMS_TILT_RAD: f64 = 0.1;

/// After the start ramp, a walk settles for this long before it is measured,
/// and is measured for as long again, in the ERS-7's seconds (scaled by the
/// robot's time scale, as the gait's periods are).
const SETTLE_S: f64 = 3.0;
const MEASURE_S: f64 = 2.0;

/// `table` with its cadence quickened by `factor` (< 1: quicker): every
/// period and step length times `factor`, the speeds unchanged.
pub fn quicken(table: GaitTable, factor: f64) -> GaitTable {
    let mut t = table;
    for p in [&mut t.idle, &mut t.fast_forwards, &mut t.fast_backwards] {
        p.period_s *= factor;
        p.step_length_m *= factor;
    }
    t
}

/// One walk of the test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TestWalk {
    /// The command, mm/s.
    pub command_mm_s: f64,
    /// The torso's mean velocity along the line of approach while measured, mm/s.
    pub velocity_mm_s: f64,
    /// The root mean square of the torso's tilt from vertical while measured, rad.
    pub rms_tilt_rad: f64,
    /// Whether the torso stayed upright all along.
    pub upright: bool,
}

/// The walk test's outcome: its walks, slowest command first.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkCheck {
    /// The walks.
    pub walks: Vec<TestWalk>,
}

impl WalkCheck {
    /// What fails the test, or `None` if it passes.
    pub fn failure(&self) -> Option<String> {
        if let Some(w) = self.walks.iter().find(|w| !w.upright) {
            return Some(format!("fell at command {:.0} mm/s", w.command_mm_s));
        }
        if let Some(w) = self
            .walks
            .iter()
            .find(|w| w.rms_tilt_rad.is_nan() || w.rms_tilt_rad > MAX_RMS_TILT_RAD)
        {
            return Some(format!(
                "rocked by {:.3} rad RMS at command {:.0} mm/s (at most {MAX_RMS_TILT_RAD})",
                w.rms_tilt_rad, w.command_mm_s
            ));
        }
        self.walks.windows(2).find_map(|pair| {
            (pair[1].velocity_mm_s.partial_cmp(&pair[0].velocity_mm_s)
                != Some(std::cmp::Ordering::Greater))
            .then(|| {
                format!(
                    "walked {:.0} mm/s at command {:.0} and {:.0} mm/s at {:.0}: not faster \
                     for a faster command",
                    pair[0].velocity_mm_s,
                    pair[0].command_mm_s,
                    pair[1].velocity_mm_s,
                    pair[1].command_mm_s
                )
            })
        })
    }
}

/// Walks `description` with `config` at the test's commands, each from a
/// fresh start (see the module's documentation), outwards from command 0,
/// stopping at the first failure: the walks so far, in command order.
pub fn check_walk(
    description: &RobotDescription,
    config: SimConfig,
) -> Result<WalkCheck, SimError> {
    let scale = RobotScale::of(description);
    let settle_s = config.walk.start_ramp_s + SETTLE_S * scale.time();
    let measure_s = MEASURE_S * scale.time();
    // Outwards from standing still: a gait that fails usually fails near
    // zero first, where the idle gait's creep meets the slowest steps.
    let mut commands = scale.paper_commands();
    commands.sort_by(|a, b| a.abs().total_cmp(&b.abs()).then(a.total_cmp(b)));
    let side_by_side = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut check = WalkCheck { walks: Vec::new() };
    // Each walk is its own world: a batch runs side by side, bit for bit as
    // one after the other.
    for batch in commands.chunks(side_by_side) {
        let walks = std::thread::scope(|scope| {
            let handles: Vec<_> = batch
                .iter()
                .map(|&command_mm_s| {
                    scope
                        .spawn(move || walk(description, config, command_mm_s, settle_s, measure_s))
                })
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().expect("a test walk panicked"))
                .collect::<Result<Vec<_>, _>>()
        })?;
        check.walks.extend(walks);
        // The walks so far cover a contiguous run of the commands.
        check
            .walks
            .sort_by(|a, b| a.command_mm_s.total_cmp(&b.command_mm_s));
        if check.failure().is_some() {
            break;
        }
    }
    Ok(check)
}

/// One walk of the test: from standing at `command_mm_s`, settled for
/// `settle_s` and measured for `measure_s`.
fn walk(
    description: &RobotDescription,
    config: SimConfig,
    command_mm_s: f64,
    settle_s: f64,
    measure_s: f64,
) -> Result<TestWalk, SimError> {
    let mut sim = QuadrupedSim::new(description, config)?;
    sim.set_command(command_mm_s)?;
    let mut upright = true;
    while sim.time_s() < settle_s {
        sim.step();
        upright &= sim.is_upright();
    }
    let (t0, x0) = (sim.time_s(), sim.torso().position_m[0]);
    let (mut sum_sq, mut n) = (0.0, 0.0);
    while sim.time_s() < settle_s + measure_s {
        sim.step();
        upright &= sim.is_upright();
        let tilt = sim.torso().up[2].clamp(-1.0, 1.0).acos();
        sum_sq += tilt * tilt;
        n += 1.0;
    }
    let (t1, x1) = (sim.time_s(), sim.torso().position_m[0]);
    Ok(TestWalk {
        command_mm_s,
        velocity_mm_s: 1000.0 * (x1 - x0) / (t1 - t0),
        rms_tilt_rad: (sum_sq / n).sqrt(),
        upright,
    })
}

/// The cadence [`fit`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct Cadence {
    /// The factor kept (1: the scaled gait).
    pub factor: f64,
    /// The failures of the factors tried before it, in order.
    pub rejected: Vec<(f64, String)>,
}

/// The first factor of [`FACTORS`] whose gait (`config` for `factor`) passes
/// the walk test, or every factor's failure if none does.
pub fn fit(
    description: &RobotDescription,
    config_for: impl Fn(f64) -> SimConfig,
) -> Result<Result<Cadence, Vec<(f64, String)>>, SimError> {
    let mut rejected = Vec::new();
    for factor in FACTORS {
        match check_walk(description, config_for(factor))?.failure() {
            None => return Ok(Ok(Cadence { factor, rejected })),
            Some(why) => rejected.push((factor, why)),
        }
    }
    Ok(Err(rejected))
}
