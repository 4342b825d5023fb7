//! Writing results: CSV files written whole or not at all (to a temporary file
//! first, then renamed), and the measured models in the paper's column layout.

use std::io::Write;
use std::path::Path;

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
