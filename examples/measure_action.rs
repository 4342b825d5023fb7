//! Measures the simulated robot's true action model by the paper's stopwatch
//! protocol: every multiple of 20 in [-300, 300], each timed across a distance
//! five times. Prints the curve, the identity model's scaled error and the best
//! polynomials' errors, and writes `measured_action.csv`.
//!
//! The command is [`scasm_testbed::commands::measure_action`] (also `scasm-testbed measure-action`).

fn main() -> anyhow::Result<()> {
    scasm_testbed::commands::measure_action::main(scasm_testbed::args::parse())
}
