//! When a trial's camera sees no beacon: intervals of the trial, a setting
//! (`camera.blank_s`) that the world applies frame by frame.

/// Up to [`Blanks::MAX`] intervals of a trial, `[start, end)` in s, during
/// which the camera gives no reading.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Blanks {
    intervals: [(f64, f64); Blanks::MAX],
    len: usize,
}

impl Blanks {
    /// The most intervals.
    pub const MAX: usize = 8;

    /// Intervals written `A..B,C..D` (s, `A < B`, in order, not overlapping,
    /// none past `duration_s`); the empty text is none.
    pub fn parse(text: &str, duration_s: f64) -> Result<Self, String> {
        let mut out = Self::default();
        for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let (a, b) = part
                .split_once("..")
                .ok_or_else(|| format!("`{part}` is not of the form A..B (s)"))?;
            let parse = |v: &str| {
                v.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| format!("`{part}`: `{v}` is not a time in s"))
            };
            let (a, b) = (parse(a)?, parse(b)?);
            if !(0.0 <= a && a < b && b <= duration_s) {
                return Err(format!(
                    "`{part}` must satisfy 0 <= A < B <= the trial's {duration_s} s"
                ));
            }
            if out.intervals[..out.len]
                .last()
                .is_some_and(|&(_, end)| a < end)
            {
                return Err(format!(
                    "`{part}` overlaps or precedes the interval before it"
                ));
            }
            if out.len == Self::MAX {
                return Err(format!("at most {} intervals", Self::MAX));
            }
            out.intervals[out.len] = (a, b);
            out.len += 1;
        }
        Ok(out)
    }

    /// Whether time `t_s` is blanked.
    pub fn contains(&self, t_s: f64) -> bool {
        self.intervals[..self.len]
            .iter()
            .any(|&(a, b)| a <= t_s && t_s < b)
    }

    /// The intervals, as [`Blanks::parse`] reads them.
    pub fn to_text(&self) -> String {
        self.intervals[..self.len]
            .iter()
            .map(|(a, b)| format!("{a}..{b}"))
            .collect::<Vec<_>>()
            .join(",")
    }

    /// The intervals.
    pub fn intervals(&self) -> &[(f64, f64)] {
        &self.intervals[..self.len]
    }
}
