//! Learners side by side: every learner on every scenario of a suite and every
//! seed, each world recorded once and fed to all the learners, judged by the
//! paper's protocol. A leaderboard row per (learner, scenario, seed), and a
//! summary per (learner, scenario): mean and spread over the seeds, the ratio
//! to the best possible polynomial, and the failed trials counted.

use std::path::{Path, PathBuf};

use crate::output;
use crate::scenario::{Scenario, SettingError};
use crate::summary::{Aggregate, Figures, TrialStatus};

/// The shipped suite's directory, relative to the repository's root.
pub const SUITE_DIR: &str = "assets/scenarios/suite";

/// A named scenario of a suite.
#[derive(Debug, Clone)]
pub struct SuiteScenario {
    /// Its name (the file's stem).
    pub name: String,
    /// The file it came from.
    pub file: PathBuf,
    /// The scenario.
    pub scenario: Scenario,
}

/// The scenario files in `dir` (`*.toml`, by name), each on top of the paper's
/// scenario, then `settings` on top of each; only those named in `only` if it is
/// not empty (an unknown name is an error that lists the known ones).
pub fn load_suite(
    dir: &Path,
    only: &[String],
    settings: &[String],
) -> Result<Vec<SuiteScenario>, SettingError> {
    let file_error = |reason: String| SettingError::File {
        file: dir.display().to_string(),
        reason,
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| file_error(e.to_string()))?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    let name_of = |p: &Path| {
        p.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let known: Vec<String> = files.iter().map(|p| name_of(p)).collect();
    if let Some(unknown) = only.iter().find(|n| !known.contains(n)) {
        return Err(file_error(format!(
            "no scenario `{unknown}`; the suite has {}",
            known.join(", ")
        )));
    }
    files
        .into_iter()
        .filter(|p| only.is_empty() || only.contains(&name_of(p)))
        .map(|file| {
            let scenario = Scenario::from_settings(None, Some(&file), settings)?;
            Ok(SuiteScenario {
                name: name_of(&file),
                file,
                scenario,
            })
        })
        .collect()
}

/// One learner's trial on one scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// The learner's name.
    pub learner: String,
    /// The scenario's name.
    pub scenario: String,
    /// The trial's seed.
    pub seed: u64,
    /// How it ended.
    pub status: TrialStatus,
    /// Its figures (NaN where there are none).
    pub figures: Figures,
}

/// `leaderboard.csv`: one row per entry: learner, scenario, seed, every
/// figure ([`Figures::FIELDS`]), whether it ended worse than its start, and
/// its status.
pub fn write_leaderboard_csv(path: &Path, entries: &[Entry]) -> std::io::Result<()> {
    let fields: Vec<&str> = Figures::FIELDS.iter().map(|f| f.name).collect();
    output::write_csv(
        path,
        &format!(
            "learner,scenario,seed,{},worse_than_start,status",
            fields.join(",")
        ),
        entries.iter().map(|e| {
            let figures: Vec<String> = Figures::FIELDS
                .iter()
                .map(|f| (f.get)(&e.figures).to_string())
                .collect();
            format!(
                "{},{},{},{},{},{}",
                e.learner,
                e.scenario,
                e.seed,
                figures.join(","),
                e.status.is_ok() && e.figures.worse_than_start(),
                e.status.to_string().replace(',', ";")
            )
        }),
    )
}

/// One (learner, scenario) cell: its trials aggregated.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// The learner.
    pub learner: String,
    /// The scenario.
    pub scenario: String,
    /// Mean and spread over the ok trials, and the failed ones.
    pub aggregate: Aggregate,
}

impl Cell {
    /// Mean action error over the best quartic's (the ratio).
    pub fn action_ratio(&self) -> f64 {
        self.action_ratio_of(&self.aggregate.mean)
    }

    /// Mean sensor error over the best cubic's.
    pub fn sensor_ratio(&self) -> f64 {
        self.sensor_ratio_of(&self.aggregate.mean)
    }

    /// A statistic of the action error (the median, say) over the best
    /// quartic's (the same in every trial of a cell: one reference).
    pub fn action_ratio_of(&self, statistic: &Figures) -> f64 {
        statistic.action_rmse_mm_s / self.aggregate.mean.action_best_rmse_mm_s
    }

    /// A statistic of the sensor error over the best cubic's.
    pub fn sensor_ratio_of(&self, statistic: &Figures) -> f64 {
        statistic.sensor_rmse_mm / self.aggregate.mean.sensor_best_rmse_mm
    }
}

/// The cells, learners in `learners`' order within scenarios in `scenarios`'.
pub fn cells(entries: &[Entry], learners: &[String], scenarios: &[String]) -> Vec<Cell> {
    let mut out = Vec::new();
    for scenario in scenarios {
        for learner in learners {
            let trials: Vec<(u64, TrialStatus, Figures)> = entries
                .iter()
                .filter(|e| &e.learner == learner && &e.scenario == scenario)
                .map(|e| (e.seed, e.status.clone(), e.figures))
                .collect();
            if !trials.is_empty() {
                out.push(Cell {
                    learner: learner.clone(),
                    scenario: scenario.clone(),
                    aggregate: Aggregate::of(&trials),
                });
            }
        }
    }
    out
}

/// The summary table: per scenario and learner, each error's mean +- std
/// and median [p10, p90], their ratios to the best polynomials (mean;
/// median), the consistency, the trials worse than their start (in the
/// means), and the trials ok.
pub fn summary_table(cells: &[Cell]) -> (Vec<String>, Vec<Vec<String>>) {
    let header = [
        "scenario",
        "learner",
        "action mm/s",
        "action median [p10, p90]",
        "action / best (mean; median)",
        "sensor mm",
        "sensor median [p10, p90]",
        "sensor / best (mean; median)",
        "consistency",
        "worse than start",
        "trials ok",
    ]
    .map(String::from)
    .to_vec();
    let rows = cells
        .iter()
        .map(|c| {
            let a = &c.aggregate;
            let (m, s) = (&a.mean, &a.std);
            let tail = |get: fn(&Figures) -> f64| {
                format!(
                    "{:.1} [{:.1}, {:.1}]",
                    get(&a.median),
                    get(&a.p10),
                    get(&a.p90)
                )
            };
            vec![
                c.scenario.clone(),
                c.learner.clone(),
                format!("{:.1} +- {:.1}", m.action_rmse_mm_s, s.action_rmse_mm_s),
                tail(|f| f.action_rmse_mm_s),
                format!(
                    "{:.2}x; {:.2}x",
                    c.action_ratio(),
                    c.action_ratio_of(&a.median)
                ),
                format!("{:.1} +- {:.1}", m.sensor_rmse_mm, s.sensor_rmse_mm),
                tail(|f| f.sensor_rmse_mm),
                format!(
                    "{:.2}x; {:.2}x",
                    c.sensor_ratio(),
                    c.sensor_ratio_of(&a.median)
                ),
                format!("{:.3} +- {:.3}", m.consistency, s.consistency),
                format!("{}/{}", a.worse_than_start.len(), a.ok()),
                format!("{}/{}", a.ok(), a.trials),
            ]
        })
        .collect();
    (header, rows)
}

/// Per learner, the scenarios where it misses the paper's level (action <= 4.9
/// % of the velocity range, sensor <= 2.9 % of the distance range, consistency
/// <= 0.08), as lines of text; `ranges` gives each scenario's velocity and
/// distance ranges.
pub fn below_paper(cells: &[Cell], ranges: &dyn Fn(&str) -> (f64, f64)) -> Vec<String> {
    cells
        .iter()
        .filter_map(|c| {
            let (v, d) = ranges(&c.scenario);
            let m = &c.aggregate.mean;
            let mut misses = Vec::new();
            let action = 100.0 * m.action_rmse_mm_s / v;
            let sensor = 100.0 * m.sensor_rmse_mm / d;
            // NaN (no ok trial) misses too.
            let within = |value: f64, limit: f64| value <= limit;
            if !within(action, 4.9) {
                misses.push(format!("action {action:.1} %"));
            }
            if !within(sensor, 2.9) {
                misses.push(format!("sensor {sensor:.1} %"));
            }
            if !within(m.consistency, 0.08) {
                misses.push(format!("consistency {:.3}", m.consistency));
            }
            (!misses.is_empty())
                .then(|| format!("{} on {}: {}", c.learner, c.scenario, misses.join(", ")))
        })
        .collect()
}
