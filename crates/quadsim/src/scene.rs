//! What a viewer draws of the world, as plain numbers: every body (the floor,
//! the beacon, the robot's links by their URDF names) with its colliders'
//! shapes in the body's own frame, the robot's kinematic tree, and where each
//! body is now. Recorders and viewers read it; nothing here feeds the physics.

use rapier3d::math::Pose;

/// A rigid placement: a translation, m, after a rotation (unit quaternion).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Translation, m.
    pub translation_m: [f64; 3],
    /// Rotation as a unit quaternion `[x, y, z, w]`.
    pub rotation_xyzw: [f64; 4],
}

impl Placement {
    /// No translation, no rotation.
    pub const IDENTITY: Self = Self {
        translation_m: [0.0; 3],
        rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
    };

    /// `p` moved by this placement.
    pub fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let [x, y, z, w] = self.rotation_xyzw;
        // v' = v + 2 w (q x v) + 2 q x (q x v), with q the vector part.
        let q = [x, y, z];
        let t = cross(q, p).map(|c| 2.0 * c);
        let u = cross(q, t);
        let m = self.translation_m;
        [
            p[0] + w * t[0] + u[0] + m[0],
            p[1] + w * t[1] + u[1] + m[1],
            p[2] + w * t[2] + u[2] + m[2],
        ]
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl From<&Pose> for Placement {
    fn from(p: &Pose) -> Self {
        let (t, q) = (p.translation, p.rotation);
        Self {
            translation_m: [t.x, t.y, t.z].map(f64::from),
            rotation_xyzw: [q.x, q.y, q.z, q.w].map(f64::from),
        }
    }
}

/// A collider's shape in its own frame.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Shape {
    /// A box, centred.
    Cuboid {
        /// Half its size along x, y and z, m.
        half_extents_m: [f64; 3],
    },
    /// A sphere, centred.
    Ball {
        /// Its radius, m.
        radius_m: f64,
    },
    /// A capsule: the points within `radius_m` of the segment `a_m`-`b_m`.
    Capsule {
        /// One end of its axis, m.
        a_m: [f64; 3],
        /// The other end, m.
        b_m: [f64; 3],
        /// Its radius, m.
        radius_m: f64,
    },
    /// A cylinder, centred, its axis along y (parry's convention).
    Cylinder {
        /// Half its length, m.
        half_height_m: f64,
        /// Its radius, m.
        radius_m: f64,
    },
    /// Any other shape (a mesh, a convex hull), by its bounding box.
    Bounds {
        /// The box's lowest corner, m.
        min_m: [f64; 3],
        /// Its highest corner, m.
        max_m: [f64; 3],
    },
}

impl Shape {
    /// The shape of a parry shape: exactly where it is one of the primitives
    /// above, else by its bounding box.
    pub fn of(shape: &dyn rapier3d::parry::shape::Shape) -> Self {
        let v = |v: rapier3d::math::Vector| [v.x, v.y, v.z].map(f64::from);
        if let Some(c) = shape.as_cuboid() {
            Self::Cuboid {
                half_extents_m: v(c.half_extents),
            }
        } else if let Some(b) = shape.as_ball() {
            Self::Ball {
                radius_m: f64::from(b.radius),
            }
        } else if let Some(c) = shape.as_capsule() {
            Self::Capsule {
                a_m: v(c.segment.a),
                b_m: v(c.segment.b),
                radius_m: f64::from(c.radius),
            }
        } else if let Some(c) = shape.as_cylinder() {
            Self::Cylinder {
                half_height_m: f64::from(c.half_height),
                radius_m: f64::from(c.radius),
            }
        } else {
            let aabb = shape.compute_local_aabb();
            Self::Bounds {
                min_m: v(aabb.mins),
                max_m: v(aabb.maxs),
            }
        }
    }
}

/// What a part of the world is, for colouring it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The floor (a very large box).
    Floor,
    /// The beacon's pole, below the band.
    BeaconPole,
    /// The beacon's coloured band, which the camera measures.
    BeaconBand,
    /// A part of the robot.
    Robot,
}

/// One collider of a body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Part {
    /// Its shape, in its own frame.
    pub shape: Shape,
    /// Its frame in its body's frame.
    pub in_body: Placement,
    /// What it is.
    pub role: Role,
}

/// One rigid body and its colliders.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneBody {
    /// `floor`, `beacon`, or the robot link's URDF name.
    pub name: String,
    /// Whether it is one of the robot's links (the world's bodies are fixed).
    pub robot_link: bool,
    /// The robot link it hangs from by a joint, as an index into
    /// [`Scene::bodies`] (`None` for the root link and the world's bodies).
    pub parent: Option<usize>,
    /// Its colliders (a link may have none).
    pub parts: Vec<Part>,
}

/// Every body of the world, in a fixed order (that of
/// [`crate::QuadrupedSim::placements`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The bodies.
    pub bodies: Vec<SceneBody>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_placement_rotates_then_translates() {
        // A quarter turn about z, then 1 m along x: (1, 0, 0) -> (1, 1, 0).
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let p = Placement {
            translation_m: [1.0, 0.0, 0.0],
            rotation_xyzw: [0.0, 0.0, h, h],
        };
        let q = p.apply([1.0, 0.0, 0.0]);
        for (a, b) in q.iter().zip([1.0, 1.0, 0.0]) {
            assert!((a - b).abs() < 1e-12, "{q:?}");
        }
        assert_eq!(Placement::IDENTITY.apply([1.0, 2.0, 3.0]), [1.0, 2.0, 3.0]);
    }
}
