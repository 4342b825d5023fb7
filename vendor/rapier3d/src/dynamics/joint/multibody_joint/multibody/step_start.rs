//! PATCH (scasm-testbed): the forward kinematics at the start of a step
//! skipped when the step before already computed them for the same
//! coordinates, and the write-back of the links' poses skipped when every
//! rigid body already holds them. A new file of the patch; `multibody.rs`
//! declares it, keeps `fk_fresh` up to date, and `substep.rs` calls these.

use super::*;

impl Multibody {
    /// PATCH (scasm-testbed): the forward kinematics at the start of a step
    /// (`forward_kinematics(bodies, true)`), skipped when they would give the
    /// same poses and jacobians as the last run: the step before ended with
    /// forward kinematics on the integrated coordinates, and since then no link
    /// was borrowed mutably or displaced, no link's rigid body was modified by
    /// the user, and the root's rigid body is where the multibody left it.
    /// Returns whether they ran.
    pub(crate) fn forward_kinematics_at_step_start(&mut self, bodies: &RigidBodySet) -> bool {
        let untouched = self.fk_fresh
            && self.links.iter().all(|link| {
                bodies
                    .get(link.rigid_body)
                    .is_some_and(|rb| rb.changes.is_empty())
            })
            && bodies.get(self.links[0].rigid_body).is_some_and(|rb| {
                rb.is_dynamic() == self.root_is_dynamic
                    && *rb.position() == self.links[0].local_to_world
            });
        if !untouched {
            self.forward_kinematics(bodies, true);
        }
        !untouched
    }

    /// PATCH (scasm-testbed): whether every link's rigid body is at the
    /// link's pose, as both its position and its next position: then
    /// [`Self::update_rigid_bodies_internal`] would write the same poses, and
    /// the mass properties the end of the last step computed at them.
    pub(crate) fn rigid_bodies_in_place(&self, bodies: &RigidBodySet) -> bool {
        self.links.iter().all(|link| {
            bodies.get(link.rigid_body).is_some_and(|rb| {
                rb.pos.position == link.local_to_world
                    && rb.pos.next_position == link.local_to_world
            })
        })
    }
}
