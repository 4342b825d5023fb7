//! The learners a run can name (`--learner NAME`, `learner.name`): the Rust
//! learners of the [`registry`] and programs over the learner protocol
//! ([`exec`]), each built for a trial from a scenario's learner settings.
//! Every run kind (train, replay, benchmark, sweep, view) builds its
//! learners here.

use scasm::declaration::{BuildContext, SHARED};
use scasm::{Mode, Polynomial};

pub mod exec;
pub mod registry;

use crate::metrics;
use crate::reference::Reference;
use crate::scenario::{LearningMode, Scenario};

pub use registry::{DEFAULT, LEARNERS, Learner, names, resolve};
pub use scasm::declaration::BoxedLearner;

/// The shared settings' values in `scenario`, and the command scale, as a
/// program is told them.
pub(crate) fn shared_values(scenario: &Scenario) -> Vec<(&'static str, f64)> {
    let mut out: Vec<(&str, f64)> = SHARED
        .iter()
        .map(|s| (s.key, (s.get)(&scenario.learner)))
        .collect();
    out.push(("command_scale", scenario.learner.command_scale));
    out
}

/// The learner `spec` names, built for `scenario`. In the one-sided modes
/// (sections IV and V) the given model is the best polynomial through the
/// measured one, in mm (location is distance, so the action model is minus
/// the forward speed); only learners that declare so learn in those modes.
pub fn build(
    spec: &str,
    scenario: &Scenario,
    reference: &Reference,
) -> Result<BoxedLearner, String> {
    build_kept(spec, scenario, reference).map(|b| b.learner)
}

/// A learner built for a trial, and what it writes beside its models.
pub struct Built {
    /// The learner.
    pub learner: BoxedLearner,
    /// A program's stderr, as it is written (`None` for a Rust learner).
    pub stderr: Option<exec::child::SharedStderr>,
}

impl Built {
    /// Ends the learner (a program first, so that its last words are in)
    /// and returns its whole stderr (`None` for a Rust learner).
    pub fn end(self) -> Option<String> {
        let Self { learner, stderr } = self;
        drop(learner);
        stderr.and_then(|s| s.lock().ok().map(|l| l.text()))
    }
}

impl std::fmt::Debug for Built {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Built")
            .field("learner", &self.learner.name())
            .field("stderr", &self.stderr)
            .finish()
    }
}

/// [`build`], keeping a handle on a program's stderr.
pub fn build_kept(spec: &str, scenario: &Scenario, reference: &Reference) -> Result<Built, String> {
    let learner = resolve(spec)?;
    if scenario.mode != LearningMode::Simultaneous && !learner.one_sided() {
        return Err(format!(
            "{} learns both models at once only (trial.mode simultaneous)",
            learner.name()
        ));
    }
    let own = scenario.own_settings(&learner);
    match learner {
        Learner::Rust(declaration) => {
            let mode = given_model(scenario, reference)?;
            Ok(Built {
                learner: (declaration.build)(&BuildContext {
                    shared: scenario.learner,
                    own,
                    mode,
                })?,
                stderr: None,
            })
        }
        Learner::Program(program) => {
            let learner = exec::ExecLearner::start(
                &program,
                &own,
                &shared_values(scenario),
                scenario.answer_timeout_s,
            )?;
            Ok(Built {
                stderr: Some(learner.stderr()),
                learner: Box::new(learner),
            })
        }
    }
}

/// What is learned from what, with the given model of a one-sided mode.
fn given_model(scenario: &Scenario, reference: &Reference) -> Result<Mode, String> {
    let config = scenario.learner;
    Ok(match scenario.mode {
        LearningMode::Simultaneous => Mode::Simultaneous,
        LearningMode::SensorFromAction => {
            let a = metrics::best_polynomial(&reference.action, config.action_degree)
                .ok_or("cannot fit the measured action model")?;
            let minus: Vec<f64> = a.coeffs().iter().map(|c| -c).collect();
            Mode::SensorFromAction(Polynomial::new(&minus).ok_or("bad action model")?)
        }
        LearningMode::ActionFromSensor => {
            let pts: Vec<(f64, f64)> = reference.sensor.iter().map(|&(d, o)| (o, d)).collect();
            Mode::ActionFromSensor(
                metrics::best_polynomial(&pts, config.sensor_degree)
                    .ok_or("cannot fit the measured sensor model")?,
            )
        }
    })
}

/// The name `spec`'s learner reports under: a Rust learner's, or a
/// program's hello's (`spec` itself if it cannot be resolved).
pub fn display_name(spec: &str) -> String {
    resolve(spec).map_or_else(|_| spec.to_string(), |l| l.name().to_string())
}

/// The settings learner `spec` runs with in `scenario`, for a run's record:
/// every shared and own setting it reads, by its full key, and a program's
/// command.
pub fn parameters(spec: &str, scenario: &Scenario) -> serde_json::Value {
    let Ok(learner) = resolve(spec) else {
        return serde_json::Value::Null;
    };
    let mut out = serde_json::Map::new();
    out.insert("name".into(), learner.name().into());
    if let Learner::Program(p) = &learner {
        out.insert("exec".into(), p.spec.clone().into());
    }
    for key in learner.shared() {
        if let Some(s) = scasm::declaration::shared(key) {
            out.insert(format!("learner.{key}"), (s.get)(&scenario.learner).into());
        }
    }
    for (key, value) in scenario.own_settings(&learner).0 {
        out.insert(format!("learner.{}.{key}", learner.name()), value.into());
    }
    serde_json::Value::Object(out)
}

/// Every built-in learner with its settings, as Markdown: the book's
/// reference page (`scripts/reference.sh`).
pub fn describe_markdown() -> String {
    let defaults = scasm::ScasmConfig::default();
    let mut out = String::new();
    for learner in LEARNERS.iter().map(Learner::Rust) {
        out += &format!("## `{}`\n\n{}\n\n", learner.name(), learner.about());
        let shared: Vec<String> = learner
            .shared()
            .iter()
            .filter_map(|k| scasm::declaration::shared(k))
            .map(|s| format!("`learner.{}` ({})", s.key, (s.get)(&defaults)))
            .collect();
        out += &format!("Shared settings it reads: {}.\n\n", shared.join(", "));
        let own = learner.settings();
        if own.is_empty() {
            out += "No settings of its own.\n\n";
            continue;
        }
        out += "| setting | default | range | meaning |\n|---|---|---|---|\n";
        for s in own {
            out += &format!(
                "| `learner.{}.{}` | {} | {} | {} |\n",
                learner.name(),
                s.key,
                s.default,
                s.range(),
                s.doc
            );
        }
        out += "\n";
    }
    out
}

/// Every Rust learner and the program `spec` (if one), with its settings
/// and their defaults at the paper's scale: what `--learner list` prints.
pub fn describe(extra: Option<&Learner>) -> String {
    let defaults = scasm::ScasmConfig::default();
    let mut out = String::new();
    let all: Vec<Learner> = LEARNERS
        .iter()
        .map(Learner::Rust)
        .chain(extra.cloned())
        .collect();
    for learner in &all {
        out += &format!("{}\n    {}\n", learner.name(), learner.about());
        let shared: Vec<String> = learner
            .shared()
            .iter()
            .filter_map(|k| scasm::declaration::shared(k))
            .map(|s| format!("learner.{} = {}", s.key, (s.get)(&defaults)))
            .collect();
        out += &format!("    shared: {}\n", shared.join(", "));
        for s in learner.settings() {
            out += &format!(
                "    learner.{}.{} = {}  in {}: {}\n",
                learner.name(),
                s.key,
                s.default,
                s.range(),
                s.doc
            );
        }
    }
    out
}
