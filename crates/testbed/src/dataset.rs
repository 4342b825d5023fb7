//! Recorded worlds on disk. A trial's recording is a dataset: what a learner
//! may see (`events.csv`: each frame's command with its interval, and the
//! reading at its end or none), the ground truth kept apart (`truth.csv`), and
//! `dataset.json` naming the robot, the scenario (every setting), the seed, the
//! format version, the measured reference models and what made it. Any learner
//! can be replayed over it with no physics; numbers are written so that they
//! read back to the same bits.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::output;
use crate::provenance::Provenance;
use crate::reference::MeasuredModels;
use crate::scenario::Scenario;
use crate::trial::{FrameRecord, Recording, Truth};

/// The format this code writes and reads.
pub const FORMAT_VERSION: u32 = 2;

/// The oldest format this code reads: version 1 had no `blew_up` column in
/// `truth.csv` (its trials read as not blown up).
const OLDEST_FORMAT_VERSION: u32 = 1;

const EVENTS_HEADER: &[&str] = &["t_s", "dt_s", "command", "obs_px"];
const TRUTH_HEADER: &[&str] = &[
    "t_s",
    "x_true_mm",
    "lateral_mm",
    "yaw_rad",
    "upright",
    "blew_up",
];
const TRUTH_HEADER_V1: &[&str] = &["t_s", "x_true_mm", "lateral_mm", "yaw_rad", "upright"];

/// A dataset that cannot be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DatasetError {
    /// A file is missing or unreadable.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// A file's contents are wrong.
    #[error("{path}:{line}: {reason}")]
    Malformed {
        /// The file.
        path: String,
        /// The line (1-based; 0 for the whole file).
        line: usize,
        /// What is wrong.
        reason: String,
    },
}

/// What a dataset says about itself.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DatasetMeta {
    /// [`FORMAT_VERSION`] when it was written.
    pub format_version: u32,
    /// The robot's name (the URDF's `<robot name>`).
    pub robot: String,
    /// The scenario, every setting, as a scenario file (`config.toml`'s form).
    pub scenario: String,
    /// The trial's master seed.
    pub seed: u64,
    /// Frames in `events.csv` and `truth.csv`.
    pub frames: usize,
    /// The measured reference models of the scenario's robot and world.
    pub reference: MeasuredModels,
    /// What recorded it.
    pub provenance: Provenance,
}

impl DatasetMeta {
    /// The description of `recording`, a trial of `scenario` judged against
    /// `reference`.
    pub fn new(
        scenario: &Scenario,
        reference: &MeasuredModels,
        recording: &Recording,
        provenance: &Provenance,
    ) -> Self {
        Self {
            format_version: FORMAT_VERSION,
            robot: scenario.description.urdf.name.clone(),
            scenario: scenario.to_toml(),
            seed: recording.seed,
            frames: recording.frames.len(),
            reference: reference.clone(),
            provenance: provenance.clone(),
        }
    }
}

/// A dataset read back: its description and its frames.
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    /// What it says about itself.
    pub meta: DatasetMeta,
    /// The recorded frames.
    pub recording: Recording,
}

/// Writes a recording as a dataset into `dir` (created if needed).
pub fn write(dir: &Path, recording: &Recording, meta: &DatasetMeta) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let cell = |v: Option<f64>| v.map(|x| x.to_string()).unwrap_or_default();
    output::write_csv(
        &dir.join("events.csv"),
        EVENTS_HEADER,
        recording.frames.iter().map(|f| {
            vec![
                f.t_s.to_string(),
                f.dt_s.to_string(),
                f.command.to_string(),
                cell(f.obs_px),
            ]
        }),
    )?;
    output::write_csv(
        &dir.join("truth.csv"),
        TRUTH_HEADER,
        recording.frames.iter().map(|f| {
            let t = &f.truth;
            vec![
                f.end_s().to_string(),
                t.x_mm.to_string(),
                t.lateral_mm.to_string(),
                t.yaw_rad.to_string(),
                u8::from(t.upright).to_string(),
                u8::from(t.blew_up).to_string(),
            ]
        }),
    )?;
    output::write_json(&dir.join("dataset.json"), meta)
}

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> DatasetError + '_ {
    move |source| DatasetError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// The rows of a CSV file with this exact header, split into cells, each
/// with its line.
fn rows(path: &Path, header: &[&str]) -> Result<Vec<(usize, Vec<String>)>, DatasetError> {
    let malformed = |line: u64, reason: String| DatasetError::Malformed {
        path: path.display().to_string(),
        line: usize::try_from(line).unwrap_or(usize::MAX),
        reason,
    };
    std::fs::metadata(path).map_err(io_error(path))?;
    let table = output::read_csv(path).map_err(|e| malformed(e.line, e.reason))?;
    if table
        .header
        .iter()
        .map(|h| h.trim())
        .ne(header.iter().copied())
    {
        return Err(malformed(
            1,
            format!(
                "header `{}`, expected `{}`",
                table.header.join(","),
                header.join(",")
            ),
        ));
    }
    Ok(table
        .rows
        .into_iter()
        .filter(|(_, cells)| !(cells.len() == 1 && cells[0].trim().is_empty()))
        .map(|(line, cells)| {
            (
                usize::try_from(line).unwrap_or(usize::MAX),
                cells.into_iter().map(|c| c.trim().to_string()).collect(),
            )
        })
        .collect())
}

/// Checks that a dataset's reference has enough points for the degrees its
/// scenario's learner fits (a polynomial of degree d through fewer than d + 1
/// points is no yardstick), each finite.
fn check_reference(meta: &DatasetMeta) -> Result<(), String> {
    let learner = toml::from_str::<toml::Table>(&meta.scenario)
        .ok()
        .and_then(|t| t.get("learner").and_then(toml::Value::as_table).cloned())
        .unwrap_or_default();
    let degree = |key: &str, default: i64| {
        learner
            .get(key)
            .and_then(toml::Value::as_integer)
            .unwrap_or(default)
    };
    let r = &meta.reference;
    for (what, points, d) in [
        ("action", r.action.len(), degree("action_degree", 4)),
        ("sensor", r.sensor.len(), degree("sensor_degree", 3)),
    ] {
        if i64::try_from(points).unwrap_or(i64::MAX) <= d {
            return Err(format!(
                "its reference {what} model has {points} points: a polynomial of degree {d} \
                 needs at least {}",
                d + 1
            ));
        }
    }
    let finite = r
        .action
        .iter()
        .all(|m| m.command.is_finite() && m.velocity_mm_s.is_finite())
        && r.sensor
            .iter()
            .all(|m| m.distance_mm.is_finite() && m.obs_px.is_finite() && m.obs_px > 0.0);
    if finite {
        Ok(())
    } else {
        Err("its reference holds a point that is not finite (or a reading <= 0 px)".into())
    }
}

/// Reads a dataset from `dir`, checking its format version and that its files
/// agree (same frames, times in order, finite numbers).
pub fn read(dir: &Path) -> Result<Dataset, DatasetError> {
    let meta_path = dir.join("dataset.json");
    let text =
        quadsim::files::read_text(&meta_path, quadsim::files::SETTINGS_LIMIT).map_err(|e| {
            DatasetError::Malformed {
                path: meta_path.display().to_string(),
                line: 0,
                reason: e.to_string(),
            }
        })?;
    let meta: DatasetMeta = serde_json::from_str(&text).map_err(|e| DatasetError::Malformed {
        path: meta_path.display().to_string(),
        line: e.line(),
        reason: e.to_string(),
    })?;
    if !(OLDEST_FORMAT_VERSION..=FORMAT_VERSION).contains(&meta.format_version) {
        return Err(DatasetError::Malformed {
            path: meta_path.display().to_string(),
            line: 0,
            reason: format!(
                "format version {}, this testbed reads {OLDEST_FORMAT_VERSION} to {FORMAT_VERSION}",
                meta.format_version
            ),
        });
    }
    check_reference(&meta).map_err(|reason| DatasetError::Malformed {
        path: meta_path.display().to_string(),
        line: 0,
        reason,
    })?;
    let (events_path, truth_path) = (dir.join("events.csv"), dir.join("truth.csv"));
    let events = rows(&events_path, EVENTS_HEADER)?;
    let truth_header = if meta.format_version == 1 {
        TRUTH_HEADER_V1
    } else {
        TRUTH_HEADER
    };
    let truth = rows(&truth_path, truth_header)?;
    let bad = |path: &Path, line: usize, reason: String| DatasetError::Malformed {
        path: path.display().to_string(),
        line,
        reason,
    };
    if events.len() != truth.len() || events.len() != meta.frames {
        return Err(bad(
            dir,
            0,
            format!(
                "{} event rows, {} truth rows, dataset.json says {} frames",
                events.len(),
                truth.len(),
                meta.frames
            ),
        ));
    }
    let number = |path: &Path, line: usize, name: &str, cell: &str| {
        cell.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                bad(
                    path,
                    line,
                    format!("{name} `{cell}` is not a finite number"),
                )
            })
    };
    let mut frames = Vec::with_capacity(events.len());
    let mut clock_s = 0.0;
    for ((line, e), (tline, t)) in events.iter().zip(&truth) {
        let (t_s, dt_s, command) = (
            number(&events_path, *line, "t_s", &e[0])?,
            number(&events_path, *line, "dt_s", &e[1])?,
            number(&events_path, *line, "command", &e[2])?,
        );
        let obs_px = match e[3].as_str() {
            "" => None,
            cell => Some(number(&events_path, *line, "obs_px", cell)?),
        };
        // A reading is the beacon's height in the image: more than nothing.
        if let Some(obs) = obs_px.filter(|o| *o <= 0.0) {
            return Err(bad(
                &events_path,
                *line,
                format!("obs_px {obs} is not a reading (a height in the image is > 0 px)"),
            ));
        }
        if dt_s <= 0.0 || t_s < clock_s - 1e-9 {
            return Err(bad(
                &events_path,
                *line,
                format!("frame [{t_s}, +{dt_s}] s is out of order"),
            ));
        }
        clock_s = t_s + dt_s;
        // Each truth row is the state at the end of its event row's frame.
        let truth_t_s = number(&truth_path, *tline, "t_s", &t[0])?;
        if (truth_t_s - clock_s).abs() > 1e-6 * clock_s.abs().max(1.0) {
            return Err(bad(
                &truth_path,
                *tline,
                format!(
                    "t_s {truth_t_s} is not the end of its frame in events.csv ({clock_s} s): \
                     the truth rows are out of order or not this recording's"
                ),
            ));
        }
        let flag = |column: usize, name: &str| match t.get(column).map(String::as_str) {
            None => Ok(false),
            Some("1") => Ok(true),
            Some("0") => Ok(false),
            Some(other) => Err(bad(&truth_path, *tline, format!("{name} `{other}`"))),
        };
        let (upright, blew_up) = (flag(4, "upright")?, flag(5, "blew_up")?);
        frames.push(FrameRecord {
            t_s,
            dt_s,
            command,
            obs_px,
            truth: Truth {
                x_mm: number(&truth_path, *tline, "x_true_mm", &t[1])?,
                lateral_mm: number(&truth_path, *tline, "lateral_mm", &t[2])?,
                yaw_rad: number(&truth_path, *tline, "yaw_rad", &t[3])?,
                upright,
                blew_up,
            },
        });
    }
    Ok(Dataset {
        recording: Recording {
            seed: meta.seed,
            frames,
            realtime_factor: f64::NAN,
        },
        meta,
    })
}

/// The datasets named by `paths`: each path is a dataset itself, or a run
/// directory whose `trial-*` subdirectories are datasets (in seed order).
pub fn find(paths: &[PathBuf]) -> Result<Vec<PathBuf>, DatasetError> {
    let mut found = Vec::new();
    for path in paths {
        if path.join("dataset.json").is_file() {
            found.push(path.clone());
            continue;
        }
        let entries = std::fs::read_dir(path).map_err(io_error(path))?;
        let mut trials: Vec<(u64, PathBuf)> = entries
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.join("dataset.json").is_file())
            .filter_map(|p| {
                let seed = p
                    .file_name()?
                    .to_str()?
                    .strip_prefix("trial-")?
                    .parse()
                    .ok()?;
                Some((seed, p))
            })
            .collect();
        if trials.is_empty() {
            return Err(DatasetError::Malformed {
                path: path.display().to_string(),
                line: 0,
                reason: "neither a dataset (dataset.json) nor a run directory of trial-*/ datasets"
                    .into(),
            });
        }
        trials.sort();
        found.extend(trials.into_iter().map(|t| t.1));
    }
    Ok(found)
}
