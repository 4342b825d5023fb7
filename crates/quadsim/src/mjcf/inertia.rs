//! A body's mass and inertia from its geoms, as MuJoCo's compiler infers
//! them where a body has no `<inertial>` (`inertiafromgeom`): each geom a
//! solid of uniform density (1000 kg/m^3 unless it says its `density` or
//! `mass`), summed about the body's centre of mass.

use crate::pose::{Rotation, compose};

use super::frames::{Frame, transpose};

/// A primitive solid's shape, in its own frame (z its axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Solid {
    /// Radius.
    Sphere(f64),
    /// Radius and half-length of the cylinder between the caps.
    Capsule(f64, f64),
    /// Radius and half-length.
    Cylinder(f64, f64),
    /// Half-sizes.
    Box([f64; 3]),
    /// Semi-axes.
    Ellipsoid([f64; 3]),
}

impl Solid {
    /// Volume, m^3.
    pub fn volume(&self) -> f64 {
        use std::f64::consts::PI;
        match *self {
            Self::Sphere(r) => 4.0 / 3.0 * PI * r.powi(3),
            Self::Capsule(r, h) => 4.0 / 3.0 * PI * r.powi(3) + PI * r * r * 2.0 * h,
            Self::Cylinder(r, h) => PI * r * r * 2.0 * h,
            Self::Box([a, b, c]) => 8.0 * a * b * c,
            Self::Ellipsoid([a, b, c]) => 4.0 / 3.0 * PI * a * b * c,
        }
    }

    /// Principal moments about the centre for `mass`, kg m^2, along x, y, z.
    pub fn moments(&self, mass: f64) -> [f64; 3] {
        match *self {
            Self::Sphere(r) => [0.4 * mass * r * r; 3],
            Self::Capsule(r, h) => {
                // The cylinder and the two caps (a sphere split), by volume.
                let v_cyl = std::f64::consts::PI * r * r * 2.0 * h;
                let v = self.volume();
                let (mc, ms) = (mass * v_cyl / v, mass * (v - v_cyl) / v);
                let len = 2.0 * h;
                let side = mc * (3.0 * r * r + len * len) / 12.0
                    + ms * (0.4 * r * r + 0.25 * len * len + 0.375 * r * len);
                [side, side, mc * 0.5 * r * r + ms * 0.4 * r * r]
            }
            Self::Cylinder(r, h) => {
                let side = mass * (3.0 * r * r + 4.0 * h * h) / 12.0;
                [side, side, 0.5 * mass * r * r]
            }
            Self::Box([a, b, c]) => [
                mass * (b * b + c * c) / 3.0,
                mass * (a * a + c * c) / 3.0,
                mass * (a * a + b * b) / 3.0,
            ],
            Self::Ellipsoid([a, b, c]) => [
                mass * (b * b + c * c) / 5.0,
                mass * (a * a + c * c) / 5.0,
                mass * (a * a + b * b) / 5.0,
            ],
        }
    }
}

/// A body's mass, centre and inertia tensor about that centre, in its frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MassProperties {
    /// kg.
    pub mass: f64,
    /// m, in the body's frame.
    pub centre: [f64; 3],
    /// kg m^2, about the centre, in the body's axes.
    pub inertia: Rotation,
}

/// The sum of solids of the given masses placed at the given frames.
pub(crate) fn combine(parts: &[(Solid, f64, Frame)]) -> Option<MassProperties> {
    let mass: f64 = parts.iter().map(|p| p.1).sum();
    if !(mass > 0.0 && mass.is_finite()) {
        return None;
    }
    let centre = [0, 1, 2].map(|i| parts.iter().map(|(_, m, f)| m * f.pos[i]).sum::<f64>() / mass);
    let mut inertia = [[0.0; 3]; 3];
    for (solid, m, f) in parts {
        let [a, b, c] = solid.moments(*m);
        let own = [[a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]];
        let turned = compose(&compose(&f.rot, &own), &transpose(&f.rot));
        let d = [0, 1, 2].map(|i| f.pos[i] - centre[i]);
        let d2: f64 = d.iter().map(|x| x * x).sum();
        for i in 0..3 {
            for j in 0..3 {
                let shift = m * (if i == j { d2 } else { 0.0 } - d[i] * d[j]);
                inertia[i][j] += turned[i][j] + shift;
            }
        }
    }
    Some(MassProperties {
        mass,
        centre,
        inertia,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_spheres_apart_are_a_dumbbell() {
        let at = |x: f64| Frame {
            pos: [x, 0.0, 0.0],
            ..Frame::ORIGIN
        };
        let s = Solid::Sphere(0.1);
        let p = combine(&[(s, 1.0, at(-0.5)), (s, 1.0, at(0.5))]).expect("mass");
        assert_eq!(p.centre, [0.0; 3]);
        let own = 0.4 * 0.01;
        assert!((p.inertia[0][0] - 2.0 * own).abs() < 1e-15);
        assert!((p.inertia[1][1] - (2.0 * own + 2.0 * 0.25)).abs() < 1e-12);
    }

    #[test]
    fn a_capsule_of_no_length_is_a_sphere() {
        let m = Solid::Capsule(0.2, 0.0).moments(3.0);
        let s = Solid::Sphere(0.2).moments(3.0);
        assert!(
            m.iter().zip(s).all(|(a, b)| (a - b).abs() < 1e-15),
            "{m:?} {s:?}"
        );
        assert!((Solid::Capsule(0.2, 0.0).volume() - Solid::Sphere(0.2).volume()).abs() < 1e-15);
    }
}
