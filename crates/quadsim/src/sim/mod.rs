//! The physical world: the quadruped as a rapier multibody on a floor, its servos
//! driven by the walk engine, and the ground-truth queries a testbed may make.
//! The robot moves only by its feet pushing on the floor.

use rapier3d::dynamics::{
    JointAxis, JointMotor, MotorModel, Multibody, MultibodyJointHandle, RigidBodyHandle,
};
use rapier3d::geometry::ColliderBuilder;
use rapier3d::math::{Pose, Real, Rotation, Vector};
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::RigidBodyBuilder;
use rapier3d_urdf::{UrdfLoaderOptions, UrdfMultibodyOptions, UrdfRobot};

use crate::config::SimConfig;
use crate::description::RobotDescription;
use crate::error::{RobotError, SimConfigError, SimError};
use crate::heading::HeadingKeeper;
use crate::ik::LegAngles;
use crate::joint_dynamics::JointDynamics;
use crate::servo::ServoSetpoints;
use crate::vision::{Camera, Frame};
use crate::walk::WalkEngine;

mod view;
use rapier3d::geometry::ColliderHandle;

/// The simulated robot in its world.
pub struct QuadrupedSim {
    config: SimConfig,
    world: PhysicsWorld,
    /// The floor's body.
    floor: RigidBodyHandle,
    /// The robot's links that have bodies: URDF name, body, and the link
    /// they hang from (an index into this list).
    links: Vec<(String, RigidBodyHandle, Option<usize>)>,
    torso: RigidBodyHandle,
    camera_parent: RigidBodyHandle,
    /// The camera's link and every link rigidly fixed to it (through fixed
    /// joints, up or down the tree): what the camera looks out of.
    camera_bodies: Vec<RigidBodyHandle>,
    camera_mount: Pose,
    /// Per leg: abduction, hip, knee.
    joints: Vec<[MultibodyJointHandle; 3]>,
    /// Each leg joint's URDF axis against its canonical one (see
    /// [`crate::description::LegDescription::axis_signs`]): the servos and
    /// the gait work about the canonical axes.
    axis_signs: Vec<[f64; 3]>,
    /// Per leg: the URDF's effort limits, N m, and velocity limits, rad/s
    /// (before the servo config's scales).
    urdf_limits: Vec<([f64; 3], [f64; 3])>,
    torque_limits: Vec<[f64; 3]>,
    /// Setpoint speed limits, rad/s, in the servos' order (leg by leg).
    speed_limits: Vec<f64>,
    walk: WalkEngine,
    servos: ServoSetpoints,
    heading: HeadingKeeper,
    /// The torso's attitude at the end of the previous step (the gyro measures
    /// the rotation between steps).
    last_attitude: Rotation,
    command_mm_s: f64,
    steps: u64,
    start_xy_m: [f64; 2],
    band: ColliderHandle,
    camera: Camera,
    frames_taken: u64,
    latest_frame: Option<Frame>,
    fresh_frame: bool,
    /// [`BLOW_UP_ENERGY`] times the potential energy of the robot's whole
    /// mass at its torso's standing height, J.
    blow_up_energy_j: f64,
    /// When the physics first blew up, s (see [`QuadrupedSim::blew_up_at_s`]).
    blew_up_at_s: Option<f64>,
    /// Each link's [`link_weights`], taken after the first step (the mass
    /// properties are final then, and nothing changes them after): the
    /// blow-up check's bound reads them every step.
    link_weights: Vec<(f32, f32)>,
}

/// A link's mass and largest principal moment of inertia, as its mass
/// properties give them (each the reciprocal of a stored inverse).
fn link_weights(local: &rapier3d::prelude::MassProperties) -> (f32, f32) {
    (local.mass(), local.principal_inertia().max_element())
}

/// A physics blow-up, told from a fall: the robot's kinetic energy (every
/// link's, translation and rotation) above this many times the potential
/// energy of its whole mass at its torso's standing height. A robot that
/// falls over turns at most about that potential energy into motion, and a
/// walking one has a tenth of it or less (the ERS-7 walking at command 300,
/// at its peak 9 %; the ANYmal C at 300, 3 %); ten times it would be a robot
/// a third of a metre tall moving at 7.7 m/s. The ANYmal C, blowing up as
/// it stands (README, "Robots by other makers"), crossed it with 44 times
/// the potential energy, 4.4 times this line.
pub const BLOW_UP_ENERGY: f64 = 10.0;

impl std::fmt::Debug for QuadrupedSim {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("QuadrupedSim")
            .field("time_s", &self.time_s())
            .field("command_mm_s", &self.command_mm_s)
            .field("config", &self.config)
            .finish_non_exhaustive()
    }
}

/// The torso's pose and motion, from the physics (ground truth).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorsoState {
    /// Position, m.
    pub position_m: [f64; 3],
    /// Orientation as a unit quaternion `[x, y, z, w]`.
    pub orientation: [f64; 4],
    /// Linear velocity, m/s.
    pub velocity_m_s: [f64; 3],
    /// The torso's up axis in the world (z component 1 when level).
    pub up: [f64; 3],
    /// Heading: the angle of the torso's forward axis about world z, rad.
    pub yaw_rad: f64,
}

impl QuadrupedSim {
    /// Builds the world and stands the robot on the floor at its start.
    pub fn new(description: &RobotDescription, config: SimConfig) -> Result<Self, SimError> {
        config.validate()?;
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -9.81);
        world.integration_parameters.dt = config.dt_s as Real;
        world.integration_parameters.num_solver_iterations = config.solver_iterations;

        let floor = world
            .bodies
            .insert(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -0.05)));
        world.colliders.insert_with_parent(
            ColliderBuilder::cuboid(50.0, 50.0, 0.05).friction(config.friction as Real),
            floor,
            &mut world.bodies,
        );

        // Stand the robot: torso high enough for the idle stance's feet to touch.
        let idle = config.walk.gait.idle;
        let leg = &description.legs[0];
        let hip_z = leg.hip_in_torso_m[2] + leg.hip_at_m[1];
        let torso_z = idle.body_height_m - hip_z + leg.foot_radius_m + 0.002;
        let band = config.beacon.insert(&mut world);
        let start_xy_m = [
            config.beacon.xy_m[0] - config.start_distance_m,
            config.beacon.xy_m[1],
        ];
        let options = UrdfLoaderOptions {
            shift: Pose::translation(
                start_xy_m[0] as Real,
                start_xy_m[1] as Real,
                torso_z as Real,
            ),
            collider_blueprint: ColliderBuilder::default()
                .density(0.0)
                .friction(config.friction as Real),
            ..Default::default()
        };
        let blueprint = options.collider_blueprint.clone();
        let mut robot = if description.meshes.is_empty() {
            UrdfRobot::from_robot(&description.urdf, options, std::path::Path::new(""))
        } else {
            // The meshes, loaded once with the description, go in as they are.
            let urdf = crate::mesh::without_meshes(&description.urdf);
            UrdfRobot::from_robot(&urdf, options, std::path::Path::new(""))
        };
        for m in &description.meshes {
            let link = robot
                .links
                .iter_mut()
                .find(|l| l.urdf_link_index == m.link)
                .ok_or_else(|| RobotError::MissingLink {
                    link: description.urdf.links[m.link].name.clone(),
                })?;
            for (shape, at) in &m.parts {
                let mut builder = blueprint.clone();
                builder.shape = shape.clone();
                link.colliders.push(rapier3d_urdf::UrdfCollider {
                    collider: builder.position(*at).build(),
                    visual: None,
                });
            }
        }
        let link_index: Vec<usize> = robot.links.iter().map(|l| l.urdf_link_index).collect();
        let joint_index: Vec<usize> = robot.joints.iter().map(|j| j.urdf_joint_index).collect();
        let handles = robot.insert_using_multibody_joints(
            &mut world.bodies,
            &mut world.colliders,
            &mut world.multibody_joints,
            UrdfMultibodyOptions::DISABLE_SELF_CONTACTS,
        );
        let body_of = |name: &str| {
            let i = description.urdf.links.iter().position(|l| l.name == name)?;
            let k = link_index.iter().position(|&u| u == i)?;
            Some(handles.links[k].body)
        };
        let joint_of = |name: &str| {
            let i = description
                .urdf
                .joints
                .iter()
                .position(|j| j.name == name)?;
            let k = joint_index.iter().position(|&u| u == i)?;
            handles.joints[k].joint
        };
        let mut links: Vec<(String, RigidBodyHandle, Option<usize>)> = Vec::new();
        for link in &description.urdf.links {
            if let Some(body) = body_of(&link.name) {
                links.push((link.name.clone(), body, None));
            }
        }
        for k in 0..links.len() {
            let parent = description
                .urdf
                .joints
                .iter()
                .find(|j| j.child.link == links[k].0)
                .and_then(|j| links.iter().position(|l| l.0 == j.parent.link));
            links[k].2 = parent;
        }
        // A checked description has these; the loader could still merge them away.
        let no_link = |link: &str| RobotError::MissingLink { link: link.into() };
        let torso =
            body_of(&description.root_link).ok_or_else(|| no_link(&description.root_link))?;
        let camera_parent = body_of(&description.camera.parent)
            .ok_or_else(|| no_link(&description.camera.parent))?;
        let camera_bodies =
            crate::urdf_tree::rigidly_fixed(&description.urdf, &description.camera.parent)
                .iter()
                .filter_map(|name| body_of(name))
                .collect();
        // The file's joint dynamics, by the multibody joint they act on.
        let joint_dynamics: Vec<(MultibodyJointHandle, JointDynamics)> = description
            .urdf
            .joints
            .iter()
            .filter_map(|j| Some((joint_of(&j.name)?, JointDynamics::of(description, j)?)))
            .collect();
        let mut joints = Vec::new();
        let mut urdf_limits = Vec::new();
        for leg in &description.legs {
            let mut h = Vec::new();
            for name in &leg.joints {
                h.push(joint_of(name).ok_or_else(|| RobotError::MissingJoint {
                    joint: name.clone(),
                })?);
            }
            joints.push([h[0], h[1], h[2]]);
            urdf_limits.push((leg.effort_nm, leg.velocity_rad_s));
        }

        let camera_mount = crate::pose::urdf_pose(description.camera.xyz, description.camera.rpy);

        WalkEngine::check_feasible(&config.walk, &description.legs)?;
        let mut walk = WalkEngine::new(config.walk, &description.legs);
        let initial = walk.update(0.0, 0.0, 0.0, 0.0);
        let initial_angles: Vec<f64> = initial
            .iter()
            .flat_map(|a| {
                let a = a.unwrap_or_default();
                [a.abduction, a.hip, a.knee]
            })
            .collect();

        let last_attitude = world.bodies[torso].position().rotation;
        // The URDF's masses (rapier fills in the bodies' own at the first step).
        let mass_kg: f64 = description
            .urdf
            .links
            .iter()
            .map(|l| l.inertial.mass.value)
            .sum();
        let blow_up_energy_j = BLOW_UP_ENERGY * mass_kg * 9.81 * torso_z;
        let mut sim = Self {
            config,
            world,
            floor,
            links,
            torso,
            camera_parent,
            camera_bodies,
            camera_mount,
            joints,
            axis_signs: description.legs.iter().map(|l| l.axis_signs).collect(),
            torque_limits: Vec::new(),
            speed_limits: Vec::new(),
            urdf_limits,
            walk,
            servos: ServoSetpoints::new(initial_angles.clone()),
            heading: HeadingKeeper::default(),
            last_attitude,
            command_mm_s: 0.0,
            steps: 0,
            start_xy_m,
            band,
            camera: Camera::new(config.camera),
            frames_taken: 0,
            latest_frame: None,
            fresh_frame: false,
            blow_up_energy_j,
            blew_up_at_s: None,
            link_weights: Vec::new(),
        };
        sim.set_joint_dynamics(&joint_dynamics);
        sim.scale_limits();
        sim.pose_joints(&initial_angles);
        sim.motorise_joints();
        sim.apply_servos();
        Ok(sim)
    }

    /// Sets the damping of every rotational degree of freedom (those rapier
    /// damps by default) to the configured value, adds the model file's own
    /// joint dynamics (see [`JointDynamics`]) on top, and sets how the
    /// multibody is stepped.
    fn set_joint_dynamics(&mut self, dynamics: &[(MultibodyJointHandle, JointDynamics)]) {
        let damping = self.config.joint_damping_nm_s_per_rad as Real;
        let dofs: Vec<(usize, usize, JointDynamics)> = dynamics
            .iter()
            .filter_map(|(h, d)| {
                let (mb, id) = self.world.multibody_joints.get(*h)?;
                let link = mb.link(id)?;
                Some((link.assembly_id(), link.joint().ndofs(), *d))
            })
            .collect();
        if let Some((mb, _)) = self.world.multibody_joints.get_mut(self.joints[0][0]) {
            for d in mb.damping_mut().iter_mut().filter(|d| **d != 0.0) {
                *d = damping;
            }
            for (first, n, d) in dofs {
                for i in first..first + n {
                    mb.damping_mut()[i] += d.damping as Real;
                    mb.frictions_mut()[i] = d.friction as Real;
                    mb.armature_mut()[i] = d.armature as Real;
                }
            }
            mb.set_dynamics(self.config.multibody.rapier());
        }
    }

    /// The servos' torque and speed limits: the URDF's, times the config's scales.
    fn scale_limits(&mut self) {
        let s = self.config.servo;
        self.torque_limits = self
            .urdf_limits
            .iter()
            .map(|(effort, _)| effort.map(|e| e * s.torque_scale))
            .collect();
        self.speed_limits = self
            .urdf_limits
            .iter()
            .flat_map(|(_, velocity)| velocity.map(|v| v * s.speed_scale))
            .collect();
    }

    /// Changes the world during a run, between two steps: the floor's and the
    /// feet's friction, the servos' torque and speed scales (a tiring
    /// battery), the beacon's band, the camera's noise. Anything else cannot
    /// change once the world is built, and is refused (see
    /// [`SimConfig::check_live_change`]); then nothing changes. The camera's
    /// noise stream carries on where it was.
    pub fn change_world(&mut self, new: SimConfig) -> Result<(), SimConfigError> {
        let mut new = new;
        new.camera.noise_seed = self.config.camera.noise_seed;
        self.config.check_live_change(&new)?;
        let old = std::mem::replace(&mut self.config, new);
        if new.friction != old.friction {
            let beacon = self.world.colliders[self.band].parent();
            let friction = new.friction as Real;
            for (_, collider) in self.world.colliders.iter_mut() {
                if collider.parent() != beacon {
                    collider.set_friction(friction);
                }
            }
        }
        if new.servo != old.servo {
            self.scale_limits();
            self.apply_servos();
        }
        if new.beacon != old.beacon {
            if let Some(body) = self.world.colliders[self.band].parent() {
                self.world.remove_body_with_colliders(body, true);
            }
            self.band = new.beacon.insert(&mut self.world);
        }
        if new.camera.noise_px != old.camera.noise_px {
            self.camera.set_noise_px(new.camera.noise_px);
        }
        Ok(())
    }

    /// Places the joints at these angles (abduction, hip, knee per leg) before the
    /// first step, so the robot starts standing rather than falling into its stance.
    fn pose_joints(&mut self, angles: &[f64]) {
        let Some((mb, _)) = self.world.multibody_joints.get_mut(self.joints[0][0]) else {
            return;
        };
        let mut disp: Vec<Real> = vec![0.0; mb.ndofs()];
        for (leg, handles) in self.joints.iter().enumerate() {
            for (k, h) in handles.iter().enumerate() {
                if let Some(link) = self
                    .world
                    .multibody_joints
                    .get(*h)
                    .and_then(|(mb, id)| mb.link(id))
                {
                    disp[link.assembly_id()] =
                        (self.axis_signs[leg][k] * angles[3 * leg + k]) as Real;
                }
            }
        }
        if let Some((mb, _)) = self.world.multibody_joints.get_mut(self.joints[0][0]) {
            mb.apply_displacements(&disp);
            mb.forward_kinematics(&self.world.bodies, true);
            mb.update_rigid_bodies(&mut self.world.bodies, false);
        }
    }

    /// Makes each leg joint's angular axis a force-based motor (once, at build).
    fn motorise_joints(&mut self) {
        for h in self.joints.iter().flatten() {
            if let Some((mb, id)) = self.world.multibody_joints.get_mut(*h) {
                if let Some(link) = mb.link_mut(id) {
                    let data = &mut link.joint.data;
                    data.set_motor_model(JointAxis::AngX, MotorModel::ForceBased);
                    data.set_motor(JointAxis::AngX, 0.0, 0.0, 0.0, 0.0);
                }
            }
        }
    }

    /// Writes the servo setpoints into the physics' joint motors. (Through
    /// `link_motor_mut`, which leaves the multibody's kinematics valid, so the
    /// physics need not redo them at the start of the step.)
    fn apply_servos(&mut self) {
        let s = self.config.servo;
        for (leg, handles) in self.joints.iter().enumerate() {
            for (k, h) in handles.iter().enumerate() {
                let i = 3 * leg + k;
                if let Some((mb, id)) = self.world.multibody_joints.get_mut(*h) {
                    if let Some(motor) = angular_motor(mb, id) {
                        let sign = self.axis_signs[leg][k];
                        motor.target_pos = (sign * self.servos.positions()[i]) as Real;
                        motor.target_vel = (sign * self.servos.velocities()[i]) as Real;
                        motor.stiffness = s.kp_nm_per_rad as Real;
                        motor.damping = s.kd_nm_s_per_rad as Real;
                        motor.max_force = self.torque_limits[leg][k] as Real;
                    }
                }
            }
        }
    }

    /// Sets the walk command (a desired velocity in [-300, 300] mm/s by Eq. 1's
    /// convention; values beyond it extrapolate the gait). Non-finite commands are
    /// refused.
    pub fn set_command(&mut self, command_mm_s: f64) -> Result<(), SimConfigError> {
        if !command_mm_s.is_finite() {
            return Err(SimConfigError::OutOfRange {
                key: "command",
                expected: "finite",
                value: command_mm_s,
            });
        }
        self.command_mm_s = command_mm_s;
        Ok(())
    }

    /// The command set last.
    pub fn command(&self) -> f64 {
        self.command_mm_s
    }

    /// Advances the physics by one timestep (and the robot's controllers when their
    /// period comes round).
    pub fn step(&mut self) {
        if self.steps % self.config.steps_per_command() == 0 {
            self.control();
        }
        self.world.step();
        if self.link_weights.is_empty() {
            self.link_weights = (self.links.iter())
                .map(|(_, handle, _)| {
                    link_weights(&self.world.bodies[*handle].mass_properties().local_mprops)
                })
                .collect();
        }
        let rate = self.gyro();
        self.heading.integrate(rate, self.config.dt_s);
        self.steps += 1;
        // The exact energy only when a cheap bound on it does not already
        // clear the threshold by a factor of two (rounding aside, the bound
        // is never below the energy); a NaN bound is checked exactly.
        let clearly_calm = || {
            let bound_j = self.kinetic_energy_bound_j();
            bound_j.is_finite() && bound_j <= 0.5 * self.blow_up_energy_j
        };
        if self.blew_up_at_s.is_none() && !clearly_calm() {
            let energy_j = self.kinetic_energy_j();
            if !energy_j.is_finite() || energy_j > self.blow_up_energy_j {
                self.blew_up_at_s = Some(self.time_s());
            }
        }
        // Frames come at their own rate: the first at one frame period, then
        // whenever simulated time reaches the next multiple of it.
        let next_frame_s = (self.frames_taken + 1) as f64 * self.config.camera.frame_period_s;
        if self.time_s() + 0.5 * self.config.dt_s >= next_frame_s {
            self.frames_taken += 1;
            let pose = self.camera_pose();
            let frame = self.camera.capture(
                next_frame_s,
                &self.world,
                &pose,
                &self.config.beacon,
                self.band,
                &self.camera_bodies,
            );
            self.heading.observe_bearing(frame.bearing_rad);
            self.latest_frame = Some(frame);
            self.fresh_frame = true;
        }
    }

    /// The frame taken since the last call, if any (the host's 20 Hz readings).
    pub fn take_frame(&mut self) -> Option<Frame> {
        if self.fresh_frame {
            self.fresh_frame = false;
            self.latest_frame
        } else {
            None
        }
    }

    /// Advances by whole timesteps covering `duration_s`.
    pub fn advance(&mut self, duration_s: f64) {
        let n = (duration_s / self.config.dt_s).round() as u64;
        for _ in 0..n {
            self.step();
        }
    }

    /// One tick of the robot's own control: read the gyro, steer, plan the feet,
    /// move the servo setpoints.
    fn control(&mut self) {
        let period = self.config.servo.command_period_s;
        let steer = self.heading.steer(&self.config.heading, self.command_mm_s);
        // The tilt sensor's pitch (nose up positive), read only if the walk
        // takes it out.
        let pitch = if self.config.walk.pitch_gain == 0.0 {
            0.0
        } else {
            let fwd = self.world.bodies[self.torso].position().rotation * Vector::X;
            f64::from(fwd.z.clamp(-1.0, 1.0).asin())
        };
        let targets = self.walk.update(period, self.command_mm_s, steer, pitch);
        let flat: Vec<Option<f64>> = targets
            .iter()
            .flat_map(|t: &Option<LegAngles>| {
                [t.map(|a| a.abduction), t.map(|a| a.hip), t.map(|a| a.knee)]
            })
            .collect();
        self.servos.track(&flat, period, &self.speed_limits);
        self.apply_servos();
    }

    /// What the torso's gyro reads: its angular velocity in its own frame, rad/s.
    /// The gyro: the torso's mean angular rate over the last step, in its own
    /// frame (from the rotation it actually made, as a rate gyro measures it).
    fn gyro(&mut self) -> [f64; 3] {
        let now = self.world.bodies[self.torso].position().rotation;
        let delta = self.last_attitude.inverse() * now;
        self.last_attitude = now;
        let (axis, angle) = delta.to_axis_angle();
        let w = axis * (angle / self.config.dt_s as Real);
        [w.x, w.y, w.z].map(f64::from)
    }

    /// Simulated time, s.
    pub fn time_s(&self) -> f64 {
        self.steps as f64 * self.config.dt_s
    }

    /// The settings in use.
    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    /// The robot's own heading estimate (from its gyro), rad.
    pub fn heading_estimate_rad(&self) -> f64 {
        self.heading.estimate_rad()
    }

    /// The command in effect after the walk engine's slewing, mm/s.
    pub fn command_in_effect(&self) -> f64 {
        self.walk.command_in_effect()
    }

    /// Ground truth: the torso's state.
    pub fn torso(&self) -> TorsoState {
        let body = &self.world.bodies[self.torso];
        let p = body.position();
        let v = body.linvel();
        let up = p.rotation * Vector::Z;
        let fwd = p.rotation * Vector::X;
        let q = p.rotation;
        TorsoState {
            position_m: [p.translation.x, p.translation.y, p.translation.z].map(f64::from),
            orientation: [q.x, q.y, q.z, q.w].map(f64::from),
            velocity_m_s: [v.x, v.y, v.z].map(f64::from),
            up: [up.x, up.y, up.z].map(f64::from),
            yaw_rad: f64::from(fwd.y.atan2(fwd.x)),
        }
    }

    /// Ground truth: the kinetic energy of the robot's links (translation and
    /// rotation), J.
    pub fn kinetic_energy_j(&self) -> f64 {
        // About each body's principal axes: rapier's own `kinetic_energy`
        // inverts the world inverse inertia, which is not finite for a link
        // without inertia about some axis (a sensor's frame, say).
        self.links_energy_j(|_, body, local| {
            let axes = body.position().rotation * local.principal_inertia_local_frame;
            let w = axes.inverse() * body.angvel();
            let i = local.principal_inertia();
            (
                local.mass(),
                i.x * w.x * w.x + i.y * w.y * w.y + i.z * w.z * w.z,
            )
        })
    }

    /// An upper bound on [`Self::kinetic_energy_j`] without rotating into
    /// each body's principal axes: each body's spin taken about its largest
    /// principal moment, `I w . w <= I_max |w|^2`. J.
    pub fn kinetic_energy_bound_j(&self) -> f64 {
        self.links_energy_j(|k, body, local| {
            let (mass, largest) = self
                .link_weights
                .get(k)
                .copied()
                .unwrap_or_else(|| link_weights(local));
            (mass, largest * body.angvel().length_squared())
        })
    }

    /// The links' kinetic energy, J: `link(k, body, local)` gives link `k`'s
    /// mass and its rotational part `I w . w` (twice its energy).
    fn links_energy_j(
        &self,
        link: impl Fn(
            usize,
            &rapier3d::prelude::RigidBody,
            &rapier3d::prelude::MassProperties,
        ) -> (f32, f32),
    ) -> f64 {
        self.links
            .iter()
            .enumerate()
            .map(|(k, (_, handle, _))| {
                let body = &self.world.bodies[*handle];
                let (mass, spin) = link(k, body, &body.mass_properties().local_mprops);
                0.5 * f64::from(mass * body.linvel().length_squared() + spin)
            })
            .sum()
    }

    /// When the physics blew up, s into the simulation, if it has: the end
    /// of the first step after which the robot's kinetic energy passed
    /// [`BLOW_UP_ENERGY`] times the potential energy of its mass at its
    /// torso's standing height (or was not finite). No legged robot walks or
    /// falls with that much; a solver that has blown up throws it about with
    /// it. A fall is [`QuadrupedSim::is_upright`]'s; a blow-up usually
    /// throws the robot over too, and is what to report when it has.
    pub fn blew_up_at_s(&self) -> Option<f64> {
        self.blew_up_at_s
    }

    /// The kinetic energy above which the physics counts as blown up
    /// ([`QuadrupedSim::blew_up_at_s`]), J.
    pub fn blow_up_energy_j(&self) -> f64 {
        self.blow_up_energy_j
    }

    /// Ground truth: whether the torso is upright (its up axis has a world z
    /// component above 0.8), the criterion for "has not fallen". Cheap enough to
    /// ask every physics step.
    pub fn is_upright(&self) -> bool {
        let up = self.world.bodies[self.torso].position().rotation * Vector::Z;
        up.z > 0.8
    }

    /// Ground truth: the torso's distance to the beacon measured along the line of
    /// approach (the line from the beacon through the start), m.
    pub fn distance_along_line_m(&self) -> f64 {
        let p = self.torso().position_m;
        self.config.beacon.xy_m[0] - p[0]
    }

    /// Ground truth: how far the torso is off the line of approach, m (left positive).
    pub fn lateral_offset_m(&self) -> f64 {
        self.torso().position_m[1] - self.start_xy_m[1]
    }

    /// Ground truth: the camera's pose in the world (optical axis +x, image up +z).
    pub fn camera_pose(&self) -> Pose {
        *self.world.bodies[self.camera_parent].position() * self.camera_mount
    }
}

/// Link `id`'s angular joint motor, to set its targets. With the patched
/// rapier3d, `link_motor_mut`, which leaves the multibody's kinematics valid.
#[cfg(not(feature = "upstream-rapier"))]
fn angular_motor(mb: &mut Multibody, id: usize) -> Option<&mut JointMotor> {
    mb.link_motor_mut(id, JointAxis::AngX)
}

/// Link `id`'s angular joint motor, through `link_mut`: rapier3d as published
/// (feature `upstream-rapier`, used only to record the upstream fixture; the
/// patched crate computes the same step either way).
#[cfg(feature = "upstream-rapier")]
fn angular_motor(mb: &mut Multibody, id: usize) -> Option<&mut JointMotor> {
    mb.link_mut(id)
        .map(|link| &mut link.joint.data.motors[JointAxis::AngX as usize])
}
