//! The paper's experiment on the simulated robot: trials of a calibration
//! learner (SCASM by default) learning the robot's action and sensor models at
//! once, judged by the paper's protocol against the models measured by
//! stopwatch and by standing at marked distances.
//!
//! The command is [`scasm_testbed::commands::train`] (also `scasm-testbed train`).

fn main() -> anyhow::Result<()> {
    scasm_testbed::commands::train::main(scasm_testbed::args::parse())
}
