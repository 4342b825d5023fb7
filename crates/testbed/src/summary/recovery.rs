//! How a model's error weathered a change of the world: before, peak, settled,
//! and when it came back.

/// The window over which a changed world's settled error is taken: the last
/// 60 s before the next change or the trial's end.
pub const SETTLED_WINDOW_S: f64 = 60.0;

/// A model back within this factor of its settled error has re-converged.
pub const RECONVERGED_WITHIN: f64 = 1.2;

/// How one model's error weathered a change of the world at `at_s`, judged
/// against the world in force at each moment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Recovery {
    /// The error at the last judgement at or before the change.
    pub before: f64,
    /// The highest error after it.
    pub peak: f64,
    /// The mean error over the last [`SETTLED_WINDOW_S`] before the window's
    /// end (the next change or the trial's end).
    pub settled: f64,
    /// From the change until the error, past its peak, is back within
    /// [`RECONVERGED_WITHIN`] x settled, s (0 if it never left that bound;
    /// NaN if it is not back by the window's end).
    pub reconvergence_s: f64,
}

impl Recovery {
    /// The recovery of the errors `(t_s, error)` (in time order) from a change
    /// at `at_s` until `end_s`; `None` without judgements on both sides.
    pub fn of(errors: &[(f64, f64)], at_s: f64, end_s: f64) -> Option<Self> {
        let before = errors.iter().rev().find(|e| e.0 <= at_s)?.1;
        let after: Vec<(f64, f64)> = errors
            .iter()
            .copied()
            .filter(|e| e.0 > at_s && e.0 <= end_s)
            .collect();
        let settled_from = (end_s - SETTLED_WINDOW_S).max(at_s);
        let settled: Vec<f64> = after
            .iter()
            .filter(|e| e.0 > settled_from)
            .map(|e| e.1)
            .collect();
        if settled.is_empty() {
            return None;
        }
        let settled = settled.iter().sum::<f64>() / settled.len() as f64;
        let peak = after.iter().map(|e| e.1).fold(f64::NEG_INFINITY, f64::max);
        // Back at the first judgement within the bound after the peak (at the
        // change if it never left the bound; NaN if not back by the end).
        let bound = RECONVERGED_WITHIN * settled;
        let peak_at = after.iter().position(|e| e.1 == peak).unwrap_or(0);
        let back_s = if peak <= bound {
            at_s
        } else {
            after[peak_at..]
                .iter()
                .find(|e| e.1 <= bound)
                .map_or(f64::NAN, |e| e.0)
        };
        Some(Self {
            before,
            peak,
            settled,
            reconvergence_s: back_s - at_s,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovery_is_read_off_the_errors_around_the_change() {
        // Settled at 10 before a change at 100, up to 40 at 130, back to 10
        // from 200; judged every 10 s to 400.
        let error = |t: f64| match t {
            t if t <= 100.0 => 10.0,
            t if t <= 130.0 => 10.0 + (t - 100.0),
            t if t < 200.0 => 40.0 - 30.0 * (t - 130.0) / 70.0,
            _ => 10.0,
        };
        let errors: Vec<(f64, f64)> = (1..=40)
            .map(|k| (10.0 * k as f64, error(10.0 * k as f64)))
            .collect();
        let r = Recovery::of(&errors, 100.0, 400.0).expect("judged on both sides");
        assert_eq!((r.before, r.peak, r.settled), (10.0, 40.0, 10.0));
        // Within 12 first at 200 s (past the peak: 40 - 30 * 60/70 = 14.3 at 190).
        assert_eq!(r.reconvergence_s, 100.0);
        // Never out of the bound: back at once.
        let flat: Vec<(f64, f64)> = errors.iter().map(|e| (e.0, 10.0)).collect();
        assert_eq!(
            Recovery::of(&flat, 100.0, 400.0).map(|r| r.reconvergence_s),
            Some(0.0)
        );
        // At its peak when the window ends (a next change at 130 s): not back.
        let r = Recovery::of(&errors, 100.0, 130.0).expect("judged");
        assert!(r.reconvergence_s.is_nan(), "{r:?}");
        // No judgement before the change: nothing to say.
        assert_eq!(Recovery::of(&errors[10..], 50.0, 400.0), None);
    }
}
