//! Point masses folded into the link they are fixed to. Published URDFs give
//! sensors and frames a mass with no inertia (HyQ's `trunk_imu`: 18 g, all
//! moments 0): a point mass, which is physical riding on a body but not as a
//! body of its own (the simulator would invert a zero inertia). Each one on a
//! fixed joint is added to its parent's inertial (mass, centre of mass, and
//! inertia by the parallel-axis theorem), and left as a massless frame. A
//! URDF without point masses is returned as it is, to the bit.

use urdf_rs::{Inertia, JointType, Robot};

/// A 3 x 3 matrix, row-major.
type Matrix = [[f64; 3]; 3];

/// Whether `link` is a point mass: positive mass, every moment of inertia 0.
fn is_point_mass(link: &urdf_rs::Link) -> bool {
    let i = &link.inertial.inertia;
    let m = link.inertial.mass.value;
    m.is_finite() && m > 0.0 && [i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz] == [0.0; 6]
}

/// `urdf` with every point mass on a fixed joint folded into its parent
/// (repeatedly, so a point mass fixed to a massless frame reaches the body
/// the frame rides on). A point mass that moves by a joint stays, for the
/// description's check to refuse.
pub fn fold_point_masses(urdf: &Robot) -> Robot {
    let mut r = urdf.clone();
    // Each pass folds at least one link into its parent, or stops: at most
    // one pass per link.
    for _ in 0..r.links.len() {
        let found = r.joints.iter().find_map(|j| {
            if !matches!(j.joint_type, JointType::Fixed) {
                return None;
            }
            let child = r.links.iter().position(|l| l.name == j.child.link)?;
            let parent = r.links.iter().position(|l| l.name == j.parent.link)?;
            is_point_mass(&r.links[child]).then_some((child, parent, j.origin.clone()))
        });
        let Some((child, parent, origin)) = found else {
            break;
        };
        let m = r.links[child].inertial.mass.value;
        // The point in the parent's frame (its own inertial frame's
        // orientation does not matter).
        let p = crate::description::place(&origin, r.links[child].inertial.origin.xyz.0);
        let into = &mut r.links[parent].inertial;
        let big_m = into.mass.value;
        let c = into.origin.xyz.0;
        // The parent's inertia about its centre, in its link frame.
        let turn = crate::description::rpy_matrix(into.origin.rpy.0);
        let own = rotated(&turn, &tensor(&into.inertia));
        let total = big_m + m;
        let at = [0, 1, 2].map(|k| (big_m * c[k] + m * p[k]) / total);
        let shift = |mass: f64, from: [f64; 3]| -> Matrix {
            let d = [0, 1, 2].map(|k| from[k] - at[k]);
            let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            [0, 1, 2]
                .map(|a| [0, 1, 2].map(|b| mass * (if a == b { dd } else { 0.0 } - d[a] * d[b])))
        };
        let (s1, s2) = (shift(big_m, c), shift(m, p));
        let i = [0, 1, 2].map(|a| [0, 1, 2].map(|b| own[a][b] + s1[a][b] + s2[a][b]));
        into.mass.value = total;
        into.origin = urdf_rs::Pose {
            xyz: urdf_rs::Vec3(at),
            rpy: urdf_rs::Vec3([0.0; 3]),
        };
        into.inertia = Inertia {
            ixx: i[0][0],
            ixy: i[0][1],
            ixz: i[0][2],
            iyy: i[1][1],
            iyz: i[1][2],
            izz: i[2][2],
        };
        let gone = &mut r.links[child].inertial;
        gone.mass.value = 0.0;
        gone.origin = urdf_rs::Pose::default();
    }
    r
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
        let folded = fold_point_masses(&urdf);
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
            format!("{:?}", fold_point_masses(&urdf)),
            format!("{urdf:?}")
        );
        let moving = URDF.replace(
            r#"name="to_imu" type="fixed""#,
            r#"name="to_imu" type="revolute""#,
        );
        let urdf = urdf_rs::read_from_string(&moving).expect("parses");
        assert_eq!(fold_point_masses(&urdf).links[2].inertial.mass.value, 0.5);
    }
}
