//! What the head's camera sees of the beacon: which pixels' rays meet the band
//! first (ray casts into the physics world, so anything in the way occludes it),
//! the blob's vertical extent as the reading, and the band's bearing.

use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rapier3d::dynamics::RigidBodyHandle;
use rapier3d::geometry::{Collider, ColliderHandle, Ray};
use rapier3d::math::{Pose, Real, Vector};
use rapier3d::pipeline::{PhysicsWorld, QueryFilter};
use std::ops::RangeInclusive;

use crate::beacon::BeaconConfig;
use crate::camera::CameraIntrinsics;

/// The camera's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraConfig {
    /// Pinhole intrinsics.
    pub intrinsics: CameraIntrinsics,
    /// Standard deviation of Gaussian noise added to each reading, px.
    pub noise_px: f64,
    /// Time between frames, s (20 Hz on the Aibo).
    pub frame_period_s: f64,
    /// Seed of the reading noise's random stream.
    pub noise_seed: u64,
}

impl Default for CameraConfig {
    /// The noise is set so that, added to what the idle gait's head bob and pixel
    /// quantisation already give (0.4 to 1.2 px), the robot's readings while it
    /// stands at the 13 test distances have a standard deviation of about 1 px on
    /// average, as the paper's did (<= 1.1 px).
    fn default() -> Self {
        Self {
            intrinsics: CameraIntrinsics::default(),
            noise_px: 0.8,
            frame_period_s: 0.05,
            noise_seed: 0,
        }
    }
}

/// The band as the image shows it, before noise.
#[derive(Debug, Clone, PartialEq)]
pub struct BandBlob {
    /// Its pixels (those whose rays meet the band first) as runs of columns,
    /// `(row, first, last)`: rows top to bottom, a row's runs left to right.
    pub runs: Vec<(u32, u32, u32)>,
    /// Topmost and bottommost rows.
    pub rows: [u32; 2],
    /// Leftmost and rightmost columns.
    pub cols: [u32; 2],
}

impl BandBlob {
    /// The pixels `(col, row)`, row by row, each row left to right.
    pub fn pixels(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.runs
            .iter()
            .flat_map(|&(row, first, last)| (first..=last).map(move |col| (col, row)))
    }

    /// How many pixels show the band.
    pub fn pixel_count(&self) -> u64 {
        self.runs
            .iter()
            .map(|&(_, a, b)| u64::from(b - a + 1))
            .sum()
    }

    /// Vertical extent, px.
    pub fn extent_px(&self) -> f64 {
        f64::from(self.rows[1] - self.rows[0] + 1)
    }

    /// Mean column position (pixel centres), px. The centres' sum is a
    /// multiple of 1/2 far below 2^53, so it is exact whichever way it is
    /// added: here twice it, `n (first + last + 1)` a run, in integers.
    pub fn mean_column(&self) -> f64 {
        let twice: u64 = self
            .runs
            .iter()
            .map(|&(_, a, b)| u64::from(b - a + 1) * u64::from(a + b + 1))
            .sum();
        twice as f64 / 2.0 / self.pixel_count() as f64
    }
}

/// Why a frame has no reading.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoReading {
    /// The band is behind the camera or outside the image.
    OutOfView,
    /// The band reaches the image border, so its extent is unknown.
    CutByBorder,
    /// Something stands between the camera and part of the band.
    Occluded,
}

/// One camera frame's result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// When it was taken, s.
    pub t_s: f64,
    /// The beacon's height in the image, px (noise included), or why there is none.
    pub obs_px: Result<f64, NoReading>,
    /// The band's horizontal bearing (rad, left positive), when it is seen.
    pub bearing_rad: Option<f64>,
}

/// The 24 directions, every 15 degrees, at which the band's rims are
/// projected to bound its silhouette: `[cos, sin]`, computed once.
static RIM_DIRECTIONS: std::sync::LazyLock<[[f64; 2]; 24]> = std::sync::LazyLock::new(|| {
    core::array::from_fn(|k| {
        let a = k as f64 * core::f64::consts::TAU / 24.0;
        [a.cos(), a.sin()]
    })
});

/// Finds the band's pixels in the image of a camera at `camera_pose`: a pixel
/// shows the band when its ray meets the band (exactly, analytically) and nothing
/// else in the physics world first. The bodies the camera is mounted on,
/// `own_bodies` (its link and every link rigidly fixed to it), hide nothing:
/// its lens looks out of them, as a camera looks out through its housing (a
/// camera mounted on its link's surface would otherwise see the inside of the
/// link, as the rounding of each step's pose puts it a hair inside or out,
/// and one found for a bare URDF at its root's front would see the inside of
/// a shell or face plate fixed there). Links that move against the camera
/// (legs) still hide the beacon.
pub fn find_band(
    world: &PhysicsWorld,
    camera_pose: &Pose,
    intrinsics: &CameraIntrinsics,
    beacon: &BeaconConfig,
    band: ColliderHandle,
    own_bodies: &[RigidBodyHandle],
) -> Result<BandBlob, NoReading> {
    // The band's silhouette lies within the projections of its rims: none of
    // them in the image is out of view, some of them is cut by the border.
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    let (mut inside, mut total) = (0, 0);
    for &[cos, sin] in RIM_DIRECTIONS.iter() {
        for z in [beacon.band_bottom_m(), beacon.band_top_m()] {
            let w = Vector::new(
                (beacon.xy_m[0] + beacon.radius_m * cos) as Real,
                (beacon.xy_m[1] + beacon.radius_m * sin) as Real,
                z as Real,
            );
            let c = camera_pose.inverse_transform_point(w);
            total += 1;
            if let Some([u, v]) = intrinsics.project([c.x, c.y, c.z].map(f64::from)) {
                inside += 1;
                lo = [lo[0].min(u), lo[1].min(v)];
                hi = [hi[0].max(u), hi[1].max(v)];
            }
        }
    }
    if inside == 0 {
        return Err(NoReading::OutOfView);
    }
    if inside < total {
        return Err(NoReading::CutByBorder);
    }
    let (w, h) = (intrinsics.width_px, intrinsics.height_px);
    let clamp = |x: f64, n: u32| (x.max(0.0) as u32).min(n - 1);
    let (c0, c1) = (clamp(lo[0].floor() - 1.0, w), clamp(hi[0].ceil() + 1.0, w));
    let (r0, r1) = (clamp(lo[1].floor() - 1.0, h), clamp(hi[1].ceil() + 1.0, h));

    let beacon_body = world.colliders[band].parent();
    let may_occlude = anything_between(world, camera_pose, beacon, beacon_body, own_bodies);
    let o = camera_pose.translation;
    let origin = [o.x, o.y, o.z].map(f64::from);
    let max_toi: Real = 1e3;
    let rays = intrinsics.pixel_rays();
    let outside_own = |_, c: &Collider| c.parent().is_none_or(|p| !own_bodies.contains(&p));
    let filter = QueryFilter::default().predicate(&outside_own);
    // The distance along the ray through pixel `(col, row)` to the band, if it
    // meets it, and the ray's direction.
    let direction = |col: u32, row: u32| {
        let [x, y, z] = rays.ray(col, row).map(|v| v as Real);
        (camera_pose.rotation * Vector::new(x, y, z)).normalize()
    };
    let as_f64 = |d: Vector| [d.x, d.y, d.z].map(f64::from);
    let mut runs: Vec<(u32, u32, u32)> = Vec::new();
    if !may_occlude {
        // Nothing can hide the band, so its pixels are those whose rays meet
        // it. The rays through one image row lie in one plane, which cuts the
        // band (a convex solid) in a convex section, so a row's pixels form
        // one run: its two ends are searched for from the last row's, its
        // inside taken whole.
        let mut near = (c0, c0);
        for row in r0..=r1 {
            let hit = |col: u32| beacon.ray_meets_band(origin, as_f64(direction(col, row)));
            let Some((first, last)) = run_in_row(hit, c0..=c1, near) else {
                continue;
            };
            near = (first, last);
            runs.push((row, first, last));
        }
    } else {
        for row in r0..=r1 {
            for col in c0..=c1 {
                let d = direction(col, row);
                let Some(band_t) = beacon.ray_hits_band(origin, as_f64(d)) else {
                    continue;
                };
                // Only something other than the beacon itself (its pole's top
                // face coincides with the band's bottom face) can hide the band.
                let first = world.cast_ray(&Ray::new(o, d), max_toi, true, filter);
                match first {
                    Some((hit, t))
                        if world.colliders[hit].parent() != beacon_body
                            && f64::from(t) < band_t - 1e-4 =>
                    {
                        return Err(NoReading::Occluded);
                    }
                    _ => match runs.last_mut() {
                        Some((r, _, last)) if *r == row && *last + 1 == col => *last = col,
                        _ => runs.push((row, col, col)),
                    },
                }
            }
        }
    }
    let (Some(top), Some(bottom)) = (runs.first(), runs.last()) else {
        return Err(NoReading::OutOfView);
    };
    let rows = [top.0, bottom.0];
    let cols = [
        runs.iter().map(|r| r.1).min().unwrap_or(0),
        runs.iter().map(|r| r.2).max().unwrap_or(0),
    ];
    if rows[0] == 0 || cols[0] == 0 || rows[1] == h - 1 || cols[1] == w - 1 {
        return Err(NoReading::CutByBorder);
    }
    Ok(BandBlob { runs, rows, cols })
}

/// The run of columns in `cols` where `hit` holds, given that they are one run
/// or none; `near` is a guess at its two ends (the last row's). Each end is
/// searched for from its guess, so a run that moved little from row to row
/// costs a few tests instead of the columns outside it.
fn run_in_row(
    hit: impl Fn(u32) -> bool,
    cols: RangeInclusive<u32>,
    near: (u32, u32),
) -> Option<(u32, u32)> {
    let (c0, c1) = (*cols.start(), *cols.end());
    // The end of the run of hits next to `from`, stepping by `step` (-1: left).
    let run_end = |from: u32, step: i32| {
        let mut end = from;
        while let Some(next) = end.checked_add_signed(step).filter(|c| cols.contains(c)) {
            if !hit(next) {
                break;
            }
            end = next;
        }
        end
    };
    let guess = near.0.clamp(c0, c1);
    let first = if hit(guess) {
        run_end(guess, -1)
    } else if let Some(right) = (guess + 1..=c1).find(|&c| hit(c)) {
        right
    } else {
        // The whole run is left of the guess: its right end first.
        run_end((c0..guess).rev().find(|&c| hit(c))?, -1)
    };
    // The run's left end hits, so its right end is at or right of it.
    let guess = near.1.clamp(first, c1);
    let last = if hit(guess) {
        run_end(guess, 1)
    } else {
        (first..guess).rev().find(|&c| hit(c)).unwrap_or(first)
    };
    Some((first, last))
}

/// Whether any collider but the beacon's own could stand between the camera and
/// the band: whether it meets the convex hull of the camera's centre and the
/// band's bounding box (upright, square, circumscribing the band), which holds
/// every ray segment from the camera to the band. If none does, no pixel's ray
/// can be blocked and the per-pixel ray casts are skipped; the answer errs only
/// on the side of casting rays, and any shape pair parry cannot test counts as
/// "may". (A hull of nine points: one of the two rims' polygons costs parry
/// ten times as much to build, a tenth of a physics step per frame.)
fn anything_between(
    world: &PhysicsWorld,
    camera_pose: &Pose,
    beacon: &BeaconConfig,
    beacon_body: Option<RigidBodyHandle>,
    own_bodies: &[RigidBodyHandle],
) -> bool {
    use rapier3d::parry::bounding_volume::{Aabb, BoundingVolume};
    use rapier3d::parry::query::intersection_test;
    use rapier3d::parry::shape::ConvexPolyhedron;
    let r = beacon.radius_m;
    let mut points = vec![camera_pose.translation];
    for (dx, dy) in [(-r, -r), (r, -r), (r, r), (-r, r)] {
        for z in [beacon.band_bottom_m(), beacon.band_top_m()] {
            points.push(Vector::new(
                (beacon.xy_m[0] + dx) as Real,
                (beacon.xy_m[1] + dy) as Real,
                z as Real,
            ));
        }
    }
    // Only a collider whose bounding box meets the points' can meet their
    // hull; most frames have none, and skip building the hull.
    let reach = Aabb::from_points(points.iter().copied());
    let mut near = world
        .colliders
        .iter()
        .filter(|(_, c)| {
            c.parent()
                .is_none_or(|p| Some(p) != beacon_body && !own_bodies.contains(&p))
        })
        .filter(|(_, c)| c.compute_aabb().intersects(&reach))
        .peekable();
    if near.peek().is_none() {
        return false;
    }
    let Some(hull) = ConvexPolyhedron::from_convex_hull(&points) else {
        return true;
    };
    let identity = Pose::IDENTITY;
    near.any(|(_, c)| {
        intersection_test(&identity, &hull, c.position(), c.shape())
            .map_or(true, |i| i.intersecting)
    })
}

/// The camera: finds the band and turns it into a noisy reading and a bearing.
#[derive(Debug, Clone)]
pub struct Camera {
    config: CameraConfig,
    noise: Normal<f64>,
    rng: ChaCha8Rng,
}

impl Camera {
    /// A camera with its own noise stream. The config must have been checked
    /// (finite, non-negative noise).
    pub(crate) fn new(config: CameraConfig) -> Self {
        use rand::SeedableRng;
        let noise = Normal::new(0.0, config.noise_px).unwrap_or_else(|_| {
            Normal::new(0.0, 0.0).unwrap_or_else(|_| unreachable!("zero spread is valid"))
        });
        Self {
            config,
            noise,
            rng: ChaCha8Rng::seed_from_u64(config.noise_seed),
        }
    }

    /// Changes the reading noise from now on (the stream carries on). The
    /// value must have been checked (finite, non-negative).
    pub(crate) fn set_noise_px(&mut self, noise_px: f64) {
        if let Ok(noise) = Normal::new(0.0, noise_px) {
            self.config.noise_px = noise_px;
            self.noise = noise;
        }
    }

    /// The settings in use.
    pub fn config(&self) -> &CameraConfig {
        &self.config
    }

    /// Takes one frame at `t_s`.
    pub(crate) fn capture(
        &mut self,
        t_s: f64,
        world: &PhysicsWorld,
        camera_pose: &Pose,
        beacon: &BeaconConfig,
        band: ColliderHandle,
        own_bodies: &[RigidBodyHandle],
    ) -> Frame {
        let intr = &self.config.intrinsics;
        match find_band(world, camera_pose, intr, beacon, band, own_bodies) {
            Ok(blob) => {
                let obs = blob.extent_px() + self.noise.sample(&mut self.rng);
                Frame {
                    t_s,
                    obs_px: if obs > 0.5 {
                        Ok(obs)
                    } else {
                        Err(NoReading::OutOfView)
                    },
                    bearing_rad: Some(intr.bearing_of_column(blob.mean_column())),
                }
            }
            Err(why) => Frame {
                t_s,
                obs_px: Err(why),
                bearing_rad: None,
            },
        }
    }
}

/// An RGB image (row-major, 3 bytes a pixel) of what the camera saw: a plain grey
/// background, the band's pixels in orange, and the measured extent marked by two
/// green lines across the blob's top and bottom rows.
pub fn render_rgb(intrinsics: &CameraIntrinsics, blob: Option<&BandBlob>) -> Vec<u8> {
    let (w, h) = (intrinsics.width_px as usize, intrinsics.height_px as usize);
    let mut img = vec![96u8; 3 * w * h];
    let mut put = |col: u32, row: u32, rgb: [u8; 3]| {
        let i = 3 * (row as usize * w + col as usize);
        img[i..i + 3].copy_from_slice(&rgb);
    };
    if let Some(b) = blob {
        for (c, r) in b.pixels() {
            put(c, r, [255, 140, 0]);
        }
        let (c0, c1) = (
            b.cols[0].saturating_sub(4),
            (b.cols[1] + 4).min(intrinsics.width_px - 1),
        );
        for row in [b.rows[0], b.rows[1]] {
            for col in c0..=c1 {
                let on_band = |&(r, a, z): &(u32, u32, u32)| r == row && (a..=z).contains(&col);
                if !b.runs.iter().any(on_band) {
                    put(col, row, [40, 220, 60]);
                }
            }
        }
    }
    img
}

#[cfg(test)]
mod tests {
    use super::run_in_row;

    /// Every run (and no run) in a row of columns, from every guess: the run
    /// found is the run, whatever the guess.
    #[test]
    fn a_rows_run_is_found_from_any_guess() {
        let cols = 3..=14u32;
        let mut runs = vec![None];
        for a in cols.clone() {
            runs.extend((a..=*cols.end()).map(|b| Some((a, b))));
        }
        for run in runs {
            let hit = |c: u32| run.is_some_and(|(a, b)| (a..=b).contains(&c));
            for g0 in 0..=16 {
                for g1 in 0..=16 {
                    assert_eq!(
                        run_in_row(hit, cols.clone(), (g0, g1)),
                        run,
                        "guess ({g0}, {g1})"
                    );
                }
            }
        }
    }
}
