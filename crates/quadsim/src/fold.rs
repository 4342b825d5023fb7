//! Mass that cannot be a body of its own, folded into the link it is rigidly
//! fixed to. Published URDFs give sensors, frames and covers a mass whose
//! inertia no rigid body has:
//! - a point mass, every moment 0 (HyQ's `trunk_imu`: 18 g);
//! - a singular tensor: ANYmal C's `hatch` (142 g) has every entry 0.001,
//!   moments (0.003, 0, 0), and the simulator, which inverts each body's
//!   inertia, blew up with it; the Go1's, HyQ's, B1's and ANYmal B's dummy
//!   roots (1e-6 kg, every entry 1e-6) are the same.
//!
//! Riding on a body, such mass is physical: a link rigidly fixed to another
//! is one body with it. So each one is added to the link across its fixed
//! joint (mass, centre of mass, and inertia by the parallel-axis theorem),
//! and left as a massless frame: to its parent if its own joint is fixed,
//! otherwise (the root, or a link that moves) to its first child fixed to it
//! whose own inertia is a body's. Mass with no such link stays, for the
//! description's check to refuse. A URDF whose every inertia is a body's is
//! returned as it is, to the bit.

use urdf_rs::{Inertia, JointType, Robot};

/// A 3 x 3 matrix, row-major.
use crate::pose::{Rotation as Matrix, compose};

/// The smallest principal moment a body's inertia may have, as a fraction of
/// its largest: the simulator inverts every body's inertia in single
/// precision, and a tensor nearer singular than this is not a body's in any
/// URDF seen (a thin rod's is about 1e-3).
pub const MIN_MOMENT_RATIO: f64 = 1e-6;

/// The principal moments of inertia (the symmetric tensor's eigenvalues),
/// smallest first.
pub fn principal_moments(i: &Inertia) -> [f64; 3] {
    let (a, b, c) = (i.ixx, i.iyy, i.izz);
    let (d, e, f) = (i.ixy, i.ixz, i.iyz);
    let off = d * d + e * e + f * f;
    let mut m = if off == 0.0 {
        [a, b, c]
    } else {
        // The closed form for a symmetric 3 x 3 matrix (Smith, 1961).
        let q = (a + b + c) / 3.0;
        let p = (((a - q).powi(2) + (b - q).powi(2) + (c - q).powi(2) + 2.0 * off) / 6.0).sqrt();
        let (a, b, c) = ((a - q) / p, (b - q) / p, (c - q) / p);
        let (d, e, f) = (d / p, e / p, f / p);
        let det = a * (b * c - f * f) - d * (d * c - f * e) + e * (d * f - b * e);
        let phi = (det / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
        let largest = q + 2.0 * p * phi.cos();
        let smallest = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
        [smallest, 3.0 * q - largest - smallest, largest]
    };
    m.sort_by(f64::total_cmp);
    m
}

/// Whether `i` can be a rigid body's own inertia: finite, every principal
/// moment positive and the smallest more than [`MIN_MOMENT_RATIO`] of the
/// largest.
pub fn is_body_inertia(i: &Inertia) -> bool {
    let [small, _, large] = principal_moments(i);
    small.is_finite() && large.is_finite() && small > MIN_MOMENT_RATIO * large
}

/// Whether `link` has mass it cannot carry as a body of its own: a positive
/// mass, finite moments, and an inertia no body has. (Mass or moments that
/// are not finite, or a negative mass, stay for the description to refuse.)
fn must_fold(link: &urdf_rs::Link) -> bool {
    let i = &link.inertial.inertia;
    let m = link.inertial.mass.value;
    m.is_finite()
        && m > 0.0
        && [i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz]
            .iter()
            .all(|v| v.is_finite())
        && !is_body_inertia(i)
}

/// `urdf` with the mass of every link whose inertia no body has moved
/// across a fixed joint (see the module), repeatedly (so that mass fixed to
/// a massless frame reaches the body the frame rides on).
pub fn fold_degenerate_links(urdf: &Robot) -> Robot {
    let mut r = urdf.clone();
    // A fold moves mass one joint up the tree, or down into a link whose
    // inertia is a body's, which then never folds: it ends within n^2 folds.
    let n = r.links.len();
    for _ in 0..(n * n).max(1) {
        let Some((from, into, turn, shift)) = next_fold(&r) else {
            break;
        };
        fold(&mut r, from, into, &turn, shift);
    }
    r
}

/// The next fold: the first link that must fold and has somewhere to go, the
/// link it goes into, and the map of its frame into that link's
/// (`x -> turn x + shift`).
fn next_fold(r: &Robot) -> Option<(usize, usize, Matrix, [f64; 3])> {
    let index = |name: &str| r.links.iter().position(|l| l.name == name);
    r.links.iter().enumerate().find_map(|(from, link)| {
        if !must_fold(link) {
            return None;
        }
        let own = r.joints.iter().find(|j| j.child.link == link.name);
        if let Some(j) = own.filter(|j| matches!(j.joint_type, JointType::Fixed)) {
            let into = index(&j.parent.link)?;
            let turn = crate::pose::rpy_matrix(j.origin.rpy.0);
            return Some((from, into, turn, j.origin.xyz.0));
        }
        // The root or a moving link: into a child fixed to it that is a body.
        r.joints.iter().find_map(|j| {
            if !matches!(j.joint_type, JointType::Fixed) || j.parent.link != link.name {
                return None;
            }
            let into = index(&j.child.link)?;
            let body = &r.links[into].inertial;
            if !(body.mass.value > 0.0 && is_body_inertia(&body.inertia)) {
                return None;
            }
            // The inverse of the child's placement: x -> R^T (x - t).
            let placed = crate::pose::rpy_matrix(j.origin.rpy.0);
            let turn = [0, 1, 2].map(|a| [0, 1, 2].map(|b| placed[b][a]));
            let t = j.origin.xyz.0;
            let shift = [0, 1, 2].map(|a| -(0..3).map(|k| turn[a][k] * t[k]).sum::<f64>());
            Some((from, into, turn, shift))
        })
    })
}

/// Moves link `from`'s mass into link `into`, whose frame `from`'s maps into
/// by `x -> turn x + shift`.
fn fold(r: &mut Robot, from: usize, into: usize, turn: &Matrix, shift: [f64; 3]) {
    let gone = r.links[from].inertial.clone();
    let m = gone.mass.value;
    // Its centre, and its own inertia, in the frame of the link it goes into.
    let r0 = crate::pose::rpy_matrix(gone.origin.rpy.0);
    let c0 = gone.origin.xyz.0;
    let turned = [0, 1, 2].map(|k| turn[k][0] * c0[0] + turn[k][1] * c0[1] + turn[k][2] * c0[2]);
    let p = [0, 1, 2].map(|k| shift[k] + turned[k]);
    let own_gone = tensor(&gone.inertia);
    let point = own_gone.iter().flatten().all(|v| *v == 0.0);
    let gone_tensor = rotated(&compose(turn, &r0), &own_gone);
    let target = &mut r.links[into].inertial;
    let big_m = target.mass.value;
    let c = target.origin.xyz.0;
    // The target's inertia about its centre, in its link frame.
    let own = rotated(
        &crate::pose::rpy_matrix(target.origin.rpy.0),
        &tensor(&target.inertia),
    );
    let total = big_m + m;
    let at = [0, 1, 2].map(|k| (big_m * c[k] + m * p[k]) / total);
    let parallel = |mass: f64, from: [f64; 3]| -> Matrix {
        let d = [0, 1, 2].map(|k| from[k] - at[k]);
        let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        [0, 1, 2].map(|a| [0, 1, 2].map(|b| mass * (if a == b { dd } else { 0.0 } - d[a] * d[b])))
    };
    let (s1, s2) = (parallel(big_m, c), parallel(m, p));
    let i = [0, 1, 2].map(|a| {
        [0, 1, 2].map(|b| {
            let sum = own[a][b] + s1[a][b] + s2[a][b];
            // A point mass has no inertia of its own to add.
            if point { sum } else { sum + gone_tensor[a][b] }
        })
    });
    target.mass.value = total;
    target.origin = urdf_rs::Pose {
        xyz: urdf_rs::Vec3(at),
        rpy: urdf_rs::Vec3([0.0; 3]),
    };
    target.inertia = tensor_inertia(&i);
    let gone = &mut r.links[from].inertial;
    gone.mass.value = 0.0;
    gone.origin = urdf_rs::Pose::default();
    gone.inertia = Inertia::default();
}

fn tensor(i: &Inertia) -> Matrix {
    [
        [i.ixx, i.ixy, i.ixz],
        [i.ixy, i.iyy, i.iyz],
        [i.ixz, i.iyz, i.izz],
    ]
}

/// `R I R^T`.
fn rotated(r: &Matrix, i: &Matrix) -> Matrix {
    let ri = [0, 1, 2].map(|a| [0, 1, 2].map(|b| (0..3).map(|k| r[a][k] * i[k][b]).sum::<f64>()));
    [0, 1, 2].map(|a| [0, 1, 2].map(|b| (0..3).map(|k| ri[a][k] * r[b][k]).sum()))
}

/// A symmetric inertia tensor as URDF writes it.
pub(crate) fn tensor_inertia(i: &Matrix) -> Inertia {
    Inertia {
        ixx: i[0][0],
        ixy: i[0][1],
        ixz: i[0][2],
        iyy: i[1][1],
        iyz: i[1][2],
        izz: i[2][2],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const URDF: &str = r#"<robot name="r">
      <link name="body"><inertial><origin xyz="0.1 0 0" rpy="0 0 0"/><mass value="2"/>
        <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.03"/></inertial></link>
      <link name="frame"/>
      <link name="imu"><inertial><origin xyz="0 0 0.1"/><mass value="0.5"/>
        <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>
      <joint name="to_frame" type="fixed"><parent link="body"/><child link="frame"/>
        <origin xyz="0.2 0 0"/></joint>
      <joint name="to_imu" type="fixed"><parent link="frame"/><child link="imu"/>
        <origin xyz="0 0.3 0"/></joint>
    </robot>"#;

    #[test]
    fn a_point_mass_reaches_the_body_through_a_massless_frame_with_its_moments() {
        let urdf = urdf_rs::read_from_string(URDF).expect("parses");
        let folded = fold_degenerate_links(&urdf);
        let [body, frame, imu] = [0, 1, 2].map(|k| &folded.links[k].inertial);
        // Mass is kept: 2 + 0.5 on the body, none left on the frame or imu.
        assert_eq!(
            (body.mass.value, frame.mass.value, imu.mass.value),
            (2.5, 0.0, 0.0)
        );
        // The imu sits at (0.2, 0.3, 0.1) in the body's frame: the centre of
        // mass moves a fifth of the way there from (0.1, 0, 0).
        let c = body.origin.xyz.0;
        let want = [0.12, 0.06, 0.02];
        assert!((0..3).all(|k| (c[k] - want[k]).abs() < 1e-12), "{c:?}");
        // Moments about the new centre: the body's own plus both masses'
        // parallel-axis terms (d_body = (-0.02, -0.06, -0.02), d_imu = (0.08, 0.24, 0.08)).
        let i = &body.inertia;
        let (d1, d2) = ([-0.02, -0.06, -0.02], [0.08, 0.24, 0.08]);
        let term = |a: usize, b: usize| {
            let pa = |d: [f64; 3], m: f64| {
                let dd: f64 = d.iter().map(|v| v * v).sum();
                m * (if a == b { dd } else { 0.0 } - d[a] * d[b])
            };
            pa(d1, 2.0) + pa(d2, 0.5)
        };
        let close = |got: f64, want: f64| (got - want).abs() < 1e-12;
        assert!(close(i.ixx, 0.01 + term(0, 0)));
        assert!(close(i.iyy, 0.02 + term(1, 1)));
        assert!(close(i.izz, 0.03 + term(2, 2)));
        assert!(close(i.ixy, term(0, 1)) && close(i.ixz, term(0, 2)) && close(i.iyz, term(1, 2)));
    }

    #[test]
    fn a_urdf_without_point_masses_is_unchanged_and_a_moving_one_stays() {
        let plain = URDF.replace(
            r#"ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0""#,
            r#"ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4""#,
        );
        let urdf = urdf_rs::read_from_string(&plain).expect("parses");
        assert_eq!(
            format!("{:?}", fold_degenerate_links(&urdf)),
            format!("{urdf:?}")
        );
        let moving = URDF.replace(
            r#"name="to_imu" type="fixed""#,
            r#"name="to_imu" type="revolute""#,
        );
        let urdf = urdf_rs::read_from_string(&moving).expect("parses");
        assert_eq!(
            fold_degenerate_links(&urdf).links[2].inertial.mass.value,
            0.5
        );
    }

    /// A body and a cover fixed to it (turned a quarter about z) whose
    /// inertia is singular, every entry 0.001 (ANYmal C's `hatch`).
    fn with_cover(cover_joint: &str) -> String {
        format!(
            r#"<robot name="r">
      <link name="body"><inertial><origin xyz="0 0 0" rpy="0 0 0"/><mass value="2"/>
        <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.03"/></inertial></link>
      <link name="cover"><inertial><origin xyz="0 0 0"/><mass value="0.5"/>
        <inertia ixx="0.001" ixy="0.001" ixz="0.001" iyy="0.001" iyz="0.001" izz="0.001"/></inertial></link>
      <joint name="to_cover" type="{cover_joint}"><parent link="body"/><child link="cover"/>
        <origin xyz="0.5 0 0" rpy="0 0 1.5707963267948966"/><axis xyz="0 0 1"/></joint>
    </robot>"#
        )
    }

    #[test]
    fn principal_moments_are_the_tensors_eigenvalues() {
        let of = |t: [f64; 6]| {
            principal_moments(&Inertia {
                ixx: t[0],
                ixy: t[1],
                ixz: t[2],
                iyy: t[3],
                iyz: t[4],
                izz: t[5],
            })
        };
        let close = |a: [f64; 3], b: [f64; 3]| (0..3).all(|k| (a[k] - b[k]).abs() < 1e-15);
        assert_eq!(of([3.0, 0.0, 0.0, 1.0, 0.0, 2.0]), [1.0, 2.0, 3.0]);
        // Every entry 0.001: 0.003 along (1, 1, 1), nothing across it.
        assert!(close(of([1e-3; 6]), [0.0, 0.0, 3e-3]));
        // [[2, 1, 0], [1, 2, 0], [0, 0, 5]]: 1, 3 and 5.
        assert!(close(of([2.0, 1.0, 0.0, 2.0, 0.0, 5.0]), [1.0, 3.0, 5.0]));
        assert!(!is_body_inertia(&Inertia {
            ixx: 1e-3,
            ixy: 1e-3,
            ixz: 1e-3,
            iyy: 1e-3,
            iyz: 1e-3,
            izz: 1e-3,
        }));
    }

    #[test]
    fn a_singular_inertia_on_a_fixed_joint_is_folded_with_its_own_moments() {
        let urdf = urdf_rs::read_from_string(&with_cover("fixed")).expect("parses");
        let folded = fold_degenerate_links(&urdf);
        let [body, cover] = [0, 1].map(|k| &folded.links[k].inertial);
        assert_eq!((body.mass.value, cover.mass.value), (2.5, 0.0));
        let c = body.origin.xyz.0;
        assert!((c[0] - 0.1).abs() < 1e-12 && c[1].abs() < 1e-12 && c[2].abs() < 1e-12);
        // The cover's own tensor, 0.003 along (1, 1, 1), turned a quarter
        // about z: along (-1, 1, 1). Plus the two masses' parallel-axis
        // terms about x = 0.1 (0.4 m and 0.1 m along x: 0.5 * 0.16 + 2 * 0.01
        // about y and z).
        let i = &body.inertia;
        let close = |got: f64, want: f64| (got - want).abs() < 1e-12;
        assert!(close(i.ixx, 0.01 + 0.001), "{i:?}");
        assert!(close(i.iyy, 0.02 + 0.1 + 0.001), "{i:?}");
        assert!(close(i.izz, 0.03 + 0.1 + 0.001), "{i:?}");
        assert!(
            close(i.ixy, -0.001) && close(i.ixz, -0.001) && close(i.iyz, 0.001),
            "{i:?}"
        );
        assert!(is_body_inertia(i));
    }

    #[test]
    fn a_root_with_a_singular_inertia_goes_into_the_body_fixed_to_it() {
        // The Go1's and HyQ's dummy root: a little mass, every entry alike,
        // with the real body fixed to it.
        let text = with_cover("fixed").replace(
            r#"<parent link="body"/><child link="cover"/>"#,
            r#"<parent link="cover"/><child link="body"/>"#,
        );
        let urdf = urdf_rs::read_from_string(&text).expect("parses");
        let folded = fold_degenerate_links(&urdf);
        let [body, cover] = [0, 1].map(|k| &folded.links[k].inertial);
        assert_eq!((body.mass.value, cover.mass.value), (2.5, 0.0));
        // The root's centre, at its origin, is at (0, 0.5, 0) in the body's
        // frame (the body sits 0.5 m along x, turned a quarter about z).
        let c = body.origin.xyz.0;
        assert!(
            c[0].abs() < 1e-12 && (c[1] - 0.1).abs() < 1e-12 && c[2].abs() < 1e-12,
            "{c:?}"
        );
        assert!(is_body_inertia(&body.inertia));
    }

    #[test]
    fn a_singular_inertia_that_moves_with_nothing_fixed_to_it_stays() {
        let urdf = urdf_rs::read_from_string(&with_cover("revolute")).expect("parses");
        assert_eq!(
            fold_degenerate_links(&urdf).links[1].inertial.mass.value,
            0.5
        );
    }
}
