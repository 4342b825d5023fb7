//! Writing results: CSV files written whole or not at all (to a temporary file
//! first, then renamed): the measured models in the paper's column layout, and
//! trials' traces and errors over time.

use std::io::Write;
use std::path::Path;

use crate::measure::{MeasuredReading, MeasuredVelocity};
use crate::reference::Judgement;
use crate::trial::TraceRow;

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

/// `measured_action.csv` in `dir`: `command,velocity_mm_s,std_mm_s,min_mm_s,max_mm_s,upright`
/// (the mean of the timings, their spread, and whether the robot stayed upright).
pub fn write_measured_action(dir: &Path, rows: &[MeasuredVelocity]) -> std::io::Result<()> {
    write_csv(
        &dir.join("measured_action.csv"),
        "command,velocity_mm_s,std_mm_s,min_mm_s,max_mm_s,upright",
        rows.iter().map(|m| {
            let t = &m.timings_mm_s;
            format!(
                "{},{},{},{},{},{}",
                m.command,
                m.velocity_mm_s,
                m.std_mm_s,
                t.iter().copied().fold(f64::INFINITY, f64::min),
                t.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                m.upright
            )
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
        "distance_mm,obs_px,std_px,nominal_mm,distance_std_mm,missed",
        rows.iter().map(|r| {
            format!(
                "{},{},{},{},{},{}",
                r.distance_mm, r.obs_px, r.std_px, r.nominal_mm, r.distance_std_mm, r.missed
            )
        }),
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
