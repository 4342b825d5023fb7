//! A URDF's mesh collision shapes: found on disk beside the URDF, loaded
//! once as convex hulls (one per mesh in the file), and handed to every
//! world built from the robot; or an error naming the link and the file. A
//! mesh is never dropped: the URDF loader, given a mesh it cannot read,
//! would leave the link colliding as nothing.

use std::path::{Path, PathBuf};

use rapier3d::geometry::{MeshConverter, MeshConverterError, SharedShape};
use rapier3d::math::{Pose, Real, Vector};
use urdf_rs::{Geometry, Robot};

use crate::error::RobotError;

/// One mesh collision shape of a link, as convex hulls in the link's frame.
#[derive(Clone)]
pub struct MeshCollision {
    /// The link's index in the URDF.
    pub link: usize,
    /// The file it was read from.
    pub file: PathBuf,
    /// Each mesh of the file: its convex hull and where it sits in the link.
    pub parts: Vec<(SharedShape, Pose)>,
}

impl std::fmt::Debug for MeshCollision {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshCollision")
            .field("link", &self.link)
            .field("file", &self.file)
            .field("parts", &self.parts.len())
            .finish()
    }
}

/// Where `filename` may be, for a URDF in `dir`: a plain path relative to
/// `dir` (or absolute); `file://PATH`; `package://PACKAGE/PATH` relative to
/// `dir` or to its parent (a ROS package's `urdf/` folder beside its
/// `meshes/`), or to a folder further up (a package holding many robots,
/// as example-robot-data's `robots/NAME/urdf/`), nearest first.
fn candidates(dir: &Path, filename: &str) -> Vec<PathBuf> {
    if let Some(path) = filename.strip_prefix("file://") {
        return vec![PathBuf::from(path)];
    }
    if let Some(rest) = filename.strip_prefix("package://") {
        let within = rest.split_once('/').map_or(rest, |(_, path)| path);
        let mut out = vec![dir.join(within), dir.join("..").join(within)];
        out.push(dir.join(rest));
        // Further up: the grandparent and beyond, as far as the path goes.
        let absolute = std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf());
        for up in absolute.ancestors().skip(2) {
            out.push(up.join(within));
        }
        return out;
    }
    vec![dir.join(filename)]
}

/// Where `filename` is, for a URDF in `dir`: the nearest of the places it
/// may be (a plain or `file://` path; `package://PACKAGE/PATH` beside `dir`,
/// beside its parent, or under any folder further up) that holds a file.
pub fn find(dir: &Path, filename: &str) -> Option<PathBuf> {
    candidates(dir, filename).into_iter().find(|p| p.is_file())
}

/// `urdf` with every mesh file name (visual and collision) that is found
/// beside `dir` made absolute: the same robot, for a copy of the URDF
/// written elsewhere (a peer simulator's).
pub fn with_absolute_meshes(urdf: &Robot, dir: &Path) -> Robot {
    let mut r = urdf.clone();
    let absolute = |geometry: &mut Geometry| {
        if let Geometry::Mesh { filename, .. } = geometry {
            if let Some(p) = find(dir, filename).and_then(|p| p.canonicalize().ok()) {
                *filename = p.display().to_string();
            }
        }
    };
    for link in &mut r.links {
        link.visual
            .iter_mut()
            .for_each(|v| absolute(&mut v.geometry));
        link.collision
            .iter_mut()
            .for_each(|c| absolute(&mut c.geometry));
    }
    r
}

/// Every mesh collision shape of `urdf`, read from beside `dir`, as convex
/// hulls; or the first that cannot be: missing, unreadable, of a format not
/// read (STL, COLLADA and Wavefront OBJ are), holding no mesh, or with no
/// hull.
pub fn load(urdf: &Robot, dir: &Path) -> Result<Vec<MeshCollision>, RobotError> {
    let mut out = Vec::new();
    for (index, link) in urdf.links.iter().enumerate() {
        for c in &link.collision {
            let Geometry::Mesh { filename, scale } = &c.geometry else {
                continue;
            };
            let refuse = |reason: String| RobotError::MeshCollision {
                link: link.name.clone(),
                file: filename.clone(),
                reason,
            };
            let looked = candidates(dir, filename);
            let file = looked
                .iter()
                .find(|p| p.is_file())
                .cloned()
                .ok_or_else(|| {
                    refuse(format!(
                        "is not there (looked for {})",
                        looked
                            .iter()
                            .map(|p| p.display().to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ))
                })?;
            let s = scale.map_or([1.0; 3], |v| v.0).map(|v| v as Real);
            let meshes = read(&file, Vector::new(s[0], s[1], s[2]))
                .map_err(|e| refuse(format!("cannot be read from {}: {e}", file.display())))?;
            if meshes.is_empty() {
                return Err(refuse(format!("{} holds no mesh", file.display())));
            }
            let at = crate::pose::urdf_pose(c.origin.xyz.0, c.origin.rpy.0);
            let parts = meshes
                .into_iter()
                .map(|m| {
                    m.map(|(shape, pose)| (shape, at * pose))
                        .map_err(|e| refuse(format!("in {}: {e}", file.display())))
                })
                .collect::<Result<Vec<_>, _>>()?;
            out.push(MeshCollision {
                link: index,
                file,
                parts,
            });
        }
    }
    Ok(out)
}

/// One mesh's convex hull and where it sits in the file's frame, or why it
/// has none.
type Hull = Result<(SharedShape, Pose), MeshConverterError>;

/// Each mesh of `file`, scaled by `scale`, as its convex hull: what
/// `rapier3d_meshloader::load_from_path` reads, except that a binary STL
/// whose 80-byte header begins with "solid" (as CAD exporters write, and
/// as Solo12's feet are), which that loader takes for ASCII and fails on, is
/// read as the binary it is. A file is binary STL when its length is
/// exactly the header, the triangle count and 50 bytes per triangle, the
/// test other loaders (trimesh, numpy-stl) make. An ASCII STL does not pass
/// it: its bytes 80-84 are text, a count of at least 0x20202020 triangles,
/// which would make the file some 27 GB.
fn read(file: &Path, scale: Vector) -> Result<Vec<Hull>, String> {
    // Whatever reads it: a regular file of bounded size.
    crate::files::check(file, crate::files::MESH_LIMIT).map_err(|e| e.to_string())?;
    let is_stl = file
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("stl"));
    if is_stl {
        // Read once, and parsed here whether ASCII or binary.
        let mut bytes =
            crate::files::read(file, crate::files::MESH_LIMIT).map_err(|e| e.to_string())?;
        if is_binary_stl(&bytes) {
            // A header of zeros, so the parser does not look for ASCII.
            bytes[..80].fill(0);
        }
        let scene = mesh_loader::stl::from_slice(&bytes).map_err(|e| e.to_string())?;
        return Ok(scene
            .meshes
            .iter()
            .map(|m| rapier3d_meshloader::load_from_raw_mesh(m, &MeshConverter::ConvexHull, scale))
            .collect());
    }
    let meshes = rapier3d_meshloader::load_from_path(file, &MeshConverter::ConvexHull, scale)
        .map_err(|e| e.to_string())?;
    Ok(meshes
        .into_iter()
        .map(|m| m.map(|m| (m.shape, m.pose)))
        .collect())
}

/// Whether `bytes` are laid out as binary STL: an 80-byte header, a
/// little-endian triangle count, and 50 bytes per triangle, to the byte.
fn is_binary_stl(bytes: &[u8]) -> bool {
    let Some(count) = bytes.get(80..84) else {
        return false;
    };
    let count = u32::from_le_bytes([count[0], count[1], count[2], count[3]]) as u64;
    bytes.len() as u64 == 84 + 50 * count
}

/// `urdf` with its mesh collision shapes taken out (as the zero-sized boxes
/// the URDF loader skips), for a loader that is given them as
/// [`MeshCollision`]s instead.
pub fn without_meshes(urdf: &Robot) -> Robot {
    let mut r = urdf.clone();
    for link in &mut r.links {
        for c in &mut link.collision {
            if matches!(c.geometry, Geometry::Mesh { .. }) {
                c.geometry = Geometry::Box {
                    size: urdf_rs::Vec3([0.0; 3]),
                };
            }
        }
    }
    r
}
