//! Analytic inverse kinematics of a three-joint leg (abduction about x, hip and
//! knee about y, two segments in the leg's plane, the hip anywhere from the
//! abduction joint, the leg's zero pose in any shape: a thigh hanging down or
//! pointing backwards, a knee straight or folded), and its forward kinematics
//! for checking.

/// A leg's geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LegGeometry {
    /// Hip to knee, m.
    pub thigh_m: f64,
    /// Knee to foot centre, m.
    pub shank_m: f64,
    /// The hip's sideways offset from the abduction axis, m (along the leg's
    /// own y axis; positive: left).
    pub hip_offset_m: f64,
    /// Which way the knee bends: `1.0` swings the foot backwards (the knee points
    /// forwards, like a dog's hind leg), `-1.0` the other way (like its elbow).
    pub knee_sign: f64,
    /// The hip joint's position from the abduction joint, forwards and up, m.
    pub hip_at_m: [f64; 2],
    /// The thigh's direction at the zero pose, from straight down, positive
    /// backwards, rad.
    pub thigh_zero_rad: f64,
    /// The shank's angle to the thigh's line at the zero pose, rad.
    pub knee_zero_rad: f64,
}

impl LegGeometry {
    /// A leg whose zero pose hangs straight down from a hip on the abduction
    /// axis, or `hip_offset_m` beside it.
    pub fn straight(thigh_m: f64, shank_m: f64, hip_offset_m: f64, knee_sign: f64) -> Self {
        Self {
            thigh_m,
            shank_m,
            hip_offset_m,
            knee_sign,
            hip_at_m: [0.0; 2],
            thigh_zero_rad: 0.0,
            knee_zero_rad: 0.0,
        }
    }
}

/// Joint angles of one leg, rad, in the URDF's conventions (right-handed rotations
/// about the joint axes: abduction about +x, hip and knee about +y, each from
/// the URDF's zero pose).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LegAngles {
    /// Abduction (roll).
    pub abduction: f64,
    /// Hip (pitch).
    pub hip: f64,
    /// Knee (pitch, relative to the thigh).
    pub knee: f64,
}

/// The foot's position relative to the abduction joint (body frame: x forwards,
/// y left, z up) for these angles.
pub fn forward(g: &LegGeometry, a: &LegAngles) -> [f64; 3] {
    // In the leg's plane (after abduction): rotation about y by q maps a vector
    // pointing down (0, 0, -l) to (-l sin q, 0, -l cos q).
    let [hip_forwards, hip_up] = g.hip_at_m;
    let (hip, knee) = (a.hip + g.thigh_zero_rad, a.knee + g.knee_zero_rad);
    let x = hip_forwards - g.thigh_m * hip.sin() - g.shank_m * (hip + knee).sin();
    let down = g.thigh_m * hip.cos() + g.shank_m * (hip + knee).cos() - hip_up;
    // Abduction rotates (0, d, -down) about x.
    let (s, c) = a.abduction.sin_cos();
    let d = g.hip_offset_m;
    [x, d * c + down * s, d * s - down * c]
}

/// The joint angles that put the foot at `p` relative to the abduction joint,
/// or `None` if it is out of reach.
pub fn inverse(g: &LegGeometry, p: [f64; 3]) -> Option<LegAngles> {
    let [x, y, z] = p;
    let d = g.hip_offset_m;
    // In the abduction plane, the foot is `down` below the hip, which is `d`
    // beside the axis: the foot's angle from straight down, less the hip's.
    let down = (y * y + z * z - d * d).sqrt();
    if down.is_nan() || down <= 0.0 {
        return None;
    }
    let abduction = y.atan2(-z) - d.atan2(down);
    // Planar two-link problem in the leg's plane, from the hip: reach
    // (x, -down) less the hip's place.
    let [hip_forwards, hip_up] = g.hip_at_m;
    let (x, down) = (x - hip_forwards, down + hip_up);
    let r2 = x * x + down * down;
    let (l1, l2) = (g.thigh_m, g.shank_m);
    let cos_knee = (r2 - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
    if !(-1.0..=1.0).contains(&cos_knee) {
        return None;
    }
    let knee = g.knee_sign * cos_knee.acos();
    // Angle of the hip-foot line from straight down, positive backwards.
    let line = (-x).atan2(down);
    let hip = line - (l2 * knee.sin()).atan2(l1 + l2 * knee.cos());
    // From the straight-down leg's angles to the zero pose's.
    Some(LegAngles {
        abduction,
        hip: hip - g.thigh_zero_rad,
        knee: knee - g.knee_zero_rad,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_then_forward_returns_the_target() {
        for knee_sign in [1.0, -1.0] {
            let g = LegGeometry {
                thigh_m: 0.07,
                shank_m: 0.07,
                hip_offset_m: 0.0,
                knee_sign,
                hip_at_m: [0.0; 2],
                thigh_zero_rad: 0.0,
                knee_zero_rad: 0.0,
            };
            for &p in &[
                [0.0, 0.0, -0.105],
                [0.04, 0.01, -0.1],
                [-0.045, -0.012, -0.09],
                [0.02, 0.0, -0.13],
            ] {
                let a = inverse(&g, p).expect("reachable");
                let q = forward(&g, &a);
                for i in 0..3 {
                    assert!((p[i] - q[i]).abs() < 1e-12, "{p:?} -> {a:?} -> {q:?}");
                }
                assert!(a.knee * knee_sign > 0.0, "knee bends the chosen way");
            }
        }
    }

    #[test]
    fn out_of_reach_is_none() {
        let g = LegGeometry {
            thigh_m: 0.07,
            shank_m: 0.07,
            hip_offset_m: 0.0,
            knee_sign: 1.0,
            hip_at_m: [0.0; 2],
            thigh_zero_rad: 0.0,
            knee_zero_rad: 0.0,
        };
        assert!(inverse(&g, [0.0, 0.0, -0.2]).is_none());
    }

    #[test]
    fn an_offset_hip_reaches_its_targets() {
        for (hip_offset_m, knee_sign) in [(0.08, 1.0), (-0.08, -1.0), (0.03, -1.0)] {
            let g = LegGeometry {
                thigh_m: 0.2,
                shank_m: 0.2,
                hip_offset_m,
                knee_sign,
                hip_at_m: [0.0; 2],
                thigh_zero_rad: 0.0,
                knee_zero_rad: 0.0,
            };
            for &p in &[
                [0.0, hip_offset_m, -0.3],
                [0.1, hip_offset_m + 0.02, -0.28],
                [-0.12, hip_offset_m - 0.03, -0.25],
            ] {
                let a = inverse(&g, p).expect("reachable");
                let q = forward(&g, &a);
                for i in 0..3 {
                    assert!((p[i] - q[i]).abs() < 1e-12, "{p:?} -> {a:?} -> {q:?}");
                }
            }
            // Standing straight below the hip needs no abduction.
            let a = inverse(&g, [0.0, hip_offset_m, -0.3]).expect("reachable");
            assert!(a.abduction.abs() < 1e-12, "{a:?}");
        }
    }

    #[test]
    fn a_leg_of_any_zero_pose_reaches_its_targets() {
        // A thigh pointing backwards and a shank folded forwards and down at
        // the zero pose, the hip ahead of and below the abduction joint.
        for knee_sign in [1.0, -1.0] {
            let g = LegGeometry {
                thigh_m: 0.25,
                shank_m: 0.284,
                hip_offset_m: 0.068,
                knee_sign,
                hip_at_m: [0.02, -0.01],
                thigh_zero_rad: std::f64::consts::FRAC_PI_2,
                knee_zero_rad: -2.978,
            };
            for &p in &[[0.0, 0.068, -0.4], [0.1, 0.09, -0.38], [-0.12, 0.04, -0.35]] {
                let a = inverse(&g, p).expect("reachable");
                let q = forward(&g, &a);
                for i in 0..3 {
                    assert!((p[i] - q[i]).abs() < 1e-12, "{p:?} -> {a:?} -> {q:?}");
                }
                // The knee bends the chosen way from the straight leg.
                assert!((a.knee + g.knee_zero_rad) * knee_sign > 0.0, "{a:?}");
            }
        }
    }
}
