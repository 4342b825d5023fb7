//! The model's keyframe as the joints' standing angles: the `<key>` named
//! `home`, else the first, its `qpos` read in MuJoCo's order (the robot's
//! free joint's 7 numbers, then each of its joints' one, in the file's
//! order). A keyframe that cannot be read that way (the world has other
//! joints, or `qpos` is not that long) is left out with a note; one with
//! a number that is not one is refused.

use std::collections::BTreeMap;

use super::MjcfError;
use super::tree::Element;

/// The standing angles by joint name (rad), and a note if the keyframe was
/// left out.
pub(crate) fn standing(
    root: &Element,
    joints: &[String],
    world_has_other_joints: bool,
) -> Result<(BTreeMap<String, f64>, Option<String>), MjcfError> {
    let keys: Vec<&Element> = root.all("keyframe").flat_map(|k| k.all("key")).collect();
    let Some(key) = keys
        .iter()
        .find(|k| k.attrs.get("name").is_some_and(|n| n == "home"))
        .or_else(|| keys.first())
    else {
        return Ok((BTreeMap::new(), None));
    };
    let left_out = |why: String| {
        Ok((
            BTreeMap::new(),
            Some(format!(
                "left out <key> at {}: {why}; the robot stands in its gait's own pose",
                key.at
            )),
        ))
    };
    let Some(qpos) = super::frames::number_list(key, &key.attrs, "qpos")? else {
        return left_out("it gives no qpos".into());
    };
    if world_has_other_joints {
        return left_out(
            "the world has joints besides the robot's, so its qpos is not only the robot's".into(),
        );
    }
    let expected = 7 + joints.len();
    if qpos.len() != expected {
        return left_out(format!(
            "its qpos has {} numbers where the robot's free joint and {} joints take {expected}",
            qpos.len(),
            joints.len()
        ));
    }
    let angles = joints
        .iter()
        .cloned()
        .zip(qpos[7..].iter().copied())
        .collect();
    Ok((angles, None))
}

/// Whether `el` or anything below it is a joint.
pub(crate) fn has_joint(el: &Element) -> bool {
    matches!(el.tag.as_str(), "joint" | "freejoint") || el.children.iter().any(has_joint)
}
