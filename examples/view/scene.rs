//! A wireframe picture of the physics world from a camera that follows the robot:
//! every collider drawn from its own shape and pose, the floor as a grid, the
//! line of approach with the test range marked.

use plotters::coord::Shift;
use plotters::prelude::*;
use quadsim::QuadrupedSim;
use rapier3d::math::{Pose, Vector};

/// A pinhole looking from `eye` at `target`, z up, into a panel of `size` pixels.
struct View {
    eye: [f64; 3],
    right: [f64; 3],
    up: [f64; 3],
    forward: [f64; 3],
    focal_px: f64,
    centre: (f64, f64),
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: [f64; 3]) -> [f64; 3] {
    let n = dot(a, a).sqrt().max(1e-12);
    [a[0] / n, a[1] / n, a[2] / n]
}

impl View {
    fn new(eye: [f64; 3], target: [f64; 3], size: (u32, u32), hfov_deg: f64) -> Self {
        let forward = unit(sub(target, eye));
        let right = unit(cross(forward, [0.0, 0.0, 1.0]));
        let up = cross(right, forward);
        let focal_px = 0.5 * f64::from(size.0) / (0.5 * hfov_deg.to_radians()).tan();
        Self {
            eye,
            right,
            up,
            forward,
            focal_px,
            centre: (0.5 * f64::from(size.0), 0.5 * f64::from(size.1)),
        }
    }

    /// Camera-frame coordinates: (right, up, depth).
    fn camera(&self, p: [f64; 3]) -> [f64; 3] {
        let d = sub(p, self.eye);
        [dot(d, self.right), dot(d, self.up), dot(d, self.forward)]
    }

    fn pixel(&self, c: [f64; 3]) -> (i32, i32) {
        (
            (self.centre.0 + self.focal_px * c[0] / c[2]).round() as i32,
            (self.centre.1 - self.focal_px * c[1] / c[2]).round() as i32,
        )
    }

    /// A segment's pixels, clipped to what lies in front of the camera.
    fn segment(&self, a: [f64; 3], b: [f64; 3]) -> Option<[(i32, i32); 2]> {
        const NEAR: f64 = 0.05;
        let (mut ca, mut cb) = (self.camera(a), self.camera(b));
        if ca[2] < NEAR && cb[2] < NEAR {
            return None;
        }
        let clip = |p: [f64; 3], q: [f64; 3]| {
            let t = (NEAR - p[2]) / (q[2] - p[2]);
            [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), NEAR]
        };
        if ca[2] < NEAR {
            ca = clip(ca, cb);
        } else if cb[2] < NEAR {
            cb = clip(cb, ca);
        }
        Some([self.pixel(ca), self.pixel(cb)])
    }
}

fn world_point(pose: &Pose, local: [f64; 3]) -> [f64; 3] {
    let v = Vector::new(local[0] as f32, local[1] as f32, local[2] as f32);
    let w = pose.transform_point(v);
    [f64::from(w.x), f64::from(w.y), f64::from(w.z)]
}

/// The edges of one collider's shape, in world coordinates.
fn edges(pose: &Pose, shape: &dyn rapier3d::parry::shape::Shape) -> Vec<[[f64; 3]; 2]> {
    let mut out = Vec::new();
    if let Some(c) = shape.as_cuboid() {
        let h = [
            f64::from(c.half_extents.x),
            f64::from(c.half_extents.y),
            f64::from(c.half_extents.z),
        ];
        if h.iter().any(|&e| e > 2.0) {
            return out; // the floor: drawn as a grid instead
        }
        let corner = |i: usize| {
            world_point(
                pose,
                [
                    if i & 1 == 0 { -h[0] } else { h[0] },
                    if i & 2 == 0 { -h[1] } else { h[1] },
                    if i & 4 == 0 { -h[2] } else { h[2] },
                ],
            )
        };
        for i in 0..8 {
            for bit in [1, 2, 4] {
                if i & bit == 0 {
                    out.push([corner(i), corner(i | bit)]);
                }
            }
        }
    } else if let Some(c) = shape.as_capsule() {
        let (a, b) = (c.segment.a, c.segment.b);
        let p = |v: Vector| [f64::from(v.x), f64::from(v.y), f64::from(v.z)];
        out.push([world_point(pose, p(a)), world_point(pose, p(b))]);
    } else if let Some(c) = shape.as_cylinder() {
        let (h, r) = (f64::from(c.half_height), f64::from(c.radius));
        ring(pose, r, &[-h, h], &mut out);
    } else if let Some(b) = shape.as_ball() {
        let r = f64::from(b.radius);
        ring(pose, r, &[0.0], &mut out);
    }
    out
}

/// Circles of radius `r` about the local y axis at heights `ys`, and (for two
/// or more) the lines joining them.
fn ring(pose: &Pose, r: f64, ys: &[f64], out: &mut Vec<[[f64; 3]; 2]>) {
    const N: usize = 16;
    let at = |k: usize, y: f64| {
        let a = std::f64::consts::TAU * k as f64 / N as f64;
        world_point(pose, [r * a.cos(), y, r * a.sin()])
    };
    for &y in ys {
        for k in 0..N {
            out.push([at(k, y), at(k + 1, y)]);
        }
    }
    if ys.len() >= 2 {
        for k in (0..N).step_by(4) {
            out.push([at(k, ys[0]), at(k, ys[ys.len() - 1])]);
        }
    }
}

/// Draws the world around the robot into `area`.
pub fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    sim: &QuadrupedSim,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    area.fill(&RGBColor(245, 245, 240))?;
    let torso = sim.torso().position_m;
    let beacon = sim.config().beacon.xy_m;
    let (w, h) = area.dim_in_pixel();
    // The robot's size relative to the ERS-7's (its stance height; the world
    // and the test range scale with it): the view and the grid follow it.
    let s = sim.config().walk.gait.idle.body_height_m
        / quadsim::SimConfig::default().walk.gait.idle.body_height_m;
    // Behind, to the left of and above the robot, looking past it at the beacon.
    let target = [torso[0] + 0.35 * s, torso[1], 0.08 * s];
    let view = View::new(
        [torso[0] - 0.55 * s, torso[1] - 0.75 * s, 0.45 * s],
        target,
        (w, h),
        60.0,
    );
    let line = |a: [f64; 3], b: [f64; 3], style: ShapeStyle| {
        view.segment(a, b)
            .map(|s| PathElement::new(s.to_vec(), style))
    };

    // The floor: a grid every 0.2 m (at the ERS-7's size) around the robot.
    let grid = RGBColor(210, 210, 205).stroke_width(1);
    let cell = 0.2 * s;
    let (gx, gy) = (
        (torso[0] / cell).round() * cell,
        (torso[1] / cell).round() * cell,
    );
    let (half, ahead) = (8.0 * cell, 16.0 * cell);
    for k in -8..=16 {
        let x = gx + cell * f64::from(k);
        area.draw(&line([x, gy - half, 0.0], [x, gy + half, 0.0], grid).unwrap_or_else(empty))?;
    }
    for k in -8..=8 {
        let y = gy + cell * f64::from(k);
        area.draw(&line([gx - half, y, 0.0], [gx + ahead, y, 0.0], grid).unwrap_or_else(empty))?;
    }
    // The line of approach and the ends of the test range.
    let approach = RGBColor(120, 160, 220).stroke_width(2);
    let (bx, by) = (beacon[0], beacon[1]);
    area.draw(&line([bx - 4.0 * s, by, 0.001], [bx, by, 0.001], approach).unwrap_or_else(empty))?;
    for d in [1.2 * s, 3.6 * s] {
        let x = bx - d;
        area.draw(
            &line(
                [x, by - 0.15 * s, 0.001],
                [x, by + 0.15 * s, 0.001],
                approach,
            )
            .unwrap_or_else(empty),
        )?;
    }

    let world = sim.world();
    let band = sim.band_collider();
    // The legs' bones: joint to joint, and from each body to its offset colliders
    // (the feet).
    let bone = RGBColor(30, 70, 160).stroke_width(3);
    let p = |v: Vector| [f64::from(v.x), f64::from(v.y), f64::from(v.z)];
    for (_, _, multibody, link) in world.multibody_joints.iter() {
        if let Some(parent) = link.parent_id().and_then(|i| multibody.link(i)) {
            let (a, b) = (
                p(parent.local_to_world().translation),
                p(link.local_to_world().translation),
            );
            if let Some(e) = line(a, b, bone) {
                area.draw(&e)?;
            }
        }
    }
    for (_, collider) in world.colliders.iter() {
        if let Some(body) = collider.parent().and_then(|b| world.bodies.get(b)) {
            let (a, b) = (
                p(body.position().translation),
                p(collider.position().translation),
            );
            if body.is_dynamic() && dot(sub(a, b), sub(a, b)) > 1e-4 {
                if let Some(e) = line(a, b, bone) {
                    area.draw(&e)?;
                }
            }
        }
    }
    for (handle, collider) in world.colliders.iter() {
        let moving = collider
            .parent()
            .and_then(|b| world.bodies.get(b))
            .is_some_and(|b| b.is_dynamic());
        let style = if handle == band {
            RGBColor(255, 140, 0).stroke_width(3)
        } else if moving {
            RGBColor(30, 70, 160).stroke_width(2)
        } else {
            RGBColor(110, 110, 110).stroke_width(2)
        };
        for [a, b] in edges(collider.position(), collider.shape()) {
            if let Some(e) = line(a, b, style) {
                area.draw(&e)?;
            }
        }
    }
    Ok(())
}

fn empty() -> PathElement<(i32, i32)> {
    PathElement::new(Vec::new(), WHITE)
}
