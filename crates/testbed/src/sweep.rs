//! Parameter sweeps: every combination of some settings' values, times every
//! seed, through the same trial code as `train`. Runs have stable keys, so a sweep
//! can be split into deterministic shards, resumed after a kill, and merged.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Mutex;

use crate::experiment::{self, Job};
use crate::output;
use crate::reference::{self, MeasuredModels};
use crate::scenario::{Scenario, SettingError};
use crate::summary::{self, Aggregate, Figures, TrialStatus};

/// A sweep that cannot be set up or read back.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SweepError {
    /// A list or range of values is malformed.
    #[error("bad values `{spec}` for {key}: {reason}")]
    Values {
        /// The setting swept.
        key: String,
        /// The values as given.
        spec: String,
        /// What is wrong.
        reason: String,
    },
    /// A setting cannot be applied.
    #[error(transparent)]
    Setting(#[from] SettingError),
    /// A world's reference models cannot be measured.
    #[error("measuring the reference models: {0}")]
    Reference(String),
    /// `--shard K/N` is malformed.
    #[error("bad shard `{0}`: expected K/N with 1 <= K <= N, or auto")]
    Shard(String),
    /// `--shard auto` outside a Slurm array task, or in one it cannot map.
    #[error("--shard auto: {0}")]
    ShardAuto(String),
    /// A results file cannot be read or written.
    #[error("{path}: {reason}")]
    File {
        /// The file.
        path: String,
        /// What is wrong.
        reason: String,
    },
}

/// One setting and the values it takes.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// The setting's key, as for `--set`.
    pub key: String,
    /// Its values, as text for `--set`.
    pub values: Vec<String>,
}

impl Axis {
    /// Values from a list `a,b,c` or an inclusive range `start:step:stop`.
    pub fn parse(key: &str, spec: &str) -> Result<Self, SweepError> {
        let bad = |reason: &str| SweepError::Values {
            key: key.into(),
            spec: spec.into(),
            reason: reason.into(),
        };
        let values: Vec<String> = if spec.contains(':') {
            let parts: Vec<f64> = spec
                .split(':')
                .map(|p| p.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|_| bad("a range is start:step:stop of numbers"))?;
            let [start, step, stop] = parts[..] else {
                return Err(bad("a range is start:step:stop"));
            };
            if !(step > 0.0 && stop >= start && ((stop - start) / step) < 10_000.0) {
                return Err(bad(
                    "a range needs step > 0, stop >= start, and at most 10000 values",
                ));
            }
            let n = ((stop - start) / step + 1e-9).floor() as usize;
            (0..=n)
                .map(|i| format!("{}", start + i as f64 * step))
                .collect()
        } else {
            spec.split(',').map(|v| v.trim().to_string()).collect()
        };
        if values.iter().any(String::is_empty) {
            return Err(bad("empty value"));
        }
        Ok(Self {
            key: key.into(),
            values,
        })
    }
}

/// One run of a sweep: a combination of values and a seed.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Run {
    /// `(key, value)` per axis, in the axes' order.
    pub settings: Vec<(String, String)>,
    /// The trial's master seed.
    pub seed: u64,
}

impl Run {
    /// A stable key naming the run: its settings and seed.
    pub fn key(&self) -> String {
        let mut k: Vec<String> = self
            .settings
            .iter()
            .map(|(a, v)| format!("{a}={v}"))
            .collect();
        k.push(format!("seed={}", self.seed));
        k.join(";")
    }

    /// The key of its combination (without the seed).
    pub fn combination_key(&self) -> String {
        self.settings
            .iter()
            .map(|(a, v)| format!("{a}={v}"))
            .collect::<Vec<_>>()
            .join(";")
    }

    /// The run's scenario: `base` with the run's settings applied.
    pub fn scenario(&self, base: &Scenario) -> Result<Scenario, SettingError> {
        let mut s = base.clone();
        for (k, v) in &self.settings {
            s.set(&format!("{k}={v}"))?;
        }
        Ok(s)
    }
}

/// Every combination of the axes' values times every seed, in a fixed order
/// (the first axis varies slowest, the seed fastest).
pub fn runs(axes: &[Axis], seeds: &[u64]) -> Vec<Run> {
    let mut combos: Vec<Vec<(String, String)>> = vec![Vec::new()];
    for axis in axes {
        combos = combos
            .into_iter()
            .flat_map(|c| {
                axis.values.iter().map(move |v| {
                    let mut c = c.clone();
                    c.push((axis.key.clone(), v.clone()));
                    c
                })
            })
            .collect();
    }
    combos
        .into_iter()
        .flat_map(|settings| {
            seeds.iter().map(move |&seed| Run {
                settings: settings.clone(),
                seed,
            })
        })
        .collect()
}

/// `K/N` into `(k, n)`, 1 <= k <= n.
pub fn parse_shard(spec: &str) -> Result<(usize, usize), SweepError> {
    let bad = || SweepError::Shard(spec.into());
    let (k, n) = spec.split_once('/').ok_or_else(bad)?;
    let (k, n): (usize, usize) = (
        k.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if k == 0 || n == 0 || k > n {
        return Err(bad());
    }
    Ok((k, n))
}

/// The Slurm array variables `--shard auto` reads.
pub const SLURM_ARRAY_VARIABLES: [&str; 3] = [
    "SLURM_ARRAY_TASK_ID",
    "SLURM_ARRAY_TASK_MIN",
    "SLURM_ARRAY_TASK_COUNT",
];

/// `K/N`, or `auto`: in a task of a Slurm array job (`sbatch --array=A-B`),
/// shard `ID - MIN + 1` of `COUNT`, from `SLURM_ARRAY_TASK_ID`,
/// `SLURM_ARRAY_TASK_MIN` and `SLURM_ARRAY_TASK_COUNT` as `env` gives them
/// (the process environment, in a real run). A requeued task keeps its
/// variables, so it runs the same shard again. An array with gaps or a step
/// (`--array=1,3,5`) cannot be mapped and is an error that says so.
pub fn parse_shard_spec(
    spec: &str,
    env: impl Fn(&str) -> Option<String>,
) -> Result<(usize, usize), SweepError> {
    if spec.trim() != "auto" {
        return parse_shard(spec);
    }
    let [id, min, count] = SLURM_ARRAY_VARIABLES.map(|name| {
        env(name).ok_or_else(|| {
            SweepError::ShardAuto(format!(
                "{name} is not set: run it as a task of a Slurm array job (sbatch --array=1-N), \
                 or give --shard K/N"
            ))
        })
    });
    let number = |name: &str, v: Result<String, SweepError>| -> Result<usize, SweepError> {
        let v = v?;
        v.trim()
            .parse()
            .map_err(|_| SweepError::ShardAuto(format!("{name}={v} is not a whole number")))
    };
    let (id, min, count) = (
        number("SLURM_ARRAY_TASK_ID", id)?,
        number("SLURM_ARRAY_TASK_MIN", min)?,
        number("SLURM_ARRAY_TASK_COUNT", count)?,
    );
    let k = id.checked_sub(min).map(|d| d + 1);
    match k {
        Some(k) if k <= count && count > 0 => Ok((k, count)),
        _ => Err(SweepError::ShardAuto(format!(
            "task {id} of an array from {min} with {count} tasks is not one of 1..{count}: \
             an array with gaps or a step cannot be split automatically; give --shard K/N"
        ))),
    }
}

/// Shard `k` of `n`: every `n`-th run from the `k`-th. Shards are disjoint and
/// together cover all runs, whatever the machine that runs them.
pub fn shard(runs: Vec<Run>, k: usize, n: usize) -> Vec<Run> {
    runs.into_iter()
        .enumerate()
        .filter(|(i, _)| i % n == k - 1)
        .map(|(_, r)| r)
        .collect()
}

/// The statistics `sweep_summary.csv` has of each figure, in column order.
pub const SUMMARY_STATISTICS: [&str; 6] = ["mean", "std", "median", "p10", "p90", "n"];

fn metric_values(f: &Figures) -> impl Iterator<Item = f64> + '_ {
    Figures::FIELDS.iter().map(move |field| (field.get)(f))
}

/// A combination's settings and its runs' `(seed, status, figures)`.
type Combination = (Vec<(String, String)>, Vec<(u64, TrialStatus, Figures)>);

/// One combination's figures over its seeds.
#[derive(Debug, Clone, PartialEq)]
pub struct CombinationSummary {
    /// The combination's settings.
    pub settings: Vec<(String, String)>,
    /// Runs that finished `ok`.
    pub runs_ok: usize,
    /// Runs that did not (fell, no model, diverged, error): not in the means.
    pub runs_failed: usize,
    /// Runs that finished `ok` with final models worse than their start
    /// ([`Figures::worse_than_start`]): in the means.
    pub runs_worse_than_start: usize,
    /// Of those, how many by their action model and how many by their
    /// sensor model (a run may be both).
    pub runs_worse_than_start_by_model: (usize, usize),
    /// Mean over the `ok` runs (NaN if none).
    pub mean: Figures,
    /// Standard deviation over them (NaN if none).
    pub std: Figures,
    /// Median, 10th and 90th percentiles over them (NaN if none).
    pub quantiles: [Figures; 3],
    /// How many `ok` runs each figure's statistics are over (those where it
    /// is defined: a re-convergence time is not where a model never came
    /// back).
    pub counted: Figures,
}

/// One finished run's row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The run.
    pub run: Run,
    /// Its figures (NaN where a model was never learned or diverged).
    pub figures: Figures,
    /// How the run ended; only `ok` runs enter a combination's means.
    pub status: TrialStatus,
}

/// The sweep's results, kept whole in memory and written whole to `sweep.csv`.
#[derive(Debug, Clone, Default)]
pub struct Results {
    keys: Vec<String>,
    rows: BTreeMap<String, Row>,
}

fn header(keys: &[String]) -> Vec<String> {
    let mut h: Vec<String> = keys.to_vec();
    h.push("seed".into());
    h.extend(Figures::FIELDS.iter().map(|m| m.name.to_string()));
    h.push("status".into());
    h
}

impl Results {
    /// Empty results for runs over these setting keys.
    pub fn new(keys: Vec<String>) -> Self {
        Self {
            keys,
            rows: BTreeMap::new(),
        }
    }

    /// Whether a run has finished.
    pub fn has(&self, run: &Run) -> bool {
        self.rows.contains_key(&run.key())
    }

    /// Records a finished run.
    pub fn insert(&mut self, row: Row) {
        self.rows.insert(row.run.key(), row);
    }

    /// The finished runs, by key.
    pub fn rows(&self) -> impl Iterator<Item = &Row> {
        self.rows.values()
    }

    /// Writes `sweep.csv` into `dir`, whole.
    pub fn write(&self, dir: &Path) -> Result<(), SweepError> {
        let path = dir.join("sweep.csv");
        output::write_csv(
            &path,
            header(&self.keys),
            self.rows.values().map(|r| {
                let mut cells: Vec<String> =
                    r.run.settings.iter().map(|(_, v)| v.clone()).collect();
                cells.push(r.run.seed.to_string());
                cells.extend(metric_values(&r.figures).map(|v| v.to_string()));
                cells.push(r.status.to_string());
                cells
            }),
        )
        .map_err(|e| file_error(&path, e))
    }

    /// Reads `sweep.csv` from `dir`; its setting columns are what precedes
    /// `seed` in its header. `None` if there is no such file yet.
    pub fn read(dir: &Path) -> Result<Option<Self>, SweepError> {
        let path = dir.join("sweep.csv");
        match std::fs::metadata(&path) {
            Ok(_) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(file_error(&path, e)),
        }
        let table = output::read_csv(&path).map_err(|e| SweepError::File {
            path: path.display().to_string(),
            reason: if e.line == 0 {
                e.reason
            } else {
                format!("line {}: {}", e.line, e.reason)
            },
        })?;
        let head = table.header.join(",");
        let columns: Vec<&str> = table.header.iter().map(String::as_str).collect();
        let keys: Vec<String> = match columns.iter().position(|c| *c == "seed") {
            Some(i) => columns[..i].iter().map(|c| c.to_string()).collect(),
            None => {
                return Err(SweepError::File {
                    path: path.display().to_string(),
                    reason: "no `seed` column: not a sweep's results".into(),
                });
            }
        };
        // Each metric column by name: a column this version does not know is
        // an error; a figure the file lacks (written by an older version) is
        // NaN in its rows.
        let metrics: Vec<&'static crate::summary::Field> = columns[keys.len() + 1..]
            .iter()
            .take(columns.len().saturating_sub(keys.len() + 2))
            .map(|c| {
                Figures::field(c).ok_or_else(|| SweepError::File {
                    path: path.display().to_string(),
                    reason: format!("column `{c}` is not a figure this version knows"),
                })
            })
            .collect::<Result<_, _>>()?;
        if columns.last() != Some(&"status") || columns.len() < keys.len() + 2 {
            return Err(SweepError::File {
                path: path.display().to_string(),
                reason: format!("columns `{head}` are not a sweep's (the last must be `status`)"),
            });
        }
        let mut results = Self::new(keys.clone());
        let keys = &keys;
        for (line, cells) in &table.rows {
            let bad = |reason: &str| SweepError::File {
                path: path.display().to_string(),
                reason: format!("line {line}: {reason}"),
            };
            let settings = keys
                .iter()
                .zip(cells)
                .map(|(k, v)| (k.clone(), v.clone()))
                .collect();
            let seed = cells[keys.len()].parse().map_err(|_| bad("bad seed"))?;
            let mut figures = Figures::filled(f64::NAN);
            for (field, cell) in metrics.iter().zip(&cells[keys.len() + 1..]) {
                *(field.get_mut)(&mut figures) = cell.parse::<f64>().map_err(|_| {
                    bad(&format!(
                        "`{cell}` in column {} is not a number",
                        field.name
                    ))
                })?;
            }
            results.insert(Row {
                run: Run { settings, seed },
                figures,
                status: TrialStatus::parse(&cells[cells.len() - 1]),
            });
        }
        Ok(Some(results))
    }

    /// Mean and standard deviation per combination, over its runs that finished
    /// `ok`.
    pub fn summary(&self) -> Vec<CombinationSummary> {
        let mut groups: BTreeMap<String, Combination> = BTreeMap::new();
        for r in self.rows.values() {
            groups
                .entry(r.run.combination_key())
                .or_insert_with(|| (r.run.settings.clone(), Vec::new()))
                .1
                .push((r.run.seed, r.status.clone(), r.figures));
        }
        groups
            .into_values()
            .map(|(settings, trials)| {
                let a = Aggregate::of(&trials);
                CombinationSummary {
                    settings,
                    runs_ok: a.ok(),
                    runs_failed: a.failed.len(),
                    runs_worse_than_start: a.worse_than_start.len(),
                    runs_worse_than_start_by_model: a.worse_by_model(),
                    mean: a.mean,
                    std: a.std,
                    quantiles: [a.median, a.p10, a.p90],
                    counted: a.counted,
                }
            })
            .collect()
    }

    /// Writes `sweep_summary.csv` into `dir`, whole: per combination, the number
    /// of runs that finished ok, that did not, and that finished ok but worse
    /// than their start, and each metric's mean, std, median, p10 and p90
    /// over the ok ones, and `n`, how many of them those are over.
    pub fn write_summary(&self, dir: &Path) -> Result<(), SweepError> {
        let path = dir.join("sweep_summary.csv");
        let mut h: Vec<String> = self.keys.clone();
        h.push("runs_ok".into());
        h.push("runs_failed".into());
        h.push("runs_worse_than_start".into());
        h.push("runs_worse_than_start_action".into());
        h.push("runs_worse_than_start_sensor".into());
        for m in Figures::FIELDS {
            for stat in SUMMARY_STATISTICS {
                h.push(format!("{}_{stat}", m.name));
            }
        }
        output::write_csv(
            &path,
            &h,
            self.summary().into_iter().map(|g| {
                let mut cells: Vec<String> = g.settings.into_iter().map(|(_, v)| v).collect();
                cells.push(g.runs_ok.to_string());
                cells.push(g.runs_failed.to_string());
                cells.push(g.runs_worse_than_start.to_string());
                cells.push(g.runs_worse_than_start_by_model.0.to_string());
                cells.push(g.runs_worse_than_start_by_model.1.to_string());
                let [median, p10, p90] = &g.quantiles;
                for field in Figures::FIELDS {
                    for f in [&g.mean, &g.std, median, p10, p90, &g.counted] {
                        cells.push((field.get)(f).to_string());
                    }
                }
                cells
            }),
        )
        .map_err(|e| file_error(&path, e))
    }

    /// The rows of another sweep over the same settings, added to these.
    pub fn merge(&mut self, other: Results) -> Result<(), SweepError> {
        if other.keys != self.keys {
            return Err(SweepError::File {
                path: "merge".into(),
                reason: format!("settings {:?} differ from {:?}", other.keys, self.keys),
            });
        }
        self.rows.extend(other.rows);
        Ok(())
    }

    /// The setting keys (column order).
    pub fn keys(&self) -> &[String] {
        &self.keys
    }
}

fn file_error(path: &Path, e: std::io::Error) -> SweepError {
    SweepError::File {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// Runs `runs[i]` (in scenario `scenarios[i]`) for every `i` in `todo`,
/// measuring one reference per distinct robot and world first (read from
/// `cache` if there) and simulating each world once for all the runs that
/// share it; `results` gets each row as it finishes and is rewritten whole
/// to `out` each time, so a killed sweep resumes where it stopped. `say`
/// reports what it measures, `done` each finished run. Returns the results
/// and the first world's velocity range (mm/s), for scoring.
pub fn run_pending(
    results: Results,
    (runs, scenarios, todo): (&[Run], &[Scenario], &[usize]),
    cache: &Path,
    out: &Path,
    say: &dyn Fn(&str),
    done: &(dyn Fn() + Sync),
) -> Result<(Results, Option<f64>), SweepError> {
    let mut references: BTreeMap<String, MeasuredModels> = BTreeMap::new();
    for &i in todo {
        let key = scenarios[i].reference_key();
        if let std::collections::btree_map::Entry::Vacant(slot) = references.entry(key) {
            say(&format!(
                "measuring the reference models for {}...",
                slot.key()
            ));
            let models = reference::measured_models(&scenarios[i], Some(cache))
                .map_err(|e| SweepError::Reference(e.to_string()))?;
            slot.insert(models);
        }
    }
    let jobs: Vec<Job<'_>> = todo
        .iter()
        .map(|&i| Job {
            scenario: &scenarios[i],
            models: &references[&scenarios[i].reference_key()],
            seed: runs[i].seed,
            learner: &scenarios[i].learner_name,
        })
        .collect();
    let worlds: std::collections::BTreeSet<String> = jobs
        .iter()
        .map(|j| experiment::world_key_for(j.scenario, j.seed, j.learner))
        .collect();
    say(&format!("{} distinct worlds to simulate", worlds.len()));
    let shared = Mutex::new((results, None::<SweepError>));
    experiment::run_jobs(&jobs, &|k, result| {
        let (i, job) = (todo[k], &jobs[k]);
        let best_possible = summary::best_possible(&job.models.reference(), &job.scenario.learner);
        let (_, status, figures) = summary::trial_row(
            job.seed,
            result.as_ref().map_err(|e| e.to_string()),
            best_possible,
        );
        if let Ok(mut guard) = shared.lock() {
            guard.0.insert(Row {
                run: runs[i].clone(),
                figures,
                status,
            });
            if let Err(e) = guard.0.write(out) {
                guard.1.get_or_insert(e);
            }
        }
        done();
    });
    let (results, write_error) = shared.into_inner().unwrap_or_else(|p| p.into_inner());
    if let Some(e) = write_error {
        return Err(e);
    }
    let velocity_range = references
        .values()
        .next()
        .map(MeasuredModels::velocity_range_mm_s);
    Ok((results, velocity_range))
}

#[cfg(test)]
mod shard_tests {
    use super::*;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |name| {
            vars.iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| v.to_string())
        }
    }

    #[test]
    fn shard_auto_reads_the_slurm_array_task() {
        let task = |id, min, count| {
            [
                ("SLURM_ARRAY_TASK_ID", id),
                ("SLURM_ARRAY_TASK_MIN", min),
                ("SLURM_ARRAY_TASK_COUNT", count),
            ]
        };
        assert_eq!(
            parse_shard_spec("auto", env(&task("3", "1", "4"))).ok(),
            Some((3, 4))
        );
        // A zero-based array: task 0 is shard 1.
        assert_eq!(
            parse_shard_spec("auto", env(&task("0", "0", "4"))).ok(),
            Some((1, 4))
        );
        assert_eq!(parse_shard_spec("2/5", env(&[])).ok(), Some((2, 5)));
        let e = parse_shard_spec("auto", env(&[]))
            .expect_err("no array")
            .to_string();
        assert!(e.contains("SLURM_ARRAY_TASK_ID is not set"), "{e}");
        // --array=1,3,5: task 5 of three cannot be mapped.
        let e = parse_shard_spec("auto", env(&task("5", "1", "3")))
            .expect_err("gaps")
            .to_string();
        assert!(e.contains("give --shard K/N"), "{e}");
        assert!(parse_shard_spec("auto", env(&task("x", "1", "3"))).is_err());
    }
}
