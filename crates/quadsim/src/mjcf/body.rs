//! MJCF bodies as URDF links: the robot is the world's body with a free
//! joint; each body below it a link, joined to its parent by its hinge (a
//! revolute or continuous joint) or fixed; its collision geoms its shapes;
//! its mass from `<inertial>` or its geoms; the first camera a `camera` link.
//!
//! A URDF joint sits at its child link's origin, an MJCF joint anywhere in
//! its body: a body whose joint has a `pos` becomes a link whose origin is
//! the joint's, with everything in the body moved by as much.

use std::collections::{BTreeMap, HashSet};

use urdf_rs::{Collision, Geometry, Inertia, Inertial, Joint, JointType, Link, Robot};

use super::frames::{self, Frame, IDENTITY, numbers};
use super::inertia::{Solid, combine};
use super::tree::Element;
use super::{Mjcf, MjcfError, Model};
use crate::pose::compose;

/// MuJoCo's camera looks along its -z with +y up; the simulator's along
/// +x with +z up. The simulator's axes in MuJoCo's camera frame (columns).
const CAMERA_AXES: [[f64; 3]; 3] = [[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]];

/// Elements that may be in a body and are not read.
const LEFT_OUT: [&str; 2] = ["site", "light"];

/// Builds the URDF as the bodies are read.
pub(crate) struct Builder<'a> {
    model: &'a Model,
    urdf: Robot,
    notes: Vec<String>,
    links: HashSet<String>,
    joints: HashSet<String>,
    camera: bool,
    armature: BTreeMap<String, f64>,
    /// The robot's joints (URDF names) in MuJoCo's qpos order.
    pub qpos_joints: Vec<String>,
    /// Whether a body of the world left out has a joint.
    pub other_joints: bool,
}

/// The link a body hangs from, and where its origin is in the parent body.
struct Parent {
    link: String,
    shift: [f64; 3],
}

impl<'a> Builder<'a> {
    pub fn new(model: &'a Model) -> Self {
        Self {
            model,
            urdf: Robot {
                name: String::new(),
                links: Vec::new(),
                joints: Vec::new(),
                materials: Vec::new(),
            },
            notes: Vec::new(),
            links: HashSet::new(),
            joints: HashSet::new(),
            camera: false,
            armature: BTreeMap::new(),
            qpos_joints: Vec::new(),
            other_joints: false,
        }
    }

    /// The robot: the first body of the world with a free joint.
    pub fn robot(mut self, root: &Element) -> Result<Mjcf, MjcfError> {
        self.urdf.name = root
            .attrs
            .get("model")
            .cloned()
            .unwrap_or_else(|| "robot".into());
        let mut robot = None;
        for world in root.all("worldbody") {
            for c in &world.children {
                match c.tag.as_str() {
                    "body" if robot.is_none() && self.is_free(c)? => robot = Some(c),
                    "body" | "geom" | "camera" => {
                        self.other_joints |= super::keyframe::has_joint(c);
                        self.notes.push(format!(
                            "left out the world's <{}> at {}: only the robot (the body with a free \
                         joint) is simulated, on the testbed's own floor",
                            c.tag, c.at
                        ))
                    }
                    t if LEFT_OUT.contains(&t) => {}
                    _ => {
                        return Err(c.error("is not an element of <worldbody> the simulator reads"));
                    }
                }
            }
        }
        let body = robot.ok_or_else(|| {
            root.error("no body of <worldbody> has a free joint (<freejoint/>): a walking robot must be free")
        })?;
        self.body(body, None, "main")?;
        let (standing, note) =
            super::keyframe::standing(root, &self.qpos_joints, self.other_joints)?;
        self.notes.extend(note);
        Ok(Mjcf {
            urdf: self.urdf,
            notes: self.notes,
            armature: self.armature,
            standing,
            servo_kp_nm_per_rad: None,
        })
    }

    fn is_free(&self, body: &Element) -> Result<bool, MjcfError> {
        for j in &body.children {
            if j.tag == "freejoint" {
                return Ok(true);
            }
            if j.tag == "joint" {
                let class = body.attrs.get("childclass").map_or("main", String::as_str);
                let attrs = self.model.defaults.resolve(j, "joint", class)?;
                if attrs.get("type").map(String::as_str) == Some("free") {
                    return Ok(true);
                }
            }
        }
        Ok(false)
    }

    /// A link's name (`joint` false) or a joint's: each kind's names are
    /// their own, in MJCF as in URDF.
    fn name(
        &mut self,
        el: &Element,
        given: Option<&String>,
        fallback: String,
    ) -> Result<String, MjcfError> {
        let name = given.cloned().unwrap_or(fallback);
        let names = if el.tag == "body" {
            &mut self.links
        } else {
            &mut self.joints
        };
        if !names.insert(name.clone()) {
            return Err(el.error(format!("the name `{name}` is used twice")));
        }
        Ok(name)
    }

    fn body(&mut self, el: &Element, parent: Option<Parent>, class: &str) -> Result<(), MjcfError> {
        let class = el.attrs.get("childclass").map_or(class, String::as_str);
        if !self.model.defaults.has(class) {
            return Err(el.error(format!("childclass `{class}` is not declared")));
        }
        let fallback = format!("body{}", self.urdf.links.len());
        let link = self.name(el, el.attrs.get("name"), fallback)?;
        let pose = frames::frame(el, &el.attrs, &self.model.angles)?;
        let joints: Vec<&Element> = el
            .children
            .iter()
            .filter(|c| c.tag == "joint" || c.tag == "freejoint")
            .collect();
        let mut shift = [0.0; 3];
        if let Some(parent) = &parent {
            let joint = match joints.as_slice() {
                [] => None,
                [j] => Some((*j, self.model.defaults.resolve(j, "joint", class)?)),
                [_, j, ..] => {
                    return Err(j.error(
                        "is a body's second joint: a URDF joint joins two links, so one per body",
                    ));
                }
            };
            if let Some((j, attrs)) = &joint {
                shift = numbers::<3>(j, attrs, "pos")?.unwrap_or([0.0; 3]);
            }
            let at = Frame {
                pos: [0, 1, 2].map(|i| pose.pos[i] - parent.shift[i]),
                rot: pose.rot,
            }
            .then(&Frame {
                pos: shift,
                rot: IDENTITY,
            });
            let joint = self.joint(joint, &parent.link, &link, at)?;
            self.urdf.joints.push(joint);
        } else if joints.len() != 1 {
            return Err(el.error("the robot's body must have its free joint and no other"));
        }
        let mut out = new_link(&link);
        self.geoms_and_mass(el, class, shift, &mut out)?;
        self.urdf.links.push(out);
        for c in &el.children {
            match c.tag.as_str() {
                "body" => self.body(
                    c,
                    Some(Parent {
                        link: link.clone(),
                        shift,
                    }),
                    class,
                )?,
                "camera" => self.camera(c, class, &link, shift)?,
                "joint" | "freejoint" | "geom" | "inertial" => {}
                t if LEFT_OUT.contains(&t) => {}
                _ => return Err(c.error("is not an element of <body> the simulator reads")),
            }
        }
        Ok(())
    }

    fn joint(
        &mut self,
        joint: Option<(&Element, BTreeMap<String, String>)>,
        parent: &str,
        child: &str,
        at: Frame,
    ) -> Result<Joint, MjcfError> {
        let mut out = fixed_joint(format!("{child}_fixed"), parent, child, at);
        let Some((el, attrs)) = joint else {
            out.name = self.name_free(&out.name);
            return Ok(out);
        };
        let kind = attrs.get("type").map_or("hinge", String::as_str);
        let unit = match kind {
            "hinge" => self.model.angles.unit,
            "slide" => 1.0,
            "free" => return Err(el.error("a free joint below the robot's body is not supported")),
            _ => return Err(el.error(format!("a {kind} joint is not supported (hinge or slide)"))),
        };
        out.name = self.name(el, attrs.get("name"), format!("{child}_joint"))?;
        self.qpos_joints.push(out.name.clone());
        let axis = numbers::<3>(el, &attrs, "axis")?.unwrap_or([0.0, 0.0, 1.0]);
        let n = axis.iter().map(|v| v * v).sum::<f64>().sqrt();
        if n.is_nan() || n <= 1e-12 {
            return Err(el.error("its axis is zero"));
        }
        out.axis.xyz = urdf_rs::Vec3(axis.map(|v| v / n));
        let range = numbers::<2>(el, &attrs, "range")?;
        let limited = match attrs.get("limited").map(String::as_str) {
            Some("true") => true,
            Some("false") => false,
            _ => self.model.autolimits && range.is_some(),
        };
        out.joint_type = match (kind, limited) {
            ("slide", _) => JointType::Prismatic,
            (_, true) => JointType::Revolute,
            (_, false) => JointType::Continuous,
        };
        if limited {
            let [lo, hi] = range.ok_or_else(|| el.error("is limited but gives no range"))?;
            out.limit.lower = lo * unit;
            out.limit.upper = hi * unit;
        }
        let number = |key: &str| -> Result<f64, MjcfError> {
            Ok(numbers::<1>(el, &attrs, key)?.map_or(0.0, |[v]| v))
        };
        let (damping, friction) = (number("damping")?, number("frictionloss")?);
        if damping != 0.0 || friction != 0.0 {
            out.dynamics = Some(urdf_rs::Dynamics { damping, friction });
        }
        let armature = number("armature")?;
        if !(armature.is_finite() && armature >= 0.0) {
            return Err(el.error(format!(
                "armature {armature}: it must be finite and not negative"
            )));
        }
        if armature > 0.0 {
            self.armature.insert(out.name.clone(), armature);
        }
        if number("stiffness")? != 0.0 {
            return Err(el.error("a joint spring (stiffness) is not simulated"));
        }
        Ok(out)
    }

    /// A name for a joint the file does not name, unused so far.
    fn name_free(&mut self, base: &str) -> String {
        let mut name = base.to_string();
        let mut k = 1;
        while !self.joints.insert(name.clone()) {
            k += 1;
            name = format!("{base}{k}");
        }
        name
    }

    /// The body's collision geoms as `link`'s shapes, and its mass.
    fn geoms_and_mass(
        &mut self,
        el: &Element,
        class: &str,
        shift: [f64; 3],
        link: &mut Link,
    ) -> Result<(), MjcfError> {
        let in_link = |f: Frame| Frame {
            pos: [0, 1, 2].map(|i| f.pos[i] - shift[i]),
            rot: f.rot,
        };
        let mut parts = Vec::new();
        let mut mesh_mass = None;
        for g in el.all("geom") {
            let attrs = self.model.defaults.resolve(g, "geom", class)?;
            let geom = self.geom(g, &attrs)?;
            let int = |key: &str, default: i64| -> Result<i64, MjcfError> {
                attrs.get(key).map_or(Ok(default), |v| {
                    v.trim()
                        .parse()
                        .map_err(|_| g.error(format!("`{key}` \"{v}\" is not an integer")))
                })
            };
            let collides = int("contype", 1)? != 0 || int("conaffinity", 1)? != 0;
            let group = int("group", 0)?;
            let [lo, hi] = self.model.inertia_groups;
            if (lo..=hi).contains(&group) {
                match geom.solid {
                    Some(solid) => {
                        let mass = match numbers::<1>(g, &attrs, "mass")? {
                            Some([m]) => m,
                            None => {
                                numbers::<1>(g, &attrs, "density")?.map_or(1000.0, |[d]| d)
                                    * solid.volume()
                            }
                        };
                        parts.push((solid, mass, geom.frame));
                    }
                    None => mesh_mass = Some(g),
                }
            }
            if collides {
                if matches!(geom.solid, Some(Solid::Ellipsoid(_))) {
                    return Err(g.error(
                        "an ellipsoid's collisions are not simulated: make it visual (contype=\"0\" \
                         conaffinity=\"0\") or another shape",
                    ));
                }
                link.collision.push(Collision {
                    name: attrs.get("name").cloned(),
                    origin: in_link(geom.frame).urdf(),
                    geometry: geom.urdf,
                });
            }
        }
        let inertial = el.all("inertial").next();
        let from_geoms = match self.model.inertia_from_geom.as_str() {
            "true" => true,
            "false" => false,
            _ => inertial.is_none(),
        };
        if from_geoms {
            if let Some(g) = mesh_mass {
                return Err(g.error(
                    "the body's mass would come from this mesh, which is not supported: give the \
                     body an <inertial>",
                ));
            }
            if let Some(p) = combine(&parts) {
                let i = p.inertia;
                link.inertial = Inertial {
                    origin: in_link(Frame {
                        pos: p.centre,
                        rot: IDENTITY,
                    })
                    .urdf(),
                    mass: urdf_rs::Mass { value: p.mass },
                    inertia: crate::fold::tensor_inertia(&i),
                };
            }
        } else if let Some(el) = inertial {
            let f = frames::frame(el, &el.attrs, &self.model.angles)?;
            let [mass] =
                numbers::<1>(el, &el.attrs, "mass")?.ok_or_else(|| el.error("needs a `mass`"))?;
            let inertia = match (
                numbers::<3>(el, &el.attrs, "diaginertia")?,
                numbers::<6>(el, &el.attrs, "fullinertia")?,
            ) {
                (Some([a, b, c]), None) => Inertia {
                    ixx: a,
                    iyy: b,
                    izz: c,
                    ..Inertia::default()
                },
                (None, Some([a, b, c, d, e, f])) => Inertia {
                    ixx: a,
                    iyy: b,
                    izz: c,
                    ixy: d,
                    ixz: e,
                    iyz: f,
                },
                _ => return Err(el.error("needs one of `diaginertia` and `fullinertia`")),
            };
            link.inertial = Inertial {
                origin: in_link(f).urdf(),
                mass: urdf_rs::Mass { value: mass },
                inertia,
            };
        }
        Ok(())
    }

    fn geom(&self, g: &Element, attrs: &BTreeMap<String, String>) -> Result<Geom, MjcfError> {
        let kind = attrs.get("type").map_or(
            if attrs.contains_key("mesh") {
                "mesh"
            } else {
                "sphere"
            },
            String::as_str,
        );
        let size: Vec<f64> = match attrs.get("size") {
            None => Vec::new(),
            Some(s) => s
                .split_whitespace()
                .map(str::parse)
                .collect::<Result<_, _>>()
                .map_err(|_| g.error(format!("size \"{s}\" is not numbers")))?,
        };
        let at = |k: usize| -> Result<f64, MjcfError> {
            size.get(k)
                .copied()
                .filter(|v| v.is_finite() && *v > 0.0)
                .ok_or_else(|| {
                    g.error(format!(
                        "a {kind} needs {} positive sizes, has \"{}\"",
                        k + 1,
                        attrs.get("size").map_or("", |s| s)
                    ))
                })
        };
        let (frame, half) = match numbers::<6>(g, attrs, "fromto")? {
            Some(v) => {
                let (f, h) = frames::from_to([v[0], v[1], v[2]], [v[3], v[4], v[5]])
                    .ok_or_else(|| g.error("`fromto`'s two points are the same"))?;
                (f, Some(h))
            }
            None => (frames::frame(g, attrs, &self.model.angles)?, None),
        };
        let long = |k: usize| half.map_or_else(|| at(k), Ok);
        let (solid, urdf) = match kind {
            "sphere" => {
                let r = at(0)?;
                (Some(Solid::Sphere(r)), Geometry::Sphere { radius: r })
            }
            "capsule" | "cylinder" => {
                let (r, h) = (at(0)?, long(1)?);
                if kind == "capsule" {
                    (
                        Some(Solid::Capsule(r, h)),
                        Geometry::Capsule {
                            radius: r,
                            length: 2.0 * h,
                        },
                    )
                } else {
                    (
                        Some(Solid::Cylinder(r, h)),
                        Geometry::Cylinder {
                            radius: r,
                            length: 2.0 * h,
                        },
                    )
                }
            }
            "box" => {
                let s = [at(0)?, at(1)?, long(2)?];
                (
                    Some(Solid::Box(s)),
                    Geometry::Box {
                        size: urdf_rs::Vec3(s.map(|v| 2.0 * v)),
                    },
                )
            }
            "ellipsoid" => {
                let s = [at(0)?, at(1)?, long(2)?];
                (Some(Solid::Ellipsoid(s)), Geometry::Sphere { radius: s[0] })
            }
            "mesh" => {
                let name = attrs
                    .get("mesh")
                    .ok_or_else(|| g.error("a mesh geom names no `mesh`"))?;
                let (file, scale) = self.model.meshes.get(name).ok_or_else(|| {
                    g.error(format!("names mesh `{name}`, which no <asset> declares"))
                })?;
                let filename = file.to_string_lossy().into_owned();
                (
                    None,
                    Geometry::Mesh {
                        filename,
                        scale: Some(urdf_rs::Vec3(*scale)),
                    },
                )
            }
            _ => return Err(g.error(format!("a {kind} geom on the robot is not supported"))),
        };
        Ok(Geom { frame, solid, urdf })
    }

    /// The first camera on the robot as its `camera` frame.
    fn camera(
        &mut self,
        c: &Element,
        class: &str,
        link: &str,
        shift: [f64; 3],
    ) -> Result<(), MjcfError> {
        if self.camera {
            self.notes.push(format!(
                "left out a second camera at {}: the first is the robot's",
                c.at
            ));
            return Ok(());
        }
        let attrs = self.model.defaults.resolve(c, "camera", class)?;
        let f = frames::frame(c, &attrs, &self.model.angles)?;
        let name = ["camera", "camera_link"]
            .into_iter()
            .find(|n| !self.links.contains(*n))
            .ok_or_else(|| c.error("the names `camera` and `camera_link` are both taken"))?
            .to_string();
        self.links.insert(name.clone());
        let at = Frame {
            pos: [0, 1, 2].map(|i| f.pos[i] - shift[i]),
            rot: compose(&f.rot, &CAMERA_AXES),
        };
        self.urdf.links.push(new_link(&name));
        let joint = self.name_free(&format!("{name}_joint"));
        self.urdf.joints.push(fixed_joint(joint, link, &name, at));
        self.camera = true;
        Ok(())
    }
}

/// A geom read: where it is in its body, its solid for the mass (none for
/// a mesh) and its URDF shape.
struct Geom {
    frame: Frame,
    solid: Option<Solid>,
    urdf: Geometry,
}

/// A link with no mass and no shapes.
fn new_link(name: &str) -> Link {
    Link {
        name: name.into(),
        inertial: Inertial::default(),
        visual: Vec::new(),
        collision: Vec::new(),
    }
}

/// A fixed joint from `parent` to `child`, whose origin is `at` in `parent`.
fn fixed_joint(name: String, parent: &str, child: &str, at: Frame) -> Joint {
    Joint {
        name,
        joint_type: JointType::Fixed,
        origin: at.urdf(),
        parent: urdf_rs::LinkName {
            link: parent.into(),
        },
        child: urdf_rs::LinkName { link: child.into() },
        axis: urdf_rs::Axis::default(),
        limit: urdf_rs::JointLimit::default(),
        calibration: None,
        dynamics: None,
        mimic: None,
        safety_controller: None,
    }
}
