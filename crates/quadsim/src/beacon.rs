//! The beacon: a coloured band on a pole, standing on the floor.

use std::ops::ControlFlow;

use rapier3d::geometry::{ColliderBuilder, ColliderHandle};
use rapier3d::math::{Pose, Real, Rotation, Vector};
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::RigidBodyBuilder;

/// Where the beacon stands and what it looks like.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeaconConfig {
    /// Position on the floor, m.
    pub xy_m: [f64; 2],
    /// Radius of the pole and band, m.
    pub radius_m: f64,
    /// Height of the band's middle above the floor, m.
    pub band_centre_m: f64,
    /// The band's height, m.
    pub band_height_m: f64,
}

impl Default for BeaconConfig {
    /// A RoboCup-legged-league-like beacon: 10 cm across, a 20 cm band centred
    /// near the camera's height.
    fn default() -> Self {
        Self {
            xy_m: [0.0, 0.0],
            radius_m: 0.05,
            band_centre_m: 0.20,
            band_height_m: 0.20,
        }
    }
}

impl BeaconConfig {
    /// Height of the band's lower edge above the floor, m.
    pub fn band_bottom_m(&self) -> f64 {
        self.band_centre_m - 0.5 * self.band_height_m
    }

    /// Height of the band's upper edge above the floor, m.
    pub fn band_top_m(&self) -> f64 {
        self.band_centre_m + 0.5 * self.band_height_m
    }

    /// Where the ray `origin + t dir` (world frame, `dir` of unit length) first
    /// meets the band: its distance `t`, exactly (a vertical cylinder's side and
    /// end discs), or `None`.
    pub fn ray_hits_band(&self, origin: [f64; 3], dir: [f64; 3]) -> Option<f64> {
        let mut best: Option<f64> = None;
        let _ = self.band_crossings(origin, dir, |t| {
            if best.is_none_or(|b| t < b) {
                best = Some(t);
            }
            ControlFlow::Continue(())
        });
        best
    }

    /// Whether the ray `origin + t dir` meets the band: whether
    /// [`Self::ray_hits_band`] is `Some`, stopping at the first crossing found.
    pub fn ray_meets_band(&self, origin: [f64; 3], dir: [f64; 3]) -> bool {
        self.band_crossings(origin, dir, |_| ControlFlow::Break(()))
            .is_break()
    }

    /// Hands `visit` each distance `t > 0` at which the ray crosses the band's
    /// surface (the side wall's two roots, then the end discs), until it breaks.
    fn band_crossings(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        mut visit: impl FnMut(f64) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let (px, py) = (origin[0] - self.xy_m[0], origin[1] - self.xy_m[1]);
        let r2 = self.radius_m * self.radius_m;
        let z_at = |t: f64| origin[2] + t * dir[2];
        let within = |z: f64| (self.band_bottom_m()..=self.band_top_m()).contains(&z);
        // Side wall: |p + t d|^2 = R^2 in the horizontal plane.
        let a = dir[0] * dir[0] + dir[1] * dir[1];
        if a > 0.0 {
            let b = 2.0 * (px * dir[0] + py * dir[1]);
            let c = px * px + py * py - r2;
            let disc = b * b - 4.0 * a * c;
            if disc >= 0.0 {
                let sq = disc.sqrt();
                for t in [(-b - sq) / (2.0 * a), (-b + sq) / (2.0 * a)] {
                    if within(z_at(t)) && t > 0.0 {
                        visit(t)?;
                    }
                }
            }
        }
        // End discs.
        if dir[2] != 0.0 {
            for z in [self.band_bottom_m(), self.band_top_m()] {
                let t = (z - origin[2]) / dir[2];
                let (x, y) = (px + t * dir[0], py + t * dir[1]);
                if x * x + y * y <= r2 && t > 0.0 {
                    visit(t)?;
                }
            }
        }
        ControlFlow::Continue(())
    }

    /// Adds the pole and the band to the world; returns the band's collider.
    pub fn insert(&self, world: &mut PhysicsWorld) -> ColliderHandle {
        let [x, y] = self.xy_m.map(|v| v as Real);
        let body = world
            .bodies
            .insert(RigidBodyBuilder::fixed().translation(Vector::new(x, y, 0.0)));
        // parry's cylinders stand along y; turn them to stand along z.
        let upright = Rotation::from_rotation_x(core::f32::consts::FRAC_PI_2);
        let r = self.radius_m as Real;
        let mut cylinder = |bottom: f64, top: f64| {
            let half = (0.5 * (top - bottom)) as Real;
            let centre = (0.5 * (top + bottom)) as Real;
            world.colliders.insert_with_parent(
                ColliderBuilder::cylinder(half, r)
                    .position(Pose::from_parts(Vector::new(0.0, 0.0, centre), upright)),
                body,
                &mut world.bodies,
            )
        };
        if self.band_bottom_m() > 0.0 {
            cylinder(0.0, self.band_bottom_m());
        }
        cylinder(self.band_bottom_m(), self.band_top_m())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rays_meet_the_band_exactly() {
        let b = BeaconConfig {
            xy_m: [1.0, 0.0],
            ..Default::default()
        };
        // Head-on at mid-height: the front of the wall, 0.95 m away.
        let t = b
            .ray_hits_band([0.0, 0.0, 0.2], [1.0, 0.0, 0.0])
            .expect("hit");
        assert!((t - 0.95).abs() < 1e-12);
        // Just above and just below the top edge of the front.
        let up = |dz: f64| {
            let n = (1.0 + dz * dz).sqrt();
            b.ray_hits_band([0.0, 0.0, 0.2], [1.0 / n, 0.0, dz / n])
        };
        assert!(up(0.1 / 0.95 - 1e-6).is_some());
        assert!(up(0.1 / 0.95 + 1e-3).is_none());
        // From above, onto the top disc.
        let t = b
            .ray_hits_band([1.0, 0.0, 1.0], [0.0, 0.0, -1.0])
            .expect("hit");
        assert!((t - 0.7).abs() < 1e-12);
        // Passing beside it.
        assert!(b.ray_hits_band([0.0, 0.2, 0.2], [1.0, 0.0, 0.0]).is_none());
    }

    #[test]
    fn meeting_the_band_is_having_a_hit() {
        use rand::{RngExt, SeedableRng};
        let b = BeaconConfig {
            xy_m: [1.0, 0.3],
            ..Default::default()
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..20_000 {
            // From around the camera's height, aimed about the band, some from
            // above and inside its radius (the end discs), some behind.
            let origin = [
                rng.random_range(-0.5..1.5),
                rng.random_range(-0.5..1.0),
                rng.random_range(0.0..0.5),
            ];
            let aim = [
                1.0 + rng.random_range(-0.08..0.08),
                0.3 + rng.random_range(-0.08..0.08),
                rng.random_range(0.05..0.35),
            ];
            let d: [f64; 3] = core::array::from_fn(|k| aim[k] - origin[k]);
            let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let dir = d.map(|v| v / n);
            let hit = b.ray_hits_band(origin, dir).is_some();
            assert_eq!(b.ray_meets_band(origin, dir), hit, "{origin:?} {dir:?}");
            if hit {
                hits += 1;
            } else {
                misses += 1;
            }
        }
        assert!(hits > 1000 && misses > 1000, "{hits} hits, {misses} misses");
    }
}
