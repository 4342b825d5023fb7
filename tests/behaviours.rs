//! The training behaviour as a seam: `behaviour.name` chooses one of the
//! declared behaviours (an unknown name is refused, listing them); the
//! `design` behaviour drives a simulated trial with commands drawn only from
//! its design (each magnitude one of the design's fractions of the largest
//! command), turning round as the paper's does; the same seed gives the same
//! commands; and the paper's is the default.

mod common;

use testbed::behaviour::{design, registry};
use testbed::experiment;
use testbed::scenario::Scenario;
use testbed::trial::{TrialConfig, TrialRunner};

/// The commands of the first `seconds` of a trial of `behaviour` from `seed`.
fn commands(behaviour: &str, seed: u64, seconds: f64) -> Vec<f64> {
    let (scenario, models) = common::paper_reference();
    let mut config = experiment::behaviour_for(scenario, models);
    config.name = registry::resolve(behaviour).expect("declared").name;
    let trial = TrialConfig {
        duration_s: seconds,
        seed,
        behaviour: config,
        judge_every_s: 5.0,
        blank: Default::default(),
        changes: Vec::new(),
    };
    let mut runner = TrialRunner::new(&scenario.description, scenario.sim, trial).expect("a trial");
    let frames = runner.record_until(|_| false).expect("recorded");
    frames.iter().map(|f| f.command).collect()
}

#[test]
fn the_design_behaviour_walks_only_its_designs_commands_and_turns_round() {
    let (scenario, _) = common::paper_reference();
    let max = scenario.max_command();
    let degree = scenario.learner.action_degree + scenario.behaviour_design_extra_degree;
    let support = design::one_phase(&design::i_optimal(degree));
    let seen = commands("design", 100, 120.0);
    for c in &seen {
        assert!(
            support
                .iter()
                .any(|(f, _)| (c.abs() - f * max).abs() < 1e-9),
            "command {c} is not one of the design's {support:?} x {max}"
        );
    }
    // Both ways, and every magnitude of the design at least once.
    assert!(
        seen.iter().any(|c| *c > 0.0) && seen.iter().any(|c| *c < 0.0),
        "turned round"
    );
    for (f, _) in &support {
        assert!(
            seen.iter().any(|c| (c.abs() - f * max).abs() < 1e-9),
            "{f} x {max} walked"
        );
    }
    assert!(
        seen == commands("design", 100, 120.0),
        "the same seed, the same commands"
    );
    assert!(
        seen != commands("design", 101, 120.0),
        "another seed, others"
    );
}

#[test]
fn the_paper_behaviour_is_the_default_and_draws_from_the_whole_range() {
    let scenario = Scenario::paper().expect("scenario");
    assert_eq!(scenario.behaviour_name, "paper");
    let seen = commands("paper", 100, 30.0);
    let mut distinct: Vec<u64> = seen.iter().map(|c| c.to_bits()).collect();
    distinct.sort_unstable();
    distinct.dedup();
    // Ten 3 s holds at least, each a fresh uniform draw.
    assert!(distinct.len() >= 10, "{} distinct commands", distinct.len());
}

#[test]
fn behaviour_name_takes_a_declared_behaviour_and_refuses_others() {
    let mut scenario = Scenario::paper().expect("scenario");
    scenario.set("behaviour.name=design").expect("declared");
    assert_eq!(scenario.behaviour_name, "design");
    let e = scenario
        .set("behaviour.name=wander")
        .expect_err("refused")
        .to_string();
    for name in registry::names() {
        assert!(e.contains(name), "{e}");
    }
    assert!(e.contains("--behaviour list"), "{e}");
    let listed = registry::describe();
    assert!(
        listed.lines().count() == registry::BEHAVIOURS.len() && listed.contains("(the default)")
    );
}
