//! The testbed as one command: `scasm-testbed <command> [flags]`, each
//! command the example of the same name (`cargo install --path .` installs
//! it; `scasm-testbed <command> --help` lists its flags).

use std::ffi::OsString;

use anyhow::Result;
use scasm_testbed::args::parse_from;
use scasm_testbed::commands;

/// A command: its name, what it does, and how it runs given its flags.
type Command = (
    &'static str,
    &'static str,
    fn(&str, Vec<OsString>) -> Result<()>,
);

const COMMANDS: &[Command] = &[
    (
        "train",
        "run the paper's experiment: calibration trials on the simulated robot",
        |n, a| commands::train::main(parse_from(Some(n), a)),
    ),
    ("replay", "feed recorded trials to a learner", |n, a| {
        commands::replay::main(parse_from(Some(n), a))
    }),
    (
        "benchmark",
        "every learner on every scenario, the same worlds: a leaderboard",
        |n, a| commands::benchmark::main(parse_from(Some(n), a)),
    ),
    ("sweep", "a grid of settings, each over seeds", |n, a| {
        commands::sweep::main(parse_from(Some(n), a))
    }),
    (
        "measure-action",
        "the robot's true command-to-velocity curve, by stopwatch",
        |n, a| commands::measure_action::main(parse_from(Some(n), a)),
    ),
    (
        "measure-sensor",
        "the camera's true sensor model, by standing at marked distances",
        |n, a| commands::measure_sensor::main(parse_from(Some(n), a)),
    ),
    (
        "peer",
        "record a walk for MuJoCo and time this build's step on it",
        |n, a| commands::peer_trace::main(parse_from(Some(n), a)),
    ),
    #[cfg(feature = "rerun")]
    ("view", "watch a trial in the Rerun viewer", |n, a| {
        commands::view::main(parse_from(Some(n), a))
    }),
];

fn usage() -> String {
    let mut out = format!(
        "scasm-testbed {}\n\nUsage: scasm-testbed <command> [flags]   (scasm-testbed <command> --help)\n\nCommands:\n",
        scasm_testbed::args::VERSION
    );
    for (name, about, _) in COMMANDS {
        out += &format!("  {name:<16} {about}\n");
    }
    out
}

fn main() -> Result<()> {
    let mut args = std::env::args_os().skip(1);
    let first = args.next();
    let Some(name) = first.as_ref().and_then(|a| a.to_str()) else {
        eprint!("{}", usage());
        std::process::exit(2);
    };
    match COMMANDS.iter().find(|(n, ..)| *n == name) {
        Some((n, _, run)) => run(&format!("scasm-testbed {n}"), args.collect()),
        None if matches!(name, "--help" | "-h" | "help") => {
            print!("{}", usage());
            Ok(())
        }
        None if matches!(name, "--version" | "-V") => {
            println!("scasm-testbed {}", scasm_testbed::args::VERSION);
            Ok(())
        }
        None => {
            eprint!("unknown command `{name}`\n\n{}", usage());
            std::process::exit(2);
        }
    }
}
