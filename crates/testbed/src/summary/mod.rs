//! The evaluation of a run: each trial's figures ([`figures`]), how it ended
//! ([`status`]), how it weathered a change of the world ([`recovery`]), and
//! the statistics over many ([`aggregate`]); here, a run's summary and
//! `summary.json`.

pub mod aggregate;
pub mod figures;
pub mod floor_ratios;
pub mod quantile;
pub mod recovery;
pub mod status;

pub use aggregate::{Aggregate, Coverage, Share, TrialRow};
pub use figures::{Field, Figures, LOCATION_WINDOW_S, best_possible};
pub use floor_ratios::{FloorRatio, FloorRatios};
pub use quantile::quantile;
pub use recovery::{RECONVERGED_WITHIN, Recovery, SETTLED_WINDOW_S};
pub use status::TrialStatus;

use crate::reference::MeasuredModels;
use crate::scenario::Scenario;
use crate::trial::TrialOutcome;

/// One trial's row for a summary: its status and figures (NaN figures for a
/// trial that could not run).
pub fn trial_row(
    seed: u64,
    outcome: Result<&TrialOutcome, String>,
    best: (f64, f64, f64),
) -> TrialRow {
    match outcome {
        Ok(o) => (seed, TrialStatus::of(o), Figures::of(o, best)),
        Err(e) => (seed, TrialStatus::Error(e), Figures::filled(f64::NAN)),
    }
}

/// A run's `summary.json`: each trial's figures and status, how many ended
/// ok and which did not, which ended worse than their start, the statistics
/// over the ok ones (mean, std, median, p10, p90, n), the paper's figures,
/// the learner and its parameters, and how the reference was taken.
pub fn summary_json(
    rows: &[TrialRow],
    learner: &str,
    learner_parameters: serde_json::Value,
    reference: &str,
) -> serde_json::Value {
    let aggregate = Aggregate::of(rows);
    let trials: Vec<serde_json::Value> = rows
        .iter()
        .map(|(seed, status, f)| {
            let mut v = serde_json::to_value(f).unwrap_or_default();
            v["seed"] = (*seed).into();
            v["status"] = status.to_string().into();
            for (name, worse) in Figures::WORSE_THAN_START {
                v[name] = (status.is_ok() && worse(f)).into();
            }
            v
        })
        .collect();
    let worse_by_model = aggregate.worse_by_model();
    let mut json = serde_json::json!({
        "learner": learner,
        "learner_parameters": learner_parameters,
        "trials": trials,
        "trials_ok": aggregate.ok(),
        "trials_failed": aggregate.failed_json(),
        "trials_worse_than_start": aggregate.worse_than_start.len(),
        "trials_worse_than_start_action": worse_by_model.0,
        "trials_worse_than_start_sensor": worse_by_model.1,
        "trials_worse_than_start_seeds": aggregate.worse_than_start_json(),
        "predicted_band_coverage": aggregate.coverage,
        "paper": Figures::paper(),
        "reference": reference,
    });
    if let Some(object) = json.as_object_mut() {
        object.extend(aggregate.statistics_json());
    }
    json
}

/// The typical trial of a run: of the ok ones, the one whose action and
/// sensor errors are together nearest the run's medians (least
/// `|a / median(a) - 1| + |s / median(s) - 1|`; the first such seed on a tie).
pub fn typical_seed(rows: &[TrialRow]) -> Option<u64> {
    let ok: Vec<&TrialRow> = rows.iter().filter(|r| r.1.is_ok()).collect();
    let median = |f: fn(&Figures) -> f64| {
        let mut v: Vec<f64> = ok.iter().map(|r| f(&r.2)).collect();
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied()
    };
    let (a, s) = (
        median(|f| f.action_rmse_mm_s)?,
        median(|f| f.sensor_rmse_mm)?,
    );
    let distance =
        |f: &Figures| (f.action_rmse_mm_s / a - 1.0).abs() + (f.sensor_rmse_mm / s - 1.0).abs();
    ok.iter()
        .min_by(|x, y| distance(&x.2).total_cmp(&distance(&y.2)))
        .map(|r| r.0)
}

/// A run's trials summarised (what `train` and `replay` report): each trial's
/// row, the best polynomials they are judged against, the aggregate, and
/// `summary.json`'s contents.
#[derive(Debug, Clone)]
pub struct RunSummary {
    /// Seed, status and figures per trial.
    pub rows: Vec<TrialRow>,
    /// The best polynomials' errors through the measured models.
    pub best: (f64, f64, f64),
    /// Statistics over the ok trials, the others named.
    pub aggregate: Aggregate,
    /// `summary.json`.
    pub json: serde_json::Value,
}

impl RunSummary {
    /// Summarises `trials` (seed and outcome, or why it could not run) of
    /// `scenario`'s learner against the measured `models`.
    pub fn of<'a>(
        trials: impl IntoIterator<Item = (u64, Result<&'a TrialOutcome, String>)>,
        scenario: &Scenario,
        models: &MeasuredModels,
    ) -> Self {
        let best = best_possible(&models.reference(), &scenario.learner);
        let rows: Vec<_> = trials
            .into_iter()
            .map(|(seed, outcome)| trial_row(seed, outcome, best))
            .collect();
        let json = summary_json(
            &rows,
            &crate::learners::display_name(&scenario.learner_name),
            crate::learners::parameters(&scenario.learner_name, scenario),
            &models.describe(&scenario.stopwatch()),
        );
        Self {
            aggregate: Aggregate::of(&rows),
            rows,
            best,
            json,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_typical_trial_is_nearest_the_medians() {
        let row = |seed, a, s, status| {
            let f = Figures {
                action_rmse_mm_s: a,
                sensor_rmse_mm: s,
                ..Figures::filled(1.0)
            };
            (seed, status, f)
        };
        let rows = [
            row(0, 5.0, 100.0, TrialStatus::Ok),
            row(1, 10.0, 20.0, TrialStatus::Ok),
            row(2, 11.0, 52.0, TrialStatus::Ok),
            row(3, 30.0, 50.0, TrialStatus::Ok),
            row(4, 10.0, 50.0, TrialStatus::Fell { at_s: None }),
        ];
        // Medians of the ok trials: 11 mm/s and 52 mm; trial 2 is both.
        assert_eq!(typical_seed(&rows), Some(2));
        assert_eq!(typical_seed(&rows[4..]), None);
    }

    #[test]
    fn summary_json_has_the_tail_and_names_the_trials_worse_than_their_start() {
        let f = |a: f64| Figures {
            action_rmse_mm_s: a,
            action_a0_rmse_mm_s: 25.0,
            sensor_rmse_mm: 40.0,
            sensor_start_rmse_mm: 300.0,
            ..Figures::filled(1.0)
        };
        let rows = [
            (1, TrialStatus::Ok, f(10.0)),
            (2, TrialStatus::Ok, f(12.0)),
            (3, TrialStatus::Ok, f(130.0)),
            (4, TrialStatus::Fell { at_s: None }, f(200.0)),
        ];
        let json = summary_json(&rows, "scasm", serde_json::Value::Null, "reference");
        assert_eq!(json["trials_ok"], 3);
        assert_eq!(json["trials_worse_than_start"], 1);
        assert_eq!(json["trials_worse_than_start_seeds"][0]["seed"], 3);
        assert_eq!(json["trials"][2]["worse_than_start"], true);
        assert_eq!(json["trials"][3]["worse_than_start"], false);
        assert_eq!(json["median"]["action_rmse_mm_s"], 12.0);
        for k in ["mean", "std", "median", "p10", "p90", "n"] {
            assert!(json[k]["sensor_rmse_mm"].is_number(), "{k}");
        }
    }
}
