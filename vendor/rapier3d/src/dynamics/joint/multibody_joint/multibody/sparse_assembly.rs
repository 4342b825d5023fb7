//! PATCH (scasm-testbed): the mass matrices assembled on each link's own
//! columns (sparse body jacobians and quadratic forms, the same bits as
//! upstream's dense assembly, which `multibody.rs` keeps as
//! `update_body_jacobians_dense` and `update_mass_matrix_dense`), and with
//! [`MultibodyDynamics::Tree`] the mass matrix by composite rigid bodies and
//! its factors along the tree. A new file of the patch; `multibody.rs`
//! declares it and calls [`Multibody::update_body_jacobians`] and
//! [`Multibody::update_mass_matrix`] where upstream called its own.

use super::*;

/// PATCH (scasm-testbed): how a multibody's free motion and its constraints'
/// responses are computed each step.
#[cfg_attr(feature = "serde-serialize", derive(Serialize, Deserialize))]
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum MultibodyDynamics {
    /// rapier's: the free acceleration solves with the mass matrix augmented
    /// with the Coriolis and gyroscopic forces linearised over the step
    /// (semi-implicit, with an energy guard falling back to the plain mass
    /// matrix), and both matrices are factored by dense LU every step.
    #[default]
    ImplicitCoriolis,
    /// The Coriolis and gyroscopic forces explicit (as MuJoCo's `implicitfast`
    /// integrator treats them; joint damping, armature and springs stay
    /// implicit on the diagonal, as in `ImplicitCoriolis`), so that the free
    /// motion and every constraint row solve with one symmetric positive
    /// definite matrix, factored once a step as `L^T D L` along the kinematic
    /// tree (no fill-in, no pivoting) and solved in time proportional to the
    /// (coordinate, ancestor) pairs instead of the square of the coordinates.
    Tree,
}

/// PATCH (scasm-testbed): a subtree's inertia about a point (see
/// `Multibody::composite_rigid_body_mass_matrix`): mass, first moment,
/// rotational inertia.
#[derive(Copy, Clone, Debug, Default)]
pub(super) struct Composite {
    mass: Real,
    moment: na::Vector3<Real>,
    inertia: na::Matrix3<Real>,
}

/// PATCH (scasm-testbed): `out1[c, c] += J[:, c]^T M1 J[:, c]` and the same
/// with `M2` into `out2`, over the columns `c` of `cols` (where `J` can be
/// non-zero), for two rigid-body mass matrices `Mk = diag(mass, inertia_k)`
/// that share their mass: `J^T M J` for a jacobian that is zero elsewhere, at
/// `(|c| / n)^2` of the dense quadratic form's cost. The values are those of
/// nalgebra's dense products (`M x` column by column, then running dot
/// products): the terms skipped are the zero blocks' `0 * x`, which change no
/// value (at most the sign of a zero), and the linear rows' products and the
/// dot products' first three terms, shared by the two forms, are computed once.
/// Then `out2[a, b] += J[:, a] . extra[:, b]` (a separate addition, as before).
#[allow(clippy::too_many_arguments)]
fn sparse_quadform_pair(
    out1: &mut DMatrix<Real>,
    out2: &mut DMatrix<Real>,
    mass: [Real; DIM],
    inertia1: &na::Matrix3<Real>,
    inertia2: &na::Matrix3<Real>,
    j: &Jacobian<Real>,
    extra: &[Real],
    cols: &[usize],
    mj: &mut Vec<[Real; 3 * DIM]>,
) {
    let (i1, i2, j) = (inertia1.as_slice(), inertia2.as_slice(), j.as_slice());
    // `inertia * w` as nalgebra's gemv: column by column.
    let angular = |m: &[Real], w: &[Real]| {
        let mut y = [0.0; DIM];
        for (yr, mr) in y.iter_mut().zip(&m[..DIM]) {
            *yr = *mr * w[0];
        }
        for k in 1..DIM {
            for (yr, mr) in y.iter_mut().zip(&m[DIM * k..DIM * (k + 1)]) {
                *yr = *mr * w[k] + *yr;
            }
        }
        y
    };
    mj.clear();
    mj.extend(cols.iter().map(|&c| {
        let x = &j[SPATIAL_DIM * c..SPATIAL_DIM * (c + 1)];
        let (w1, w2) = (angular(i1, &x[DIM..]), angular(i2, &x[DIM..]));
        [
            mass[0] * x[0],
            mass[1] * x[1],
            mass[2] * x[2],
            w1[0],
            w1[1],
            w1[2],
            w2[0],
            w2[1],
            w2[2],
        ]
    }));
    for &a in cols {
        let ja = &j[SPATIAL_DIM * a..SPATIAL_DIM * (a + 1)];
        for (y, &b) in mj.iter().zip(cols) {
            let mut linear = 0.0;
            for r in 0..DIM {
                linear += ja[r] * y[r];
            }
            let (mut s1, mut s2) = (linear, linear);
            for r in 0..DIM {
                s1 += ja[DIM + r] * y[DIM + r];
                s2 += ja[DIM + r] * y[2 * DIM + r];
            }
            out1[(a, b)] += s1;
            out2[(a, b)] += s2;
            out2[(a, b)] += spatial_dot(ja, &extra[SPATIAL_DIM * b..]);
        }
    }
}

/// PATCH (scasm-testbed): nalgebra's dot product of two 6-vectors, in its
/// order (a running sum from zero).
#[inline]
fn spatial_dot(a: &[Real], b: &[Real]) -> Real {
    let mut sum = 0.0;
    for (x, y) in a[..SPATIAL_DIM].iter().zip(&b[..SPATIAL_DIM]) {
        sum += *x * *y;
    }
    sum
}

impl Multibody {
    pub(super) fn update_body_jacobians(&mut self) {
        // PATCH (scasm-testbed): each link's jacobian columns that can be
        // non-zero, recomputed only when the tree's shape changes. Links come
        // parents first.
        let signature_matches = self.link_dofs_signature.len() == self.links.len()
            && self.links.iter().enumerate().all(|(i, l)| {
                self.link_dofs_signature[i] == (l.parent_internal_id, l.assembly_id, l.joint.ndofs())
            });
        if !signature_matches {
            self.link_dofs_signature.clear();
            self.link_dofs_signature.extend(
                self.links
                    .iter()
                    .map(|l| (l.parent_internal_id, l.assembly_id, l.joint.ndofs())),
            );
            self.link_dofs.clear();
        }
        self.link_dofs.resize_with(self.links.len(), Vec::new);
        for i in (0..self.links.len()).filter(|_| !signature_matches) {
            let link = &self.links[i];
            let (own, mut dofs) = (
                link.assembly_id..link.assembly_id + link.joint.ndofs(),
                core::mem::take(&mut self.link_dofs[i]),
            );
            dofs.clear();
            if i != 0 {
                dofs.extend_from_slice(&self.link_dofs[link.parent_internal_id]);
            }
            dofs.extend(own);
            dofs.sort_unstable();
            dofs.dedup();
            self.link_dofs[i] = dofs;
        }
        if self.dynamics == MultibodyDynamics::Tree {
            self.update_body_jacobians_tree(signature_matches);
            return;
        }

        for i in 0..self.links.len() {
            let link = &self.links[i];

            if self.body_jacobians[i].ncols() != self.ndofs {
                // TODO: use a resize instead.
                self.body_jacobians[i] = Jacobian::zeros(self.ndofs);
            } else if !signature_matches {
                // PATCH (scasm-testbed): the columns outside the link's are
                // never written below, and must be zero.
                self.body_jacobians[i].fill(0.0);
            }

            let parent_to_world;

            // PATCH (scasm-testbed): the link's own columns start from zero
            // (they were the parent's, which are zero there).
            let own = link.assembly_id..link.assembly_id + link.joint.ndofs();
            self.body_jacobians[i].as_mut_slice()[SPATIAL_DIM * own.start..SPATIAL_DIM * own.end]
                .fill(0.0);

            if i != 0 {
                let parent_id = link.parent_internal_id;
                let parent_link = &self.links[parent_id];
                parent_to_world = parent_link.local_to_world;

                let (link_j, parent_j) = self.body_jacobians.index_mut_const(i, parent_id);
                // PATCH (scasm-testbed): the parent's columns only; the
                // others are zero in both.
                for &c in &self.link_dofs[parent_id] {
                    link_j.column_mut(c).copy_from(&parent_j.column(c));
                }

                {
                    let mut link_j_v = link_j.fixed_rows_mut::<DIM>(0);
                    let parent_j_w = parent_j.fixed_rows::<ANG_DIM>(DIM);

                    let shift_tr = vect_to_na(link.shift02).gcross_matrix_tr();
                    // PATCH (scasm-testbed): the gemm's column by column
                    // products (the same bits), on the parent's columns only:
                    // the others of `parent_j_w` are zero.
                    for &c in &self.link_dofs[parent_id] {
                        link_j_v
                            .column_mut(c)
                            .gemv(1.0, &shift_tr, &parent_j_w.column(c), 1.0);
                    }
                }
            } else {
                // PATCH (scasm-testbed): the root's columns are its own, zeroed above.
                parent_to_world = Pose::IDENTITY;
            }

            let ndofs = link.joint.ndofs();
            let mut tmp = SMatrix::<Real, SPATIAL_DIM, SPATIAL_DIM>::zeros();
            let mut link_joint_j = tmp.columns_mut(0, ndofs);
            let mut link_j_part = self.body_jacobians[i].columns_mut(link.assembly_id, ndofs);
            link.joint.jacobian(
                &(parent_to_world.rotation * link.joint.data.local_frame1.rotation),
                &mut link_joint_j,
            );
            link_j_part += link_joint_j;

            {
                let link_j = &mut self.body_jacobians[i];
                let (mut link_j_v, link_j_w) =
                    link_j.rows_range_pair_mut(0..DIM, DIM..DIM + ANG_DIM);
                let shift_tr = vect_to_na(link.shift23).gcross_matrix_tr();
                // PATCH (scasm-testbed): on the link's columns only.
                for &c in &self.link_dofs[i] {
                    link_j_v
                        .column_mut(c)
                        .gemv(1.0, &shift_tr, &link_j_w.column(c), 1.0);
                }
            }
        }
    }

    pub(crate) fn update_mass_matrix(&mut self, dt: Real, bodies: &RigidBodySet) {
        if self.ndofs == 0 {
            return; // Nothing to do.
        }
        // PATCH (scasm-testbed): the links' inertias, once a step.
        self.link_inertia.clear();
        self.link_inertia.extend(self.links.iter().map(|link| {
            let mprops = &bodies[link.rigid_body].mprops;
            (mprops.effective_mass(), mprops.effective_angular_inertia())
        }));
        if self.dynamics == MultibodyDynamics::Tree {
            self.update_mass_matrix_tree(dt, bodies);
            return;
        }

        if self.augmented_mass.ncols() != self.ndofs {
            // TODO: do a resize instead of a full reallocation.
            self.augmented_mass = DMatrix::zeros(self.ndofs, self.ndofs);
            self.acc_augmented_mass = DMatrix::zeros(self.ndofs, self.ndofs);
        } else {
            self.augmented_mass.as_mut_slice().fill(0.0); // PATCH (scasm-testbed): a memset.
            self.acc_augmented_mass.as_mut_slice().fill(0.0); // PATCH (scasm-testbed): a memset.
        }

        self.augmented_mass_indices.clear();

        // Resize coriolis workspaces if the link count or number of DOFs change.
        let coriolis_ndofs = self.coriolis_v.first().map(|m| m.ncols());
        if self.coriolis_v.len() != self.links.len() || coriolis_ndofs != Some(self.ndofs) {
            self.coriolis_v = vec![OMatrix::<Real, Dim, Dyn>::zeros(self.ndofs); self.links.len()];
            self.coriolis_w =
                vec![OMatrix::<Real, AngDim, Dyn>::zeros(self.ndofs); self.links.len()];
            self.i_coriolis_dt = Jacobian::zeros(self.ndofs);
        }

        let mut curr_assembly_id = 0;

        for i in 0..self.links.len() {
            let link = &self.links[i];
            let rb = &bodies[link.rigid_body];
            let (rb_mass, rb_inertia) = self.link_inertia[i]; // PATCH (scasm-testbed)
            let rb_inertia = rb_inertia.into_matrix();
            let body_jacobian = &self.body_jacobians[i];

            // NOTE: the mass matrix index reordering operates on the assumption that the assembly
            //       ids are traversed in order. This assert is here to ensure the assumption always
            //       hold.
            assert_eq!(
                curr_assembly_id, link.assembly_id,
                "Internal error: contiguity assumption on assembly_id does not hold."
            );
            curr_assembly_id += link.joint.ndofs();

            if link.joint.kinematic {
                for k in link.assembly_id..link.assembly_id + link.joint.ndofs() {
                    self.augmented_mass_indices.remove(k);
                }
            } else {
                for k in link.assembly_id..link.assembly_id + link.joint.ndofs() {
                    self.augmented_mass_indices.keep(k);
                }
            }

            #[allow(unused_mut)] // mut is needed for 3D but not for 2D.
            let mut augmented_inertia = rb_inertia;

            #[cfg(feature = "dim3")]
            {
                // Derivative of gyroscopic forces.
                let gyroscopic_matrix = rb.vels.angvel.gcross_matrix() * rb_inertia
                    - (rb_inertia * rb.vels.angvel).gcross_matrix();

                augmented_inertia += gyroscopic_matrix * dt;
            }

            /*
             *
             * Coriolis matrix.
             *
             */
            let rb_j = &self.body_jacobians[i];
            let rb_j_w = rb_j.fixed_rows::<ANG_DIM>(DIM);

            let ndofs = link.joint.ndofs();

            if i != 0 {
                let parent_id = link.parent_internal_id;
                let parent_link = &self.links[parent_id];
                let parent_rb = &bodies[parent_link.rigid_body];
                let parent_j = &self.body_jacobians[parent_id];
                let parent_j_w = parent_j.fixed_rows::<ANG_DIM>(DIM);
                let parent_w = SimdAngVector::<Real>::from(parent_rb.vels.angvel).gcross_matrix();

                let (coriolis_v, parent_coriolis_v) = self.coriolis_v.index_mut2(i, parent_id);
                let (coriolis_w, parent_coriolis_w) = self.coriolis_w.index_mut2(i, parent_id);

                coriolis_v.copy_from(parent_coriolis_v);
                coriolis_w.copy_from(parent_coriolis_w);

                // [c1 - c0].gcross() * (JDot + JDot/u * qdot)"
                let shift_cross_tr = vect_to_na(link.shift02).gcross_matrix_tr();
                // JDot (but the 2.0 originates from the sum of two identical terms in JDot and JDot/u * gdot)
                let dvel_cross = vect_to_na(
                    rb.vels.angvel.gcross(link.shift02) + 2.0 * link.joint_velocity.linvel,
                )
                .gcross_matrix_tr();
                // JDot/u * qdot, and the term above, on the parent's jacobian.
                let on_parent_j_w = dvel_cross
                    + vect_to_na(link.joint_velocity.linvel).gcross_matrix_tr()
                    + parent_w * shift_cross_tr;
                #[cfg(feature = "dim3")]
                let vel_wrt_joint_w = vect_to_na(link.joint_velocity.angvel).gcross_matrix();
                // PATCH (scasm-testbed): the parent's columns only; the
                // others of `parent_coriolis_w` and `parent_j_w` are zero.
                for &c in &self.link_dofs[parent_id] {
                    let pcw = parent_coriolis_w.column(c).into_owned();
                    let pjw = parent_j_w.column(c).into_owned();
                    let mut v = coriolis_v.column_mut(c);
                    v += shift_cross_tr * pcw + on_parent_j_w * pjw;
                    #[cfg(feature = "dim3")]
                    {
                        let mut w = coriolis_w.column_mut(c);
                        w -= vel_wrt_joint_w * pjw;
                    }
                }

                // JDot (but the 2.0 originates from the sum of two identical terms in JDot and JDot/u * gdot)
                if !link.joint.kinematic {
                    let mut coriolis_v_part = coriolis_v.columns_mut(link.assembly_id, ndofs);

                    let mut tmp1 = SMatrix::<Real, SPATIAL_DIM, SPATIAL_DIM>::zeros();
                    let mut rb_joint_j = tmp1.columns_mut(0, ndofs);
                    link.joint.jacobian(
                        &(parent_link.local_to_world.rotation
                            * link.joint.data.local_frame1.rotation),
                        &mut rb_joint_j,
                    );

                    let rb_joint_j_v = rb_joint_j.fixed_rows::<DIM>(0);
                    coriolis_v_part.gemm(2.0, &parent_w, &rb_joint_j_v, 1.0);

                    #[cfg(feature = "dim3")]
                    {
                        let rb_joint_j_w = rb_joint_j.fixed_rows::<ANG_DIM>(DIM);
                        let mut coriolis_w_part = coriolis_w.columns_mut(link.assembly_id, ndofs);
                        coriolis_w_part.gemm(1.0, &parent_w, &rb_joint_j_w, 1.0);
                    }
                }
            } else {
                self.coriolis_v[i].as_mut_slice().fill(0.0); // PATCH (scasm-testbed): a memset.
                self.coriolis_w[i].as_mut_slice().fill(0.0); // PATCH (scasm-testbed): a memset.
            }

            let coriolis_v = &mut self.coriolis_v[i];
            let coriolis_w = &mut self.coriolis_w[i];

            {
                // [c3 - c2].gcross() * (JDot + JDot/u * qdot)
                let shift_cross_tr = vect_to_na(link.shift23).gcross_matrix_tr();
                // JDot
                let dvel_cross = vect_to_na(rb.vels.angvel.gcross(link.shift23)).gcross_matrix_tr();
                // JDot/u * qdot, and the term above, on the link's jacobian.
                let on_rb_j_w = dvel_cross
                    + SimdAngVector::<Real>::from(rb.vels.angvel).gcross_matrix() * shift_cross_tr;
                // PATCH (scasm-testbed): the link's columns only.
                for &c in &self.link_dofs[i] {
                    let cw = coriolis_w.column(c).into_owned();
                    let jw = rb_j_w.column(c).into_owned();
                    let mut v = coriolis_v.column_mut(c);
                    v += shift_cross_tr * cw + on_rb_j_w * jw;
                }
            }

            let coriolis_v = &mut self.coriolis_v[i];
            let coriolis_w = &mut self.coriolis_w[i];

            /*
             * Meld with the mass matrix.
             */
            // PATCH (scasm-testbed): the link's columns only; the others of
            // `i_coriolis_dt` are not read below.
            let rb_mass_dt = vect_to_na(rb_mass * dt);
            #[cfg(feature = "dim3")]
            let inertia_dt = mat_to_na(rb_inertia) * dt;
            for &c in &self.link_dofs[i] {
                let v = coriolis_v.column(c).component_mul(&rb_mass_dt);
                self.i_coriolis_dt.fixed_view_mut::<DIM, 1>(0, c).copy_from(&v);
                #[cfg(feature = "dim3")]
                {
                    let w = inertia_dt * coriolis_w.column(c);
                    self.i_coriolis_dt
                        .fixed_view_mut::<ANG_DIM, 1>(DIM, c)
                        .copy_from(&w);
                }
            }

            #[cfg(feature = "dim2")]
            {
                let mut i_coriolis_dt_w = self.i_coriolis_dt.fixed_rows_mut::<ANG_DIM>(DIM);
                // NOTE: this is just an axpy, but on row columns.
                i_coriolis_dt_w.zip_apply(coriolis_w, |o, x| *o = x * dt * rb_inertia);
            }
            // PATCH (scasm-testbed): the quadratic forms `J^T M J` on the link's
            // columns, knowing the structure of the rigid-body mass matrices,
            // and `J^T (I C dt)` added to the second in the same pass.
            sparse_quadform_pair(
                &mut self.augmented_mass,
                &mut self.acc_augmented_mass,
                [rb_mass.x, rb_mass.y, rb_mass.z],
                &mat_to_na(rb_inertia),
                &mat_to_na(augmented_inertia),
                body_jacobian,
                self.i_coriolis_dt.as_slice(),
                &self.link_dofs[i],
                &mut self.mj_workspace,
            );
        }

        /*
         * Damping and armature.
         *
         * Damping is a velocity-proportional force made implicit, so it adds
         * `dt · d` to the mass-matrix diagonal. Armature is a "reflected
         * rotor inertia" (additional inertia to account for the joint’s
         * mass and geometry itself): it adds to the diagonal directly.
         */
        for i in 0..self.ndofs {
            let diag = self.damping[i] * dt + self.armature[i];
            self.acc_augmented_mass[(i, i)] += diag;
            self.augmented_mass[(i, i)] += diag;
        }

        // Implicit joint springs: `dt²·k` on the mass-matrix diagonal (force term in `update_acceleration`)
        // keeps a stiff spring on a low-inertia link stable where an explicit position motor injects energy.
        // The spring lives on the link's `MultibodyJoint` so it travels with the link through topology changes.
        let dt2 = dt * dt;
        for li in 0..self.links.len() {
            let mut idx = self.links[li].assembly_id;
            let locked = self.links[li].joint.data.locked_axes.bits();
            for a in 0..SPATIAL_DIM {
                if (locked >> a) & 1 == 0 {
                    let k = self.links[li].joint.spring_stiffness[a];
                    if k != 0.0 {
                        let d = k * dt2;
                        self.acc_augmented_mass[(idx, idx)] += d;
                        self.augmented_mass[(idx, idx)] += d;
                    }
                    idx += 1;
                }
            }
        }

        let effective_dim = self
            .augmented_mass_indices
            .dim_after_removal(self.acc_augmented_mass.nrows());

        // PERF: since we clone the matrix anyway for LU, should be directly output
        //       a new matrix instead of applying permutations?
        self.augmented_mass_indices
            .rearrange_columns(&mut self.acc_augmented_mass, true);
        self.augmented_mass_indices
            .rearrange_columns(&mut self.augmented_mass, true);

        self.augmented_mass_indices
            .rearrange_rows(&mut self.acc_augmented_mass, true);
        self.augmented_mass_indices
            .rearrange_rows(&mut self.augmented_mass, true);

        // PATCH (scasm-testbed): factored in place, no allocation.
        self.acc_inv_augmented_mass
            .factor(&self.acc_augmented_mass, effective_dim);
        self.inv_augmented_mass
            .factor(&self.augmented_mass, effective_dim);
    }

    /// PATCH (scasm-testbed): [`MultibodyDynamics::Tree`]'s mass matrix (with
    /// damping, armature and springs on its diagonal as in
    /// [`Self::update_mass_matrix`]), factored along the tree. The matrix with
    /// the Coriolis terms is not assembled.
    pub(super) fn update_mass_matrix_tree(&mut self, dt: Real, bodies: &RigidBodySet) {
        if self.augmented_mass.ncols() != self.ndofs {
            self.augmented_mass = DMatrix::zeros(self.ndofs, self.ndofs);
        } else {
            self.augmented_mass.as_mut_slice().fill(0.0); // PATCH (scasm-testbed): a memset.
        }
        self.augmented_mass_indices.clear();
        for link in self.links.iter() {
            let range = link.assembly_id..link.assembly_id + link.joint.ndofs();
            if link.joint.kinematic {
                range.for_each(|k| self.augmented_mass_indices.remove(k));
            } else {
                range.for_each(|k| self.augmented_mass_indices.keep(k));
            }
        }

        self.composite_rigid_body_mass_matrix(bodies);

        let dt2 = dt * dt;
        let rows = self.augmented_mass.nrows();
        let mass = self.augmented_mass.as_mut_slice();
        let (damping, armature) = (self.damping.as_slice(), self.armature.as_slice());
        for link in self.links.iter() {
            let mut idx = link.assembly_id;
            let locked = link.joint.data.locked_axes.bits();
            for a in 0..SPATIAL_DIM {
                if (locked >> a) & 1 == 0 {
                    let k = link.joint.spring_stiffness[a];
                    mass[idx * rows + idx] += damping[idx] * dt + armature[idx] + k * dt2;
                    idx += 1;
                }
            }
        }

        // Removing kinematic coordinates keeps the others' order (parents first).
        let effective_dim = self
            .augmented_mass_indices
            .dim_after_removal(self.augmented_mass.nrows());
        self.augmented_mass_indices
            .rearrange_columns(&mut self.augmented_mass, true);
        self.augmented_mass_indices
            .rearrange_rows(&mut self.augmented_mass, true);
        self.inv_augmented_mass
            .factor_tree(&self.augmented_mass, effective_dim);
    }

    /// PATCH (scasm-testbed): [`Self::update_body_jacobians`] for
    /// [`MultibodyDynamics::Tree`], on the jacobians' raw column-major storage:
    /// a link's column `c` (velocity `v`, angular velocity `w` of its centre of
    /// mass) is its parent's moved by the parent-to-link shift,
    /// `v + w x (shift02 + shift23)`, and its own joint's columns are the
    /// joint's motion moved by `shift23`. The same jacobians as the default's
    /// two steps (`gemv` by each shift's cross matrix), to f32 rounding.
    pub(super) fn update_body_jacobians_tree(&mut self, signature_matches: bool) {
        const S: usize = SPATIAL_DIM;
        // A column (v, w) moved by `shift`: (v + w x shift, w).
        let shifted = |col: &[Real], shift: Vector| {
            let w = Vector::new(col[3], col[4], col[5]);
            let v = Vector::new(col[0], col[1], col[2]) + w.cross(shift);
            [v.x, v.y, v.z, w.x, w.y, w.z]
        };
        for i in 0..self.links.len() {
            if self.body_jacobians[i].ncols() != self.ndofs {
                self.body_jacobians[i] = Jacobian::zeros(self.ndofs);
            } else if !signature_matches {
                self.body_jacobians[i].as_mut_slice().fill(0.0);
            }
            let link = &self.links[i];
            let own = link.assembly_id..link.assembly_id + link.joint.ndofs();
            let parent_to_world = if i != 0 {
                let parent_id = link.parent_internal_id;
                let shift = link.shift02 + link.shift23;
                let (link_j, parent_j) = self.body_jacobians.index_mut_const(i, parent_id);
                let (out, from) = (link_j.as_mut_slice(), parent_j.as_slice());
                for &c in &self.link_dofs[parent_id] {
                    out[S * c..S * c + S].copy_from_slice(&shifted(&from[S * c..S * c + S], shift));
                }
                self.links[parent_id].local_to_world
            } else {
                Pose::IDENTITY
            };
            let mut tmp = SMatrix::<Real, SPATIAL_DIM, SPATIAL_DIM>::zeros();
            link.joint.jacobian(
                &(parent_to_world.rotation * link.joint.data.local_frame1.rotation),
                &mut tmp.columns_mut(0, own.len()),
            );
            let out = self.body_jacobians[i].as_mut_slice();
            for (k, c) in own.enumerate() {
                let joint_col = &tmp.as_slice()[S * k..S * k + S];
                out[S * c..S * c + S].copy_from_slice(&shifted(joint_col, link.shift23));
            }
        }
    }

    /// PATCH (scasm-testbed): adds the upper triangle of the joint-space mass
    /// matrix `sum J^T M J` over the links to `self.augmented_mass` (the tree's
    /// factorisation reads no other; the lower stays zero), by the composite-rigid-body
    /// algorithm (Featherstone 2008, section 6.2) in world coordinates: every
    /// spatial quantity is taken about one point `o` (the root's centre of
    /// mass), so that a subtree's inertia is the plain sum of its links' and a
    /// coordinate's force needs no transform on its way up the tree. Entry
    /// `(j, k)`, for `j` an ancestor of `k` or `k` itself, is `s_j . (I_k s_k)`
    /// with `s` a coordinate's motion about `o` (from its link's body
    /// jacobian) and `I_k` the inertia of the subtree it moves; the others are
    /// zero.
    pub(super) fn composite_rigid_body_mass_matrix(&mut self, bodies: &RigidBodySet) {
        let o = vect_to_na(bodies[self.links[0].rigid_body].mprops.world_com);
        let mut composite = core::mem::take(&mut self.crb_workspace);
        composite.clear();
        for (link, (link_mass, link_inertia)) in self.links.iter().zip(&self.link_inertia) {
            let rb = &bodies[link.rigid_body];
            // The effective masses of a multibody link are isotropic (no locked axes).
            let mass = link_mass.x;
            let r = vect_to_na(rb.mprops.world_com) - o;
            let inertia = mat_to_na(link_inertia.into_matrix())
                + (na::Matrix3::identity() * r.norm_squared() - r * r.transpose()) * mass;
            composite.push(Composite {
                mass,
                moment: r * mass,
                inertia,
            });
        }
        for i in (1..self.links.len()).rev() {
            let (child, parent) = (composite[i], self.links[i].parent_internal_id);
            let c = &mut composite[parent];
            c.mass += child.mass;
            c.moment += child.moment;
            c.inertia += child.inertia;
        }
        // Each coordinate's motion about o.
        let n = self.ndofs;
        let mut motion = core::mem::take(&mut self.mj_workspace);
        motion.clear();
        motion.resize(n, [0.0; 3 * DIM]);
        for (i, link) in self.links.iter().enumerate() {
            let com = vect_to_na(bodies[link.rigid_body].mprops.world_com);
            let j = self.body_jacobians[i].as_slice();
            for k in link.assembly_id..link.assembly_id + link.joint.ndofs() {
                let col = &j[SPATIAL_DIM * k..SPATIAL_DIM * (k + 1)];
                let (v, w) = (
                    na::Vector3::new(col[0], col[1], col[2]),
                    na::Vector3::new(col[3], col[4], col[5]),
                );
                // The velocity of the point at o moving with the link.
                let v_o = v + (com - o).cross(&w);
                motion[k] = [v_o.x, v_o.y, v_o.z, w.x, w.y, w.z, 0.0, 0.0, 0.0];
            }
        }
        let rows = self.augmented_mass.nrows();
        let out = self.augmented_mass.as_mut_slice();
        for (i, link) in self.links.iter().enumerate() {
            let c = &composite[i];
            for k in link.assembly_id..link.assembly_id + link.joint.ndofs() {
                let s = &motion[k];
                let (v, w) = (
                    na::Vector3::new(s[0], s[1], s[2]),
                    na::Vector3::new(s[3], s[4], s[5]),
                );
                // The subtree's momentum moving with coordinate k.
                let f_lin = v * c.mass + w.cross(&c.moment);
                let f_ang = c.moment.cross(&v) + c.inertia * w;
                let f = [f_lin.x, f_lin.y, f_lin.z, f_ang.x, f_ang.y, f_ang.z];
                for &j in self.link_dofs[i].iter().take_while(|&&j| j <= k) {
                    let sj = &motion[j];
                    let mut m = 0.0;
                    for r in 0..SPATIAL_DIM {
                        m += sj[r] * f[r];
                    }
                    // The upper triangle only: the factorisation reads no
                    // other (`TreeLdl::factor`).
                    out[k * rows + j] += m;
                }
            }
        }
        self.mj_workspace = motion;
        self.crb_workspace = composite;
    }

    /// PATCH (scasm-testbed): the mass matrices without and with the
    /// gyroscopic and Coriolis terms, as last assembled (for tests).
    #[doc(hidden)]
    pub fn mass_matrices(&self) -> (&DMatrix<Real>, &DMatrix<Real>) {
        (&self.augmented_mass, &self.acc_augmented_mass)
    }

    /// PATCH (scasm-testbed): computes the body jacobians of the current
    /// configuration and assembles the mass matrices as a step does, with the
    /// patched code or with upstream's dense code (for tests).
    #[doc(hidden)]
    pub fn assemble_mass_matrices(&mut self, dt: Real, bodies: &RigidBodySet, dense: bool) {
        if dense {
            self.update_body_jacobians_dense();
            self.update_mass_matrix_dense(dt, bodies);
        } else {
            self.update_body_jacobians();
            self.update_mass_matrix(dt, bodies);
            if self.dynamics == MultibodyDynamics::Tree {
                // A step assembles the upper triangle only; mirror it.
                let m = &mut self.augmented_mass;
                for k in 0..m.ncols() {
                    for j in 0..k {
                        m[(k, j)] = m[(j, k)];
                    }
                }
            }
        }
    }
}
