//! # report: pictures and pages of results
//!
//! Draws what people would rather look at than read: the paper's figures from a
//! training run, an HTML page of them beside the results table, and heatmaps of
//! parameter sweeps. PNG and SVG both, with a bundled font (DejaVu Sans), so
//! nothing depends on the fonts of the machine.
#![warn(missing_docs)]

pub mod heatmap;
pub mod leaderboard;
pub mod page;
pub mod paper;
pub mod plot;
#[cfg(feature = "rerun")]
pub mod rrd;
pub mod run;
pub mod spread;
pub mod sweep;
pub mod table;

use std::path::Path;

/// A figure or page that could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// Drawing failed.
    #[error("drawing: {0}")]
    Draw(String),
    /// A file could not be written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
}

/// Writes `bytes` to `path` whole or not at all (a temporary file, then renamed).
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    let io = |source| ReportError::Io {
        path: path.display().to_string(),
        source,
    };
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    std::fs::write(&tmp, bytes).map_err(io)?;
    std::fs::rename(&tmp, path).map_err(io)
}

/// Writes an RGB image (row-major, 3 bytes a pixel) of `size` as a PNG, whole or
/// not at all.
pub fn write_png(path: &Path, rgb: &[u8], size: (u32, u32)) -> Result<(), ReportError> {
    write_atomic(path, &plot::encode_png(rgb, size)?)
}

/// An RGB image of `size` with each pixel drawn as a `k` x `k` block, so that a
/// person can see a small camera's pixels. Returns the image and its size.
pub fn upscale_rgb(rgb: &[u8], (w, h): (u32, u32), k: u32) -> (Vec<u8>, (u32, u32)) {
    let (w, h, k) = (w as usize, h as usize, k.max(1) as usize);
    let mut big = Vec::with_capacity(rgb.len() * k * k);
    for row in 0..h * k {
        for col in 0..w * k {
            let i = 3 * ((row / k) * w + col / k);
            big.extend_from_slice(&rgb[i..i + 3]);
        }
    }
    (big, ((w * k) as u32, (h * k) as u32))
}
