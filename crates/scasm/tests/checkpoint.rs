//! Checkpoint and resume: a learner serialised mid-run and restored ends
//! bit-identical to one never stopped.

mod common;

use scasm::{CalibrationLearner, Scasm};

#[test]
fn resumed_run_is_bit_identical() {
    let (first, second) = (common::events(0, 1400), common::events(1400, 3000));
    let mut straight = Scasm::default();
    common::feed(&mut straight, &first);
    let checkpoint = serde_json::to_string(&straight).expect("serialise");
    common::feed(&mut straight, &second);

    let mut resumed: Scasm = serde_json::from_str(&checkpoint).expect("deserialise");
    common::feed(&mut resumed, &second);

    let bits = |p: Option<scasm::Polynomial>| -> Vec<u64> {
        p.expect("model")
            .coeffs()
            .iter()
            .map(|c| c.to_bits())
            .collect()
    };
    assert_eq!(bits(straight.action_model()), bits(resumed.action_model()));
    assert_eq!(bits(straight.sensor_model()), bits(resumed.sensor_model()));
    assert_eq!(
        straight.x_a().map(f64::to_bits),
        resumed.x_a().map(f64::to_bits)
    );
    // The whole state, not just what is exposed.
    assert_eq!(
        serde_json::to_string(&straight).expect("serialise"),
        serde_json::to_string(&resumed).expect("serialise")
    );
}
