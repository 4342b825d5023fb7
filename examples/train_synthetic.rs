//! Trains SCASM in the synthetic closed loop with no physics: a point robot with
//! a made-up nonlinear action model and an ideal pinhole camera with Gaussian pixel
//! noise, under the paper's behaviour. It prints the learned models beside the
//! truth and the errors beside the paper's. A check of the learner on its own; the
//! robot's experiment is `train`.
//!
//! The command is [`scasm_testbed::commands::train_synthetic`] (also `scasm-testbed train-synthetic`).

fn main() -> anyhow::Result<()> {
    scasm_testbed::commands::train_synthetic::main(scasm_testbed::args::parse())
}
