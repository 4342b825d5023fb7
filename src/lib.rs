//! Command-line pieces shared by the examples: the flags that choose a scenario
//! and a run's trials, `--learner list`, and run directories.
#![warn(missing_docs)]

use std::path::{Path, PathBuf};

use testbed::scenario::{Scenario, SettingError};

/// The flags that choose a scenario: robot, scenario file, and settings.
#[derive(Debug, Clone, clap::Args)]
pub struct ScenarioArgs {
    /// The robot: a shipped robot's name (ers7, trotter: assets/robots/) or a
    /// robot file's path (default: ers7) [robot.file].
    #[arg(long, value_name = "NAME_OR_PATH")]
    pub robot: Option<String>,
    /// A bare URDF in the shipped robot's naming, walked with the default gait
    /// (a robot file is the general way) [robot.urdf].
    #[arg(long)]
    pub urdf: Option<PathBuf>,
    /// A scenario file (TOML, e.g. assets/scenarios/paper.toml, or a run's
    /// config.toml); --set and the flags below override it.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// A setting as key=value (repeatable), e.g. learner.gamma=0.995.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

impl ScenarioArgs {
    /// The scenario these flags ask for.
    pub fn scenario(&self) -> Result<Scenario, SettingError> {
        self.scenario_with(&[])
    }

    /// The scenario these flags ask for, then `extra` settings on top.
    pub fn scenario_with(&self, extra: &[String]) -> Result<Scenario, SettingError> {
        let robot = self.robot.iter().map(|r| format!("robot.file={r}"));
        let settings: Vec<String> = robot
            .chain(self.set.iter().cloned())
            .chain(extra.iter().cloned())
            .collect();
        Scenario::from_settings(self.urdf.as_deref(), self.config.as_deref(), &settings)
    }
}

/// The flags that choose a run's trials and learner; each is a setting (named
/// in brackets) and, when given, overrides the scenario file and `--set`.
#[derive(Debug, Clone, clap::Args)]
pub struct TrialArgs {
    /// Number of trials, seeds 0..N [trial.seeds].
    #[arg(long)]
    pub trials: Option<u64>,
    /// Seeds as a range A..B, B excluded [trial.seeds].
    #[arg(long)]
    pub seeds: Option<String>,
    /// Trial length, s [trial.duration].
    #[arg(long)]
    pub duration: Option<f64>,
    /// The learner; `list` prints the available ones [learner.name].
    #[arg(long)]
    pub learner: Option<String>,
    /// What is learned from what: simultaneous, sensor-from-action or
    /// action-from-sensor [trial.mode].
    #[arg(long)]
    pub mode: Option<String>,
}

impl TrialArgs {
    /// The settings these flags stand for.
    pub fn settings(&self) -> Vec<String> {
        let mut s = Vec::new();
        if let Some(n) = self.trials {
            s.push(format!("trial.seeds=0..{n}"));
        }
        if let Some(seeds) = &self.seeds {
            s.push(format!("trial.seeds={seeds}"));
        }
        if let Some(d) = self.duration {
            s.push(format!("trial.duration={d}"));
        }
        if let Some(l) = &self.learner {
            s.push(format!("learner.name={l}"));
        }
        if let Some(m) = &self.mode {
            s.push(format!("trial.mode={m}"));
        }
        s
    }
}

/// If `--learner list` was asked for, prints the learners' names, one per line,
/// and returns true.
pub fn list_learners_if_asked(learner: Option<&str>) -> bool {
    if learner != Some("list") {
        return false;
    }
    for name in testbed::learners::names() {
        println!("{name}");
    }
    true
}

/// A run's directory, created: `out`, or `runs/<kind>-<unix time>`.
pub fn create_run_dir(out: Option<&Path>, kind: &str) -> anyhow::Result<PathBuf> {
    let dir = out.map_or_else(
        || {
            let t = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_secs())
                .unwrap_or(0);
            PathBuf::from(format!("runs/{kind}-{t}"))
        },
        Path::to_path_buf,
    );
    std::fs::create_dir_all(&dir)
        .map_err(|e| anyhow::anyhow!("creating {}: {e}", dir.display()))?;
    Ok(dir)
}

/// A progress bar over `len` items of `what`.
pub fn progress_bar(len: u64, what: &str) -> indicatif::ProgressBar {
    indicatif::ProgressBar::new(len).with_style(
        indicatif::ProgressStyle::with_template(&format!(
            "  [{{elapsed_precise}}] {{bar:40}} {{pos}}/{{len}} {what}, eta {{eta}}"
        ))
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    )
}
