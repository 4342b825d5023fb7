//! How every binary reads its command line: clap, plus `--version` with the
//! commit the binary was built from, and a hidden `--help-markdown` that prints
//! the flags as Markdown for the book's reference (`scripts/reference.sh`).

use clap::{Arg, ArgAction, CommandFactory, FromArgMatches};

/// The version and the commit the binary was built from.
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("SCASM_BUILD_COMMIT"),
    ")"
);

/// The command line, parsed into `T`; `--version` and `--help-markdown` print
/// and exit.
pub fn parse<T: FromArgMatches + CommandFactory>() -> T {
    let mut args = std::env::args_os();
    let name = args.next().and_then(|a| {
        std::path::Path::new(&a)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
    });
    parse_from(name.as_deref(), args.collect())
}

/// As [`parse`], for a command named `name` (`scasm-testbed train`) given the
/// flags `args` (those after its name).
pub fn parse_from<T: FromArgMatches + CommandFactory>(
    name: Option<&str>,
    args: Vec<std::ffi::OsString>,
) -> T {
    let named = |c: clap::Command| match name {
        // Once per process: clap keeps the name for the life of the program.
        Some(n) => c.name(&*n.to_string().leak()),
        None => c,
    };
    // Before parsing: a binary with a required argument prints its flags too.
    if args.iter().any(|a| a == "--help-markdown") {
        print!("{}", markdown(&named(T::command())));
        std::process::exit(0);
    }
    let command = named(T::command()).version(VERSION).arg(
        Arg::new("help-markdown")
            .long("help-markdown")
            .action(ArgAction::SetTrue)
            .hide(true),
    );
    let argv =
        std::iter::once(std::ffi::OsString::from(name.unwrap_or("scasm-testbed"))).chain(args);
    T::from_arg_matches(&command.get_matches_from(argv)).unwrap_or_else(|e| e.exit())
}

/// A command's flags as a Markdown section: its about line, usage and a table.
pub fn markdown(command: &clap::Command) -> String {
    let name = command.get_name();
    let mut out = format!("## `{name}`\n\n");
    if let Some(about) = command.get_long_about().or(command.get_about()) {
        out += &format!("{}\n\n", one_line(&about.to_string()));
    }
    out += "| flag | value | default | meaning |\n|---|---|---|---|\n";
    for arg in command.get_arguments().filter(|a| !a.is_hide_set()) {
        let id = arg.get_id().as_str();
        if id == "help" || id == "version" {
            continue;
        }
        let flag = match (arg.get_long(), arg.get_short()) {
            (Some(l), _) => format!("`--{l}`"),
            (None, Some(s)) => format!("`-{s}`"),
            (None, None) => format!("`{}` (positional)", id.to_uppercase()),
        };
        let takes_value = arg.get_num_args().is_none_or(|n| n.takes_values())
            && !matches!(
                arg.get_action(),
                ArgAction::SetTrue | ArgAction::SetFalse | ArgAction::Count
            );
        let value = if takes_value {
            arg.get_value_names()
                .map(|v| {
                    v.iter()
                        .map(|n| n.to_string())
                        .collect::<Vec<_>>()
                        .join(" ")
                })
                .unwrap_or_else(|| id.to_uppercase())
        } else {
            String::new()
        };
        let default = arg
            .get_default_values()
            .iter()
            .map(|v| v.to_string_lossy().into_owned())
            .collect::<Vec<_>>()
            .join(", ");
        let repeat = if matches!(arg.get_action(), ArgAction::Append) {
            " (repeatable)"
        } else {
            ""
        };
        let help = arg
            .get_long_help()
            .or(arg.get_help())
            .map(|h| one_line(&h.to_string()))
            .unwrap_or_default();
        out += &format!(
            "| {flag} | {} | {} | {}{repeat} |\n",
            cell(&value),
            cell(&default),
            cell(&help)
        );
    }
    out + "\n"
}

fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn cell(text: &str) -> String {
    text.replace('|', "\\|")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
