//! A URDF's numbers checked for what a physicist would accept, before any of
//! them is used: finite everywhere; collision shapes of positive size; a
//! link's mass, if it has one, between a milligram and a hundred tonnes, its
//! inertia a rigid body's (principal moments that satisfy the triangle
//! inequality, [`rigid_inertia`]); joints whose effort and speed limits, where given, are
//! positive, and whose damping and friction are not negative. Each refusal names the element, the value and what it must be.

use urdf_rs::{Geometry, Robot};

use crate::error::RobotError;
use crate::legs::LegDescription;

/// The lightest mass a link may have, kg (a milligram): below it a body's
/// dynamics are numerical noise.
pub const MIN_MASS_KG: f64 = 1e-6;
/// The heaviest, kg (a hundred tonnes).
pub const MAX_MASS_KG: f64 = 1e5;
/// The smallest positive effort limit, N m or N (a joint that can push less
/// is broken, not weak).
pub const MIN_EFFORT: f64 = 1e-6;
/// How far the largest principal moment may exceed the sum of the other two,
/// relative: published robots' CAD exports miss the triangle inequality by
/// a few per cent (pybullet's Mini Cheetah's thigh by 4 %), which a
/// simulator takes; a body that misses it by more is no rigid body's.
pub const TRIANGLE_TOLERANCE: f64 = 0.1;

/// Checks every number of `urdf` (see the module's documentation).
pub fn values(urdf: &Robot) -> Result<(), RobotError> {
    for link in &urdf.links {
        let bad = |reason: String| RobotError::BadValue {
            element: format!("link `{}`", link.name),
            reason,
        };
        let i = &link.inertial;
        finite(
            "inertial origin",
            &[i.origin.xyz.0, i.origin.rpy.0].concat(),
        )
        .map_err(bad)?;
        let m = i.mass.value;
        let moments = [i.inertia.ixx, i.inertia.iyy, i.inertia.izz];
        let products = [i.inertia.ixy, i.inertia.ixz, i.inertia.iyz];
        finite("mass", &[m]).map_err(bad)?;
        finite("inertia", &[moments, products].concat()).map_err(bad)?;
        if m != 0.0 && !(MIN_MASS_KG..=MAX_MASS_KG).contains(&m) {
            return Err(bad(format!(
                "mass {m} kg: a link's mass is 0 (none) or in [{MIN_MASS_KG}, {MAX_MASS_KG}] kg"
            )));
        }
        for (k, collision) in link.collision.iter().enumerate() {
            let what = |reason: String| bad(format!("collision {k}: {reason}"));
            let o = &collision.origin;
            finite("origin", &[o.xyz.0, o.rpy.0].concat()).map_err(what)?;
            geometry(&collision.geometry).map_err(what)?;
        }
    }
    for joint in &urdf.joints {
        let bad = |reason: String| RobotError::BadValue {
            element: format!("joint `{}`", joint.name),
            reason,
        };
        let o = &joint.origin;
        finite("origin", &[o.xyz.0, o.rpy.0].concat()).map_err(bad)?;
        let axis = joint.axis.xyz.0;
        finite("axis", &axis).map_err(bad)?;
        let l = &joint.limit;
        finite("limit", &[l.effort, l.velocity]).map_err(bad)?;
        for (name, v) in [("lower", l.lower), ("upper", l.upper)] {
            if v.is_nan() {
                return Err(bad(format!("limit {name} is NaN")));
            }
        }
        if l.effort < 0.0 || (l.effort > 0.0 && l.effort < MIN_EFFORT) {
            return Err(bad(format!(
                "effort limit {} : it must be 0 (none given) or at least {MIN_EFFORT}",
                l.effort
            )));
        }
        if l.velocity < 0.0 {
            return Err(bad(format!("velocity limit {} is negative", l.velocity)));
        }
        if let Some(d) = &joint.dynamics {
            finite("dynamics", &[d.damping, d.friction]).map_err(bad)?;
            if d.damping < 0.0 || d.friction < 0.0 {
                return Err(bad(format!(
                    "dynamics damping {} friction {}: neither may be negative",
                    d.damping, d.friction
                )));
            }
        }
    }
    Ok(())
}

/// Checks that each massive link's inertia could be a rigid body's: its
/// largest principal moment at most the sum of the other two (within
/// [`TRIANGLE_TOLERANCE`]). Checked on each link that is a body of its own,
/// not on one that rides on a fixed joint (a camera's frame or a cover may
/// carry an inertia no body alone has; it is part of the body it is fixed
/// to, into which it is folded).
pub fn rigid_inertia(urdf: &Robot) -> Result<(), RobotError> {
    // A link on a fixed joint is part of the body it is fixed to: only that
    // body as a whole must be a rigid body (a camera's frame often is not).
    let on_fixed = |name: &str| {
        urdf.joints
            .iter()
            .any(|j| j.child.link == name && matches!(j.joint_type, urdf_rs::JointType::Fixed))
    };
    for link in urdf
        .links
        .iter()
        .filter(|l| l.inertial.mass.value > 0.0 && !on_fixed(&l.name))
    {
        let i = &link.inertial.inertia;
        let [a, b, c] = crate::fold::principal_moments(i);
        let largest = a.max(b).max(c);
        let others = a + b + c - largest;
        if a.min(b).min(c) > 0.0 && largest > others * (1.0 + TRIANGLE_TOLERANCE) {
            return Err(RobotError::BadValue {
                element: format!("link `{}`", link.name),
                reason: format!(
                    "principal moments of inertia ({a:.4e}, {b:.4e}, {c:.4e}) kg m^2 break the \
                     triangle inequality (the largest must be at most the sum of the other two, \
                     within {:.0} %): no rigid body has them",
                    100.0 * TRIANGLE_TOLERANCE
                ),
            });
        }
    }
    Ok(())
}

/// Checks that the legs are mapped as a quadruped's are: each leg's joints
/// its own (no joint in two legs); left legs on the left of the torso (+y)
/// and right legs on the right, front legs ahead of the rear ones (+x), as
/// REP 103's body frame has them; and each foot smaller than half its leg (a
/// foot as large as the leg is no foot).
pub fn legs(legs: &[LegDescription]) -> Result<(), RobotError> {
    let bad = |leg: &str, reason: String| RobotError::BadValue {
        element: format!("leg `{leg}`"),
        reason,
    };
    for (k, a) in legs.iter().enumerate() {
        for b in &legs[k + 1..] {
            if let Some(j) = a.joints.iter().find(|j| b.joints.contains(j)) {
                return Err(bad(
                    a.name,
                    format!(
                        "joint `{j}` is in leg `{}` too: each leg has joints of its own",
                        b.name
                    ),
                ));
            }
        }
        let y = a.hip_in_torso_m[1];
        let left = a.name.ends_with('l');
        if (left && y <= 0.0) || (!left && y >= 0.0) {
            return Err(bad(
                a.name,
                format!(
                    "its hip is at y = {y:.3} m in the torso's frame, on the {} side: a {} leg \
                     (legs mapped left for right?)",
                    if y > 0.0 { "left" } else { "right" },
                    if left { "left" } else { "right" }
                ),
            ));
        }
        let leg_m = a.thigh_m + a.shank_m;
        // NaN fails too: the radius must be known to be small enough.
        if a.foot_radius_m.partial_cmp(&(0.5 * leg_m)) != Some(std::cmp::Ordering::Less) {
            return Err(bad(
                a.name,
                format!(
                    "its foot's radius, {:.3} m, is not less than half its leg's length, {leg_m:.3} m",
                    a.foot_radius_m
                ),
            ));
        }
    }
    let x = |prefix: char| {
        legs.iter()
            .filter(move |l| l.name.starts_with(prefix))
            .map(|l| l.hip_in_torso_m[0])
    };
    let front = x('f').fold(f64::INFINITY, f64::min);
    let rear = x('h').fold(f64::NEG_INFINITY, f64::max);
    if front.partial_cmp(&rear) != Some(std::cmp::Ordering::Greater) {
        return Err(bad(
            "fl",
            format!(
                "the front hips (x >= {front:.3} m) are not ahead of the rear ones (x <= {rear:.3} \
                 m) in the torso's frame (legs mapped front for rear?)"
            ),
        ));
    }
    Ok(())
}

/// A collision shape's size: finite and positive.
fn geometry(g: &Geometry) -> Result<(), String> {
    let positive = |what: &str, values: &[f64]| {
        finite(what, values)?;
        if values.iter().all(|v| *v > 0.0) {
            Ok(())
        } else {
            Err(format!(
                "{what} {values:?}: a collision shape's size must be positive (it would collide as \
                 nothing)"
            ))
        }
    };
    match g {
        Geometry::Box { size } => positive("box size", &size.0),
        Geometry::Cylinder { radius, length } | Geometry::Capsule { radius, length } => {
            positive("radius and length", &[*radius, *length])
        }
        Geometry::Sphere { radius } => positive("sphere radius", &[*radius]),
        Geometry::Mesh { scale, .. } => match scale {
            Some(s) => {
                finite("mesh scale", &s.0)?;
                if s.0.contains(&0.0) {
                    Err(format!("mesh scale {:?} flattens it to nothing", s.0))
                } else {
                    Ok(())
                }
            }
            None => Ok(()),
        },
    }
}

fn finite(what: &str, values: &[f64]) -> Result<(), String> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(format!("{what} {values:?} is not finite"))
    }
}
