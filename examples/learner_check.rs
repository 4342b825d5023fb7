//! The learner protocol's conformance check, for anyone who writes a learner
//! program: drives it through every path of the protocol (hello, its
//! settings at their defaults and at both ends of their ranges, every event
//! kind, a stretch with no readings, a whole trial, the end) in a world with
//! no physics, and prints whether it kept each rule, quoting what went wrong.
//!
//! ```sh
//! cargo run --release --example learner_check -- 'exec:python3 examples/learners/quickstart.py'
//! ```

use anyhow::{Result, bail};
use clap::Parser;
use testbed::learners::exec::{self, conformance};

/// Check a learner program against the learner protocol, rule by rule.
#[derive(Debug, Parser)]
struct Args {
    /// The program, as a run names it: exec:COMMAND ARGS...
    spec: String,
    /// How long it may take to answer a query, s [exec.answer_timeout_s].
    #[arg(long, default_value_t = exec::ANSWER_TIMEOUT_S)]
    answer_timeout_s: f64,
}

fn main() -> Result<()> {
    let args: Args = scasm_testbed::args::parse();
    if !args.spec.starts_with(exec::PREFIX) {
        bail!("`{}`: name the program as exec:COMMAND ARGS...", args.spec);
    }
    println!(
        "Checking `{}` against the learner protocol, version 1...\n",
        args.spec
    );
    let rules = conformance::check(&args.spec, args.answer_timeout_s);
    for r in &rules {
        println!("{} {}", if r.passed { "pass" } else { "FAIL" }, r.rule);
        for line in r.detail.lines() {
            println!("       {line}");
        }
    }
    let failed = rules.iter().filter(|r| !r.passed).count();
    println!(
        "\n{} of {} rules kept. (A program learns in the simultaneous mode only:\n\
         the host refuses the others for programs.)",
        rules.len() - failed,
        rules.len()
    );
    if failed > 0 {
        bail!("{failed} rules broken");
    }
    Ok(())
}
