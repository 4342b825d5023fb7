//! The book's reference pages that come from the code's own tables: every
//! setting (`settings`) and every built-in learner with its settings
//! (`learners`), as Markdown on stdout, and every per-trial figure with its
//! doc (`figures`). `scripts/reference.sh` writes them,
//! with each binary's flags (`--help-markdown`) and the output files, into
//! `book/src/reference/`, and `--check` fails where a page differs.

use anyhow::{Result, bail};
use clap::Parser;

/// Print a reference page of the book, generated from the code.
#[derive(Debug, Parser)]
struct Args {
    /// The page: settings, learners, or figures (each per-trial figure's
    /// name and doc, tab-separated, for the output files' page).
    page: String,
}

fn main() -> Result<()> {
    let args: Args = scasm_testbed::args::parse();
    match args.page.as_str() {
        "settings" => print!("{}", testbed::scenario::describe_settings_markdown()),
        "learners" => print!("{}", testbed::learners::describe_markdown()),
        "figures" => {
            for f in testbed::summary::Figures::FIELDS {
                let doc = f.doc.split_whitespace().collect::<Vec<_>>().join(" ");
                println!("{}\t{doc}", f.name);
            }
        }
        other => bail!("no page `{other}`: settings, learners or figures"),
    }
    Ok(())
}
