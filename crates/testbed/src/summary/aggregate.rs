//! Many trials' figures: the mean, spread, median and 10th and 90th
//! percentiles over the trials that ended ok, the failed trials counted and
//! named, and the trials that ended worse than their uncalibrated start named.

use super::figures::Figures;
use super::floor_ratios::{FloorRatio, FloorRatios};
use super::quantile::quantile;
use super::recovery::RECONVERGED_WITHIN;
use super::status::TrialStatus;

/// One trial of a run: its seed, how it ended and its figures.
pub type TrialRow = (u64, TrialStatus, Figures);

fn defined(values: &[f64]) -> Vec<f64> {
    values.iter().copied().filter(|v| !v.is_nan()).collect()
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

fn percentile(values: &[f64], q: f64) -> f64 {
    let mut v = defined(values);
    v.sort_by(f64::total_cmp);
    quantile(&v, q)
}

/// Many trials' figures. Every statistic of a figure is over the `Ok` trials
/// in which that figure is defined (not NaN: a re-convergence time is NaN in a
/// trial whose model never came back), and [`Aggregate::counted`] says how
/// many those were; a trial that is `Ok` but worse than its start stays in
/// them (a bad model is a result, not a missing one).
#[derive(Debug, Clone, PartialEq)]
pub struct Aggregate {
    /// Trials in all.
    pub trials: usize,
    /// Mean (NaN if no trial counted).
    pub mean: Figures,
    /// Population standard deviation.
    pub std: Figures,
    /// Median.
    pub median: Figures,
    /// 10th percentile.
    pub p10: Figures,
    /// 90th percentile.
    pub p90: Figures,
    /// How many trials each figure's statistics are over.
    pub counted: Figures,
    /// The errors against their information floors, by root mean square
    /// over the `Ok` trials that have one (see [`FloorRatio`]).
    pub floor: FloorRatios,
    /// The trials that did not end `Ok`: seed and status.
    pub failed: Vec<(u64, TrialStatus)>,
    /// The `Ok` trials whose final models are worse than the uncalibrated
    /// start ([`Figures::worse_than_start`]): seed and figures.
    pub worse_than_start: Vec<(u64, Figures)>,
    /// In how many of the `Ok` trials whose learner predicted its errors
    /// the measured error fell inside the predicted 90 % band.
    pub coverage: Coverage,
    /// The `Ok` trials in which the learner, by its check on itself,
    /// reported older models in place of its own for a while
    /// ([`Figures::fallback_s`] above 0).
    pub fell_back: usize,
}

/// How many of some trials had a property, of those where it is defined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Share {
    /// The trials that had it.
    pub yes: usize,
    /// The trials where it is defined.
    pub of: usize,
}

impl Share {
    fn of(values: impl Iterator<Item = Option<bool>>) -> Self {
        values.flatten().fold(Self { yes: 0, of: 0 }, |s, v| Self {
            yes: s.yes + usize::from(v),
            of: s.of + 1,
        })
    }
}

impl std::fmt::Display for Share {
    /// "43 of 50 (86 %)", or "none" of no trials.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.of == 0 {
            return write!(f, "none");
        }
        let percent = 100.0 * self.yes as f64 / self.of as f64;
        write!(f, "{} of {} ({percent:.0} %)", self.yes, self.of)
    }
}

/// The share of trials whose measured error fell inside the learner's
/// predicted 90 % band, by model ([`Figures::action_in_band`]); about 90 %
/// if the learner knows how sure it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Coverage {
    /// The action model's.
    pub action: Share,
    /// The sensor model's.
    pub sensor: Share,
}

impl Aggregate {
    /// Aggregates `(seed, status, figures)` per trial.
    pub fn of(trials: &[TrialRow]) -> Self {
        let ok: Vec<Figures> = trials.iter().filter(|t| t.1.is_ok()).map(|t| t.2).collect();
        Self {
            trials: trials.len(),
            mean: Figures::map(&ok, |v| mean(&defined(v))),
            std: Figures::map(&ok, |v| {
                let v = defined(v);
                let m = mean(&v);
                (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
            }),
            median: Figures::map(&ok, |v| percentile(v, 0.5)),
            p10: Figures::map(&ok, |v| percentile(v, 0.1)),
            p90: Figures::map(&ok, |v| percentile(v, 0.9)),
            counted: Figures::map(&ok, |v| defined(v).len() as f64),
            floor: FloorRatios {
                action: FloorRatio::of(
                    ok.iter()
                        .map(|f| (f.action_rmse_mm_s, f.action_crb_rmse_mm_s)),
                ),
                sensor: FloorRatio::of(ok.iter().map(|f| (f.sensor_rmse_mm, f.sensor_crb_rmse_mm))),
                action_likelihood: FloorRatio::of(
                    ok.iter()
                        .map(|f| (f.action_rmse_mm_s, f.action_likelihood_floor_mm_s)),
                ),
                sensor_likelihood: FloorRatio::of(
                    ok.iter()
                        .map(|f| (f.sensor_rmse_mm, f.sensor_likelihood_floor_mm)),
                ),
            },
            failed: trials
                .iter()
                .filter(|t| !t.1.is_ok())
                .map(|t| (t.0, t.1.clone()))
                .collect(),
            worse_than_start: trials
                .iter()
                .filter(|t| t.1.is_ok() && t.2.worse_than_start())
                .map(|t| (t.0, t.2))
                .collect(),
            coverage: Coverage {
                action: Share::of(ok.iter().map(Figures::action_in_band)),
                sensor: Share::of(ok.iter().map(Figures::sensor_in_band)),
            },
            fell_back: trials
                .iter()
                .filter(|t| t.1.is_ok() && t.2.fallback_s > 0.0)
                .count(),
        }
    }

    /// Trials that ended `Ok`.
    pub fn ok(&self) -> usize {
        self.trials - self.failed.len()
    }

    /// "15 of 15 trials ok", or "13 of 15 trials ok; not in the means: seed 3
    /// (fell), seed 9 (no model)", and then, if any, "; 1 worse than the
    /// uncalibrated start (in the means): seed 4 (action 30.1 mm/s against
    /// A0's 25.5)", and, for a learner that checks itself, "; fell back on
    /// its last good models (self-check) in 3 trials, 4.2 s a trial on
    /// average".
    pub fn describe(&self) -> String {
        let mut s = format!("{} of {} trials ok", self.ok(), self.trials);
        if !self.failed.is_empty() {
            let named: Vec<String> = self
                .failed
                .iter()
                .map(|(seed, status)| format!("seed {seed} ({status})"))
                .collect();
            s.push_str(&format!("; not in the means: {}", named.join(", ")));
        }
        if !self.worse_than_start.is_empty() {
            let named: Vec<String> = self
                .worse_than_start
                .iter()
                .map(|(seed, f)| {
                    let mut why = Vec::new();
                    if f.action_rmse_mm_s > f.action_a0_rmse_mm_s {
                        why.push(format!(
                            "action {:.1} mm/s against A0's {:.1}",
                            f.action_rmse_mm_s, f.action_a0_rmse_mm_s
                        ));
                    }
                    if f.sensor_rmse_mm > f.sensor_start_rmse_mm {
                        why.push(format!(
                            "sensor {:.1} mm against the start's {:.1}",
                            f.sensor_rmse_mm, f.sensor_start_rmse_mm
                        ));
                    }
                    format!("seed {seed} ({})", why.join(", "))
                })
                .collect();
            s.push_str(&format!(
                "; {} worse than the uncalibrated start (in the means): {}",
                self.worse_than_start.len(),
                named.join(", ")
            ));
        }
        if self.coverage.action.of + self.coverage.sensor.of > 0 {
            s.push_str(&format!(
                "; measured error inside the learner's predicted 90 % band: action {}, sensor {}",
                self.coverage.action, self.coverage.sensor
            ));
        }
        if self.counted.fallback_s > 0.0 {
            s.push_str(&format!(
                "; fell back on its last good models (self-check) in {} of {} trials, {:.1} s a \
                 trial on average",
                self.fell_back, self.counted.fallback_s, self.mean.fallback_s
            ));
        }
        s
    }

    /// The failed trials as JSON: `[{"seed": 3, "status": "fell at 12.35 s",
    /// "fell_at_s": 12.35}, {"seed": 9, "status": "no model"}, ...]` (a
    /// blow-up's date is `blew_up_at_s`).
    pub fn failed_json(&self) -> serde_json::Value {
        self.failed
            .iter()
            .map(|(seed, status)| {
                let mut row = serde_json::json!({"seed": seed, "status": status.to_string()});
                match status {
                    TrialStatus::Fell { at_s: Some(t) } => row["fell_at_s"] = serde_json::json!(t),
                    TrialStatus::BlewUp { at_s: Some(t) } => {
                        row["blew_up_at_s"] = serde_json::json!(t);
                    }
                    _ => {}
                }
                row
            })
            .collect()
    }

    /// Of the trials worse than their start, how many by their action model
    /// and how many by their sensor model (a trial may be both).
    pub fn worse_by_model(&self) -> (usize, usize) {
        let count = |worse: fn(&Figures) -> bool| {
            self.worse_than_start
                .iter()
                .filter(|(_, f)| worse(f))
                .count()
        };
        (
            count(Figures::action_worse_than_start),
            count(Figures::sensor_worse_than_start),
        )
    }

    /// The trials worse than their start as JSON: `[{"seed": 4,
    /// "action_rmse_mm_s": .., "action_a0_rmse_mm_s": .., "sensor_rmse_mm":
    /// .., "sensor_start_rmse_mm": ..}, ...]`.
    pub fn worse_than_start_json(&self) -> serde_json::Value {
        self.worse_than_start
            .iter()
            .map(|(seed, f)| {
                serde_json::json!({
                    "seed": seed,
                    "action_rmse_mm_s": f.action_rmse_mm_s,
                    "action_a0_rmse_mm_s": f.action_a0_rmse_mm_s,
                    "sensor_rmse_mm": f.sensor_rmse_mm,
                    "sensor_start_rmse_mm": f.sensor_start_rmse_mm,
                })
            })
            .collect()
    }

    /// A figure as `mean +- std, median [p10, p90]`, to `decimals`.
    pub fn spread(&self, get: fn(&Figures) -> f64, decimals: usize) -> String {
        format!(
            "{:.d$} +- {:.d$}, median {:.d$} [{:.d$}, {:.d$}]",
            get(&self.mean),
            get(&self.std),
            get(&self.median),
            get(&self.p10),
            get(&self.p90),
            d = decimals
        )
    }

    /// The localisers' figures as a small table: location RMSE over the last
    /// 60 s, after the best affine map to mm, over the ok trials.
    pub fn describe_localisation(&self) -> String {
        type Get = fn(&Figures) -> f64;
        let rows: [(&str, Get); 6] = [
            ("filter, learned models", |f| f.localisation_rmse_mm),
            ("filter, measured (true) models", |f| {
                f.localisation_true_models_rmse_mm
            }),
            ("filter, best polynomials of the learner's degrees", |f| {
                f.localisation_best_poly_rmse_mm
            }),
            ("filter, A0 and its section IV sensor model", |f| {
                f.localisation_a0_rmse_mm
            }),
            ("raw x_s (learned S of each reading)", |f| f.x_s_rmse_mm),
            ("raw x_a (the learner's dead reckoning)", |f| f.x_a_rmse_mm),
        ];
        let mut out = String::from(
            "location RMSE, last 60 s (mm, after the best affine map; mean +- std, median [p10, p90]):\n",
        );
        for (name, get) in rows {
            out.push_str(&format!("  {name:<50} {}\n", self.spread(get, 1)));
        }
        out.push_str(&format!(
            "  (the learned-model filter over the whole trial: {})",
            self.spread(|f| f.localisation_whole_rmse_mm, 1)
        ));
        out
    }

    /// How the ok trials weathered the first change of the world, as a small
    /// table (`None` if the world did not change): each model's error before
    /// the change, at its peak after it and settled in the new world, and the
    /// re-convergence time, each over the trials where it is defined (the
    /// time over those that came back), with how many those were.
    pub fn describe_recovery(&self, change: &str) -> Option<String> {
        if self.counted.change_settled_action_rmse_mm_s == 0.0 {
            return None;
        }
        let mut out = format!(
            "the world changes: {change}; error before / peak after / settled (mean +- std), \
             and re-convergence to within {RECONVERGED_WITHIN}x of settled:\n"
        );
        type Get = fn(&Figures) -> f64;
        let models: [(&str, [Get; 4]); 2] = [
            (
                "action (mm/s)",
                [
                    |f| f.change_before_action_rmse_mm_s,
                    |f| f.change_peak_action_rmse_mm_s,
                    |f| f.change_settled_action_rmse_mm_s,
                    |f| f.reconvergence_action_s,
                ],
            ),
            (
                "sensor (mm)",
                [
                    |f| f.change_before_sensor_rmse_mm,
                    |f| f.change_peak_sensor_rmse_mm,
                    |f| f.change_settled_sensor_rmse_mm,
                    |f| f.reconvergence_sensor_s,
                ],
            ),
        ];
        let (m, s) = (&self.mean, &self.std);
        for (name, [before, peak, settled, back]) in models {
            out.push_str(&format!(
                "  {name:<14} {:6.1} +- {:<5.1} / {:6.1} +- {:<5.1} / {:6.1} +- {:<5.1}  back after \
                 {:5.0} +- {:.0} s, median {:.0} ({} of {} trials came back)\n",
                before(m),
                before(s),
                peak(m),
                peak(s),
                settled(m),
                settled(s),
                back(m),
                back(s),
                back(&self.median),
                back(&self.counted),
                self.ok()
            ));
        }
        out.push_str(&format!(
            "  both models back after {:.0} +- {:.0} s, median {:.0} ({} of {} trials came back)",
            m.reconvergence_s,
            s.reconvergence_s,
            self.median.reconvergence_s,
            self.counted.reconvergence_s,
            self.ok()
        ));
        Some(out)
    }

    /// The statistics as `summary.json` has them: `mean`, `std`, `median`,
    /// `p10`, `p90` and `n` (how many trials each figure's are over), each an
    /// object of every figure, and `floor_ratios` (each model's
    /// [`FloorRatio`]).
    pub fn statistics_json(&self) -> serde_json::Map<String, serde_json::Value> {
        let floor = (
            "floor_ratios".to_string(),
            serde_json::to_value(self.floor).unwrap_or_default(),
        );
        [
            ("mean", &self.mean),
            ("std", &self.std),
            ("median", &self.median),
            ("p10", &self.p10),
            ("p90", &self.p90),
            ("n", &self.counted),
        ]
        .into_iter()
        .map(|(k, f)| (k.to_string(), serde_json::to_value(f).unwrap_or_default()))
        .chain(std::iter::once(floor))
        .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A trial's figures from a learner with no self-check and no posterior.
    fn figures(action: f64) -> Figures {
        Figures {
            action_rmse_mm_s: action,
            action_a0_rmse_mm_s: 100.0,
            fallback_s: f64::NAN,
            ..without_bands(Figures::filled(1.0))
        }
    }

    fn without_bands(f: Figures) -> Figures {
        Figures {
            action_predicted_low_mm_s: f64::NAN,
            action_predicted_high_mm_s: f64::NAN,
            sensor_predicted_low_mm: f64::NAN,
            sensor_predicted_high_mm: f64::NAN,
            ..f
        }
    }

    #[test]
    fn the_bands_coverage_counts_the_ok_trials_with_a_band_and_says_so() {
        let banded = |action: f64, low: f64, high: f64| Figures {
            action_predicted_low_mm_s: low,
            action_predicted_high_mm_s: high,
            ..figures(action)
        };
        let a = Aggregate::of(&[
            (0, TrialStatus::Ok, banded(10.0, 8.0, 12.0)),
            (1, TrialStatus::Ok, banded(20.0, 8.0, 12.0)),
            (2, TrialStatus::Ok, banded(5.0, 8.0, 12.0)),
            (3, TrialStatus::Ok, banded(12.0, 8.0, 12.0)),
            (4, TrialStatus::Ok, figures(10.0)),
            (5, TrialStatus::Fell { at_s: None }, banded(10.0, 8.0, 12.0)),
        ]);
        assert_eq!(a.coverage.action, Share { yes: 2, of: 4 });
        assert_eq!(a.coverage.sensor, Share { yes: 0, of: 0 });
        assert!(
            a.describe().ends_with(
                "measured error inside the learner's predicted 90 % band: action 2 of 4 \
                 (50 %), sensor none"
            ),
            "{}",
            a.describe()
        );
        assert!(
            !Aggregate::of(&[(6, TrialStatus::Ok, figures(1.0))])
                .describe()
                .contains("band")
        );
    }

    #[test]
    fn failed_trials_are_counted_named_and_kept_out_of_the_mean() {
        let a = Aggregate::of(&[
            (0, TrialStatus::Ok, figures(10.0)),
            (1, TrialStatus::Fell { at_s: Some(260.1) }, figures(1000.0)),
            (2, TrialStatus::Ok, figures(20.0)),
            (3, TrialStatus::NoModel, Figures::filled(f64::NAN)),
            (4, TrialStatus::BlewUp { at_s: Some(0.05) }, figures(1e12)),
        ]);
        assert_eq!((a.trials, a.ok()), (5, 2));
        assert_eq!(a.mean.action_rmse_mm_s, 15.0);
        assert_eq!(
            a.describe(),
            "2 of 5 trials ok; not in the means: seed 1 (fell at 260.10 s), seed 3 (no model), \
             seed 4 (physics blew up at 0.05 s)"
        );
        let failed = a.failed_json();
        assert_eq!(failed[0]["fell_at_s"], serde_json::json!(260.1));
        assert_eq!(failed[1]["status"], "no model");
        assert!(failed[1].get("fell_at_s").is_none());
        assert_eq!(failed[2]["blew_up_at_s"], serde_json::json!(0.05));
        assert!(failed[2].get("fell_at_s").is_none());
        let none = Aggregate::of(&[(5, TrialStatus::Diverged, figures(1.0))]);
        assert!(none.mean.action_rmse_mm_s.is_nan());
        assert!(none.median.action_rmse_mm_s.is_nan());
        assert_eq!(none.counted.action_rmse_mm_s, 0.0);
    }

    #[test]
    fn quantiles_interpolate_between_ranks() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0];
        assert_eq!(quantile(&v, 0.5), 6.0);
        assert_eq!(quantile(&v, 0.1), 2.0);
        assert_eq!(quantile(&v, 0.9), 10.0);
        assert_eq!(quantile(&[1.0, 2.0], 0.5), 1.5);
        assert_eq!(quantile(&[4.0], 0.9), 4.0);
        assert!(quantile(&[], 0.5).is_nan());
    }

    #[test]
    fn the_tail_is_shown_and_a_trial_worse_than_its_start_is_named_and_kept() {
        // Nine good trials and one far worse than A0 (25 mm/s).
        let mut rows: Vec<TrialRow> = (0..9)
            .map(|k| {
                let f = Figures {
                    action_rmse_mm_s: 10.0 + k as f64,
                    action_a0_rmse_mm_s: 25.0,
                    sensor_start_rmse_mm: 300.0,
                    sensor_rmse_mm: 50.0,
                    fallback_s: f64::NAN,
                    ..Figures::filled(1.0)
                };
                (100 + k, TrialStatus::Ok, f)
            })
            .collect();
        let bad = Figures {
            action_rmse_mm_s: 130.0,
            sensor_rmse_mm: 480.0,
            ..rows[0].2
        };
        rows.push((9002, TrialStatus::Ok, bad));
        // And one worse by its sensor model alone.
        let sensor_only = Figures {
            sensor_rmse_mm: 310.0,
            ..rows[0].2
        };
        rows.push((9003, TrialStatus::Ok, sensor_only));
        let a = Aggregate::of(&rows);
        assert_eq!(a.ok(), 11);
        assert_eq!(a.worse_than_start.len(), 2);
        assert_eq!(a.worse_than_start[0].0, 9002);
        assert_eq!(a.worse_by_model(), (1, 2));
        rows.pop();
        let a = Aggregate::of(&rows);
        assert_eq!(a.ok(), 10);
        assert_eq!(a.worse_than_start.len(), 1);
        // In the mean, which it pulls far from the median; the p90 shows it.
        assert_eq!(a.mean.action_rmse_mm_s, (126.0 + 130.0) / 10.0);
        assert_eq!(a.median.action_rmse_mm_s, 14.5);
        assert!(a.p90.action_rmse_mm_s > 20.0, "{}", a.p90.action_rmse_mm_s);
        let text = a.describe();
        assert!(
            text.contains(
                "1 worse than the uncalibrated start (in the means): seed 9002 \
                 (action 130.0 mm/s against A0's 25.0, sensor 480.0 mm against the start's 300.0)"
            ),
            "{text}"
        );
        assert!(
            !text.contains("self-check"),
            "no learner here checks itself: {text}"
        );
        // A learner that checks itself, falling back in two trials of ten.
        for (k, row) in rows.iter_mut().enumerate() {
            row.2.fallback_s = if k < 2 { 3.0 } else { 0.0 };
        }
        let text = Aggregate::of(&rows).describe();
        assert!(
            text.ends_with(
                "; fell back on its last good models (self-check) in 2 of 10 trials, 0.6 s a \
                 trial on average"
            ),
            "{text}"
        );
    }

    #[test]
    fn statistics_skip_undefined_values_and_say_how_many_they_are_over() {
        // Re-converged after 40 and 60 s in two trials; never in the third.
        let rows: Vec<TrialRow> = [40.0, f64::NAN, 60.0]
            .into_iter()
            .enumerate()
            .map(|(k, t)| {
                let f = Figures {
                    reconvergence_s: t,
                    change_settled_action_rmse_mm_s: 8.0,
                    ..Figures::filled(1.0)
                };
                (k as u64, TrialStatus::Ok, f)
            })
            .collect();
        let a = Aggregate::of(&rows);
        assert_eq!(a.mean.reconvergence_s, 50.0);
        assert_eq!(a.counted.reconvergence_s, 2.0);
        assert_eq!(a.counted.action_rmse_mm_s, 3.0);
        let json = serde_json::Value::Object(a.statistics_json());
        assert_eq!(json["mean"]["reconvergence_s"], 50.0);
        assert_eq!(json["n"]["reconvergence_s"], 2.0);
        let text = a
            .describe_recovery("world.friction=0.5 at 100 s")
            .expect("a change");
        assert!(
            text.contains("both models back after 50 +- 10 s, median 50 (2 of 3 trials came back)"),
            "{text}"
        );
    }
}
