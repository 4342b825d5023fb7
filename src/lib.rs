//! The testbed's commands ([`commands`]: train, replay, benchmark, sweep,
//! measure, peer, view), and the command-line pieces they share: the flags
//! that choose a scenario and a run's trials, `--learner list`, and run
//! directories.
#![warn(missing_docs)]

pub mod args;
pub mod commands;

use std::path::{Path, PathBuf};

use testbed::reference::MeasuredModels;
use testbed::scenario::{Scenario, SettingError};
use testbed::summary::{Figures, TrialStatus};
use testbed::trial::{Recording, TrialOutcome};

/// The flags that choose a scenario: robot, scenario file, and settings.
#[derive(Debug, Clone, clap::Args)]
pub struct ScenarioArgs {
    /// The robot: a shipped robot's name (ers7, trotter: assets/robots/), a
    /// robot file's path, or a URDF's (legs, camera and cadence found from
    /// it; default: ers7) [robot.file].
    #[arg(long, value_name = "NAME_OR_PATH")]
    pub robot: Option<String>,
    /// A URDF as published: the same as --robot FILE.urdf (kept as an
    /// alias) [robot.urdf].
    #[arg(long)]
    pub urdf: Option<PathBuf>,
    /// A scenario file (TOML, e.g. assets/scenarios/paper.toml, or a run's
    /// config.toml); --set and the flags below override it.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// A setting as key=value (repeatable), e.g. learner.gamma=0.995;
    /// `list` prints them all.
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

/// Refuses a scenario whose trials do not walk the robot in rapier, for a
/// command (`command`) that measures or shows that robot.
pub fn needs_rapier(scenario: &Scenario, command: &str) -> anyhow::Result<()> {
    anyhow::ensure!(
        scenario.world == testbed::world::WorldKind::Rapier,
        "{command} measures or shows the robot in rapier, and trial.world is {}: leave \
         --world and trial.world out, or use train, replay, benchmark or sweep, which take any world",
        scenario.world.name()
    );
    Ok(())
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
    /// The training behaviour, what chooses each walk command; `list`
    /// prints the available ones [behaviour.name].
    #[arg(long)]
    pub behaviour: Option<String>,
    /// What is learned from what: simultaneous, sensor-from-action or
    /// action-from-sensor [trial.mode].
    #[arg(long)]
    pub mode: Option<String>,
    /// The world the trials walk in: rapier (the robot, the default) or
    /// synthetic (a point robot with no physics) [trial.world].
    #[arg(long)]
    pub world: Option<String>,
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
        if let Some(b) = &self.behaviour {
            s.push(format!("behaviour.name={b}"));
        }
        if let Some(m) = &self.mode {
            s.push(format!("trial.mode={m}"));
        }
        if let Some(w) = &self.world {
            s.push(format!("trial.world={w}"));
        }
        s
    }
}

/// The flags that write a run's trial to a Rerun recording.
#[derive(Debug, Clone, clap::Args)]
pub struct RerunArgs {
    /// Write a trial to this Rerun recording (.rrd) to scrub in the Rerun
    /// viewer: the robot, the camera's view, the series and the models
    /// (needs the `rerun` feature: `--features rerun`).
    #[arg(long, value_name = "FILE.rrd")]
    pub rerun: Option<PathBuf>,
    /// The trial written by --rerun (default: the typical one, whose errors
    /// are nearest the run's medians).
    #[arg(long, value_name = "SEED", requires = "rerun")]
    pub rerun_seed: Option<u64>,
}

/// One trial of a run, as [`RerunArgs::write`] chooses among them.
#[derive(Debug, Clone, Copy)]
pub struct RunTrial<'a> {
    /// Its scenario.
    pub scenario: &'a Scenario,
    /// The models it is judged against.
    pub models: &'a MeasuredModels,
    /// Its recorded world.
    pub recording: &'a Recording,
    /// Its learner's run.
    pub outcome: &'a TrialOutcome,
    /// Its status and figures.
    pub row: &'a (u64, TrialStatus, Figures),
}

impl RerunArgs {
    /// Refuses `--rerun` early, before a long run, in a build without the
    /// `rerun` feature.
    pub fn check(&self) -> anyhow::Result<()> {
        anyhow::ensure!(
            self.rerun.is_none() || cfg!(feature = "rerun"),
            "--rerun needs the `rerun` feature: cargo run --release --features rerun --example ..."
        );
        Ok(())
    }

    /// If `--rerun FILE` was given, writes `--rerun-seed`'s trial (or the
    /// typical one) of `trials` to FILE: the trial is simulated again, its
    /// frames checked against its recording, and its learner run again.
    pub fn write(&self, trials: &[RunTrial<'_>]) -> anyhow::Result<()> {
        let Some(path) = &self.rerun else {
            return Ok(());
        };
        self.check()?;
        if let Some(t) = trials.first() {
            needs_rapier(t.scenario, "--rerun")?;
        }
        let rows: Vec<_> = trials.iter().map(|t| t.row.clone()).collect();
        let seed = self
            .rerun_seed
            .or_else(|| testbed::summary::typical_seed(&rows))
            .ok_or_else(|| anyhow::anyhow!("--rerun: no trial finished ok to record"))?;
        let trial = trials
            .iter()
            .find(|t| t.recording.seed == seed)
            .ok_or_else(|| anyhow::anyhow!("--rerun-seed {seed}: no such trial in this run"))?;
        write_rerun(path, trial)
    }
}

#[cfg(feature = "rerun")]
fn write_rerun(path: &Path, trial: &RunTrial<'_>) -> anyhow::Result<()> {
    use report::rrd::{TrialLog, log_trial};
    let seed = trial.recording.seed;
    println!(
        "Writing trial {seed} to the Rerun recording {}...",
        path.display()
    );
    let mut log = TrialLog::save(path, trial.models)?;
    let learner = &trial.scenario.learner_name;
    let (_, outcome) = log_trial(
        &mut log,
        trial.scenario,
        trial.models,
        seed,
        learner,
        Some(trial.recording),
    )?;
    log.finish()?;
    anyhow::ensure!(
        outcome.action_model == trial.outcome.action_model
            && outcome.sensor_model == trial.outcome.sensor_model,
        "trial {seed}: the learner {learner} ended with other models when run again"
    );
    println!(
        "  wrote {} (open it with `rerun {}`)",
        path.display(),
        path.display()
    );
    Ok(())
}

#[cfg(not(feature = "rerun"))]
fn write_rerun(_: &Path, _: &RunTrial<'_>) -> anyhow::Result<()> {
    Ok(())
}

/// If `--learner list` was asked for, prints the learners' names, one per line,
/// and returns true.
pub fn list_learners_if_asked(learner: Option<&str>) -> bool {
    if learner != Some("list") {
        return false;
    }
    print!("{}", testbed::learners::describe(None));
    true
}

/// If `--behaviour list` was asked for, prints the behaviours, a line each,
/// and returns true.
pub fn list_behaviours_if_asked(behaviour: Option<&str>) -> bool {
    if behaviour != Some("list") {
        return false;
    }
    print!("{}", testbed::behaviour::registry::describe());
    true
}

/// Prints every setting, its type, default and what it does, if `--set list`
/// was given; says whether it did. With a learner program named
/// (`--learner exec:...`), its own settings too, as its hello declares them.
pub fn list_settings_if_asked(set: &[String], learner: Option<&str>) -> bool {
    if !set.iter().any(|s| s == "list") {
        return false;
    }
    print!("{}", testbed::scenario::describe_settings());
    if let Some(spec) = learner.filter(|l| l.starts_with(testbed::learners::exec::PREFIX)) {
        match testbed::learners::resolve(spec) {
            Ok(program) => {
                for s in program.settings() {
                    println!(
                        "{:<26} {:<7} {:<14} {} (in {})",
                        format!("learner.{}.{}", program.name(), s.key),
                        if s.kind == scasm::declaration::Kind::Count {
                            "count"
                        } else {
                            "number"
                        },
                        s.default,
                        s.doc,
                        s.range()
                    );
                }
            }
            Err(e) => eprintln!("{e}"),
        }
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
