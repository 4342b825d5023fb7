//! The learner protocol's conformance check: drives a program through every
//! path of the protocol, with no physics (the synthetic world's commands and
//! readings), and says of each rule whether the program kept it, quoting
//! what went wrong. `cargo run --release --example learner_check --
//! 'exec:COMMAND'` prints it.

use rand_distr::{Distribution, Normal};
use scasm::declaration::{Kind, Setting, Values};
use scasm::{CalibrationLearner, Event};

use crate::behaviour::{Behaviour, BehaviourConfig, Phase, TrainingBehaviour};
use crate::learners::exec::{ExecLearner, Program};
use crate::scenario::Scenario;
use crate::seeds::{self, Stream};
use crate::synthetic::{true_obs_px, true_velocity_mm_s};

/// One rule of the protocol and whether the program kept it.
#[derive(Debug, Clone, PartialEq)]
pub struct RuleCheck {
    /// The rule, in a few words.
    pub rule: &'static str,
    /// Whether it was kept.
    pub passed: bool,
    /// What was seen: on a failure, the first thing that went wrong.
    pub detail: String,
}

/// The frame interval of the check's trials, s (the testbed's camera's).
const FRAME_S: f64 = 0.05;

/// Checks program `spec` (`exec:COMMAND ARGS...`) against every rule, each
/// answer within `answer_timeout_s`. A rule whose start failed (the program
/// would not say hello) is not tried, and says so.
pub fn check(spec: &str, answer_timeout_s: f64) -> Vec<RuleCheck> {
    let mut out = Vec::new();
    let rule = |rule, result: Result<String, String>| {
        let passed = result.is_ok();
        let detail = result.unwrap_or_else(|e| e);
        RuleCheck {
            rule,
            passed,
            detail,
        }
    };
    let program = match Program::probe(spec) {
        Ok(p) => p,
        Err(e) => {
            out.push(rule("says a valid hello first, within 30 s", Err(e)));
            return out;
        }
    };
    out.push(rule(
        "says a valid hello first, within 30 s",
        Ok(format!(
            "`{}`, protocol 1, {} settings of its own",
            program.name(),
            program.settings().len()
        )),
    ));
    let defaults: Vec<(String, f64)> = program
        .settings()
        .iter()
        .map(|s| (s.key.clone(), s.default))
        .collect();
    let run = |own: &[(String, f64)], frames: usize, every_reading: usize| {
        trial(&program, own, frames, every_reading, answer_timeout_s)
    };
    out.push(rule(
        "takes its settings at their defaults, a command and a reading, and answers a query",
        run(&defaults, 2, 1).map(|_| "answered".into()),
    ));
    let ends = |pick: fn(&Setting) -> f64| -> Vec<(String, f64)> {
        program
            .settings()
            .iter()
            .map(|s| {
                let v = pick(s);
                let v = if v.is_finite() { v } else { s.default };
                (s.key.clone(), v)
            })
            .collect()
    };
    let typed = program
        .settings()
        .iter()
        .map(|s| match s.kind {
            Kind::Count => format!("{} (integer)", s.key),
            Kind::Number => s.key.clone(),
        })
        .collect::<Vec<_>>();
    let at_ends = run(&ends(lowest), 2, 1).and_then(|_| run(&ends(|s| s.max), 2, 1));
    out.push(rule(
        "takes every setting at both ends of its range (integers as integers)",
        at_ends.map(|_| {
            if typed.is_empty() {
                "no settings of its own".into()
            } else {
                typed.join(", ")
            }
        }),
    ));
    out.push(rule(
        "answers through 10 s of commands with no reading (a blank stretch)",
        run(&defaults, 200, usize::MAX).map(|_| "answered 200 queries".into()),
    ));
    let long = run(&defaults, 3000, 1);
    out.push(rule(
        "answers every query of a 150 s trial (3000 frames)",
        long.as_ref()
            .map(|_| "answered 3000 queries".into())
            .map_err(Clone::clone),
    ));
    out.push(rule(
        "ends a trial with both models",
        match &long {
            Ok(end) => match (&end.action, &end.sensor) {
                (true, true) => Ok("an action and a sensor model".into()),
                (a, s) => Err(format!(
                    "no {} at the end of a 150 s trial: such a trial fails with `no model`",
                    match (a, s) {
                        (false, false) => "models",
                        (false, true) => "action model",
                        _ => "sensor model",
                    }
                )),
            },
            Err(_) => Err("not tried: the trial did not run to its end".into()),
        },
    ));
    out.push(rule(
        "answers `posterior` at the end with draws right in form, if it says it has one",
        match &long {
            _ if !program.has_posterior() => Ok("says it has none (it is optional)".into()),
            Ok(end) => end.draws.clone().map(|draws| match draws {
                Some(n) => format!("{n} draws of the {} asked for", crate::predicted::DRAWS),
                None => "null: none at the end of a 150 s trial".into(),
            }),
            Err(_) => Err("not tried: the trial did not run to its end".into()),
        },
    ));
    out.push(rule(
        "exits within 2 s of `end`",
        match &long {
            Ok(end) if end.exited => Ok("exited".into()),
            Ok(_) => Err("still running 2 s after `end` (it was killed)".into()),
            Err(_) => Err("not tried: the trial did not run to its end".into()),
        },
    ));
    out
}

/// The smallest value of a setting's range (its default if the range is
/// open there).
fn lowest(s: &Setting) -> f64 {
    if s.min_open { s.default } else { s.min }
}

/// What a check's trial ended with.
#[derive(Debug, Clone)]
struct TrialEnd {
    action: bool,
    sensor: bool,
    /// How many draws its posterior had at the end, if it gave one, or how
    /// its answer failed.
    draws: Result<Option<usize>, String>,
    exited: bool,
}

/// `frames` frames of the synthetic world to `program` started with `own`,
/// a reading with every `every_reading`-th frame, a query after each; then
/// `end`.
fn trial(
    program: &Program,
    own: &[(String, f64)],
    frames: usize,
    every_reading: usize,
    answer_timeout_s: f64,
) -> Result<TrialEnd, String> {
    let scenario = Scenario::paper().map_err(|e| e.to_string())?;
    let shared = crate::learners::shared_values(&scenario);
    let mut learner =
        ExecLearner::start(program, &Values(own.to_vec()), &shared, answer_timeout_s)?;
    let mut behaviour = TrainingBehaviour::new(
        BehaviourConfig::paper(300.0, true_obs_px(1100.0), true_obs_px(3800.0)),
        seeds::rng(0, Stream::Behaviour),
        Phase::Forwards,
    );
    let mut rng = seeds::rng(0, Stream::SensorNoise);
    let noise = Normal::new(0.0, 1.0).map_err(|e| e.to_string())?;
    let mut distance_mm = 2400.0;
    let failed = |learner: &ExecLearner, k: usize| {
        learner
            .failure()
            .map(|why| format!("at frame {k}: {why}"))
            .unwrap_or_else(|| format!("at frame {k}: the learner refused an event"))
    };
    for k in 0..frames {
        let t_s = k as f64 * FRAME_S;
        let command = behaviour.command(t_s);
        learner
            .handle(Event::Command {
                t_s,
                dt_s: FRAME_S,
                command,
            })
            .map_err(|_| failed(&learner, k))?;
        distance_mm -= true_velocity_mm_s(command) * FRAME_S;
        let t_next = t_s + FRAME_S;
        let reading = (k % every_reading.max(1) == 0)
            .then(|| true_obs_px(distance_mm) + noise.sample(&mut rng));
        if let Some(obs_px) = reading {
            learner
                .handle(Event::Reading {
                    t_s: t_next,
                    obs_px,
                })
                .map_err(|_| failed(&learner, k))?;
        }
        behaviour.observe(t_next, reading);
        let _ = learner.action_model();
        if learner.failure().is_some() {
            return Err(failed(&learner, k));
        }
    }
    let (action, sensor) = (
        learner.action_model().is_some(),
        learner.sensor_model().is_some(),
    );
    if learner.failure().is_some() {
        return Err(failed(&learner, frames));
    }
    let posterior = learner.posterior(crate::predicted::DRAWS);
    let draws = match learner.failure() {
        Some(why) => Err(why.to_string()),
        None => Ok(posterior.map(|p| p.draws.len())),
    };
    let exited = learner.end();
    Ok(TrialEnd {
        action,
        sensor,
        draws,
        exited,
    })
}
