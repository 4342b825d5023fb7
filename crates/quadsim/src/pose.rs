//! URDF frames: roll-pitch-yaw rotations, composing them, and placing a
//! point of a child frame in its parent's (plain `f64` arithmetic, so a
//! robot's geometry is read the same on every machine).

/// A 3 x 3 rotation matrix, row-major.
pub(crate) type Rotation = [[f64; 3]; 3];

/// URDF's roll-pitch-yaw (fixed axes x, y, z): `Rz(yaw) Ry(pitch) Rx(roll)`.
pub(crate) fn rpy_matrix([r, p, y]: [f64; 3]) -> Rotation {
    let (sr, cr, sp, cp, sy, cy) = (r.sin(), r.cos(), p.sin(), p.cos(), y.sin(), y.cos());
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

pub(crate) fn rotate(m: &Rotation, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

/// A URDF origin (`xyz`, and `rpy` about the fixed x, y and z axes:
/// `Rz(yaw) Ry(pitch) Rx(roll)`) as a rapier pose.
pub(crate) fn urdf_pose(xyz: [f64; 3], rpy: [f64; 3]) -> rapier3d::math::Pose {
    use rapier3d::math::{Pose, Real, Rotation, Vector};
    let [x, y, z] = xyz.map(|v| v as Real);
    let [roll, pitch, yaw] = rpy.map(|v| v as Real);
    Pose::from_parts(
        Vector::new(x, y, z),
        Rotation::from_euler(rapier3d::glamx::EulerRot::ZYX, yaw, pitch, roll),
    )
}

/// `v`, a point in a joint's child frame, in its parent's frame.
pub(crate) fn place(origin: &urdf_rs::Pose, v: [f64; 3]) -> [f64; 3] {
    let r = rotate(&rpy_matrix(origin.rpy.0), v);
    [0, 1, 2].map(|i| origin.xyz.0[i] + r[i])
}

pub(crate) fn compose(a: &Rotation, b: &Rotation) -> Rotation {
    [0, 1, 2].map(|i| [0, 1, 2].map(|k| (0..3).map(|j| a[i][j] * b[j][k]).sum()))
}
