//! Sweeps SCASM's hyper-parameters (or any other setting) over a grid, every
//! combination times every seed, through the same trial code as `train`.
//!
//! The command is [`scasm_testbed::commands::sweep`] (also `scasm-testbed sweep`).

fn main() -> anyhow::Result<()> {
    scasm_testbed::commands::sweep::main(scasm_testbed::args::parse())
}
