//! MuJoCo's MJCF, as MuJoCo Menagerie publishes its robots, read into the
//! URDF model the rest of the simulator reads: each body a link, each hinge
//! a revolute (or, unlimited, continuous) joint, a body without a joint
//! fixed to its parent, the collision geoms (sphere, capsule, cylinder, box,
//! mesh) its shapes, `<inertial>` or MuJoCo's inference from the geoms its
//! mass, the actuators' force limits its joints' effort limits, and the
//! first `<camera>` on the robot its `camera` frame. Legs, feet and camera
//! are then found from the tree as for a bare URDF (see [`crate::discover`]).
//!
//! What is read: `<include>`, `<default>` classes (nested, `childclass`),
//! `<compiler angle meshdir assetdir autolimits eulerseq inertiafromgeom
//! inertiagrouprange>`, frames by `pos` and `quat`, `euler`, `axisangle`,
//! `xyaxes` or `zaxis`, `<freejoint>`, hinge joints (`axis range limited
//! damping frictionloss armature`: simulated, see [`Mjcf::armature`]), geoms (`type size fromto mesh contype
//! conaffinity group mass density`), `<mesh file scale>` assets, and the
//! `joint` actuators (`gear ctrlrange forcerange`). What changes the
//! mechanics and is not simulated (a tendon, an equality constraint, a ball
//! or slide joint, an ellipsoid's collisions) is refused, naming the element
//! and its line; what does not (lights, materials, sensors, visual geoms,
//! the solver's `<option>`) is left out, the mechanical ones with a note. The
//! keyframe `home` (else the first) gives the standing pose ([`Mjcf::standing`]).

mod body;
mod frames;
mod inertia;
mod keyframe;
mod tree;

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use urdf_rs::Robot;

use crate::error::RobotError;
use frames::Angles;
use tree::{Defaults, Element};

/// An MJCF element that cannot be read, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct MjcfError {
    /// The element and where it is written (`<geom> at go2.xml line 40`).
    pub at: String,
    /// What is wrong.
    pub reason: String,
}

impl From<MjcfError> for RobotError {
    fn from(e: MjcfError) -> Self {
        RobotError::Mjcf {
            at: e.at,
            reason: e.reason,
        }
    }
}

/// An MJCF model read as a URDF.
#[derive(Debug, Clone)]
pub struct Mjcf {
    /// The robot as a URDF (mesh file names absolute).
    pub urdf: Robot,
    /// What was left out or read differently from MuJoCo, a line each.
    pub notes: Vec<String>,
    /// Each hinge's `armature` (rotor inertia reflected through its gear,
    /// kg m^2) by the URDF joint's name, where not 0: URDF has no place for it.
    pub armature: BTreeMap<String, f64>,
    /// The joints' standing angles (rad) by the URDF joint's name, from the
    /// keyframe `home` (else the first), if it could be read (its `qpos` in
    /// MuJoCo's order, the robot's alone): the gait stands its feet where they are at these angles
    /// (see [`crate::stance`]).
    pub standing: BTreeMap<String, f64>,
    /// The actuators' gain, N m/rad, where every actuator is a `position`
    /// servo with the same joint-space `kp` (times its gear squared). Named
    /// in a note, not used: the testbed's servos keep their scaled gains
    /// (the book's MJCF page says why).
    pub servo_kp_nm_per_rad: Option<f64>,
}

/// Whether `text` is MJCF: its first element is `<mujoco>`.
pub fn is_mjcf(text: &str) -> bool {
    let mut rest = text.trim_start_matches('\u{feff}');
    loop {
        rest = rest.trim_start();
        let skip = if rest.starts_with("<?") {
            rest.find("?>").map(|k| k + 2)
        } else if rest.starts_with("<!--") {
            rest.find("-->").map(|k| k + 3)
        } else if rest.starts_with("<!") {
            rest.find('>').map(|k| k + 1)
        } else {
            return rest.starts_with("<mujoco")
                && rest[7..].starts_with(|c: char| c.is_whitespace() || c == '>' || c == '/');
        };
        match skip {
            Some(k) => rest = &rest[k..],
            None => return false,
        }
    }
}

/// The top-level elements: read, left out with a note, or refused.
const READ: [&str; 6] = [
    "compiler",
    "default",
    "asset",
    "worldbody",
    "actuator",
    "keyframe",
];
const LEFT_OUT: [&str; 7] = [
    "option",
    "size",
    "visual",
    "statistic",
    "custom",
    "sensor",
    "extension",
];
const NOTED: [&str; 1] = ["contact"];
const REFUSED: [&str; 3] = ["tendon", "equality", "deformable"];

/// Reads an MJCF model (the file and what it includes).
pub fn read(path: &Path) -> Result<Mjcf, RobotError> {
    let root = tree::read(path)?;
    let mut notes = Vec::new();
    for el in &root.children {
        let tag = el.tag.as_str();
        if REFUSED.contains(&tag) && !el.children.is_empty() {
            return Err(el
                .error(format!(
                    "a {tag} constrains the mechanism, which the simulator does not model"
                ))
                .into());
        }
        if NOTED.contains(&tag) && !el.children.is_empty() {
            notes.push(format!(
                "left out <{tag}> at {}: the simulator's own contact rules apply (a link never \
                 collides with its parent)",
                el.at
            ));
        }
        let known = READ.contains(&tag)
            || LEFT_OUT.contains(&tag)
            || NOTED.contains(&tag)
            || REFUSED.contains(&tag);
        if !known {
            return Err(el
                .error("is not an MJCF element the simulator reads")
                .into());
        }
    }
    let dir = path.parent().unwrap_or_else(|| Path::new(""));
    let model = Model::of(&root, dir)?;
    let mut robot = body::Builder::new(&model).robot(&root)?;
    robot.notes.splice(0..0, notes);
    actuators(&root, &model, &mut robot)?;
    Ok(robot)
}

/// What the whole model says that bodies are read with.
pub(crate) struct Model {
    pub defaults: Defaults,
    pub angles: Angles,
    /// Whether a range alone makes a joint limited (`autolimits`).
    pub autolimits: bool,
    /// `inertiafromgeom`: `auto`, `true` or `false`.
    pub inertia_from_geom: String,
    /// The geom groups whose geoms count for an inferred inertia.
    pub inertia_groups: [i64; 2],
    /// Mesh assets by name: the file and its scale.
    pub meshes: HashMap<String, (PathBuf, [f64; 3])>,
}

impl Model {
    fn of(root: &Element, dir: &Path) -> Result<Self, MjcfError> {
        let defaults = Defaults::of(root)?;
        let mut model = Model {
            defaults,
            angles: Angles {
                unit: std::f64::consts::PI / 180.0,
                seq: *b"xyz",
            },
            autolimits: true,
            inertia_from_geom: "auto".into(),
            inertia_groups: [0, 5],
            meshes: HashMap::new(),
        };
        let (mut meshdir, mut assetdir) = (None, None);
        for c in root.all("compiler") {
            for (k, v) in &c.attrs {
                match k.as_str() {
                    "angle" => {
                        model.angles.unit = match v.as_str() {
                            "radian" => 1.0,
                            "degree" => std::f64::consts::PI / 180.0,
                            _ => {
                                return Err(
                                    c.error(format!("angle \"{v}\" is not radian or degree"))
                                );
                            }
                        }
                    }
                    "eulerseq" => {
                        let ok = v.len() == 3 && v.bytes().all(|b| b"xyzXYZ".contains(&b));
                        model.angles.seq =
                            v.as_bytes().try_into().ok().filter(|_| ok).ok_or_else(|| {
                                c.error(format!("eulerseq \"{v}\" is not three of xyzXYZ"))
                            })?;
                    }
                    "autolimits" => model.autolimits = v == "true",
                    "inertiafromgeom" if ["auto", "true", "false"].contains(&v.as_str()) => {
                        model.inertia_from_geom = v.clone();
                    }
                    "inertiagrouprange" => {
                        let [a, b] = frames::numbers::<2>(c, &c.attrs, k)?.unwrap_or([0.0, 5.0]);
                        model.inertia_groups = [a as i64, b as i64];
                    }
                    "meshdir" => meshdir = Some(v.clone()),
                    "assetdir" => assetdir = Some(v.clone()),
                    "texturedir" | "discardvisual" | "strippath" | "fusestatic" | "usethread"
                    | "boundmass" | "boundinertia" | "balanceinertia" | "alignfree" => {
                        if matches!(k.as_str(), "boundmass" | "boundinertia" | "balanceinertia")
                            && !matches!(v.as_str(), "0" | "false")
                        {
                            return Err(
                                c.error(format!("{k}=\"{v}\" is not supported: give the masses"))
                            );
                        }
                    }
                    _ => {
                        return Err(c.error(format!(
                            "`{k}` is not a compiler setting the simulator reads"
                        )));
                    }
                }
            }
        }
        // Absolute, so the URDF written from the model finds its meshes from anywhere.
        let mesh_dir = dir.join(meshdir.or(assetdir).unwrap_or_default());
        let mesh_dir = std::path::absolute(&mesh_dir).unwrap_or(mesh_dir);
        for asset in root.all("asset") {
            for m in asset.all("mesh") {
                let attrs = model.defaults.resolve(m, "mesh", "main")?;
                let file = attrs
                    .get("file")
                    .ok_or_else(|| m.error("a mesh asset needs a `file`"))?;
                let name = attrs.get("name").cloned().unwrap_or_else(|| {
                    Path::new(file)
                        .file_stem()
                        .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
                });
                let scale = frames::numbers::<3>(m, &attrs, "scale")?.unwrap_or([1.0; 3]);
                model.meshes.insert(name, (mesh_dir.join(file), scale));
            }
        }
        Ok(model)
    }
}

/// Each actuated joint's effort limit from its actuator: the force range
/// where it is limited, else a motor's control range times its gear; a
/// joint no actuator drives, or one with no limit, is limited by nothing.
fn actuators(root: &Element, model: &Model, robot: &mut Mjcf) -> Result<(), MjcfError> {
    let mut any = false;
    // Each actuator's joint-space position gain (a `position` actuator's
    // `kp` times its gear squared), `None` for any other kind.
    let mut gains: Vec<Option<f64>> = Vec::new();
    for act in root.all("actuator").flat_map(|a| a.children.iter()) {
        if !tree::ACTUATORS.contains(&act.tag.as_str()) {
            return Err(act.error(
                "is not an actuator the simulator reads (motor, position, velocity, general)",
            ));
        }
        let attrs = model.defaults.resolve(act, "actuator", "main")?;
        let joint = attrs.get("joint").ok_or_else(|| {
            act.error("acts on no joint (a tendon or site actuator is not supported)")
        })?;
        let j = robot
            .urdf
            .joints
            .iter_mut()
            .find(|j| &j.name == joint)
            .ok_or_else(|| {
                act.error(format!(
                    "names joint `{joint}`, which the robot does not have"
                ))
            })?;
        let gear = attrs
            .get("gear")
            .map(|g| g.split_whitespace().next().unwrap_or("1").parse::<f64>())
            .transpose()
            .map_err(|_| act.error("its gear is not a number"))?
            .unwrap_or(1.0);
        let limited = |key: &str, range: &str| match attrs.get(key).map(String::as_str) {
            Some("true") => true,
            Some("false") => false,
            _ => model.autolimits && attrs.contains_key(range),
        };
        let bound = |range: &str| -> Result<Option<f64>, MjcfError> {
            Ok(frames::numbers::<2>(act, &attrs, range)?.map(|[lo, hi]| lo.abs().max(hi.abs())))
        };
        let effort = if limited("forcelimited", "forcerange") {
            bound("forcerange")?
        } else if act.tag == "motor" && limited("ctrllimited", "ctrlrange") {
            bound("ctrlrange")?.map(|c| c * gear.abs())
        } else {
            None
        };
        if let Some(e) = effort.filter(|e| *e > 0.0) {
            j.limit.effort = e;
        }
        gains.push(if act.tag == "position" {
            // MuJoCo's default kp is 1.
            let [kp] = frames::numbers::<1>(act, &attrs, "kp")?.unwrap_or([1.0]);
            if kp <= 0.0 {
                return Err(act.error(format!("kp {kp}: a position servo's gain must be positive")));
            }
            Some(kp * gear * gear)
        } else {
            None
        });
        any = true;
    }
    if !any {
        return Ok(());
    }
    let first = gains[0];
    robot.servo_kp_nm_per_rad = first.filter(|_| gains.iter().all(|g| *g == first));
    robot.notes.push(
        match (robot.servo_kp_nm_per_rad, gains.iter().any(Option::is_some)) {
            (Some(kp), _) => format!(
                "the actuators' force limits are the joints' effort limits; their gain, kp {kp} N \
             m/rad, is not the servos': the testbed's own servos, with gains scaled from the \
             ERS-7's, drive the joints (`--set servo.kp={kp}` gives them the file's gain)"
            ),
            (None, true) => {
                "the actuators' force limits are the joints' effort limits; their kinds or \
             gains differ, so the testbed's own servos, with its scaled gains, drive the joints"
                    .into()
            }
            (None, false) => {
                "the actuators' force limits are the joints' effort limits; the testbed's \
             own position servos drive the joints"
                    .into()
            }
        },
    );
    Ok(())
}
