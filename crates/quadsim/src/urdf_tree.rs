//! Reading URDF text, and the questions the checks ask of its tree: which
//! link is the root, which joints join which links, which links are rigidly
//! fixed together.

use std::collections::{HashMap, HashSet};

use urdf_rs::{JointType, Robot};

use crate::error::RobotError;
use crate::pose::{Rotation, compose, rotate, rpy_matrix};

/// URDF text parsed as ROS reads it (see [`crate::urdf_xml`]), with a
/// floating base's frame left out (see [`floating_base`]): the robot, and a
/// note for each thing left out.
pub(crate) fn parse(text: &str) -> Result<(Robot, Vec<String>), RobotError> {
    let cleaned = crate::urdf_xml::clean(text)?;
    let urdf = urdf_rs::read_from_string(&cleaned.xml).map_err(|e| RobotError::Parse {
        reason: e.to_string(),
    })?;
    let mut notes = cleaned.notes;
    let (urdf, note) = floating_base(urdf)?;
    notes.extend(note);
    Ok((urdf, notes))
}

/// A robot whose root is a frame joined to its body by a `floating` (or
/// `planar`) joint, as ROS writes a mobile robot (`base_footprint` ->
/// `base_link`), with that frame and joint left out: the body is the root,
/// free in space as the simulator's root always is. The frame must be only
/// that, with no mass, no collision shape and no other child; a floating or
/// planar joint anywhere else is refused. Returns a note saying what was
/// left out, if anything was.
pub(crate) fn floating_base(mut urdf: Robot) -> Result<(Robot, Option<String>), RobotError> {
    let free = |j: &urdf_rs::Joint| matches!(j.joint_type, JointType::Floating | JointType::Planar);
    let Some(k) = urdf.joints.iter().position(free) else {
        return Ok((urdf, None));
    };
    let j = &urdf.joints[k];
    let frame = j.parent.link.clone();
    let refuse = |reason: String| RobotError::BadJoint {
        joint: j.name.clone(),
        reason: format!(
            "is {}, which is taken only from the root frame to the robot's body (ROS's \
             base_footprint), and {reason}",
            kind(&j.joint_type)
        ),
    };
    if let Some(other) = urdf.joints.iter().skip(k + 1).find(|j| free(j)) {
        return Err(refuse(format!("joint `{}` is another", other.name)));
    }
    if urdf.joints.iter().any(|o| o.child.link == frame) {
        return Err(refuse(format!("its parent `{frame}` is not the root")));
    }
    if let Some(o) = urdf
        .joints
        .iter()
        .find(|o| o.parent.link == frame && o.name != j.name)
    {
        return Err(refuse(format!(
            "its parent `{frame}` holds joint `{}` too",
            o.name
        )));
    }
    if let Some(l) = urdf.links.iter().find(|l| l.name == frame)
        && (l.inertial.mass.value != 0.0 || !l.collision.is_empty())
    {
        return Err(refuse(format!(
            "its parent `{frame}` has mass or a collision shape"
        )));
    }
    let note = format!(
        "left out the root frame `{frame}` and its {} joint `{}`: `{}` is the root, free in \
         space{}",
        kind(&j.joint_type),
        j.name,
        j.child.link,
        if matches!(j.joint_type, JointType::Planar) {
            " (not held to the joint's plane)"
        } else {
            ""
        }
    );
    urdf.joints.remove(k);
    urdf.links.retain(|l| l.name != frame);
    Ok((urdf, Some(note)))
}

/// A free joint's type as URDF writes it.
fn kind(t: &JointType) -> &'static str {
    if matches!(t, JointType::Planar) {
        "planar"
    } else {
        "floating"
    }
}

fn link_names(urdf: &Robot) -> Result<HashSet<&str>, RobotError> {
    let mut names = HashSet::new();
    for l in &urdf.links {
        if !names.insert(l.name.as_str()) {
            return Err(RobotError::DuplicateLink {
                link: l.name.clone(),
            });
        }
    }
    Ok(names)
}

/// Every joint names existing links, every link but the root has exactly one
/// parent, and every link is reachable from the root (the first link without a
/// parent): returns the root.
pub(crate) fn check_tree(urdf: &Robot) -> Result<String, RobotError> {
    let names = link_names(urdf)?;
    let mut parent_of: HashMap<&str, &str> = HashMap::new();
    for j in &urdf.joints {
        for link in [&j.parent.link, &j.child.link] {
            if !names.contains(link.as_str()) {
                return Err(RobotError::DanglingJoint {
                    joint: j.name.clone(),
                    link: link.clone(),
                });
            }
        }
        if parent_of.insert(&j.child.link, &j.parent.link).is_some() {
            return Err(RobotError::NotATree {
                link: j.child.link.clone(),
                reason: "it is the child of more than one joint",
            });
        }
    }
    let root = urdf
        .links
        .iter()
        .map(|l| l.name.as_str())
        .find(|l| !parent_of.contains_key(l))
        .ok_or_else(|| RobotError::NotATree {
            link: urdf
                .links
                .first()
                .map_or_else(String::new, |l| l.name.clone()),
            reason: "no link is without a parent, so there is no root",
        })?;
    for &link in &names {
        let (mut at, mut steps) = (link, 0);
        while at != root {
            at = parent_of
                .get(at)
                .copied()
                .ok_or_else(|| RobotError::NotATree {
                    link: link.into(),
                    reason: "it is not connected to the root (the first link without a parent)",
                })?;
            steps += 1;
            if steps > names.len() {
                return Err(RobotError::NotATree {
                    link: link.into(),
                    reason: "its joints form a cycle",
                });
            }
        }
    }
    Ok(root.to_string())
}

pub(crate) fn joint<'a>(urdf: &'a Robot, name: &str) -> Result<&'a urdf_rs::Joint, RobotError> {
    urdf.joints
        .iter()
        .find(|j| j.name == name)
        .ok_or_else(|| RobotError::MissingJoint { joint: name.into() })
}

pub(crate) fn bad_joint(joint: &str, reason: String) -> RobotError {
    RobotError::BadJoint {
        joint: joint.into(),
        reason,
    }
}

/// The fixed joints from link `from` down to link `to`, in that order (none
/// if they are the same link), or `None` if `to` is not `from` or fixed
/// below it.
pub(crate) fn fixed_path<'a>(
    urdf: &'a Robot,
    from: &str,
    to: &str,
) -> Option<Vec<&'a urdf_rs::Joint>> {
    let mut path = Vec::new();
    let mut at = to;
    while at != from {
        let j = urdf
            .joints
            .iter()
            .find(|j| j.child.link == at && matches!(j.joint_type, JointType::Fixed))?;
        path.push(j);
        at = &j.parent.link;
    }
    path.reverse();
    Some(path)
}

/// The link `name` and every link rigidly fixed to it: joined through fixed
/// joints only, up or down the tree (a camera's link, its housing, the body
/// it is bolted to), `name` first and the rest in URDF joint order.
pub(crate) fn rigidly_fixed(urdf: &Robot, name: &str) -> Vec<String> {
    let mut out = vec![name.to_string()];
    let mut k = 0;
    while k < out.len() {
        for j in urdf
            .joints
            .iter()
            .filter(|j| matches!(j.joint_type, JointType::Fixed))
        {
            let other = if j.parent.link == out[k] {
                &j.child.link
            } else if j.child.link == out[k] {
                &j.parent.link
            } else {
                continue;
            };
            if !out.contains(other) {
                out.push(other.clone());
            }
        }
        k += 1;
    }
    out
}

/// The link `name` and every link fixed below it (by fixed joints, to any
/// depth): each link's index, with where its frame sits and how it turns in
/// `name`'s frame; `name` first, at the origin, unturned.
pub(crate) fn fixed_to(urdf: &Robot, name: &str) -> Vec<(usize, [f64; 3], Rotation)> {
    let Some(first) = urdf.links.iter().position(|l| l.name == name) else {
        return Vec::new();
    };
    let identity = rpy_matrix([0.0; 3]);
    let mut out = vec![(first, [0.0; 3], identity)];
    let mut frontier = vec![(name.to_string(), [0.0; 3], identity)];
    while let Some((name, at, turn)) = frontier.pop() {
        for j in urdf
            .joints
            .iter()
            .filter(|j| j.parent.link == name && matches!(j.joint_type, JointType::Fixed))
        {
            let Some(k) = urdf.links.iter().position(|l| l.name == j.child.link) else {
                continue;
            };
            let r = rotate(&turn, j.origin.xyz.0);
            let here = [at[0] + r[0], at[1] + r[1], at[2] + r[2]];
            let turned = compose(&turn, &rpy_matrix(j.origin.rpy.0));
            out.push((k, here, turned));
            frontier.push((j.child.link.clone(), here, turned));
        }
    }
    out
}

/// The joint that moves `link`, if `link` is moved by a joint (not fixed to
/// its parent) and neither it nor any link fixed below it has mass.
pub(crate) fn moving_without_mass(urdf: &Robot, link: &str) -> Option<String> {
    let joint = urdf.joints.iter().find(|j| j.child.link == link)?;
    if matches!(joint.joint_type, JointType::Fixed) {
        return None;
    }
    fn has_mass(urdf: &Robot, link: &str) -> bool {
        let own = urdf
            .links
            .iter()
            .any(|l| l.name == link && l.inertial.mass.value > 0.0);
        own || urdf.joints.iter().any(|j| {
            j.parent.link == link
                && matches!(j.joint_type, JointType::Fixed)
                && has_mass(urdf, &j.child.link)
        })
    }
    (!has_mass(urdf, link)).then(|| joint.name.clone())
}
