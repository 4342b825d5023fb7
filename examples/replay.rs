//! Runs a learner over recorded worlds, with no physics: any dataset a `train`
//! run wrote (its `trial-*` directories), or such a run directory whole. The
//! learner gets exactly the events it would have got live, so for the same
//! learner and settings the models are the live run's, bit for bit.
//!
//! The command is [`scasm_testbed::commands::replay`] (also `scasm-testbed replay`).

fn main() -> anyhow::Result<()> {
    scasm_testbed::commands::replay::main(scasm_testbed::args::parse())
}
