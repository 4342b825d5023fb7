//! The robot's motion for a peer simulator, and this build's own step time on
//! it: the robot stands for 0.5 s and then walks at `--command` for the rest of
//! `--seconds`, towards the beacon but starting far enough from it that it
//! touches nothing but the floor (the peer's world has nothing else). Every physics step's servo targets go to DIR/targets.csv, and
//! what a peer needs to build the same robot goes to DIR/peer.json: the URDF,
//! the time step, the servo gains and torque limits, the joints in order, the
//! start, and this build's full step (servos, walk engine and 20 Hz camera
//! included) in microseconds, the best of `--repeats` runs, with its contact
//! points per step. Only the steps are timed: building the robot and its world
//! is not, as the peer's model compilation is not.
//!
//! The command is [`scasm_testbed::commands::peer_trace`] (also `scasm-testbed peer-trace`).

fn main() -> anyhow::Result<()> {
    scasm_testbed::commands::peer_trace::main(scasm_testbed::args::parse())
}
