//! Mesh collision shapes (STL, Wavefront OBJ, COLLADA) are loaded as convex hulls
//! from beside the URDF, and a mesh that cannot be loaded is an error naming
//! the link and the file: never a link that collides as nothing.

use std::path::{Path, PathBuf};

use quadsim::scene::Shape;
use quadsim::{ERS7_URDF, QuadrupedSim, RobotDescription, SimConfig};

const TORSO_BOX: &str = r#"<geometry><box size="0.20 0.10 0.08"/></geometry></collision>"#;
const HALF: [f64; 3] = [0.10, 0.05, 0.04];

fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("quadsim-meshes-{name}-{}", std::process::id()));
    std::fs::create_dir_all(d.join("meshes")).expect("dir");
    d
}

include!("common/cube.rs");

/// The box's corners and its twelve outward triangles.
fn box_mesh() -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    (cube_corners(HALF), CUBE_FACES.to_vec())
}

fn obj() -> String {
    let (v, f) = box_mesh();
    let mut s = String::new();
    for p in v {
        s += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for t in f {
        s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s
}

fn stl() -> String {
    let (v, f) = box_mesh();
    let mut s = String::from("solid torso\n");
    for t in f {
        s += "facet normal 0 0 0\nouter loop\n";
        for i in t {
            s += &format!("vertex {} {} {}\n", v[i][0], v[i][1], v[i][2]);
        }
        s += "endloop\nendfacet\n";
    }
    s + "endsolid torso\n"
}

/// The box as a COLLADA 1.4 document (as ROS packages ship `.dae` meshes).
fn dae() -> String {
    let (v, f) = box_mesh();
    let floats: Vec<String> = v.iter().flatten().map(f64::to_string).collect();
    let indices: Vec<String> = f.iter().flatten().map(usize::to_string).collect();
    format!(
        r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="torso-mesh" name="torso"><mesh>
    <source id="torso-positions">
      <float_array id="torso-positions-array" count="{}">{}</float_array>
      <technique_common><accessor source="#torso-positions-array" count="{}" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common>
    </source>
    <vertices id="torso-vertices"><input semantic="POSITION" source="#torso-positions"/></vertices>
    <triangles count="{}"><input semantic="VERTEX" source="#torso-vertices" offset="0"/><p>{}</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="torso">
    <instance_geometry url="#torso-mesh"/>
  </node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"##,
        floats.len(),
        floats.join(" "),
        v.len(),
        f.len(),
        indices.join(" ")
    )
}

/// The ERS-7 with its torso's box given as the mesh `filename`, read from `dir`.
fn with_torso_mesh(dir: &Path, filename: &str) -> Result<RobotDescription, quadsim::RobotError> {
    let text = ERS7_URDF.replacen(
        TORSO_BOX,
        &format!(r#"<geometry><mesh filename="{filename}"/></geometry></collision>"#),
        1,
    );
    let urdf = urdf_rs::read_from_string(&text).expect("parses");
    let map = quadsim::description::RobotMap::conventional(&urdf).expect("map");
    RobotDescription::from_urdf_in(urdf, &map, dir)
}

/// The torso collides as its box did: one convex part the box's size, and
/// the robot stands and walks.
fn collides_as_the_box(d: &RobotDescription) {
    assert_eq!(d.meshes.len(), 1);
    assert_eq!(d.meshes[0].parts.len(), 1);
    let mut sim = QuadrupedSim::new(d, SimConfig::default()).expect("a world");
    let scene = sim.scene();
    let torso = scene
        .bodies
        .iter()
        .find(|b| b.name == "torso")
        .expect("the torso");
    let [part] = torso.parts.as_slice() else {
        panic!("one collider on the torso: {:?}", torso.parts);
    };
    let Shape::Bounds { min_m, max_m } = part.shape else {
        panic!("a hull: {:?}", part.shape);
    };
    for k in 0..3 {
        assert!((max_m[k] - HALF[k]).abs() < 1e-5 && (min_m[k] + HALF[k]).abs() < 1e-5);
    }
    sim.advance(1.0);
    sim.set_command(150.0).expect("finite");
    sim.advance(2.0);
    assert!(sim.is_upright());
    assert!(sim.distance_along_line_m() < SimConfig::default().start_distance_m - 0.1);
}

#[test]
fn a_wavefront_obj_mesh_is_loaded_as_its_hull() {
    let d = dir("obj");
    std::fs::write(d.join("meshes/torso.obj"), obj()).expect("write");
    collides_as_the_box(&with_torso_mesh(&d, "meshes/torso.obj").expect("loads"));
}

#[test]
fn a_collada_mesh_is_loaded_as_its_hull() {
    let d = dir("dae");
    std::fs::write(d.join("meshes/torso.dae"), dae()).expect("write");
    collides_as_the_box(&with_torso_mesh(&d, "meshes/torso.dae").expect("loads"));
}

#[test]
fn an_stl_mesh_from_a_ros_package_path_is_loaded_as_its_hull() {
    // package://ers7/meshes/torso.stl, for a URDF in the package's urdf/.
    let d = dir("stl");
    std::fs::write(d.join("meshes/torso.stl"), stl()).expect("write");
    std::fs::create_dir_all(d.join("urdf")).expect("dir");
    let found = with_torso_mesh(&d.join("urdf"), "package://ers7/meshes/torso.stl");
    collides_as_the_box(&found.expect("loads"));
}

#[test]
fn a_missing_mesh_file_is_refused_naming_the_link_and_file() {
    let d = dir("missing");
    let e = with_torso_mesh(&d, "meshes/nowhere.stl")
        .expect_err("refused")
        .to_string();
    for needle in [
        "link `torso`",
        "mesh collision shape (meshes/nowhere.stl)",
        "is not there",
        "nowhere.stl",
    ] {
        assert!(e.contains(needle), "`{e}` should say `{needle}`");
    }
}

#[test]
fn a_mesh_that_cannot_be_read_is_refused() {
    let d = dir("garbage");
    std::fs::write(d.join("meshes/torso.obj"), "this is not a mesh\n").expect("write");
    std::fs::write(d.join("meshes/torso.xyz"), obj()).expect("write");
    for file in ["meshes/torso.obj", "meshes/torso.xyz"] {
        let e = with_torso_mesh(&d, file).expect_err(file).to_string();
        assert!(e.contains("link `torso`") && e.contains(file), "{e}");
    }
}
