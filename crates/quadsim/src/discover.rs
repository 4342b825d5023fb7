//! A URDF's legs and camera found from its tree, for a robot given as a bare
//! URDF: a leg is a chain of three actuated joints from the root link to a
//! sphere foot (on the lower leg or on a link fixed to it), or, when there
//! are not four of those, to a link of any shape fixed at its end; front and rear,
//! left and right come from where the hips sit; the camera is the URDF's
//! `camera` or `camera_link` frame if it has one on a fixed joint, else it
//! looks forward from the front of the root link. A robot file still says any
//! of it instead.

use std::collections::BTreeMap;

use urdf_rs::{Geometry, JointType, Robot};

use crate::error::RobotError;
use crate::legs::{CameraMount, LEG_NAMES, RobotMap};
use crate::urdf_tree::check_tree;

/// The actuated joints (revolute or continuous) from the root down to `link`,
/// root first, or `None` if a joint on the way is neither actuated nor fixed.
fn chain<'a>(urdf: &'a Robot, link: &str) -> Option<Vec<&'a urdf_rs::Joint>> {
    let mut out = Vec::new();
    let mut at = link;
    while let Some(j) = urdf.joints.iter().find(|j| j.child.link == at) {
        match j.joint_type {
            JointType::Revolute | JointType::Continuous => out.push(j),
            JointType::Fixed => {}
            _ => return None,
        }
        at = &j.parent.link;
    }
    out.reverse();
    Some(out)
}

/// Where `joint` sits in the root link's frame at the zero pose: its origin
/// through every joint above it.
fn position_in_root(urdf: &Robot, joint: &urdf_rs::Joint) -> [f64; 3] {
    let mut p = joint.origin.xyz.0;
    let mut at = &joint.parent.link;
    while let Some(j) = urdf.joints.iter().find(|j| &j.child.link == at) {
        p = crate::pose::place(&j.origin, p);
        at = &j.parent.link;
    }
    p
}

/// The chains of three actuated joints from the root to each link that
/// `is_foot` takes (by joint names, with where the first joint sits), and
/// the foot links that end some other chain (why, for the error).
fn chains(
    urdf: &Robot,
    is_foot: impl Fn(&urdf_rs::Link) -> bool,
) -> (BTreeMap<Vec<String>, [f64; 3]>, Vec<String>) {
    let mut legs: BTreeMap<Vec<String>, [f64; 3]> = BTreeMap::new();
    let mut others: Vec<String> = Vec::new();
    for link in urdf.links.iter().filter(|l| is_foot(l)) {
        let Some(joints) = chain(urdf, &link.name) else {
            others.push(format!(
                "{} (below a joint that is neither actuated nor fixed)",
                link.name
            ));
            continue;
        };
        if joints.len() == 3 {
            let names = joints.iter().map(|j| j.name.clone()).collect();
            legs.insert(names, position_in_root(urdf, joints[0]));
        } else if !joints.is_empty() {
            others.push(format!(
                "{} ({} actuated joints from the root)",
                link.name,
                joints.len()
            ));
        }
    }
    (legs, others)
}

/// The legs and camera of `urdf` (see the module's documentation), or what
/// was found instead.
pub fn discover(urdf: &Robot) -> Result<RobotMap, RobotError> {
    let root = check_tree(urdf)?;
    let not_found = |reason: String| RobotError::LegsNotFound { reason };
    // Every link with a sphere collision ends a chain; legs are the chains of
    // three, each counted once (a toe and its lower leg share one). With no
    // four such, a foot may be a link of any shape fixed at a leg's end (a
    // mesh toe, as Unitree's Go2 and ODRI's Solo 12 have).
    let sphere = |link: &urdf_rs::Link| {
        link.collision
            .iter()
            .any(|c| matches!(c.geometry, Geometry::Sphere { .. }))
    };
    let fixed_shape = |link: &urdf_rs::Link| {
        !link.collision.is_empty()
            && urdf
                .joints
                .iter()
                .any(|j| j.child.link == link.name && matches!(j.joint_type, JointType::Fixed))
    };
    let (mut legs, mut others) = chains(urdf, sphere);
    let mut foot = "a sphere foot";
    if legs.len() != 4 {
        let (any_legs, any_others) = chains(urdf, fixed_shape);
        if any_legs.len() == 4 {
            (legs, others) = (any_legs, any_others);
        } else {
            foot = "a sphere foot, or to a link of any shape fixed at its end,";
            // With no sphere foot at all, the error tells of the other feet.
            if legs.is_empty() && others.is_empty() {
                (legs, others) = (any_legs, any_others);
            }
        }
    }
    if legs.len() != 4 {
        return Err(not_found(format!(
            "{} chains of three actuated joints from the root `{root}` to {foot} ({}){}; a \
             quadruped has four: give a robot file that names them",
            legs.len(),
            if legs.is_empty() {
                "none".to_string()
            } else {
                legs.keys()
                    .map(|k| k.join(" > "))
                    .collect::<Vec<_>>()
                    .join("; ")
            },
            if others.is_empty() {
                String::new()
            } else {
                format!(", and feet elsewhere: {}", others.join(", "))
            }
        )));
    }
    // Front and rear, left and right, about the hips' centre.
    let n = legs.len() as f64;
    let centre = [0, 1].map(|k| legs.values().map(|h| h[k]).sum::<f64>() / n);
    let mut named: [Option<[String; 3]>; 4] = Default::default();
    for (joints, hip) in &legs {
        let (front, left) = (hip[0] > centre[0], hip[1] > centre[1]);
        let slot = match (front, left) {
            (true, true) => 0,
            (true, false) => 1,
            (false, true) => 2,
            (false, false) => 3,
        };
        if named[slot].is_some() {
            return Err(not_found(format!(
                "two legs' hips sit {} of the hips' centre ({}): a robot file must say which is which",
                LEG_NAMES[slot], joints[0]
            )));
        }
        named[slot] = Some([joints[0].clone(), joints[1].clone(), joints[2].clone()]);
    }
    let [Some(fl), Some(fr), Some(hl), Some(hr)] = named else {
        return Err(not_found("the hips are not one in each corner".into()));
    };
    // A camera frame the URDF names (`camera` or `camera_link`, on a fixed
    // joint: its optical axis +x, image up +z, as REP 103's camera_link)...
    let named = urdf.joints.iter().find(|j| {
        matches!(j.joint_type, JointType::Fixed)
            && ["camera", "camera_link"].contains(&j.child.link.as_str())
    });
    if let Some(j) = named {
        return Ok(RobotMap {
            legs: [fl, fr, hl, hr],
            camera: CameraMount {
                parent: j.parent.link.clone(),
                xyz: j.origin.xyz.0,
                rpy: j.origin.rpy.0,
            },
        });
    }
    // ... or at the middle of the root's front face (its collision box's, or
    // the front hips' line), looking forward.
    let root_link = urdf.links.iter().find(|l| l.name == root);
    let front_face = root_link
        .into_iter()
        .flat_map(|l| &l.collision)
        .filter_map(|c| match c.geometry {
            Geometry::Box { size } if c.origin.rpy.0.iter().all(|v| v.abs() < 1e-9) => {
                Some(c.origin.xyz.0[0] + 0.5 * size.0[0])
            }
            _ => None,
        })
        .fold(f64::NEG_INFINITY, f64::max);
    let front_x = if front_face.is_finite() {
        front_face
    } else {
        legs.values()
            .map(|h| h[0])
            .fold(f64::NEG_INFINITY, f64::max)
    };
    Ok(RobotMap {
        legs: [fl, fr, hl, hr],
        camera: CameraMount {
            parent: root,
            xyz: [front_x, 0.0, 0.0],
            rpy: [0.0; 3],
        },
    })
}
