//! Every shipped robot's true action model, measured by the paper's stopwatch
//! protocol, is what calibration needs to find: monotone in the command and
//! nonlinear enough that the identity model A0 is wrong (its error, after its
//! best scale, 4-12 % of the velocity range, as the paper's robot), with a
//! shape a quartic follows far better than a line.

use scasm::Polynomial;
use testbed::scenario::Scenario;
use testbed::{measure, metrics};

fn check(robot: &str) {
    let scenario = Scenario::from_settings(None, None, &[format!("robot.file={robot}")])
        .expect("a shipped robot");
    let commands = scenario.scale().paper_commands();
    let measured = measure::measure_action(
        &scenario.description,
        scenario.sim,
        &scenario.stopwatch(),
        &commands,
    )
    .expect("measured");
    assert!(measured.iter().all(|m| m.upright), "{robot} fell");
    let points: Vec<(f64, f64)> = measured
        .iter()
        .map(|m| (m.command, m.velocity_mm_s))
        .collect();
    assert!(
        points.windows(2).all(|w| w[1].1 > w[0].1),
        "{robot}: not monotone: {points:?}"
    );
    let range = points.last().expect("points").1 - points[0].1;
    let a0 = metrics::action_error(&Polynomial::identity(), &points).rmse / range;
    assert!(
        (0.04..=0.12).contains(&a0),
        "{robot}: A0's error is {:.1} % of the range",
        100.0 * a0
    );
    let line = metrics::best_polynomial_rmse(&points, 1).expect("line");
    let quartic = metrics::best_polynomial_rmse(&points, 4).expect("quartic");
    assert!(
        quartic < line / 3.0,
        "{robot}: quartic {quartic:.1} mm/s, line {line:.1} mm/s"
    );
}

#[test]
fn the_ers7s_response_is_monotone_and_nonlinear() {
    check("ers7");
}

#[test]
fn the_trotters_response_is_monotone_and_nonlinear() {
    check("trotter");
}
