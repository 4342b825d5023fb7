//! Writing results: CSV files written whole or not at all (to a temporary file
//! first, then renamed): the measured models in the paper's column layout, and
//! trials' traces and errors over time.

use std::io::Write;
use std::path::Path;

use crate::trial::{Judgement, TraceRow};

/// Writes `header` and `rows` to `path`: to `path.tmp`, then renamed into place,
/// so that a reader never sees half a file.
pub fn write_csv(
    path: &Path,
    header: &str,
    rows: impl IntoIterator<Item = String>,
) -> std::io::Result<()> {
    let tmp = path.with_extension("csv.tmp");
    {
        let mut f = std::io::BufWriter::new(std::fs::File::create(&tmp)?);
        writeln!(f, "{header}")?;
        for r in rows {
            writeln!(f, "{r}")?;
        }
        f.flush()?;
    }
    std::fs::rename(&tmp, path)
}

/// `measured_action.csv` in `dir`: `command,velocity_mm_s,std_mm_s`.
pub fn write_measured_action(dir: &Path, rows: &[(f64, f64, f64)]) -> std::io::Result<()> {
    write_csv(
        &dir.join("measured_action.csv"),
        "command,velocity_mm_s,std_mm_s",
        rows.iter().map(|(c, v, s)| format!("{c},{v},{s}")),
    )
}

/// `measured_sensor.csv` in `dir`: `distance_mm,obs_px,std_px`.
pub fn write_measured_sensor(dir: &Path, rows: &[(f64, f64, f64)]) -> std::io::Result<()> {
    write_csv(
        &dir.join("measured_sensor.csv"),
        "distance_mm,obs_px,std_px",
        rows.iter().map(|(d, o, s)| format!("{d},{o},{s}")),
    )
}

/// An optional number as a CSV cell (empty if none).
fn cell(v: Option<f64>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

/// A trace, one row per camera frame: `t,command,obs,x_true_mm,x_a,x_s` (empty
/// cells where there was no reading or no model).
pub fn write_trace(path: &Path, trace: &[TraceRow]) -> std::io::Result<()> {
    write_csv(
        path,
        "t,command,obs,x_true_mm,x_a,x_s",
        trace.iter().map(|r| {
            format!(
                "{},{},{},{},{},{}",
                r.t_s,
                r.command,
                cell(r.obs_px),
                r.x_true_mm,
                cell(r.x_a),
                cell(r.x_s)
            )
        }),
    )
}

/// Errors over time: `t,action_rmse_mm_s,sensor_rmse_mm,consistency`.
pub fn write_errors_over_time(path: &Path, over_time: &[Judgement]) -> std::io::Result<()> {
    write_csv(
        path,
        "t,action_rmse_mm_s,sensor_rmse_mm,consistency",
        over_time.iter().map(|j| {
            format!(
                "{},{},{},{}",
                j.t_s,
                cell(j.action_rmse_mm_s),
                cell(j.sensor_rmse_mm),
                cell(j.consistency)
            )
        }),
    )
}
