//! The quantile every summary statistic uses (numpy's default).

/// The `q`-quantile (0 to 1) of `sorted` (ascending), interpolated linearly
/// between the closest ranks (numpy's default); NaN if it is empty.
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    let Some(last) = sorted.len().checked_sub(1) else {
        return f64::NAN;
    };
    let h = last as f64 * q.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    match sorted.get(lo + 1) {
        Some(&next) => sorted[lo] + (h - lo as f64) * (next - sorted[lo]),
        None => sorted[lo],
    }
}
