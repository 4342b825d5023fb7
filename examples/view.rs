//! Watch the robot learn in the Rerun viewer: the paper's training trial,
//! from the same simulation and trial code as `train`, streamed live to a
//! Rerun viewer (started if none is running; `pip install rerun-sdk==0.36.3`
//! gives the `rerun` command) or saved to a recording.
//!
//! The command is [`scasm_testbed::commands::view`] (also `scasm-testbed view`).

fn main() -> anyhow::Result<()> {
    scasm_testbed::commands::view::main(scasm_testbed::args::parse())
}
