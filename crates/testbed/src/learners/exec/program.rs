//! A learner that is a program (`exec:COMMAND ARGS...`): started once when a
//! run names it, to read its hello (its name and settings), then once per
//! trial as an [`ExecLearner`].

use std::sync::{Mutex, OnceLock};
use std::time::Duration;

use scasm::declaration::{Setting, Values};
use scasm::{CalibrationLearner, Event, EventError, Polynomial, Posterior};

use crate::learners::exec::child::{Child, Fault, SharedStderr};
use crate::learners::exec::protocol::{self, Models, Said};

/// The prefix that names a learner program.
pub const PREFIX: &str = "exec:";

/// How long a program has to say hello, s: a first start may import a large
/// library.
pub const HELLO_TIMEOUT_S: f64 = 30.0;

/// The default time limit for a learner's answer to a query, s
/// (`exec.answer_timeout_s`).
pub const ANSWER_TIMEOUT_S: f64 = 5.0;

/// A learner program, as its hello declared it.
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    /// As named: `exec:COMMAND ARGS...`.
    pub spec: String,
    /// The command's words.
    pub words: Vec<String>,
    /// Its hello.
    pub hello: protocol::Hello,
}

impl Program {
    /// Starts the program named by `spec` (`exec:COMMAND ARGS...`), reads its
    /// hello and ends it: whether it can run at all, and what it takes.
    pub fn probe(spec: &str) -> Result<Self, String> {
        let command = spec
            .strip_prefix(PREFIX)
            .ok_or_else(|| format!("`{spec}` does not start with {PREFIX}"))?;
        let words = shell_words::split(command)
            .map_err(|e| format!("`{spec}`: cannot split the command into words: {e}"))?;
        let mut child = Child::spawn(&words).map_err(|e| format!("`{spec}`: {e}"))?;
        let hello = read_hello(&mut child).map_err(|e| format!("`{spec}` {e}"))?;
        let _ = child.finish(protocol::END);
        Ok(Self {
            spec: spec.into(),
            words,
            hello,
        })
    }

    /// Its name (its hello's).
    pub fn name(&self) -> &str {
        &self.hello.name
    }

    /// Its own settings.
    pub fn settings(&self) -> Vec<Setting> {
        self.hello.settings.clone()
    }

    /// Whether its hello says it answers `posterior` at the end of a trial.
    pub fn has_posterior(&self) -> bool {
        self.hello.posterior
    }
}

/// The first line of a started program: its hello.
fn read_hello(child: &mut Child) -> Result<protocol::Hello, String> {
    let said = child
        .receive(Duration::from_secs_f64(HELLO_TIMEOUT_S))
        .map_err(|f| fault(&f, child, "before saying hello"))
        .and_then(|line| protocol::parse(&line).map_err(|e| with_stderr(&e, child)))?;
    match said {
        Said::Hello(h) => Ok(h),
        Said::Error(m) => Err(with_stderr(&format!("refused to start: {m}"), child)),
        Said::Models(_) | Said::Posterior(_) => Err("answered before saying hello".into()),
    }
}

/// A fault in words, with the child's last stderr lines.
fn fault(f: &Fault, child: &Child, when: &str) -> String {
    let what = match f {
        Fault::Gone(Some(how)) => format!("crashed {when}: it {how}"),
        Fault::Gone(None) => format!(
            "closed its stdout {when}, and had not exited 2 s later (stdout is the protocol's)"
        ),
        Fault::Silent(s) => format!("did not answer within {s} s {when} (exec.answer_timeout_s)"),
        Fault::NotALine(why) => format!("{why} {when}"),
    };
    with_stderr(&what, child)
}

fn with_stderr(what: &str, child: &Child) -> String {
    format!("{what}; {}", child.stderr_tail())
}

/// The programs named so far in this process, each started once to read its
/// hello.
static PROGRAMS: Mutex<Vec<Program>> = Mutex::new(Vec::new());

/// The program `spec`, started once per process to read its hello.
pub fn program(spec: &str) -> Result<Program, String> {
    let known = |list: &[Program]| list.iter().find(|p| p.spec == spec).cloned();
    if let Some(p) = PROGRAMS.lock().ok().and_then(|l| known(&l)) {
        return Ok(p);
    }
    let probed = Program::probe(spec)?;
    let mut list = PROGRAMS
        .lock()
        .map_err(|_| "the program list is poisoned")?;
    if let Some(other) = list
        .iter()
        .find(|p| p.name() == probed.name() && p.spec != spec)
    {
        return Err(format!(
            "`{spec}` calls itself `{}`, as `{}` does: two learners in one run need two names",
            probed.name(),
            other.spec
        ));
    }
    if known(&list).is_none() {
        list.push(probed.clone());
    }
    Ok(probed)
}

/// The program named so far whose hello says `name`.
pub fn program_named(name: &str) -> Option<Program> {
    PROGRAMS
        .lock()
        .ok()?
        .iter()
        .find(|p| p.name() == name)
        .cloned()
}

/// A learner program running for one trial, driven over the protocol. Its
/// models are asked for once per frame, when the host first wants one after
/// new events, and kept until the next event.
#[derive(Debug)]
pub struct ExecLearner {
    name: String,
    stderr: SharedStderr,
    answer_timeout: Duration,
    state: Mutex<State>,
    failure: OnceLock<String>,
    /// Whether its hello said it answers `posterior`.
    posterior: bool,
}

#[derive(Debug)]
struct State {
    child: Child,
    /// Whether `models` answers for every event sent.
    current: bool,
    models: Models,
}

impl ExecLearner {
    /// Starts `program` for a trial and tells it its settings: its own `own`
    /// and the shared ones.
    pub fn start(
        program: &Program,
        own: &Values,
        shared: &[(&str, f64)],
        answer_timeout_s: f64,
    ) -> Result<Self, String> {
        let spec = &program.spec;
        let mut child = Child::spawn(&program.words).map_err(|e| format!("`{spec}`: {e}"))?;
        let hello = read_hello(&mut child).map_err(|e| format!("`{spec}` {e}"))?;
        if hello != program.hello {
            return Err(format!(
                "`{spec}` said another hello than when the run began (its name and settings \
                 must not change between starts)"
            ));
        }
        child
            .send(&protocol::settings_line(
                &own.0,
                &program.hello.settings,
                shared,
            ))
            .map_err(|f| format!("`{spec}` {}", fault(&f, &child, "on its settings")))?;
        Ok(Self {
            name: hello.name,
            stderr: child.stderr_log(),
            answer_timeout: Duration::from_secs_f64(answer_timeout_s),
            state: Mutex::new(State {
                child,
                current: false,
                models: Models::default(),
            }),
            failure: OnceLock::new(),
            posterior: hello.posterior,
        })
    }

    /// Its program's whole stderr, as it is written: kept by the host for the
    /// trial's folder.
    pub fn stderr(&self) -> SharedStderr {
        std::sync::Arc::clone(&self.stderr)
    }

    /// Records why the learner failed (the first reason stands).
    fn fail(&self, why: String) {
        let _ = self.failure.set(format!("learner `{}` {why}", self.name));
    }

    /// Its models for every event so far, asking once if they are not known.
    fn models(&self) -> Models {
        if self.failure.get().is_some() {
            return Models::default();
        }
        let Ok(mut state) = self.state.lock() else {
            return Models::default();
        };
        if !state.current {
            // A protocol is one answer per query: a line written unasked
            // (a second answer, a stray print) is a fault, not a late answer.
            // (An `error` may come at any time: a learner that refuses an event.)
            if self.failed_unasked(&state.child) {
                return Models::default();
            }
            let answer = state
                .child
                .send(protocol::QUERY)
                .and_then(|()| state.child.receive(self.answer_timeout));
            let said = answer
                .map_err(|f| fault(&f, &state.child, "when asked for its models"))
                .and_then(|line| protocol::parse(&line).map_err(|e| with_stderr(&e, &state.child)));
            match said {
                Ok(Said::Models(m)) => {
                    state.models = m;
                    state.current = true;
                }
                Ok(Said::Error(m)) => {
                    self.fail(format!("gave up: {m}; {}", state.child.stderr_tail()));
                }
                Ok(Said::Hello(_)) => self.fail("said hello again instead of answering".into()),
                Ok(Said::Posterior(_)) => {
                    self.fail("answered a posterior when asked for its models".into());
                }
                Err(e) => self.fail(e),
            }
            if self.failure.get().is_some() {
                return Models::default();
            }
        }
        state.models
    }

    /// Fails the learner if it wrote a line nobody asked for (a second
    /// answer, a stray print; an `error` says why it gave up), as a protocol
    /// of one answer per question has it; whether it did.
    fn failed_unasked(&self, child: &Child) -> bool {
        let Some(extra) = child.unasked() else {
            return false;
        };
        let said = match protocol::parse(&extra) {
            Ok(Said::Error(m)) => format!("gave up: {m}"),
            _ => format!(
                "wrote a line nobody asked for: `{}` (one answer per query; logs go to stderr)",
                extra.chars().take(160).collect::<String>()
            ),
        };
        self.fail(with_stderr(&said, child));
        true
    }

    /// Its posterior: asked once, after its last models, if its hello said it
    /// has one. An answer that is not a posterior, more draws than asked, or
    /// an impossible draw fails the trial like a bad answer to a query.
    fn ask_posterior(&self, draws: usize) -> Option<Posterior> {
        if !self.posterior || self.failure.get().is_some() {
            return None;
        }
        let mut state = self.state.lock().ok()?;
        if self.failed_unasked(&state.child) {
            return None;
        }
        let answer = state
            .child
            .send(&protocol::posterior_request(draws))
            .and_then(|()| state.child.receive(self.answer_timeout));
        let said = answer
            .map_err(|f| fault(&f, &state.child, "when asked for its posterior"))
            .and_then(|line| protocol::parse(&line).map_err(|e| with_stderr(&e, &state.child)));
        match said {
            Ok(Said::Posterior(Some(p))) if p.draws.len() > draws => self.fail(format!(
                "answered {} draws of its posterior when asked for {draws}",
                p.draws.len()
            )),
            Ok(Said::Posterior(p)) => return p,
            Ok(Said::Error(m)) => {
                self.fail(format!("gave up: {m}; {}", state.child.stderr_tail()));
            }
            Ok(_) => self.fail("answered something else when asked for its posterior".into()),
            Err(e) => self.fail(e),
        }
        None
    }
}

impl CalibrationLearner for ExecLearner {
    fn name(&self) -> &str {
        &self.name
    }

    fn handle(&mut self, event: Event) -> Result<(), EventError> {
        if self.failure.get().is_some() {
            return Err(EventError::Failed);
        }
        let sent = match self.state.get_mut() {
            Ok(state) => {
                state.current = false;
                state.child.send(&protocol::event_line(event)).map_err(|f| {
                    // A learner that said why before it went, said so.
                    match state.child.unasked().map(|l| protocol::parse(&l)) {
                        Some(Ok(Said::Error(m))) => {
                            with_stderr(&format!("gave up: {m}"), &state.child)
                        }
                        _ => fault(&f, &state.child, "while taking events"),
                    }
                })
            }
            Err(_) => Err("its state is poisoned".into()),
        };
        sent.map_err(|e| {
            self.fail(e);
            EventError::Failed
        })
    }

    fn action_model(&self) -> Option<Polynomial> {
        self.models().action
    }

    fn sensor_model(&self) -> Option<Polynomial> {
        self.models().sensor
    }

    fn x_a(&self) -> Option<f64> {
        self.models().x_a
    }

    fn x_s(&self) -> Option<f64> {
        self.models().x_s
    }

    fn posterior(&self, draws: usize) -> Option<Posterior> {
        self.ask_posterior(draws)
    }

    fn failure(&self) -> Option<&str> {
        self.failure.get().map(String::as_str)
    }
}

impl ExecLearner {
    /// Ends the trial: sends `end`; whether the program then exited by
    /// itself within 2 s (it is killed either way).
    pub fn end(mut self) -> bool {
        self.state
            .get_mut()
            .is_ok_and(|state| state.child.finish(protocol::END))
    }
}

impl Drop for ExecLearner {
    fn drop(&mut self) {
        if let Ok(state) = self.state.get_mut() {
            state.child.finish(protocol::END);
        }
    }
}
