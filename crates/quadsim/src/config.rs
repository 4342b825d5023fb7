//! Settings of one simulated world: the robot's controllers, camera, beacon
//! and floor, their validation, and which of them may change during a run.

use crate::beacon::BeaconConfig;
use crate::error::SimConfigError;
use crate::heading::HeadingConfig;
use crate::servo::ServoConfig;
use crate::vision::CameraConfig;
use crate::walk::WalkConfig;

/// How the physics steps the robot's multibody each step (`physics.multibody`).
/// Both are rapier's multibody with its constraint solver; they differ in the
/// free motion's integrator and in the linear algebra (`vendor/PATCH.md`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MultibodyDynamics {
    /// The mass matrix by the composite-rigid-body algorithm, factored once a
    /// step along the kinematic tree, its inverse serving every constraint
    /// row; Coriolis and gyroscopic forces explicit, as MuJoCo's
    /// `implicitfast` integrator has them (joint damping implicit in both).
    /// The default: the same robot as `Rapier` (the torsos' paths agree to
    /// a fraction of a millimetre over seconds of walking), at half the cost.
    #[default]
    Tree,
    /// rapier's own: the mass matrix summed as `J^T M J` over the links,
    /// with the Coriolis and gyroscopic forces linearised into it over the
    /// step (semi-implicit), factored by dense LU. The default until the
    /// tree's step was as fast as MuJoCo's; kept for comparison, and pinned
    /// bit for bit against rapier3d as published (`tests/upstream_fixture.rs`).
    Rapier,
}

impl MultibodyDynamics {
    /// Every value, as a scenario file writes it.
    pub const NAMES: [&'static str; 2] = ["tree", "rapier"];

    /// The value of a scenario file's `physics.multibody`.
    pub fn parse(text: &str) -> Result<Self, String> {
        match text {
            "tree" => Ok(Self::Tree),
            "rapier" => Ok(Self::Rapier),
            other => Err(format!(
                "`{other}` is not a multibody dynamics: one of {}",
                Self::NAMES.join(", ")
            )),
        }
    }

    /// As a scenario file writes it.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Tree => "tree",
            Self::Rapier => "rapier",
        }
    }

    /// rapier's setting.
    pub(crate) fn rapier(self) -> rapier3d::dynamics::MultibodyDynamics {
        match self {
            Self::Tree => rapier3d::dynamics::MultibodyDynamics::Tree,
            Self::Rapier => rapier3d::dynamics::MultibodyDynamics::ImplicitCoriolis,
        }
    }
}

/// Settings of one simulated world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimConfig {
    /// Physics timestep, s.
    pub dt_s: f64,
    /// Velocity-solver iterations per step.
    pub solver_iterations: usize,
    /// How the robot's multibody is stepped (`physics.multibody`).
    pub multibody: MultibodyDynamics,
    /// Coulomb friction of the feet and floor.
    pub friction: f64,
    /// Viscous damping on every rotational degree of freedom of the robot (its
    /// twelve joints and the torso's free rotation), N m s/rad. rapier gives
    /// each multibody 0.1 by default; it is set here so that it can scale with
    /// the robot (see [`crate::scale`]): on the ERS-7 it is nearly as strong as
    /// the servos' own damping, and left at 0.1 a robot 8 times heavier rocks
    /// and drifts.
    pub joint_damping_nm_s_per_rad: f64,
    /// The leg servos.
    pub servo: ServoConfig,
    /// The walk engine.
    pub walk: WalkConfig,
    /// The heading keeper.
    pub heading: HeadingConfig,
    /// The beacon.
    pub beacon: BeaconConfig,
    /// The head's camera.
    pub camera: CameraConfig,
    /// How far from the beacon the robot starts, facing it along +x, m.
    pub start_distance_m: f64,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            // 4 ms with one solver pass: the gait's speeds agree with 2 ms within
            // about 1 %, at twice the speed; 8 ms changes the physics visibly.
            dt_s: 0.004,
            solver_iterations: 1,
            multibody: MultibodyDynamics::Tree,
            friction: 0.9,
            joint_damping_nm_s_per_rad: 0.1,
            servo: ServoConfig::default(),
            walk: WalkConfig::default(),
            heading: HeadingConfig::default(),
            beacon: BeaconConfig::default(),
            camera: CameraConfig::default(),
            start_distance_m: 2.4,
        }
    }
}

impl SimConfig {
    /// Each checked value: its setting's key, the value, whether it is in
    /// range, and the range in words (for errors and the settings reference).
    pub fn ranges(&self) -> [(&'static str, f64, bool, &'static str); 21] {
        let (b, c) = (&self.beacon, &self.camera);
        [
            (
                "physics.dt",
                self.dt_s,
                (1e-4..=0.01).contains(&self.dt_s),
                "in [0.0001, 0.01] s (finer is days of computing a trial)",
            ),
            (
                "physics.solver_iterations",
                self.solver_iterations as f64,
                (1..=50).contains(&self.solver_iterations),
                "in 1..=50",
            ),
            (
                "world.friction",
                self.friction,
                self.friction >= 0.0 && self.friction <= 5.0,
                "in [0, 5]",
            ),
            (
                "physics.joint_damping",
                self.joint_damping_nm_s_per_rad,
                self.joint_damping_nm_s_per_rad >= 0.0,
                ">= 0 N m s/rad",
            ),
            (
                "servo.kp",
                self.servo.kp_nm_per_rad,
                self.servo.kp_nm_per_rad > 0.0,
                "> 0",
            ),
            (
                "servo.kd",
                self.servo.kd_nm_s_per_rad,
                self.servo.kd_nm_s_per_rad >= 0.0,
                ">= 0",
            ),
            (
                "servo.torque_scale",
                self.servo.torque_scale,
                (0.05..=20.0).contains(&self.servo.torque_scale),
                "in [0.05, 20]",
            ),
            (
                "servo.speed_scale",
                self.servo.speed_scale,
                (0.05..=20.0).contains(&self.servo.speed_scale),
                "in [0.05, 20]",
            ),
            (
                "servo.command_period",
                self.servo.command_period_s,
                self.servo.command_period_s >= self.dt_s,
                ">= physics.dt",
            ),
            (
                "world.start_distance_m",
                self.start_distance_m,
                self.start_distance_m > 0.3 && self.start_distance_m <= 100.0,
                "in (0.3, 100] m",
            ),
            (
                "walk.command_slew",
                self.walk.command_slew_mm_s2,
                (1.0..=1e6).contains(&self.walk.command_slew_mm_s2),
                "in [1, 1000000] (mm/s) per s",
            ),
            (
                "walk.pitch_gain",
                self.walk.pitch_gain,
                (0.0..=1.0).contains(&self.walk.pitch_gain),
                "in [0, 1]",
            ),
            (
                "beacon.radius_m",
                b.radius_m,
                (0.001..=5.0).contains(&b.radius_m),
                "in [0.001, 5] m",
            ),
            (
                "beacon.height_m",
                b.band_height_m,
                (0.01..=10.0).contains(&b.band_height_m),
                "in [0.01, 10] m",
            ),
            (
                "beacon.centre_m",
                b.band_centre_m,
                b.band_bottom_m() >= 0.0,
                ">= half the band's height (the band stands on the floor)",
            ),
            (
                "camera.width_px",
                f64::from(c.intrinsics.width_px),
                (8..=4096).contains(&c.intrinsics.width_px),
                "in [8, 4096] px",
            ),
            (
                "camera.height_px",
                f64::from(c.intrinsics.height_px),
                (8..=4096).contains(&c.intrinsics.height_px),
                "in [8, 4096] px",
            ),
            (
                "camera.hfov_deg",
                c.intrinsics.hfov_deg,
                c.intrinsics.hfov_deg > 0.0 && c.intrinsics.hfov_deg < 170.0,
                "in (0, 170) degrees",
            ),
            (
                "camera.vfov_deg",
                c.intrinsics.vfov_deg,
                c.intrinsics.vfov_deg > 0.0 && c.intrinsics.vfov_deg < 170.0,
                "in (0, 170) degrees",
            ),
            (
                "camera.noise_px",
                c.noise_px,
                (0.0..=50.0).contains(&c.noise_px),
                "in [0, 50] px",
            ),
            (
                "camera.frame_period_s",
                c.frame_period_s,
                c.frame_period_s >= self.dt_s && c.frame_period_s <= 1.0,
                "in [physics.dt, 1] s (a learner needs readings)",
            ),
        ]
    }

    /// Checks every value's range ([`SimConfig::ranges`]).
    pub fn validate(&self) -> Result<(), SimConfigError> {
        for (key, value, ok, expected) in self.ranges() {
            if !(ok && value.is_finite()) {
                return Err(SimConfigError::OutOfRange {
                    key,
                    expected,
                    value,
                });
            }
        }
        Ok(())
    }

    /// Checks that `new` differs from these settings only in what can change
    /// during a run ([`QuadrupedSim::change_world`](crate::sim::QuadrupedSim::change_world)): the floor's friction, the
    /// servos' torque and speed scales, the beacon's band (not where it stands)
    /// and the camera's noise. Names the first other setting that differs.
    pub fn check_live_change(&self, new: &SimConfig) -> Result<(), SimConfigError> {
        new.validate()?;
        let (a, b) = (self, new);
        let fixed: [(&'static str, bool); 13] = [
            ("physics.dt", a.dt_s == b.dt_s),
            (
                "physics.solver_iterations",
                a.solver_iterations == b.solver_iterations,
            ),
            ("physics.multibody", a.multibody == b.multibody),
            (
                "physics.joint_damping",
                a.joint_damping_nm_s_per_rad == b.joint_damping_nm_s_per_rad,
            ),
            ("servo.kp", a.servo.kp_nm_per_rad == b.servo.kp_nm_per_rad),
            (
                "servo.kd",
                a.servo.kd_nm_s_per_rad == b.servo.kd_nm_s_per_rad,
            ),
            (
                "servo.command_period",
                a.servo.command_period_s == b.servo.command_period_s,
            ),
            ("walk", a.walk == b.walk),
            ("heading", a.heading == b.heading),
            ("beacon.xy", a.beacon.xy_m == b.beacon.xy_m),
            (
                "camera intrinsics",
                a.camera.intrinsics == b.camera.intrinsics,
            ),
            (
                "camera.frame_period_s",
                a.camera.frame_period_s == b.camera.frame_period_s,
            ),
            (
                "world.start_distance_m",
                a.start_distance_m == b.start_distance_m,
            ),
        ];
        match fixed.iter().find(|(_, same)| !same) {
            Some(&(key, _)) => Err(SimConfigError::NotLive { key }),
            None => Ok(()),
        }
    }

    pub(crate) fn steps_per_command(&self) -> u64 {
        ((self.servo.command_period_s / self.dt_s).round() as u64).max(1)
    }
}
