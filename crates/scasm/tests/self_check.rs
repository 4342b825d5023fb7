//! The SCASM learner's check on itself: in a clean world it ends with the
//! coupling's own models; when a stretch of the trial turns its action model
//! back on itself (the robot held in place while it is commanded to walk), it
//! notices, and reports its last good models, nearer the truth, until its
//! own pass again.

mod common;

use scasm::self_check::{TURN_TOLERANCE, turn_back};
use scasm::{CalibrationLearner, Event, Mode, Scasm, ScasmConfig, SelfCheck};

const CHECK: SelfCheck = SelfCheck { good_after_s: 10.0 };

/// 150 s of the common world's robot, held in place (its feet slipping) from
/// `held_s.0` to `held_s.1` whatever the command.
fn events_held(held_s: (f64, f64)) -> Vec<Event> {
    let dt = common::DT_S;
    let (mut x, mut dir, mut out) = (2400.0_f64, 1.0_f64, Vec::new());
    let mut lcg: u64 = 4242;
    let mut command = 0.0;
    for k in 0..3000 {
        let t_s = f64::from(k) * dt;
        if k % 60 == 0 {
            command = dir * common::uniform(&mut lcg) * 300.0;
        }
        if !(held_s.0..held_s.1).contains(&t_s) {
            x -= common::true_velocity(command) * dt;
        }
        let obs_px = 76_800.0 / x + (common::uniform(&mut lcg) - 0.5) * 2.0;
        if (dir > 0.0 && x < 1200.0) || (dir < 0.0 && x > 3600.0) {
            dir = -dir;
        }
        common::push_frame(&mut out, t_s, command, obs_px);
    }
    out
}

/// The learner unchecked and checked, at the defaults but for the action
/// prior: the prior is a defence of its own (it keeps many a hold from
/// turning A back at all), and these tests are of the check's.
fn learners() -> (Scasm, Scasm) {
    let params = ScasmConfig {
        action_prior: 0.0,
        ..ScasmConfig::default()
    }
    .validate()
    .expect("the defaults");
    (
        Scasm::new(params, Mode::Simultaneous).expect("a learner"),
        Scasm::with_self_check(params, Mode::Simultaneous, CHECK).expect("a learner"),
    )
}

#[test]
fn in_a_clean_world_it_ends_with_the_couplings_own_models() {
    let (mut plain, mut checked) = learners();
    common::feed(&mut plain, &events_held((0.0, 0.0)));
    common::feed(&mut checked, &events_held((0.0, 0.0)));
    // Its models may fail for a moment as the commands reach new ground;
    // once they pass, they are reported as they are.
    assert_eq!(checked.falling_back(), Some(false));
    assert_eq!(plain.falling_back(), None, "no check, no answer");
    assert_eq!(plain.action_model(), checked.action_model());
    assert_eq!(plain.sensor_model(), checked.sensor_model());
    assert_eq!(plain.x_a(), checked.x_a(), "the coupling runs on unchanged");
}

#[test]
fn a_robot_held_in_place_is_noticed_and_the_last_good_models_are_reported() {
    // Held for 15 s (its feet slipping) at eight moments of the trial, each
    // once the check has run for `good_after_s` and more (it starts at
    // `2 t_start`), and ending by the trial's end at 150 s.
    let checked_from_s = 2.0 * ScasmConfig::default().t_start_s + CHECK.good_after_s;
    let holds =
        [10.0, 20.0, 30.0, 40.0, 45.0, 50.0, 55.0, 60.0].map(|after| checked_from_s + after);
    assert!(
        holds[7] + 15.0 <= 150.0,
        "the defaults leave no room for the holds"
    );
    let (mut much_better, mut noticed) = (0, 0);
    for from_s in holds {
        let events = events_held((from_s, from_s + 15.0));
        let (mut plain, mut checked) = learners();
        common::feed(&mut plain, &events);
        common::feed(&mut checked, &events);
        let e_plain = common::action_error(&plain.action_model().expect("a model"));
        let e_checked = common::action_error(&checked.action_model().expect("a model"));
        eprintln!(
            "held from {from_s} s: unchecked {e_plain:.1} mm/s, checked {e_checked:.1} mm/s, \
             {} fallbacks",
            checked.fallbacks()
        );
        // A model the stretch turned back on itself, to the end, is noticed.
        let a_plain = plain.action_model().expect("a model");
        if turn_back(&a_plain, -300.0, 300.0) > TURN_TOLERANCE {
            assert!(
                checked.fallbacks() >= 1,
                "held from {from_s} s: not noticed"
            );
        }
        if checked.fallbacks() >= 1 {
            noticed += 1;
        }
        assert!(
            e_checked <= e_plain,
            "held from {from_s} s: {e_checked} > {e_plain}"
        );
        if checked.falling_back() == Some(true) {
            let (a, s) = (
                checked.action_model().expect("a model"),
                checked.sensor_model().expect("a model"),
            );
            assert!(turn_back(&a, -300.0, 300.0) <= TURN_TOLERANCE);
            assert!(turn_back(&s, 21.3, 64.0) <= TURN_TOLERANCE);
        }
        if e_checked < 0.5 * e_plain {
            much_better += 1;
        }
    }
    assert!(
        noticed >= holds.len() / 2 && much_better >= holds.len() / 2,
        "noticed {noticed}, much better {much_better}, of {}",
        holds.len()
    );
}

#[test]
fn a_bad_setting_is_refused() {
    let params = ScasmConfig::default().validate().expect("the defaults");
    for bad in [f64::NAN, -1.0, f64::INFINITY] {
        let check = SelfCheck { good_after_s: bad };
        assert!(Scasm::with_self_check(params, Mode::Simultaneous, check).is_err());
    }
}
