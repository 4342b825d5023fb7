//! The learners a run can name, each listed once: the Rust learners'
//! declarations (beside their algorithms, in the physics-free `scasm` crate)
//! and learner programs (`exec:COMMAND`), resolved from a name to what the
//! host needs before building one: its name, settings and modes.

use scasm::declaration::{Declaration, Setting};

use crate::learners::exec::{self, Program};

/// The learner a run uses unless told otherwise.
pub const DEFAULT: &str = "scasm";

/// Every Rust learner, one line each.
pub const LEARNERS: &[Declaration] = &[
    scasm::SCASM_PAPER,
    scasm::SCASM,
    scasm::SCASM_EIV,
    scasm::BATCH_ML,
    scasm::BATCH_ML_LAG,
];

/// The Rust learners' names, in the order above.
pub fn names() -> impl Iterator<Item = &'static str> {
    LEARNERS.iter().map(|l| l.name)
}

/// A learner a run names: a Rust declaration or a program.
#[derive(Debug, Clone)]
pub enum Learner {
    /// Built into the testbed.
    Rust(&'static Declaration),
    /// A program speaking the learner protocol.
    Program(Program),
}

impl Learner {
    /// Its name in reports and in its settings' keys.
    pub fn name(&self) -> &str {
        match self {
            Self::Rust(d) => d.name,
            Self::Program(p) => p.name(),
        }
    }

    /// One line on what it is.
    pub fn about(&self) -> &str {
        match self {
            Self::Rust(d) => d.about,
            Self::Program(p) => &p.hello.about,
        }
    }

    /// Its own settings (`learner.<name>.<key>`).
    pub fn settings(&self) -> Vec<Setting> {
        match self {
            Self::Rust(d) => (d.settings)(),
            Self::Program(p) => p.settings(),
        }
    }

    /// The shared settings it reads (keys after `learner.`): a program is
    /// told all of them.
    pub fn shared(&self) -> Vec<&'static str> {
        match self {
            Self::Rust(d) => d.shared.to_vec(),
            Self::Program(_) => scasm::declaration::SHARED.iter().map(|s| s.key).collect(),
        }
    }

    /// Whether it can learn one model from the other given.
    pub fn one_sided(&self) -> bool {
        matches!(self, Self::Rust(d) if d.one_sided)
    }
}

/// The learner `spec` names: a Rust learner's name, or `exec:COMMAND ARGS...`
/// (started once, here, to read its hello: a program that cannot start is
/// an error before any trial runs).
pub fn resolve(spec: &str) -> Result<Learner, String> {
    if spec.starts_with(exec::PREFIX) {
        let program = exec::program(spec)?;
        if names().any(|n| n == program.name()) {
            return Err(format!(
                "`{spec}` calls itself `{}`, the name of a built-in learner: give it its own",
                program.name()
            ));
        }
        return Ok(Learner::Program(program));
    }
    LEARNERS
        .iter()
        .find(|d| d.name == spec)
        .map(Learner::Rust)
        .ok_or_else(|| {
            format!(
                "unknown learner `{spec}`; known: {}, or exec:COMMAND for a program",
                names().collect::<Vec<_>>().join(", ")
            )
        })
}

/// The learner whose name is `name`: a Rust learner, or a program this run
/// has named (its settings' keys are `learner.<its hello's name>.<key>`).
pub fn named(name: &str) -> Option<Learner> {
    LEARNERS
        .iter()
        .find(|d| d.name == name)
        .map(Learner::Rust)
        .or_else(|| exec::program_named(name).map(Learner::Program))
}
