//! A scenario: everything a trial depends on besides its seed, built from
//! defaults, a scenario file and `key=value` settings, each checked at the
//! door: what it is (`data`), the one table of its settings (`table`), and
//! how settings, files and scheduled changes are applied (`settings`).

mod data;
mod settings;
mod table;

pub use data::{Change, LearningMode, MAX_DURATION_S, PAPER_DURATION_S, Scenario, SettingError};
pub use table::{describe_settings, describe_settings_markdown, parse_seeds, setting_keys};
