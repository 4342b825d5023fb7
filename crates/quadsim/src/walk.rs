//! The walk engine: turns a walk command into twelve joint targets, the way the
//! robot's own motion module would. The command sets the gait parameters by Eq. 1;
//! a change of command is slewed so the feet never jump; a trot clock places each
//! foot on its locus; inverse kinematics turns feet into angles. By default the
//! walk is open loop; `pitch_gain` lets it take out a share of the torso's pitch.

use crate::description::LegDescription;
use crate::error::RobotError;
use crate::gait::{FootTarget, GaitClock, GaitTable, foot_target};
use crate::ik::{self, LegAngles, LegGeometry};

/// Settings of the walk engine beyond the gait table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkConfig {
    /// The three parameter vectors and Eq. 1's speeds.
    pub gait: GaitTable,
    /// How fast the command in effect may change, (mm/s) per s.
    pub command_slew_mm_s2: f64,
    /// Time over which stepping ramps in from standing at the start, s.
    pub start_ramp_s: f64,
    /// How much of the torso's pitch, as its tilt sensor reads it, the legs
    /// take out: each foot is raised by `pitch_gain` times the pitch times
    /// its leg's distance ahead of the torso's centre (0: open loop).
    pub pitch_gain: f64,
}

impl Default for WalkConfig {
    fn default() -> Self {
        Self {
            gait: GaitTable::default(),
            command_slew_mm_s2: 1500.0,
            start_ramp_s: 1.0,
            pitch_gain: 0.0,
        }
    }
}

/// Per-leg constants: where the hip is, how the leg bends, its trot phase.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Leg {
    geometry: LegGeometry,
    /// The abduction joint's distance ahead of the torso's centre, m.
    ahead_m: f64,
    side: f64,
    phase_offset: f64,
}

impl Leg {
    /// Where the foot must be, relative to the abduction joint, for the
    /// gait's target relative to the hip joint (below it, outwards of the
    /// leg's plane).
    fn target(&self, t: FootTarget) -> [f64; 3] {
        let g = &self.geometry;
        let [forwards, up] = g.hip_at_m;
        [
            t.x + forwards,
            self.side * t.outwards + g.hip_offset_m,
            t.z + up,
        ]
    }
}

/// The walk engine's state.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkEngine {
    config: WalkConfig,
    legs: Vec<Leg>,
    clock: GaitClock,
    command_mm_s: f64,
    elapsed_s: f64,
}

impl WalkEngine {
    /// An engine for these legs (each knee bending as
    /// [`LegDescription::knee_sign`] says; diagonal pairs step together).
    pub fn new(config: WalkConfig, legs: &[LegDescription]) -> Self {
        let legs = legs
            .iter()
            .map(|l| {
                let front = l.is_front();
                Leg {
                    geometry: l.geometry(l.knee_sign()),
                    ahead_m: l.hip_in_torso_m[0],
                    side: l.side(),
                    // fl with hr, fr with hl.
                    phase_offset: if front == (l.side() > 0.0) { 0.0 } else { 0.5 },
                }
            })
            .collect();
        Self {
            config,
            legs,
            clock: GaitClock::default(),
            command_mm_s: 0.0,
            elapsed_s: 0.0,
        }
    }

    /// The command in effect after slewing, mm/s.
    pub fn command_in_effect(&self) -> f64 {
        self.command_mm_s
    }

    /// Checks that every leg can walk the gait at every command in
    /// `[v_min, v_max]` (21 commands, 64 phases of each cycle, no steering):
    /// each foot target within reach and each joint angle within its URDF
    /// limits; or says which leg or joint cannot, and where.
    pub fn check_feasible(config: &WalkConfig, legs: &[LegDescription]) -> Result<(), RobotError> {
        const COMMANDS: u32 = 21;
        const PHASES: u32 = 64;
        let g = &config.gait;
        let engine = Self::new(*config, legs);
        for (leg, description) in engine.legs.iter().zip(legs) {
            for c in 0..COMMANDS {
                let t = f64::from(c) / f64::from(COMMANDS - 1);
                let command_mm_s = g.v_min_mm_s + t * (g.v_max_mm_s - g.v_min_mm_s);
                let p = g.params_for(command_mm_s);
                for k in 0..PHASES {
                    let phase = f64::from(k) / f64::from(PHASES);
                    let target_m = leg.target(foot_target(&p, p.step_length_m, phase));
                    let Some(a) = ik::inverse(&leg.geometry, target_m) else {
                        return Err(RobotError::GaitOutOfReach {
                            leg: description.name,
                            command_mm_s,
                            target_m,
                            thigh_m: leg.geometry.thigh_m,
                            shank_m: leg.geometry.shank_m,
                        });
                    };
                    let angles = [a.abduction, a.hip, a.knee];
                    for ((angle_rad, [lower_rad, upper_rad]), joint) in angles
                        .into_iter()
                        .zip(description.limits_rad)
                        .zip(&description.joints)
                    {
                        if !(lower_rad..=upper_rad).contains(&angle_rad) {
                            return Err(RobotError::GaitOutOfLimits {
                                joint: joint.clone(),
                                command_mm_s,
                                angle_rad,
                                lower_rad,
                                upper_rad,
                            });
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Advances by `dt_s` towards `command_mm_s`, turning by `steer_m` (positive:
    /// left, as a difference of step lengths between the sides) and taking out
    /// `pitch_gain` of the torso's pitch `pitch_rad` (nose up positive, as the
    /// tilt sensor reads it; unread at gain 0), and returns the joint targets
    /// for every leg, or `None` for a leg whose foot is out of reach.
    pub fn update(
        &mut self,
        dt_s: f64,
        command_mm_s: f64,
        steer_m: f64,
        pitch_rad: f64,
    ) -> Vec<Option<LegAngles>> {
        let max_change = self.config.command_slew_mm_s2 * dt_s;
        self.command_mm_s += (command_mm_s - self.command_mm_s).clamp(-max_change, max_change);
        self.elapsed_s += dt_s;
        let ramp = if self.config.start_ramp_s > 0.0 {
            (self.elapsed_s / self.config.start_ramp_s).min(1.0)
        } else {
            1.0
        };
        let mut p = self.config.gait.params_for(self.command_mm_s);
        p.step_height_m *= ramp;
        self.clock.advance(dt_s, p.period_s);
        self.legs
            .iter()
            .map(|leg| {
                let step = ramp * (p.step_length_m - leg.side * steer_m);
                let phase = (self.clock.phase() + leg.phase_offset).fract();
                let mut target = leg.target(foot_target(&p, step, phase));
                if self.config.pitch_gain != 0.0 {
                    target[2] += self.config.pitch_gain * pitch_rad * leg.ahead_m;
                }
                ik::inverse(&leg.geometry, target)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ERS7_URDF, RobotDescription};

    fn engine(pitch_gain: f64) -> (WalkEngine, RobotDescription) {
        let d = RobotDescription::from_urdf_str(ERS7_URDF).expect("urdf");
        let config = WalkConfig {
            pitch_gain,
            ..WalkConfig::default()
        };
        (WalkEngine::new(config, &d.legs), d)
    }

    #[test]
    fn without_a_gain_the_pitch_changes_nothing() {
        let (mut level, _) = engine(0.0);
        let mut told = level.clone();
        for k in 0..50 {
            let pitch = 0.1 * f64::from(k % 7) - 0.3;
            assert_eq!(
                level.update(0.008, 200.0, 0.0, 0.0),
                told.update(0.008, 200.0, 0.0, pitch)
            );
        }
    }

    #[test]
    fn a_nose_up_pitch_raises_the_front_feet_and_lowers_the_hind_ones() {
        let (mut level, d) = engine(0.3);
        let mut pitched = level.clone();
        let pitch = 0.1;
        let a = level.update(0.008, 200.0, 0.0, 0.0);
        let b = pitched.update(0.008, 200.0, 0.0, pitch);
        for ((leg, a), b) in d.legs.iter().zip(&a).zip(&b) {
            let g = leg.geometry(leg.knee_sign());
            let (a, b) = (a.expect("reached"), b.expect("reached"));
            let raised = ik::forward(&g, &b)[2] - ik::forward(&g, &a)[2];
            let want = 0.3 * pitch * leg.hip_in_torso_m[0];
            assert!(
                (raised - want).abs() < 1e-9,
                "{}: raised by {raised} m, want {want}",
                leg.name
            );
            assert_eq!(raised > 0.0, leg.is_front(), "{}", leg.name);
        }
    }
}
