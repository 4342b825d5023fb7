//! Measures the simulated robot's true sensor model by the paper's protocol: the
//! robot stands at 1.2, 1.4, ..., 3.6 m from the beacon and takes 100 readings at
//! each, stepping in place at the command that does not creep (found from the
//! stopwatch protocol, cached like `train`'s reference). Each point is labelled
//! with the distance the robot actually held while reading. Prints the table and
//! writes `measured_sensor.csv`; `--save-frame` also writes a PNG of what the
//! camera sees at each distance.
//!
//! The command is [`scasm_testbed::commands::measure_sensor`] (also `scasm-testbed measure-sensor`).

fn main() -> anyhow::Result<()> {
    scasm_testbed::commands::measure_sensor::main(scasm_testbed::args::parse())
}
