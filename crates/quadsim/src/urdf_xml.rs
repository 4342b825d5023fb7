//! URDF text as ROS's own parser (urdfdom) and PyBullet read it, made into
//! the plain XML urdf-rs reads: comments and processing instructions dropped
//! wherever they are (a xacro output has them inside `<geometry>`), and the
//! elements the simulator has no use for (`<gazebo>`, `<transmission>`,
//! `<ros2_control>`, `<sensor>`, a namespaced element) left out, each named
//! in a note with its line. A joint that follows another (`<mimic>`) is
//! refused: nothing here would drive it.
//!
//! The XML is read by roxmltree (its nesting first bounded by
//! [`crate::files::check_xml`]); urdf-rs then reads what is left.

use roxmltree::{Document, Node, ParsingOptions};

use crate::error::RobotError;

/// What each URDF element may hold, for the elements whose children are
/// checked here (deeper ones are urdf-rs's to read).
const KNOWN: [(&str, &[&str]); 3] = [
    ("robot", &["link", "joint", "material"]),
    ("link", &["inertial", "visual", "collision"]),
    (
        "joint",
        &[
            "origin",
            "parent",
            "child",
            "axis",
            "calibration",
            "dynamics",
            "limit",
            "mimic",
            "safety_controller",
        ],
    ),
];

/// At most this many XML nodes (elements, attributes' text, comments): a
/// URDF of the size [`crate::files::URDF_LIMIT`] allows has far fewer.
const NODES_LIMIT: u32 = 4_000_000;

/// URDF text, cleaned for urdf-rs: the XML it reads, and a note for each
/// element left out (`ignored <gazebo> at line 40: ...`).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Cleaned {
    /// The XML urdf-rs is given.
    pub xml: String,
    /// One line per element left out.
    pub notes: Vec<String>,
}

/// Reads URDF text as urdfdom does (see the module's documentation).
pub(crate) fn clean(text: &str) -> Result<Cleaned, RobotError> {
    let parse = |reason: String| RobotError::Parse { reason };
    crate::files::check_xml(text).map_err(parse)?;
    let options = ParsingOptions {
        allow_dtd: true,
        nodes_limit: NODES_LIMIT,
    };
    let doc = Document::parse_with_options(text, options).map_err(|e| parse(e.to_string()))?;
    let root = doc.root_element();
    if root.tag_name().name() != "robot" || root.tag_name().namespace().is_some() {
        return Err(parse(format!(
            "the document's root element is <{}>, not <robot>",
            root.tag_name().name()
        )));
    }
    let mut out = Cleaned {
        xml: String::with_capacity(text.len()),
        notes: Vec::new(),
    };
    write(&doc, root, &mut out)?;
    Ok(out)
}

/// Writes `node` (an element) and what it holds, leaving out comments,
/// processing instructions and the elements its parent may not hold.
fn write(doc: &Document, node: Node, out: &mut Cleaned) -> Result<(), RobotError> {
    let name = node.tag_name().name();
    let line = |n: Node| doc.text_pos_at(n.range().start).row;
    if name == "mimic" {
        let joint = node
            .parent_element()
            .and_then(|j| j.attribute("name"))
            .unwrap_or("?");
        return Err(RobotError::BadJoint {
            joint: joint.into(),
            reason: format!(
                "has <mimic> (line {}): a joint that follows another is not simulated; make it \
                 fixed, or remove its <mimic> to let it move on its own",
                line(node)
            ),
        });
    }
    out.xml.push('<');
    out.xml.push_str(name);
    for a in node.attributes() {
        if a.namespace().is_some() {
            continue;
        }
        out.xml.push(' ');
        out.xml.push_str(a.name());
        out.xml.push_str("=\"");
        escape(a.value(), &mut out.xml);
        out.xml.push('"');
    }
    out.xml.push('>');
    let allowed = KNOWN.iter().find(|(k, _)| *k == name).map(|(_, v)| *v);
    for child in node.children() {
        if child.is_text() {
            escape(child.text().unwrap_or(""), &mut out.xml);
        } else if child.is_element() {
            let tag = child.tag_name();
            let known = tag.namespace().is_none()
                && allowed.is_none_or(|allowed| allowed.contains(&tag.name()));
            if known {
                write(doc, child, out)?;
            } else {
                out.notes.push(format!(
                    "ignored <{}{}> at line {} (in <{name}>): the simulator does not use it",
                    child
                        .lookup_prefix(tag.namespace().unwrap_or(""))
                        .filter(|_| tag.namespace().is_some())
                        .map_or_else(String::new, |p| format!("{p}:")),
                    tag.name(),
                    line(child)
                ));
            }
        }
        // Comments and processing instructions: dropped.
    }
    out.xml.push_str("</");
    out.xml.push_str(name);
    out.xml.push('>');
    Ok(())
}

/// `text` with XML's special characters escaped, appended to `out`.
fn escape(text: &str, out: &mut String) {
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_and_instructions_anywhere_are_dropped() {
        let text = "<?xml version=\"1.0\"?>\n<!-- made by xacro -->\n<robot name=\"r\" \
                    xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<link name=\"a\"><collision>\
                    <geometry><!-- a ball --><sphere radius=\"0.1\"/><?pi x?></geometry>\
                    </collision></link>\n</robot>";
        let c = clean(text).expect("as written");
        assert!(
            !c.xml.contains("<!--") && !c.xml.contains("<?"),
            "{}",
            c.xml
        );
        assert!(c.notes.is_empty(), "{:?}", c.notes);
        let robot = urdf_rs::read_from_string(&c.xml).expect("as written");
        assert!(matches!(
            robot.links[0].collision[0].geometry,
            urdf_rs::Geometry::Sphere { radius } if radius == 0.1
        ));
    }

    #[test]
    fn elements_the_simulator_does_not_use_are_named_with_their_line() {
        let text = "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n\
                    <link name=\"a\"><sensor name=\"imu\"/></link>\n\
                    <gazebo reference=\"a\"><mu1>0.6</mu1></gazebo>\n\
                    <transmission name=\"t\"/>\n<xacro:property name=\"p\" value=\"1\"/>\n\
                    </robot>";
        let c = clean(text).expect("as written");
        assert_eq!(c.notes.len(), 4, "{:?}", c.notes);
        for (note, (tag, line)) in c.notes.iter().zip([
            ("sensor", 2),
            ("gazebo", 3),
            ("transmission", 4),
            ("xacro:property", 5),
        ]) {
            assert!(
                note.contains(&format!("<{tag}>")) && note.contains(&format!("line {line} ")),
                "{note}"
            );
        }
        assert!(!c.xml.contains("gazebo") && !c.xml.contains("mu1"));
    }

    #[test]
    fn a_mimic_joint_is_refused_by_name() {
        let text = "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/>\n<joint name=\"j\" \
                    type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\n<mimic \
                    joint=\"k\"/></joint></robot>";
        let e = clean(text).expect_err("refused").to_string();
        assert!(e.contains("`j`") && e.contains("<mimic> (line 3)"), "{e}");
    }

    #[test]
    fn special_characters_survive_and_a_wrong_root_is_named() {
        let c = clean("<robot name=\"a &amp; b &lt;c&gt;\"><link name=\"x\"/></robot>")
            .expect("as written");
        assert_eq!(
            urdf_rs::read_from_string(&c.xml).expect("as written").name,
            "a & b <c>"
        );
        let e = clean("<mujoco model=\"m\"/>")
            .expect_err("refused")
            .to_string();
        assert!(e.contains("<mujoco>"), "{e}");
        assert!(clean("<robot><link name=\"x\"></robot>").is_err());
    }
}
