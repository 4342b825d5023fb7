//! One leg read from the URDF: its three joints (abduction, hip, knee) in
//! order below the root, their axes, limits and servo limits, the segments'
//! lengths and zero angles, and its foot (a sphere, or the sphere inside a
//! foot link's shapes).

use urdf_rs::{Geometry, JointType, Robot};

use crate::error::RobotError;
use crate::legs::LegDescription;
use crate::pose::{Rotation, compose, rotate, rpy_matrix};
use crate::urdf_tree::{bad_joint, fixed_path, fixed_to, joint};

/// How far a joint's axis may be from its canonical direction (or its
/// opposite), component by component.
const AXIS_TOLERANCE: f64 = 1e-4;

pub(crate) fn check_leg(
    urdf: &Robot,
    meshes: &[crate::mesh::MeshCollision],
    root: &str,
    name: &'static str,
    names: &[String; 3],
) -> Result<LegDescription, RobotError> {
    let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let mut joints = Vec::with_capacity(3);
    let mut limits_rad = [[0.0; 2]; 3];
    let mut effort_nm = [0.0; 3];
    let mut velocity_rad_s = [0.0; 3];
    let mut axis_signs = [1.0; 3];
    // The zero pose, in the root's orientation: each joint's frame turned by
    // the origins' rotations so far, and the offsets from joint to joint.
    // The chain: root -> abduction -> hip -> knee, with links fixed between.
    let mut turn = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut abduction_at = [0.0; 3];
    let mut offsets = [[0.0; 3]; 2];
    let mut above = root.to_string();
    for (k, jn) in names.iter().enumerate() {
        let j = joint(urdf, jn)?;
        let continuous = matches!(j.joint_type, JointType::Continuous);
        if !matches!(j.joint_type, JointType::Revolute) && !continuous {
            return Err(bad_joint(
                jn,
                format!("must be revolute or continuous, is {:?}", j.joint_type),
            ));
        }
        let fixed = fixed_path(urdf, &above, &j.parent.link).ok_or_else(|| {
            bad_joint(
                jn,
                format!("its parent must be `{above}` or a link fixed to it"),
            )
        })?;
        // From the joint above (or the root) through the fixed links to this
        // joint, in the root's orientation.
        let mut from_above = [0.0; 3];
        for f in &fixed {
            let step = rotate(&turn, f.origin.xyz.0);
            from_above = [0, 1, 2].map(|i| from_above[i] + step[i]);
            turn = compose(&turn, &rpy_matrix(f.origin.rpy.0));
        }
        let own = rotate(&turn, j.origin.xyz.0);
        let at = if fixed.is_empty() {
            // As written (no sums: the ERS-7's geometry to the bit).
            if k == 0 { j.origin.xyz.0 } else { own }
        } else {
            [0, 1, 2].map(|i| from_above[i] + own[i])
        };
        if k == 0 {
            abduction_at = at;
        } else {
            offsets[k - 1] = at;
        }
        above.clone_from(&j.child.link);
        turn = compose(&turn, &rpy_matrix(j.origin.rpy.0));
        // An axis may point either way along its canonical one, in the root
        // link's frame (to within the rounding of angles written to a few
        // digits, as 1.5708 for a quarter turn: 1e-4).
        let axis = rotate(&turn, j.axis.xyz.0);
        let along = |sign: f64| {
            axis.iter()
                .zip(&axes[k])
                .all(|(a, b)| (a - sign * b).abs() <= AXIS_TOLERANCE)
        };
        let axis_sign = if along(1.0) {
            1.0
        } else if along(-1.0) {
            -1.0
        } else {
            return Err(bad_joint(
                jn,
                format!(
                    "axis must be {:?} or its opposite in the root link's frame, is {axis:?}",
                    axes[k]
                ),
            ));
        };
        // A continuous joint has no limits: the gait's own range is its range.
        // A revolute joint's range need not hold its zero (a knee that is
        // never straight): the gait is checked against it as the robot is read.
        let (lo, hi) = if continuous {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            (j.limit.lower, j.limit.upper)
        };
        let ranged = lo.is_finite() && hi.is_finite() && lo < hi;
        if !(continuous || ranged) {
            return Err(bad_joint(
                jn,
                format!("limits must be finite with lower < upper, are [{lo}, {hi}]"),
            ));
        }
        // An effort or velocity limit of 0 is none given (urdf-rs reads a
        // missing one as 0; PyBullet reads it as no limit; MuJoCo has no
        // speed limit and a joint no actuator limits has no torque limit):
        // its servo is limited in neither.
        let given = |v: f64| if v == 0.0 { f64::INFINITY } else { v };
        let (effort, velocity) = (given(j.limit.effort), given(j.limit.velocity));
        if effort.is_nan() || effort <= 0.0 {
            return Err(bad_joint(
                jn,
                format!("effort must be > 0 or none, is {}", j.limit.effort),
            ));
        }
        if velocity.is_nan() || velocity <= 0.0 {
            return Err(bad_joint(
                jn,
                format!(
                    "velocity limit must be > 0 or none, is {}",
                    j.limit.velocity
                ),
            ));
        }
        // About the canonical axis, the range is the joint's, mirrored if
        // its axis points the other way.
        limits_rad[k] = if axis_sign > 0.0 {
            [lo, hi]
        } else {
            [-hi, -lo]
        };
        axis_signs[k] = axis_sign;
        effort_nm[k] = effort;
        velocity_rad_s[k] = velocity;
        joints.push(j);
    }
    let [hip, knee] = offsets;
    let shank_link = &joints[2].child.link;
    let shank = urdf
        .links
        .iter()
        .find(|l| &l.name == shank_link)
        .ok_or_else(|| RobotError::MissingLink {
            link: shank_link.clone(),
        })?;
    let (foot, foot_radius_m) = find_foot(urdf, shank, [0.0; 3], turn)
        .or_else(|| foot_link(urdf, meshes, shank, turn))
        .ok_or_else(|| RobotError::MissingFoot {
            link: shank_link.clone(),
        })?;
    // A direction in the leg's plane from straight down, positive backwards
    // (a plain zero, not -0, for a segment that hangs straight down).
    let from_down = |v: [f64; 3]| {
        let a = (-v[0]).atan2(-v[2]);
        if a == 0.0 { 0.0 } else { a }
    };
    let (thigh_m, shank_m) = (knee[0].hypot(knee[2]), foot[0].hypot(foot[2]));
    if !(thigh_m > 1e-6 && thigh_m.is_finite()) {
        return Err(bad_joint(
            &names[2],
            format!("must sit away from the hip's axis, sits at {knee:?} m from the hip"),
        ));
    }
    if !(shank_m > 1e-6 && shank_m.is_finite()) {
        return Err(RobotError::MissingFoot {
            link: shank_link.clone(),
        });
    }
    let thigh_zero_rad = from_down(knee);
    let knee_zero_rad = from_down(foot) - thigh_zero_rad;
    Ok(LegDescription {
        name,
        hip_in_torso_m: abduction_at,
        hip_offset_m: hip[1] + knee[1] + foot[1],
        hip_at_m: [hip[0], hip[2]],
        thigh_m,
        shank_m,
        thigh_zero_rad,
        knee_zero_rad,
        foot_radius_m,
        joints: names.clone(),
        limits_rad,
        axis_signs,
        effort_nm,
        velocity_rad_s,
    })
}

/// The foot: the first sphere collision on `link`, or on a link fixed to it
/// (a toe, as many published URDFs have), as its centre in the frame where
/// `link` sits at `at` turned by `turn`, and its radius.
fn find_foot(
    urdf: &Robot,
    link: &urdf_rs::Link,
    at: [f64; 3],
    turn: Rotation,
) -> Option<([f64; 3], f64)> {
    let place = |v: [f64; 3]| {
        let r = rotate(&turn, v);
        [at[0] + r[0], at[1] + r[1], at[2] + r[2]]
    };
    let own = link.collision.iter().find_map(|c| match c.geometry {
        Geometry::Sphere { radius } if radius > 0.0 => Some((place(c.origin.xyz.0), radius)),
        _ => None,
    });
    own.or_else(|| {
        urdf.joints
            .iter()
            .filter(|j| j.parent.link == link.name && matches!(j.joint_type, JointType::Fixed))
            .find_map(|j| {
                let child = urdf.links.iter().find(|l| l.name == j.child.link)?;
                let turn = compose(&turn, &rpy_matrix(j.origin.rpy.0));
                find_foot(urdf, child, place(j.origin.xyz.0), turn)
            })
    })
}

/// A foot that is not a sphere: the link fixed below `shank` (a toe or foot
/// link, as Unitree's Go2 and ODRI's Solo 12 have, with a mesh, box,
/// cylinder or capsule) whose shapes' centre is farthest from the knee,
/// taken as the sphere inside its shapes' bounds: centred on the bounds,
/// with half their smallest extent as radius (a ball's hull gives the ball).
/// In the frame where `shank` sits at the origin turned by `turn`.
fn foot_link(
    urdf: &Robot,
    meshes: &[crate::mesh::MeshCollision],
    shank: &urdf_rs::Link,
    turn: Rotation,
) -> Option<([f64; 3], f64)> {
    // Every link fixed below the shank, with where it sits and how it turns.
    let below: Vec<(usize, [f64; 3], Rotation)> = fixed_to(urdf, &shank.name)
        .into_iter()
        .skip(1)
        .map(|(k, at, own)| (k, rotate(&turn, at), compose(&turn, &own)))
        .collect();
    let mut best: Option<([f64; 3], f64, f64)> = None;
    for (k, at, turn) in below {
        let corners = shape_corners(&urdf.links[k], k, meshes);
        if corners.is_empty() {
            continue;
        }
        let placed: Vec<[f64; 3]> = corners
            .iter()
            .map(|&v| {
                let r = rotate(&turn, v);
                [at[0] + r[0], at[1] + r[1], at[2] + r[2]]
            })
            .collect();
        let lo = [0, 1, 2].map(|i| placed.iter().map(|p| p[i]).fold(f64::INFINITY, f64::min));
        let hi = [0, 1, 2].map(|i| {
            placed
                .iter()
                .map(|p| p[i])
                .fold(f64::NEG_INFINITY, f64::max)
        });
        let centre = [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i]));
        let radius = (0..3)
            .map(|i| 0.5 * (hi[i] - lo[i]))
            .fold(f64::INFINITY, f64::min);
        let reach = centre.iter().map(|v| v * v).sum::<f64>().sqrt();
        if radius > 0.0 && radius.is_finite() && best.is_none_or(|b| reach > b.2) {
            best = Some((centre, radius, reach));
        }
    }
    best.map(|(centre, radius, _)| (centre, radius))
}

/// The corners of the boxes bounding each collision shape of `link` (index
/// `k`), in its frame: a box's own, a cylinder's or capsule's bounding box,
/// a mesh's hull's bounds.
fn shape_corners(
    link: &urdf_rs::Link,
    k: usize,
    meshes: &[crate::mesh::MeshCollision],
) -> Vec<[f64; 3]> {
    let box_corners = |half: [f64; 3], origin: &urdf_rs::Pose| -> Vec<[f64; 3]> {
        let turn = rpy_matrix(origin.rpy.0);
        (0..8)
            .map(|c| {
                let v = [0, 1, 2].map(|i| if c >> i & 1 == 1 { half[i] } else { -half[i] });
                let r = rotate(&turn, v);
                [0, 1, 2].map(|i| origin.xyz.0[i] + r[i])
            })
            .collect()
    };
    let mut out = Vec::new();
    for c in &link.collision {
        let half = match c.geometry {
            Geometry::Box { size } => size.0.map(|v| 0.5 * v),
            Geometry::Cylinder { radius, length } => [radius, radius, 0.5 * length],
            Geometry::Capsule { radius, length } => [radius, radius, 0.5 * length + radius],
            Geometry::Sphere { radius } => [radius; 3],
            Geometry::Mesh { .. } => continue,
        };
        out.extend(box_corners(half, &c.origin));
    }
    for m in meshes.iter().filter(|m| m.link == k) {
        for (shape, pose) in &m.parts {
            let aabb = shape.compute_aabb(pose);
            let (lo, hi) = (aabb.mins, aabb.maxs);
            let centre = urdf_rs::Pose {
                xyz: urdf_rs::Vec3([0, 1, 2].map(|i| 0.5 * f64::from(lo[i] + hi[i]))),
                rpy: urdf_rs::Vec3([0.0; 3]),
            };
            let half = [0, 1, 2].map(|i| 0.5 * f64::from(hi[i] - lo[i]));
            out.extend(box_corners(half, &centre));
        }
    }
    out
}
