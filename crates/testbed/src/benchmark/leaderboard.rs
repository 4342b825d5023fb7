//! The leaderboard: a row per (learner, scenario, seed) written to and read
//! from `leaderboard.csv`, shards' rows merged, and a cell per (learner,
//! scenario) aggregated over its seeds, with the summary table.

use std::path::Path;

use crate::output;
use crate::summary::{Aggregate, Figures, TrialStatus};

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
/// figure ([`Figures::FIELDS`]), whether it ended worse than its start in
/// all and by model ([`Figures::WORSE_THAN_START`]), and its status.
pub fn write_leaderboard_csv(path: &Path, entries: &[Entry]) -> std::io::Result<()> {
    let header = ["learner", "scenario", "seed"]
        .into_iter()
        .chain(Figures::FIELDS.iter().map(|f| f.name))
        .chain(Figures::WORSE_THAN_START.iter().map(|w| w.0))
        .chain(["status"]);
    output::write_csv(
        path,
        header,
        entries.iter().map(|e| {
            let mut cells = vec![e.learner.clone(), e.scenario.clone(), e.seed.to_string()];
            cells.extend(
                Figures::FIELDS
                    .iter()
                    .map(|f| (f.get)(&e.figures).to_string()),
            );
            cells.extend(
                Figures::WORSE_THAN_START
                    .iter()
                    .map(|w| (e.status.is_ok() && (w.1)(&e.figures)).to_string()),
            );
            cells.push(e.status.to_string());
            cells
        }),
    )
}

/// A `leaderboard.csv` that cannot be read back.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {reason}")]
pub struct LeaderboardError {
    /// The file.
    pub path: String,
    /// What is wrong, with the line.
    pub reason: String,
}

/// Reads back what [`write_leaderboard_csv`] wrote: figures by column name (a
/// figure the file lacks is NaN; a column this version does not know, a
/// truncated line or a bad number is an error naming the file and line).
/// The worse-than-start columns before the status are derived from the
/// figures and not read; a file from before the by-model ones reads too.
pub fn read_leaderboard_csv(path: &Path) -> Result<Vec<Entry>, LeaderboardError> {
    let error = |reason: String| LeaderboardError {
        path: path.display().to_string(),
        reason,
    };
    let table = output::read_csv(path).map_err(|e| {
        error(if e.line == 0 {
            e.reason
        } else {
            format!("line {}: {}", e.line, e.reason)
        })
    })?;
    let head: Vec<&str> = table.header.iter().map(String::as_str).collect();
    let n = head.len();
    // The figures end where the derived columns, then the status, begin.
    let derived = head[..n.saturating_sub(1)]
        .iter()
        .rev()
        .take_while(|c| Figures::WORSE_THAN_START.iter().any(|w| w.0 == **c))
        .count();
    let end = n.saturating_sub(1 + derived);
    if n < 6
        || head[..3] != ["learner", "scenario", "seed"]
        || head[n - 1] != "status"
        || head.get(end) != Some(&"worse_than_start")
    {
        return Err(error(format!(
            "columns `{}` are not a leaderboard's",
            head.join(",")
        )));
    }
    let fields: Vec<&'static crate::summary::Field> = head[3..end]
        .iter()
        .map(|c| {
            Figures::field(c)
                .ok_or_else(|| error(format!("column `{c}` is not a figure this version knows")))
        })
        .collect::<Result<_, _>>()?;
    let mut entries = Vec::new();
    for (line, cells) in &table.rows {
        let bad = |reason: String| error(format!("line {line}: {reason}"));
        let mut figures = Figures::filled(f64::NAN);
        for (field, cell) in fields.iter().zip(&cells[3..end]) {
            *(field.get_mut)(&mut figures) = cell
                .parse()
                .map_err(|_| bad(format!("`{cell}` in column {} is not a number", field.name)))?;
        }
        entries.push(Entry {
            learner: cells[0].to_string(),
            scenario: cells[1].to_string(),
            seed: cells[2]
                .parse()
                .map_err(|_| bad(format!("`{}` is not a seed", cells[2])))?,
            status: TrialStatus::parse(&cells[n - 1]),
            figures,
        });
    }
    Ok(entries)
}

/// The entries of several shards' leaderboards as one, refusing an entry
/// (learner, scenario, seed) that two of them hold.
pub fn merge_entries(parts: Vec<(String, Vec<Entry>)>) -> Result<Vec<Entry>, LeaderboardError> {
    let mut seen: std::collections::BTreeMap<(String, String, u64), String> = Default::default();
    let mut out = Vec::new();
    for (source, entries) in parts {
        for e in entries {
            let key = (e.learner.clone(), e.scenario.clone(), e.seed);
            if let Some(first) = seen.insert(key, source.clone()) {
                return Err(LeaderboardError {
                    path: source,
                    reason: format!(
                        "{} on {} seed {} is also in {first}: shards must be disjoint",
                        e.learner, e.scenario, e.seed
                    ),
                });
            }
            out.push(e);
        }
    }
    Ok(out)
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
/// median), the information floors (the metric's and the likelihood's) by
/// root mean square over the trials (the error over each by RMS, and the
/// per-trial ratios' median and p90), the
/// consistency, the trials worse than their start (in the
/// means), and the trials ok.
pub fn summary_table(cells: &[Cell]) -> (Vec<String>, Vec<Vec<String>>) {
    let header = [
        "scenario",
        "learner",
        "action mm/s",
        "action median [p10, p90]",
        "action / best (mean; median)",
        "action floor, RMS (/ floor; median, p90)",
        "action likelihood's floor, RMS (/ floor; median, p90)",
        "sensor mm",
        "sensor median [p10, p90]",
        "sensor / best (mean; median)",
        "sensor floor, RMS (/ floor; median, p90)",
        "sensor likelihood's floor, RMS (/ floor; median, p90)",
        "consistency",
        "worse than start (action, sensor)",
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
                a.floor.action.cell(),
                a.floor.action_likelihood.cell(),
                format!("{:.1} +- {:.1}", m.sensor_rmse_mm, s.sensor_rmse_mm),
                tail(|f| f.sensor_rmse_mm),
                format!(
                    "{:.2}x; {:.2}x",
                    c.sensor_ratio(),
                    c.sensor_ratio_of(&a.median)
                ),
                a.floor.sensor.cell(),
                a.floor.sensor_likelihood.cell(),
                format!("{:.3} +- {:.3}", m.consistency, s.consistency),
                {
                    let (action, sensor) = a.worse_by_model();
                    format!(
                        "{}/{} ({action}, {sensor})",
                        a.worse_than_start.len(),
                        a.ok()
                    )
                },
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
            let [action_ok, sensor_ok, consistency_ok] = m.at_paper_level(v, d);
            if !action_ok {
                misses.push(format!("action {:.1} %", 100.0 * m.action_rmse_mm_s / v));
            }
            if !sensor_ok {
                misses.push(format!("sensor {:.1} %", 100.0 * m.sensor_rmse_mm / d));
            }
            if !consistency_ok {
                misses.push(format!("consistency {:.3}", m.consistency));
            }
            (!misses.is_empty())
                .then(|| format!("{} on {}: {}", c.learner, c.scenario, misses.join(", ")))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(learner: &str, seed: u64, action: f64) -> Entry {
        Entry {
            learner: learner.into(),
            scenario: "default".into(),
            seed,
            status: TrialStatus::Ok,
            figures: Figures {
                action_rmse_mm_s: action,
                ..Figures::filled(f64::NAN)
            },
        }
    }

    #[test]
    fn a_leaderboard_reads_back_as_written_and_shards_merge_only_when_disjoint() {
        let dir = std::env::temp_dir().join(format!("leaderboard-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("leaderboard.csv");
        let entries = vec![entry("scasm", 1, 12.5), entry("batch-ml", 1, 0.1 + 0.2)];
        write_leaderboard_csv(&path, &entries).expect("write");
        let back = read_leaderboard_csv(&path).expect("read");
        assert_eq!(back.len(), 2);
        assert_eq!(
            back[1].figures.action_rmse_mm_s.to_bits(),
            (0.1f64 + 0.2).to_bits()
        );
        assert!(back[0].figures.sensor_rmse_mm.is_nan());
        let merged = merge_entries(vec![
            ("a".into(), back.clone()),
            ("b".into(), vec![entry("scasm", 2, 9.0)]),
        ])
        .expect("disjoint");
        assert_eq!(merged.len(), 3);
        let e = merge_entries(vec![("a".into(), back.clone()), ("b".into(), back)])
            .expect_err("the same entries twice")
            .to_string();
        assert!(e.contains("scasm on default seed 1 is also in a"), "{e}");
        // Truncated mid-line: refused, naming the file and the line.
        let text = std::fs::read_to_string(&path).expect("text");
        std::fs::write(&path, &text[..text.len() - 9]).expect("truncate");
        let e = read_leaderboard_csv(&path)
            .expect_err("truncated")
            .to_string();
        assert!(e.contains("leaderboard.csv: line 3"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_crashed_learners_multi_line_status_reads_back_as_one_row() {
        // A learner program's traceback, with commas, quotes and line breaks,
        // is the status of its trial: the file must still hold one row per
        // entry, and read back to the same status (issue 55).
        let dir = std::env::temp_dir().join(format!("leaderboard-crash-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("leaderboard.csv");
        let status = TrialStatus::Error(
            "crashed: it exited with status 1; the last lines of its stderr:\n    \
             Traceback (most recent call last):\n      File \"crash.py\", line 3, in <module>\n    \
             ValueError: a, b"
                .into(),
        );
        let mut crashed = entry("crash-py", 2, f64::NAN);
        crashed.status = status.clone();
        let entries = vec![entry("scasm", 1, 12.5), crashed, entry("scasm", 3, 9.0)];
        write_leaderboard_csv(&path, &entries).expect("write");
        let back = read_leaderboard_csv(&path).expect("read");
        assert_eq!(back.len(), 3);
        assert_eq!(back[1].status, status);
        assert_eq!(back[2].seed, 3);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn worse_than_start_is_written_by_model_and_an_older_file_still_reads() {
        let dir = std::env::temp_dir().join(format!("leaderboard-worse-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("leaderboard.csv");
        // Worse by the sensor model only.
        let mut e = entry("scasm", 4, 10.0);
        e.figures.action_a0_rmse_mm_s = 20.0;
        e.figures.sensor_rmse_mm = 90.0;
        e.figures.sensor_start_rmse_mm = 80.0;
        write_leaderboard_csv(&path, &[e]).expect("write");
        let table = output::read_csv(&path).expect("csv");
        let cell = |name: &str| {
            let i = table.header.iter().position(|h| h == name).expect(name);
            table.rows[0].1[i].clone()
        };
        assert_eq!(cell("worse_than_start"), "true");
        assert_eq!(cell("worse_than_start_action"), "false");
        assert_eq!(cell("worse_than_start_sensor"), "true");
        let back = read_leaderboard_csv(&path).expect("read");
        assert_eq!(back[0].figures.sensor_start_rmse_mm, 80.0);
        // A leaderboard written before the by-model columns: the same figures.
        let text = std::fs::read_to_string(&path).expect("text");
        let older = text
            .replace(",worse_than_start_action,worse_than_start_sensor,", ",")
            .replace(",true,false,true,", ",true,");
        assert_ne!(older, text);
        std::fs::write(&path, older).expect("older");
        let back = read_leaderboard_csv(&path).expect("an older leaderboard reads");
        assert_eq!(back[0].figures.sensor_rmse_mm, 90.0);
        assert_eq!(back[0].status, TrialStatus::Ok);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
