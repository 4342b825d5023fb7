//! Learners as programs in any language, over the line protocol of
//! `book/src/learner/protocol.md`: its messages, the child process, and the
//! learner that drives one.

pub mod child;
pub mod conformance;
pub mod program;
pub mod protocol;

pub use program::{ANSWER_TIMEOUT_S, ExecLearner, PREFIX, Program, program, program_named};
