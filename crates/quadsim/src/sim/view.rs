//! Read-only views of the simulated world for viewers, peer simulators and
//! tests: its bodies and shapes, what the head camera sees, the contacts,
//! the servos' setpoints. Nothing here changes the world.

use rapier3d::dynamics::RigidBodyHandle;
use rapier3d::geometry::ColliderHandle;
use rapier3d::pipeline::PhysicsWorld;

use super::QuadrupedSim;
use crate::scene::{Part, Placement, Role, Scene, SceneBody, Shape};

impl QuadrupedSim {
    /// The servos' position setpoints now, rad, leg by leg in the
    /// description's order (abduction, hip, knee), each about its joint's
    /// own URDF axis: what the joint motors track (for a peer simulator to
    /// replay the same motion).
    pub fn servo_targets(&self) -> Vec<f64> {
        self.servos
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| self.axis_signs[i / 3][i % 3] * p)
            .collect()
    }

    /// The contact points the solver works with after the last step.
    pub fn contact_points(&self) -> usize {
        self.contact_points_where(|_| true)
    }

    /// The contact points the solver works with after the last step between
    /// two things neither of which is the floor (the robot on the beacon, say).
    pub fn contact_points_off_floor(&self) -> usize {
        let on_floor = |c: ColliderHandle| self.world.colliders[c].parent() == Some(self.floor);
        self.contact_points_where(|p| !on_floor(p.collider1) && !on_floor(p.collider2))
    }

    /// The solver's contact points over the contact pairs `pick` picks.
    fn contact_points_where(
        &self,
        pick: impl Fn(&rapier3d::geometry::ContactPair) -> bool,
    ) -> usize {
        self.world
            .narrow_phase
            .contact_pairs()
            .filter(|p| p.has_any_active_contact() && pick(p))
            .flat_map(|p| p.solver_manifolds().iter())
            .map(|m| m.data.solver_contacts.len())
            .sum()
    }

    /// What the head camera sees now, as an RGB image of its intrinsics' size
    /// (see [`crate::vision::render_rgb`]): for viewers and saved frames, not
    /// the noisy reading the host gets.
    pub fn camera_image(&self) -> Vec<u8> {
        crate::vision::render_rgb(&self.config.camera.intrinsics, self.camera_blob().as_ref())
    }

    /// The band as the head camera sees it now, before noise (for viewers:
    /// the host gets only the noisy reading), or `None` where it gives no
    /// reading.
    pub fn camera_blob(&self) -> Option<crate::vision::BandBlob> {
        crate::vision::find_band(
            &self.world,
            &self.camera_pose(),
            &self.config.camera.intrinsics,
            &self.config.beacon,
            self.band,
            &self.camera_bodies,
        )
        .ok()
    }

    /// Every body of the world with its colliders' shapes (see
    /// [`crate::scene`]), in the order of [`QuadrupedSim::placements`]: the
    /// floor, the beacon, then the robot's links in URDF order.
    pub fn scene(&self) -> Scene {
        let beacon = self.world.colliders[self.band].parent();
        let parts = |body: RigidBodyHandle| -> Vec<Part> {
            self.world.bodies[body]
                .colliders()
                .iter()
                .map(|&c| {
                    let collider = &self.world.colliders[c];
                    let role = if body == self.floor {
                        Role::Floor
                    } else if c == self.band {
                        Role::BeaconBand
                    } else if Some(body) == beacon {
                        Role::BeaconPole
                    } else {
                        Role::Robot
                    };
                    Part {
                        shape: Shape::of(collider.shape()),
                        in_body: collider
                            .position_wrt_parent()
                            .map_or(Placement::IDENTITY, Placement::from),
                        role,
                    }
                })
                .collect()
        };
        let world_body = |name: &str, body: RigidBodyHandle| SceneBody {
            name: name.into(),
            robot_link: false,
            parent: None,
            parts: parts(body),
        };
        let mut bodies = vec![world_body("floor", self.floor)];
        bodies.extend(beacon.map(|b| world_body("beacon", b)));
        let first_link = bodies.len();
        bodies.extend(self.links.iter().map(|(name, body, parent)| SceneBody {
            name: name.clone(),
            robot_link: true,
            parent: parent.map(|p| first_link + p),
            parts: parts(*body),
        }));
        Scene { bodies }
    }

    /// Where every body of [`QuadrupedSim::scene`] is now, in its order.
    pub fn placements(&self) -> Vec<Placement> {
        let beacon = self.world.colliders[self.band].parent();
        std::iter::once(self.floor)
            .chain(beacon)
            .chain(self.links.iter().map(|l| l.1))
            .map(|b| Placement::from(self.world.bodies[b].position()))
            .collect()
    }

    /// The band's collider in the world (for rendering what the camera sees).
    pub fn band_collider(&self) -> ColliderHandle {
        self.band
    }

    /// [`QuadrupedSim::camera_pose`] as a [`Placement`].
    pub fn camera_placement(&self) -> Placement {
        Placement::from(&self.camera_pose())
    }

    /// The robot's multibody (for tests of the physics itself).
    pub fn multibody(&self) -> Option<&rapier3d::dynamics::Multibody> {
        self.world
            .multibody_joints
            .get(self.joints[0][0])
            .map(|(mb, _)| mb)
    }

    /// The physics world, read-only (for rendering and sensors).
    pub fn world(&self) -> &PhysicsWorld {
        &self.world
    }
}
