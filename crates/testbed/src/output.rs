//! Writing results, each file whole or not at all (to a temporary file first,
//! then renamed): the measured models in the paper's column layout, a run's
//! settings, and each trial's dataset, trace, errors over time and models.

use std::path::Path;

use scasm::Polynomial;

use crate::measure::{MeasuredReading, MeasuredVelocity};
use crate::provenance::Provenance;
use crate::reference::Judgement;
use crate::scenario::Scenario;
use crate::trial::{TraceRow, TrialOutcome};

/// Writes `header` and `rows` to `path` as CSV (quoted where a cell needs it,
/// by the `csv` crate): to `path.tmp`, then renamed into place, so that a
/// reader never sees half a file.
pub fn write_csv<H, R>(path: &Path, header: H, rows: R) -> std::io::Result<()>
where
    H: IntoIterator,
    H::Item: AsRef<[u8]>,
    R: IntoIterator<Item = Vec<String>>,
{
    let tmp = path.with_extension("csv.tmp");
    {
        let mut w = csv::WriterBuilder::new()
            .flexible(false)
            .from_writer(std::io::BufWriter::new(std::fs::File::create(&tmp)?));
        w.write_record(header)?;
        for r in rows {
            w.write_record(&r)?;
        }
        w.flush()?;
    }
    std::fs::rename(&tmp, path)
}

/// A CSV file as read by [`read_csv`]: its header and each row's cells with
/// the line the row starts on (1-based, the header being line 1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CsvTable {
    /// The header's cells.
    pub header: Vec<String>,
    /// Each row: the line it starts on, and its cells.
    pub rows: Vec<(u64, Vec<String>)>,
}

/// Why a CSV file could not be read: the line (0 for the file as a whole)
/// and what is wrong there.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CsvError {
    /// The line, 1-based; 0 for the whole file.
    pub line: u64,
    /// What is wrong.
    pub reason: String,
}

/// Reads a CSV file whole (by the `csv` crate: quoted cells may hold commas,
/// quotes and line breaks), a regular file of at most
/// [`quadsim::files::TABLE_LIMIT`] bytes. Every row must have as many cells as the header;
/// blank lines are skipped. Errors name the line.
pub fn read_csv(path: &Path) -> Result<CsvTable, CsvError> {
    let whole = |reason: String| CsvError { line: 0, reason };
    let file = quadsim::files::open(path, quadsim::files::TABLE_LIMIT)
        .map_err(|e| whole(e.to_string()))?;
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(std::io::BufReader::new(file));
    let mut records = reader.records();
    let header: Vec<String> = match records.next() {
        Some(Ok(h)) => h.iter().map(String::from).collect(),
        Some(Err(e)) => return Err(csv_error(&e)),
        None => return Err(whole("empty file".into())),
    };
    let mut rows = Vec::new();
    for record in records {
        let record = record.map_err(|e| csv_error(&e))?;
        let line = record.position().map_or(0, csv::Position::line);
        if record.len() != header.len() {
            return Err(CsvError {
                line,
                reason: format!(
                    "{} cells where the header has {} columns (a truncated or damaged file?)",
                    record.len(),
                    header.len()
                ),
            });
        }
        rows.push((line, record.iter().map(String::from).collect()));
    }
    Ok(CsvTable { header, rows })
}

fn csv_error(e: &csv::Error) -> CsvError {
    CsvError {
        line: e.position().map_or(0, csv::Position::line),
        reason: match e.kind() {
            csv::ErrorKind::Utf8 { .. } => "not UTF-8 text".into(),
            _ => e.to_string(),
        },
    }
}

/// Writes `bytes` to `path` via `path.tmp` and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = std::path::PathBuf::from(tmp);
    std::fs::write(&tmp, bytes)?;
    std::fs::rename(&tmp, path)
}

/// Writes `value` as pretty JSON.
pub fn write_json<T: serde::Serialize + ?Sized>(path: &Path, value: &T) -> std::io::Result<()> {
    let text = serde_json::to_string_pretty(value).map_err(std::io::Error::other)?;
    write_atomic(path, text.as_bytes())
}

/// `models.json`: `{"action": [...], "sensor": [...]}`, raw-unit coefficients,
/// lowest power first (`null` for a model never learned).
pub fn write_models(
    path: &Path,
    action: Option<Polynomial>,
    sensor: Option<Polynomial>,
) -> std::io::Result<()> {
    write_json(
        path,
        &serde_json::json!({
            "action": action.map(|p| p.coeffs().to_vec()),
            "sensor": sensor.map(|p| p.coeffs().to_vec()),
        }),
    )
}

/// `config.toml` in `dir`: every setting of the run's scenario, so that
/// `--config DIR/config.toml` runs it again, headed by what made it.
pub fn write_config(dir: &Path, scenario: &Scenario, made_by: &Provenance) -> std::io::Result<()> {
    let text = format!(
        "# Every setting of this run; `--config` this file to run it again.\n\
         # Made by {}\n# Command: {}\n\n{}",
        made_by.describe(),
        made_by.command,
        scenario.to_toml()
    );
    write_atomic(&dir.join("config.toml"), text.as_bytes())
}

/// A trial's learner files in `dir` (created if needed): `trace.csv`,
/// `errors_over_time.csv` and `models.json`.
pub fn write_learner_run(dir: &Path, outcome: &TrialOutcome) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    write_trace(&dir.join("trace.csv"), &outcome.trace)?;
    write_errors_over_time(&dir.join("errors_over_time.csv"), &outcome.over_time)?;
    write_models(
        &dir.join("models.json"),
        outcome.action_model,
        outcome.sensor_model,
    )
}

/// `measured_action.csv` in `dir`:
/// `command,velocity_mm_s,std_mm_s,min_mm_s,max_mm_s,upright,blew_up` (the mean
/// of the timings, their spread, whether the robot stayed upright and whether
/// the physics blew up).
pub fn write_measured_action(dir: &Path, rows: &[MeasuredVelocity]) -> std::io::Result<()> {
    write_csv(
        &dir.join("measured_action.csv"),
        [
            "command",
            "velocity_mm_s",
            "std_mm_s",
            "min_mm_s",
            "max_mm_s",
            "upright",
            "blew_up",
        ],
        rows.iter().map(|m| {
            vec![
                m.command.to_string(),
                m.velocity_mm_s.to_string(),
                m.std_mm_s.to_string(),
                m.min_mm_s().to_string(),
                m.max_mm_s().to_string(),
                m.upright.to_string(),
                m.blew_up.to_string(),
            ]
        }),
    )
}

/// `measured_sensor.csv` in `dir`:
/// `distance_mm,obs_px,std_px,nominal_mm,distance_std_mm,missed` (the distance
/// actually held while reading, the readings' mean and spread, where the robot
/// was put, how far it moved, and frames without a reading).
pub fn write_measured_sensor(dir: &Path, rows: &[MeasuredReading]) -> std::io::Result<()> {
    write_csv(
        &dir.join("measured_sensor.csv"),
        [
            "distance_mm",
            "obs_px",
            "std_px",
            "nominal_mm",
            "distance_std_mm",
            "missed",
        ],
        rows.iter().map(|r| {
            vec![
                r.distance_mm.to_string(),
                r.obs_px.to_string(),
                r.std_px.to_string(),
                r.nominal_mm.to_string(),
                r.distance_std_mm.to_string(),
                r.missed.to_string(),
            ]
        }),
    )
}

/// An optional number as a CSV cell (empty if none).
fn cell(v: Option<f64>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

/// A trace, one row per camera frame:
/// `t,command,obs,x_true_mm,x_a,x_s,x_loc,x_loc_std,x_loc_true_mm,x_loc_a0,x_loc_best_mm,falling_back`
/// (empty cells where there was no reading or no model; `x_loc` is the
/// localiser's estimate with the learned models, in their units,
/// `x_loc_true_mm` with the measured ones, `x_loc_a0` with A0 and the sensor
/// model learned from it, `x_loc_best_mm` with the best polynomials of the
/// learner's degrees through the measured models; `falling_back` is 1 where
/// the learner, by its check on itself, reported older models in place of
/// its own, 0 where not, empty for a learner with no such check).
pub fn write_trace(path: &Path, trace: &[TraceRow]) -> std::io::Result<()> {
    write_csv(
        path,
        [
            "t",
            "command",
            "obs",
            "x_true_mm",
            "x_a",
            "x_s",
            "x_loc",
            "x_loc_std",
            "x_loc_true_mm",
            "x_loc_a0",
            "x_loc_best_mm",
            "falling_back",
        ],
        trace.iter().map(|r| {
            vec![
                r.t_s.to_string(),
                r.command.to_string(),
                cell(r.obs_px),
                r.x_true_mm.to_string(),
                cell(r.x_a),
                cell(r.x_s),
                cell(r.x_loc),
                cell(r.x_loc_std),
                cell(r.x_loc_true_mm),
                cell(r.x_loc_a0),
                cell(r.x_loc_best_mm),
                cell(r.falling_back.map(|b| f64::from(u8::from(b)))),
            ]
        }),
    )
}

/// Errors over time: `t,action_rmse_mm_s,sensor_rmse_mm,consistency`.
pub fn write_errors_over_time(path: &Path, over_time: &[Judgement]) -> std::io::Result<()> {
    write_csv(
        path,
        ["t", "action_rmse_mm_s", "sensor_rmse_mm", "consistency"],
        over_time.iter().map(|j| {
            vec![
                j.t_s.to_string(),
                cell(j.action_rmse_mm_s),
                cell(j.sensor_rmse_mm),
                cell(j.consistency),
            ]
        }),
    )
}
