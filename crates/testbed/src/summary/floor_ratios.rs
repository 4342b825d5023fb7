//! Errors set against their information floors over many trials. A trial's
//! floor bounds the mean square of an unbiased learner's error (see
//! [`crate::floor`]), so the trials' errors are compared with it by root mean
//! square: `sqrt(mean e^2) / sqrt(mean f^2)`, which no such learner goes
//! below on average. The mean error over the mean floor, which the summary
//! gave before, flatters a learner whose errors spread (by Jensen's
//! inequality it is never above the RMS ratio when the floors are alike).
//! Beside it, the median and 90th percentile of the per-trial ratios `e / f`
//! say how the trials spread.

use serde::Serialize;

use super::quantile::quantile;

/// One model's errors against its floors over the trials where both are finite.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FloorRatio {
    /// The floors' root mean square over the trials (mm/s or mm).
    pub floor_rms: f64,
    /// The errors' root mean square over the floors'.
    pub rms: f64,
    /// The median of the per-trial ratios.
    pub median: f64,
    /// The 90th percentile of the per-trial ratios.
    pub p90: f64,
    /// How many trials these are over.
    pub n: usize,
}

impl FloorRatio {
    /// Over `(error, floor)` pairs; trials where either is not finite or the
    /// floor is not positive are left out (a world that changed, a learner
    /// that gives no degrees). NaN figures if none is left.
    pub fn of(pairs: impl IntoIterator<Item = (f64, f64)>) -> Self {
        let kept: Vec<(f64, f64)> = pairs
            .into_iter()
            .filter(|(e, f)| e.is_finite() && f.is_finite() && *f > 0.0)
            .collect();
        let n = kept.len();
        let rms =
            |v: &mut dyn Iterator<Item = f64>| (v.map(|x| x * x).sum::<f64>() / n as f64).sqrt();
        let (errors, floors) = (
            rms(&mut kept.iter().map(|p| p.0)),
            rms(&mut kept.iter().map(|p| p.1)),
        );
        let mut each: Vec<f64> = kept.iter().map(|(e, f)| e / f).collect();
        each.sort_by(f64::total_cmp);
        Self {
            floor_rms: floors,
            rms: errors / floors,
            median: quantile(&each, 0.5),
            p90: quantile(&each, 0.9),
            n,
        }
    }

    /// As a table cell: "13.9 (1.35x; 1.30x, 1.61x)", the floor's RMS, the
    /// RMS ratio, and the per-trial ratios' median and 90th percentile; "-
    /// (none)" where no trial has a floor.
    pub fn cell(&self) -> String {
        if self.n == 0 {
            "- (none)".into()
        } else {
            format!(
                "{:.1} ({:.2}x; {:.2}x, {:.2}x)",
                self.floor_rms, self.rms, self.median, self.p90
            )
        }
    }
}

/// Both models' [`FloorRatio`]s, against both floors.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FloorRatios {
    /// The action model's, against the metric's floor (mm/s).
    pub action: FloorRatio,
    /// The sensor model's, against the metric's floor (mm).
    pub sensor: FloorRatio,
    /// The action model's, against the likelihood's floor (mm/s).
    pub action_likelihood: FloorRatio,
    /// The sensor model's, against the likelihood's floor (mm).
    pub sensor_likelihood: FloorRatio,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ratio_is_by_root_mean_square_and_never_below_the_mean_ratio() {
        // Equal floors, spread errors: the mean error over the mean floor is
        // 2, the RMS ratio sqrt((1 + 9) / 2) = 2.236.
        let r = FloorRatio::of([(1.0, 1.0), (3.0, 1.0)]);
        assert!((r.rms - 5f64.sqrt()).abs() < 1e-15);
        assert!((r.median - 2.0).abs() < 1e-15 && (r.p90 - 2.8).abs() < 1e-12);
        assert_eq!((r.floor_rms, r.n), (1.0, 2));
        assert_eq!(r.cell(), "1.0 (2.24x; 2.00x, 2.80x)");
    }

    #[test]
    fn trials_without_a_floor_are_left_out_and_none_is_said() {
        let r = FloorRatio::of([(2.0, 1.0), (5.0, f64::NAN), (f64::NAN, 1.0), (4.0, 0.0)]);
        assert_eq!((r.n, r.rms), (1, 2.0));
        let none = FloorRatio::of([(5.0, f64::NAN)]);
        assert_eq!(none.n, 0);
        assert!(none.rms.is_nan());
        assert_eq!(none.cell(), "- (none)");
    }
}
