//! Every command of the testbed, each a module with its flags (`Args`) and
//! its `main`: the `scasm-testbed` binary's subcommands (`cargo install
//! --path .`), and the examples (`cargo run --release --example train`),
//! which are one-line wrappers of the same functions.

// The commands' doc comments are also their `--help` text, written for a
// terminal: `runs/train-<unix time>` is a path there, not an HTML tag.
#![allow(rustdoc::invalid_html_tags)]

pub mod benchmark;
pub mod measure_action;
pub mod measure_sensor;
pub mod peer_trace;
pub mod replay;
pub mod sweep;
pub mod train;
#[cfg(feature = "rerun")]
pub mod view;
