//! Every learner on every scenario of the suite (`assets/scenarios/suite/`) and
//! every seed, in parallel: each world is simulated once and fed to all the
//! learners. Writes DIR/leaderboard.csv (a row per learner, scenario and seed),
//! leaderboard.md and index.html (the summary table and a figure of the ratios
//! to the best possible polynomials), and each scenario's config-<name>.toml.
//!
//! The command is [`scasm_testbed::commands::benchmark`] (also `scasm-testbed benchmark`).

fn main() -> anyhow::Result<()> {
    scasm_testbed::commands::benchmark::main(scasm_testbed::args::parse())
}
