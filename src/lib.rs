//! Command-line pieces shared by the examples.
#![warn(missing_docs)]

use std::path::PathBuf;

use testbed::scenario::{Scenario, SettingError};

/// The flags that choose a scenario: robot, scenario file, and settings.
#[derive(Debug, Clone, clap::Args)]
pub struct ScenarioArgs {
    /// Robot description (default: the shipped assets/ers7.urdf).
    #[arg(long)]
    pub urdf: Option<PathBuf>,
    /// A scenario file (TOML, e.g. assets/scenarios/paper.toml); --set overrides it.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// A setting as key=value (repeatable), e.g. learner.gamma=0.995.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

impl ScenarioArgs {
    /// The scenario these flags ask for.
    pub fn scenario(&self) -> Result<Scenario, SettingError> {
        Scenario::from_settings(self.urdf.as_deref(), self.config.as_deref(), &self.set)
    }
}
