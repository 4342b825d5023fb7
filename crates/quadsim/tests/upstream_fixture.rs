//! The patched rapier3d (vendor/, see vendor/PATCH.md) against rapier3d
//! 0.36.1 as published: the robot's torso over 625 physics steps (standing,
//! walking forwards, walking backwards), recorded with the unpatched crate by
//! `tools/upstream-fixture` into `tests/fixtures/upstream_track.txt`, and
//! stepped here by the patched one: the same bits at every step. (The patch
//! sums the Coriolis mass matrix's terms in another order, which could part
//! the two by f32 rounding; over these 625 steps it does not. A change that
//! alters rounding on purpose would relax this to a stated tolerance; the
//! failure message gives the largest difference to state it from.) Any change
//! to what the step computes (a sign, a dropped term, a reordered constraint)
//! moves the torso by millimetres within a few steps.

include!("common/track.rs");

fn fixture() -> Vec<[f64; 7]> {
    let text = include_str!("fixtures/upstream_track.txt");
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let v: Vec<f64> = l.split(' ').map(|c| c.parse().expect("a number")).collect();
            v.try_into().expect("seven numbers a line")
        })
        .collect()
}

#[test]
fn the_patched_step_follows_upstreams_trajectory() {
    let upstream = fixture();
    let patched = torso_track();
    assert_eq!(upstream.len(), PHASES.iter().map(|p| p.1).sum::<usize>());
    assert_eq!(patched.len(), upstream.len());
    let (mut worst_position, mut worst_rotation, mut same_bits) = (0.0f64, 0.0f64, 0);
    for (p, u) in patched.iter().zip(&upstream) {
        let position = (0..3).map(|i| (p[i] - u[i]).abs()).fold(0.0, f64::max);
        let rotation = (3..7).map(|i| (p[i] - u[i]).abs()).fold(0.0, f64::max);
        worst_position = worst_position.max(position);
        worst_rotation = worst_rotation.max(rotation);
        same_bits += usize::from(p.map(f64::to_bits) == u.map(f64::to_bits));
    }
    assert_eq!(
        same_bits,
        upstream.len(),
        "steps with the same bits as upstream's; largest differences {worst_position:e} m and \
         {worst_rotation:e} (quaternion)"
    );
    // The walk moved the torso: the comparison is over motion, not rest.
    let travel = (upstream[424][0] - upstream[124][0]).abs();
    assert!(travel > 0.05, "walking at 300 for 1.2 s moved {travel} m");
}
