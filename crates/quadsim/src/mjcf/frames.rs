//! MJCF frames as MuJoCo's compiler reads them: a position and one of
//! `quat` (w x y z), `euler` (in the compiler's `eulerseq` and `angle`
//! unit), `axisangle`, `xyaxes` or `zaxis`; a geom's `fromto`. Rotations are
//! 3 x 3 matrices (row-major) and turn into URDF's roll-pitch-yaw.

use std::collections::BTreeMap;

use super::MjcfError;
use super::tree::Element;
use crate::pose::{Rotation, compose};

/// The compiler's settings that frames depend on.
#[derive(Debug, Clone)]
pub(crate) struct Angles {
    /// Radians per unit of the file's angles (1, or pi/180 for degrees).
    pub unit: f64,
    /// The Euler sequence, as `eulerseq` writes it (`xyz` by default).
    pub seq: [u8; 3],
}

/// A rigid frame: where its origin is and how it is turned, in its parent's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Frame {
    /// Position, m.
    pub pos: [f64; 3],
    /// Rotation (columns: the frame's axes in its parent's).
    pub rot: Rotation,
}

pub(crate) const IDENTITY: Rotation = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

impl Frame {
    /// The frame at the origin, unturned.
    #[cfg(test)]
    pub const ORIGIN: Self = Self {
        pos: [0.0; 3],
        rot: IDENTITY,
    };

    /// `child`, given in this frame, in this frame's parent's.
    pub fn then(&self, child: &Frame) -> Frame {
        let p = apply(&self.rot, child.pos);
        Frame {
            pos: [0, 1, 2].map(|i| self.pos[i] + p[i]),
            rot: compose(&self.rot, &child.rot),
        }
    }

    /// The frame as URDF writes an origin: `xyz` and roll-pitch-yaw.
    pub fn urdf(&self) -> urdf_rs::Pose {
        urdf_rs::Pose {
            xyz: urdf_rs::Vec3(self.pos),
            rpy: urdf_rs::Vec3(rpy(&self.rot)),
        }
    }
}

/// `m v`.
pub(crate) fn apply(m: &Rotation, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

/// `m` transposed (its inverse).
pub(crate) fn transpose(m: &Rotation) -> Rotation {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| m[j][i]))
}

/// URDF's roll, pitch and yaw of `m` (`m = Rz(yaw) Ry(pitch) Rx(roll)`).
pub(crate) fn rpy(m: &Rotation) -> [f64; 3] {
    let sp = (-m[2][0]).clamp(-1.0, 1.0);
    if sp.abs() > 1.0 - 1e-12 {
        // Pitch at a quarter turn: roll and yaw turn about one axis.
        [0.0, sp.asin(), (-m[0][1]).atan2(m[1][1])]
    } else {
        [m[2][1].atan2(m[2][2]), sp.asin(), m[1][0].atan2(m[0][0])]
    }
}

/// The rotation of unit quaternion `w x y z` (normalised).
pub(crate) fn quat(q: [f64; 4]) -> Option<Rotation> {
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !(n > 1e-12 && n.is_finite()) {
        return None;
    }
    let [w, x, y, z] = q.map(|v| v / n);
    Some([
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ])
}

/// The rotation by `angle` about `axis` (normalised).
pub(crate) fn axis_angle(axis: [f64; 3], angle: f64) -> Option<Rotation> {
    let n = norm(axis);
    if !(n > 1e-12 && n.is_finite() && angle.is_finite()) {
        return None;
    }
    let h = 0.5 * angle;
    let s = h.sin() / n;
    quat([h.cos(), axis[0] * s, axis[1] * s, axis[2] * s])
}

fn norm(v: [f64; 3]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The least rotation taking +z to `z` (MuJoCo's `zaxis`).
pub(crate) fn z_axis(z: [f64; 3]) -> Option<Rotation> {
    let n = norm(z);
    if !(n > 1e-12 && n.is_finite()) {
        return None;
    }
    let z = z.map(|v| v / n);
    let axis = cross([0.0, 0.0, 1.0], z);
    let s = norm(axis);
    if s < 1e-12 {
        return Some(if z[2] > 0.0 {
            IDENTITY
        } else {
            [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]
        });
    }
    axis_angle(axis, s.atan2(z[2]))
}

/// Numbers of attribute `key` of `attrs`, exactly `n` of them, if given.
pub(crate) fn numbers<const N: usize>(
    el: &Element,
    attrs: &BTreeMap<String, String>,
    key: &str,
) -> Result<Option<[f64; N]>, MjcfError> {
    let Some(v) = number_list(el, attrs, key)? else {
        return Ok(None);
    };
    let text = attrs.get(key).map_or("", String::as_str);
    <[f64; N]>::try_from(v.as_slice())
        .map(Some)
        .map_err(|_| el.error(format!("`{key}` is \"{text}\": it takes {N} numbers")))
}

/// Numbers of attribute `key` of `attrs`, as many as it gives, if given;
/// each must be finite.
pub(crate) fn number_list(
    el: &Element,
    attrs: &BTreeMap<String, String>,
    key: &str,
) -> Result<Option<Vec<f64>>, MjcfError> {
    let Some(text) = attrs.get(key) else {
        return Ok(None);
    };
    let v: Vec<f64> = text
        .split_whitespace()
        .map(str::parse::<f64>)
        .collect::<Result<_, _>>()
        .map_err(|_| el.error(format!("`{key}` is \"{text}\", not numbers")))?;
    if v.iter().any(|x| !x.is_finite()) {
        return Err(el.error(format!(
            "`{key}` is \"{text}\": every number must be finite"
        )));
    }
    Ok(Some(v))
}

/// The frame an element's `pos` and orientation attributes give.
pub(crate) fn frame(
    el: &Element,
    attrs: &BTreeMap<String, String>,
    angles: &Angles,
) -> Result<Frame, MjcfError> {
    let pos = numbers::<3>(el, attrs, "pos")?.unwrap_or([0.0; 3]);
    let given: Vec<&str> = ["quat", "euler", "axisangle", "xyaxes", "zaxis"]
        .into_iter()
        .filter(|k| attrs.contains_key(*k))
        .collect();
    if given.len() > 1 {
        return Err(el.error(format!(
            "gives its orientation {} ways ({}): give one",
            given.len(),
            given.join(", ")
        )));
    }
    let bad = |key: &str| el.error(format!("`{key}` does not give a rotation (a zero vector?)"));
    let rot = match given.first().copied() {
        None => IDENTITY,
        Some("quat") => numbers::<4>(el, attrs, "quat")?
            .and_then(quat)
            .ok_or_else(|| bad("quat"))?,
        Some("axisangle") => {
            let [x, y, z, a] = numbers::<4>(el, attrs, "axisangle")?.unwrap_or_default();
            axis_angle([x, y, z], a * angles.unit).ok_or_else(|| bad("axisangle"))?
        }
        Some("zaxis") => numbers::<3>(el, attrs, "zaxis")?
            .and_then(z_axis)
            .ok_or_else(|| bad("zaxis"))?,
        Some("xyaxes") => {
            let v = numbers::<6>(el, attrs, "xyaxes")?.unwrap_or_default();
            xy_axes([v[0], v[1], v[2]], [v[3], v[4], v[5]]).ok_or_else(|| bad("xyaxes"))?
        }
        Some(_) => {
            let e = numbers::<3>(el, attrs, "euler")?.unwrap_or_default();
            euler(e.map(|a| a * angles.unit), angles.seq)
        }
    };
    Ok(Frame { pos, rot })
}

/// The frame whose x axis is along `x` and y axis in the plane of `x` and `y`.
fn xy_axes(x: [f64; 3], y: [f64; 3]) -> Option<Rotation> {
    let nx = norm(x);
    if !(nx > 1e-12 && nx.is_finite()) {
        return None;
    }
    let x = x.map(|v| v / nx);
    let d: f64 = (0..3).map(|i| x[i] * y[i]).sum();
    let y = [0, 1, 2].map(|i| y[i] - d * x[i]);
    let ny = norm(y);
    if !(ny > 1e-12 && ny.is_finite()) {
        return None;
    }
    let y = y.map(|v| v / ny);
    let z = cross(x, y);
    Some([0, 1, 2].map(|i| [x[i], y[i], z[i]]))
}

/// Rotations about the axes `seq` names, in order: lower case about the
/// turned frame's axes (intrinsic), upper case about the fixed ones.
fn euler(angles: [f64; 3], seq: [u8; 3]) -> Rotation {
    let mut r = IDENTITY;
    for (a, c) in angles.into_iter().zip(seq) {
        let axis = match c.to_ascii_lowercase() {
            b'x' => [1.0, 0.0, 0.0],
            b'y' => [0.0, 1.0, 0.0],
            _ => [0.0, 0.0, 1.0],
        };
        let step = axis_angle(axis, a).unwrap_or(IDENTITY);
        r = if c.is_ascii_lowercase() {
            compose(&r, &step)
        } else {
            compose(&step, &r)
        };
    }
    r
}

/// A capsule's, cylinder's or box's frame and half-length from `fromto`:
/// centred between the two points, its z axis along them.
pub(crate) fn from_to(from: [f64; 3], to: [f64; 3]) -> Option<(Frame, f64)> {
    let d = [0, 1, 2].map(|i| to[i] - from[i]);
    let half = 0.5 * norm(d);
    let rot = z_axis(d)?;
    Some((
        Frame {
            pos: [0, 1, 2].map(|i| 0.5 * (from[i] + to[i])),
            rot,
        },
        half,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &Rotation, b: &Rotation) -> bool {
        (0..3).all(|i| (0..3).all(|j| (a[i][j] - b[i][j]).abs() < 1e-12))
    }

    #[test]
    fn every_way_of_writing_a_quarter_turn_about_z_is_the_same() {
        let want = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert!(close(&quat([h, 0.0, 0.0, h]).expect("unit"), &want));
        assert!(close(
            &axis_angle([0.0, 0.0, 2.0], std::f64::consts::FRAC_PI_2).expect("axis"),
            &want
        ));
        assert!(close(
            &xy_axes([0.0, 1.0, 0.0], [-1.0, 0.5, 0.0]).expect("axes"),
            &want
        ));
        assert!(close(
            &euler([0.0, 0.0, std::f64::consts::FRAC_PI_2], *b"xyz"),
            &want
        ));
    }

    #[test]
    fn urdf_rpy_is_mujoco_xyz_extrinsic_and_round_trips() {
        let a = [0.3, -0.7, 1.1];
        let m = euler(a, *b"XYZ");
        assert!(close(&m, &crate::pose::rpy_matrix(a)));
        let back = rpy(&m);
        assert!(
            a.iter().zip(back).all(|(x, y)| (x - y).abs() < 1e-12),
            "{back:?}"
        );
        // Intrinsic x-y-z is extrinsic Z-Y-X in reverse order.
        assert!(close(
            &euler(a, *b"xyz"),
            &euler([a[2], a[1], a[0]], *b"ZYX")
        ));
    }

    #[test]
    fn zaxis_and_fromto_point_z_where_asked() {
        for z in [[1.0, 2.0, -0.5], [0.0, 0.0, -3.0], [0.0, 0.0, 1.0]] {
            let m = z_axis(z).expect("a direction");
            let n = norm(z);
            let col = [m[0][2], m[1][2], m[2][2]];
            assert!((0..3).all(|i| (col[i] - z[i] / n).abs() < 1e-12), "{col:?}");
        }
        let (f, half) = from_to([0.0, 0.0, 0.0], [0.0, 0.2, 0.0]).expect("apart");
        assert!((half - 0.1).abs() < 1e-15 && (f.pos[1] - 0.1).abs() < 1e-15);
        assert!(from_to([1.0; 3], [1.0; 3]).is_none());
    }
}
