//! The one-sided learning modes of sections IV and V.

mod common;

use scasm::{CalibrationLearner, Event, Mode, Polynomial, Scasm, ScasmConfig};

/// The made-up truth as a given action model: the rate of change of distance,
/// which is minus the forward speed `common::true_velocity`.
fn true_action() -> Polynomial {
    let s = 300.0_f64;
    Polynomial::new(&[0.0, -300.0 / s, -40.0 / (s * s), 30.0 / (s * s * s)]).expect("poly")
}

#[test]
fn sensor_from_a_given_action_model_recovers_distance_up_to_shift() {
    let mut l =
        Scasm::new(Default::default(), Mode::SensorFromAction(true_action())).expect("mode");
    common::feed(&mut l, &common::events(0, 3000));
    let s = l.sensor_model().expect("learned");
    // x_a = distance - 2400 (start), so S(obs) + 2400 should be the distance.
    for d in [1400.0, 2000.0, 2600.0, 3200.0] {
        let est = s.eval(76_800.0 / d) + 2400.0;
        assert!((est - d).abs() < 60.0, "at {d} mm: {est}");
    }
}

#[test]
fn action_from_a_given_sensor_model_recovers_velocity() {
    // An exact given sensor: the reading is turned into a distance (76800 / obs,
    // noise included) and S is the identity. No forgetting, so every command of
    // the 150 s counts.
    let params = ScasmConfig {
        gamma: 1.0,
        ..Default::default()
    }
    .validate()
    .expect("cfg");
    let mut l = Scasm::new(params, Mode::ActionFromSensor(Polynomial::identity())).expect("mode");
    for e in common::events(0, 3000) {
        let e = match e {
            Event::Reading { t_s, obs_px } => Event::Reading {
                t_s,
                obs_px: 76_800.0 / obs_px,
            },
            command => command,
        };
        l.handle(e).expect("valid");
    }
    let a = l.action_model().expect("learned");
    for c in [-250.0, -150.0, 0.0, 100.0, 250.0] {
        let v = -a.eval(c); // distance falls when walking forwards
        let truth = common::true_velocity(c);
        assert!((v - truth).abs() < 3.0, "at {c}: {v} vs {truth}");
    }
}

#[test]
fn sensor_from_a_constant_action_is_an_affine_image_of_time() {
    let mut l = Scasm::new(Default::default(), Mode::SensorFromConstantAction).expect("mode");
    // Walk forwards at a constant command for 10 s from 3.6 m: distance = 3600 - v t.
    let v = common::true_velocity(200.0);
    for k in 0..200 {
        let t_s = f64::from(k) * 0.05;
        l.handle(Event::Command {
            t_s,
            dt_s: 0.05,
            command: 200.0,
        })
        .expect("valid");
        let d = 3600.0 - v * (t_s + 0.05);
        l.handle(Event::Reading {
            t_s: t_s + 0.05,
            obs_px: 76_800.0 / d,
        })
        .expect("valid");
    }
    let s = l.sensor_model().expect("learned");
    // S(obs) is "seconds of this walk": t = (3600 - d) / v.
    // Within 1.5 % of the 10 s walk: a cubic in obs cannot follow 1/obs exactly.
    for d in [1600.0, 2200.0, 3000.0, 3500.0] {
        let t = (3600.0 - d) / v;
        let err = (s.eval(76_800.0 / d) - t).abs();
        assert!(err < 0.15, "at {d} mm: {err} s");
    }
}

/// Error (mm) of `S(obs) + 2400` against the distance over the test range.
fn distance_rmse(s: &Polynomial) -> f64 {
    let ds: Vec<f64> = (0..=12).map(|i| 1200.0 + 200.0 * f64::from(i)).collect();
    let sq: f64 = ds
        .iter()
        .map(|&d| (s.eval(76_800.0 / d) + 2400.0 - d).powi(2))
        .sum();
    (sq / ds.len() as f64).sqrt()
}

#[test]
fn averaging_readings_shrinks_the_errors_in_variables_bias() {
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    // Readings with 2 px of Gaussian noise: regressing location on them flattens
    // the fitted curve where a pixel spans most distance (far away).
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let noise = Normal::new(0.0, 2.0).expect("normal");
    let events: Vec<Event> = common::events(0, 12_000)
        .into_iter()
        .map(|e| match e {
            Event::Reading { t_s, obs_px } => Event::Reading {
                t_s,
                obs_px: obs_px + noise.sample(&mut rng),
            },
            other => other,
        })
        .collect();
    let error_with = |sensor_window| {
        let config = ScasmConfig {
            sensor_window,
            gamma: 1.0,
            ..Default::default()
        };
        let mut l = Scasm::new(
            config.validate().expect("valid"),
            Mode::SensorFromAction(true_action()),
        )
        .expect("mode");
        common::feed(&mut l, &events);
        distance_rmse(&l.sensor_model().expect("learned"))
    };
    let (one, five, twenty) = (error_with(1), error_with(5), error_with(20));
    assert!(five < 0.7 * one, "window 5: {five:.1} mm vs 1: {one:.1} mm");
    assert!(
        twenty < five,
        "window 20: {twenty:.1} mm vs 5: {five:.1} mm"
    );
}
