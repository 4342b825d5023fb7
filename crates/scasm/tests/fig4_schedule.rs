//! Pins the schedule of the paper's Fig. 4 on a small hand-worked example: no
//! action learning until a reading after `t_start`; dead reckoning with the
//! identity A0 for commands starting before `2 t_start` and with the learned A
//! from then on; and, at each reading after `t_start`, x_s from the sensor model
//! as it was before this reading, A updated from x_s, x_a pulled by beta, and
//! only then S updated with the pulled x_a.
//!
//! The example is small enough to follow by hand: straight-line models (degree
//! 1), no forgetting, every reading its own point, `t_start = 1.5 s`, frames of
//! 0.25 s, and a pull of one half, with readings falling exactly on `t_start`
//! and commands starting exactly on `2 t_start`. An oracle written straight
//! from the paper's pseudo-code (with batch line fits) must agree with the
//! learner after every event; targeted tests name each rule. Changing any of
//! the schedule's comparisons (`>` for `>=`, `<` for `<=`, the factor 2), or
//! updating S before x_s is read from it, or S before the pull, makes at least
//! one of them fail. (Updating A and pulling x_a commute, since A learns from
//! x_s alone, so their order cannot be observed.)

use scasm::{CalibrationLearner, Event, Mode, Polynomial, Scasm, ScasmConfig};

const T_START_S: f64 = 1.5;
const DT_S: f64 = 0.25;
const BETA: f64 = 0.5;

fn learner() -> Scasm {
    let params = ScasmConfig {
        gamma: 1.0,
        beta: BETA,
        t_start_s: T_START_S,
        sensor_degree: 1,
        action_degree: 1,
        command_scale: 1.0,
        sensor_window: 1,
        // The paper's Eq. 5: least squares on the location itself.
        action_highpass_s: 0.0,
        action_robust: 0.0,
        ..Default::default()
    }
    .validate()
    .expect("valid");
    Scasm::new(params, Mode::Simultaneous).expect("learner")
}

/// Frame `k` (from 0): the command in force over `[k dt, (k+1) dt)` and the
/// reading taken at its end. The robot's true velocity is `0.8 c + 20` and the
/// reading is an affine image of its location, so A0 = identity is visibly
/// wrong and every model is learnable.
fn frame(k: usize) -> (f64, f64) {
    const COMMANDS: [f64; 8] = [100.0, -60.0, 160.0, 40.0, -120.0, 200.0, -20.0, 80.0];
    let command = COMMANDS[k % COMMANDS.len()];
    let x: f64 = (0..=k)
        .map(|j| (0.8 * COMMANDS[j % COMMANDS.len()] + 20.0) * DT_S)
        .sum();
    (command, 50.0 + 0.1 * x)
}

fn command_event(k: usize) -> Event {
    Event::Command {
        t_s: k as f64 * DT_S,
        dt_s: DT_S,
        command: frame(k).0,
    }
}

fn reading_event(k: usize) -> Event {
    Event::Reading {
        t_s: (k + 1) as f64 * DT_S,
        obs_px: frame(k).1,
    }
}

/// The least-squares line through `(v, y)` points with an intercept, and any
/// number of regressors, by the normal equations (tiny and well scaled here).
fn batch_fit(rows: &[(Vec<f64>, f64)]) -> Option<Vec<f64>> {
    let p = rows.first()?.0.len() + 1;
    if rows.len() < p {
        return None;
    }
    let mut m = vec![vec![0.0; p + 1]; p];
    for (v, y) in rows {
        let z: Vec<f64> = std::iter::once(1.0).chain(v.iter().copied()).collect();
        for i in 0..p {
            for j in 0..p {
                m[i][j] += z[i] * z[j];
            }
            m[i][p] += z[i] * y;
        }
    }
    // Gauss-Jordan with partial pivoting.
    for c in 0..p {
        let piv = (c..p).max_by(|&a, &b| m[a][c].abs().total_cmp(&m[b][c].abs()))?;
        if m[piv][c].abs() < 1e-9 * (1.0 + m[c][c].abs()) {
            return None;
        }
        m.swap(c, piv);
        for r in 0..p {
            if r != c {
                let f = m[r][c] / m[c][c];
                for k in c..=p {
                    m[r][k] -= f * m[c][k];
                }
            }
        }
    }
    Some((0..p).map(|i| m[i][p] / m[i][i]).collect())
}

/// The paper's Fig. 4, written out as it reads.
#[derive(Debug, Default)]
struct Oracle {
    t_s: f64,
    x_a: f64,
    x_s: Option<f64>,
    /// `V_0 = t` and `V_1 = integral of C`.
    v: [f64; 2],
    sensor_points: Vec<(Vec<f64>, f64)>,
    action_points: Vec<(Vec<f64>, f64)>,
}

impl Oracle {
    fn sensor(&self) -> Option<Polynomial> {
        let b = batch_fit(&self.sensor_points)?;
        Polynomial::new(&b)
    }

    /// A's coefficients `[a_0, a_1]` (the fit's intercept is `x(0)`).
    fn action(&self) -> Option<Polynomial> {
        let b = batch_fit(&self.action_points)?;
        Polynomial::new(&b[1..])
    }

    fn handle(&mut self, e: Event) {
        match e {
            Event::Command { t_s, dt_s, command } => {
                let a = if t_s < 2.0 * T_START_S {
                    Polynomial::identity()
                } else {
                    self.action().unwrap_or_else(Polynomial::identity)
                };
                self.x_a += a.eval(command) * dt_s;
                self.v[0] += dt_s;
                self.v[1] += command * dt_s;
                self.t_s = t_s + dt_s;
            }
            Event::Reading { t_s, obs_px } => {
                if t_s > T_START_S {
                    if let Some(s) = self.sensor() {
                        let x_s = s.eval(obs_px);
                        self.x_s = Some(x_s);
                        self.action_points.push((self.v.to_vec(), x_s));
                        self.x_a = (1.0 - BETA) * self.x_a + BETA * x_s;
                    }
                }
                self.sensor_points.push((vec![obs_px], self.x_a));
            }
        }
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-7 * (1.0 + a.abs().max(b.abs()))
}

fn same_model(a: Option<Polynomial>, b: Option<Polynomial>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => [-150.0, 0.0, 75.0, 250.0]
            .iter()
            .all(|&x| close(a.eval(x), b.eval(x))),
        _ => false,
    }
}

/// Feeds frames `0..frames`, calling `check` after every event.
fn run(frames: usize, mut check: impl FnMut(&Event, &Scasm, &Scasm)) {
    let mut l = learner();
    for k in 0..frames {
        for e in [command_event(k), reading_event(k)] {
            let before = l.clone();
            l.handle(e).expect("valid event");
            check(&e, &before, &l);
        }
    }
}

#[test]
fn the_learner_follows_the_papers_pseudo_code_event_by_event() {
    let mut oracle = Oracle::default();
    run(32, |e, _, l| {
        oracle.handle(*e);
        let t = oracle.t_s;
        assert!(close(l.x_a().expect("x_a"), oracle.x_a), "x_a at {t} s");
        assert_eq!(l.x_s().is_some(), oracle.x_s.is_some(), "x_s at {t} s");
        if let (Some(a), Some(b)) = (l.x_s(), oracle.x_s) {
            assert!(close(a, b), "x_s at {t} s: {a} vs {b}");
        }
        assert!(same_model(l.sensor_model(), oracle.sensor()), "S at {t} s");
        assert!(same_model(l.action_model(), oracle.action()), "A at {t} s");
    });
}

#[test]
fn no_action_learning_until_a_reading_after_t_start() {
    run(32, |e, before, after| {
        if let Event::Reading { t_s, .. } = *e {
            let learned = after.action_model() != before.action_model()
                || after.action_start() != before.action_start();
            if t_s <= T_START_S {
                // Including the reading at exactly t_start (frame 5).
                assert!(after.action_model().is_none(), "A exists at {t_s} s");
                assert!(after.x_s().is_none(), "x_s at {t_s} s");
                assert!(!learned, "A learned from the reading at {t_s} s");
            } else if t_s >= T_START_S + 3.0 * DT_S {
                // A line with an intercept x(0) needs three points.
                assert!(learned, "A did not learn from the reading at {t_s} s");
            }
        }
    });
}

#[test]
fn dead_reckoning_uses_a0_before_2_t_start_and_the_learned_a_from_it() {
    let mut used_learned = 0;
    run(32, |e, before, after| {
        if let Event::Command { t_s, dt_s, command } = *e {
            let step = after.x_a().expect("x_a") - before.x_a().expect("x_a");
            let expected = if t_s < 2.0 * T_START_S {
                command * dt_s
            } else {
                used_learned += 1;
                let a = before.action_model().expect("A is learned by 2 t_start");
                a.eval(command) * dt_s
            };
            assert!(
                close(step, expected),
                "the command at {t_s} s moved x_a by {step}, expected {expected}"
            );
            // The learned A here is visibly not the identity, so the two
            // branches cannot be confused.
            if let Some(a) = before.action_model().filter(|_| t_s < 2.0 * T_START_S) {
                assert!((a.eval(command) - command).abs() > 1e-3 * command.abs().max(1.0));
            }
        }
    });
    // The command starting exactly at 2 t_start (frame 12) and all after it.
    assert_eq!(used_learned, 20);
}

#[test]
fn a_reading_after_t_start_uses_the_old_s_then_updates_a_pulls_x_a_and_updates_s() {
    let mut checked = 0;
    let mut sensor_points: Vec<(Vec<f64>, f64)> = Vec::new();
    run(32, |e, before, after| {
        let Event::Reading { t_s, obs_px } = *e else {
            return;
        };
        let x_a_before = before.x_a().expect("x_a");
        if t_s > T_START_S {
            if let Some(s_before) = before.sensor_model() {
                // x_s comes from S as it was before this reading.
                let x_s = s_before.eval(obs_px);
                assert!(close(after.x_s().expect("x_s"), x_s), "x_s at {t_s} s");
                // x_a is pulled a fraction beta towards it.
                let pulled = (1.0 - BETA) * x_a_before + BETA * x_s;
                assert!(close(after.x_a().expect("x_a"), pulled), "pull at {t_s} s");
                // S then learns from the pulled x_a, not the one before the pull.
                sensor_points.push((vec![obs_px], pulled));
                let s = batch_fit(&sensor_points).expect("S");
                let expected = Polynomial::new(&s);
                assert!(same_model(after.sensor_model(), expected), "S at {t_s} s");
                assert!((pulled - x_a_before).abs() > 1e-6, "the pull moved x_a");
                checked += 1;
                return;
            }
        }
        assert!(
            close(after.x_a().expect("x_a"), x_a_before),
            "no pull at {t_s} s"
        );
        sensor_points.push((vec![obs_px], x_a_before));
    });
    assert_eq!(checked, 26, "readings after t_start, from frame 6 on");
}
