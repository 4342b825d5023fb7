//! The figures of a trial, and of many: how each trial ended, and the mean and
//! spread over the trials that ended well, with every failed trial counted and
//! named rather than dropped.

use scasm::{Polynomial, ScasmConfig};
use serde::{Deserialize, Serialize};

use crate::metrics;
use crate::reference::{MeasuredModels, Reference};
use crate::scenario::Scenario;
use crate::trial::TrialOutcome;

/// Figures of one trial, as `summary.json` has them.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Figures {
    /// Learned action model's RMSE after the best scale, mm/s.
    pub action_rmse_mm_s: f64,
    /// Learned sensor model's RMSE after the best affine map, mm.
    pub sensor_rmse_mm: f64,
    /// Best quartic through the measured action model, mm/s.
    pub action_best_rmse_mm_s: f64,
    /// Best cubic through the measured sensor model, mm.
    pub sensor_best_rmse_mm: f64,
    /// The identity model A0 after its best scale, mm/s.
    pub action_a0_rmse_mm_s: f64,
    /// `| |k / b| - 1 |`.
    pub consistency: f64,
    /// Simulated seconds per wall-clock second.
    pub realtime_factor: f64,
    /// The localiser with the learned models: location RMSE over the last 60 s
    /// after the best affine map to mm, mm.
    pub localisation_rmse_mm: f64,
    /// The same over the whole trial (from the first estimate), mm.
    pub localisation_whole_rmse_mm: f64,
    /// The localiser with the measured (true) models, last 60 s, mm.
    pub localisation_true_models_rmse_mm: f64,
    /// The localiser with A0 and the sensor model learned from it (section
    /// IV), last 60 s, mm.
    pub localisation_a0_rmse_mm: f64,
    /// The localiser with the best polynomials of the learner's degrees
    /// through the measured models (the model class's floor), last 60 s, mm.
    #[serde(default = "nan")]
    pub localisation_best_poly_rmse_mm: f64,
    /// The learner's raw `x_s` alone, last 60 s, mm.
    pub x_s_rmse_mm: f64,
    /// The learner's raw `x_a` alone, last 60 s, mm.
    pub x_a_rmse_mm: f64,
    /// The fields from here on say how the learner weathered the world's
    /// first change during the trial (see [`Recovery`]); NaN, and absent
    /// from JSON, if the world did not change. This one: the action model's
    /// error at the last judgement before the change, mm/s.
    #[serde(default = "nan", skip_serializing_if = "is_nan")]
    pub change_before_action_rmse_mm_s: f64,
    /// Its highest error after the change, mm/s.
    #[serde(default = "nan", skip_serializing_if = "is_nan")]
    pub change_peak_action_rmse_mm_s: f64,
    /// Its settled error in the changed world, mm/s.
    #[serde(default = "nan", skip_serializing_if = "is_nan")]
    pub change_settled_action_rmse_mm_s: f64,
    /// How long after the change its error is back within 1.2x of settled, s.
    #[serde(default = "nan", skip_serializing_if = "is_nan")]
    pub reconvergence_action_s: f64,
    /// The sensor model's error at the last judgement before the change, mm.
    #[serde(default = "nan", skip_serializing_if = "is_nan")]
    pub change_before_sensor_rmse_mm: f64,
    /// Its highest error after the change, mm.
    #[serde(default = "nan", skip_serializing_if = "is_nan")]
    pub change_peak_sensor_rmse_mm: f64,
    /// Its settled error in the changed world, mm.
    #[serde(default = "nan", skip_serializing_if = "is_nan")]
    pub change_settled_sensor_rmse_mm: f64,
    /// How long after the change its error is back within 1.2x of settled, s.
    #[serde(default = "nan", skip_serializing_if = "is_nan")]
    pub reconvergence_sensor_s: f64,
    /// How long after the change both models are back: the later of the two, s.
    #[serde(default = "nan", skip_serializing_if = "is_nan")]
    pub reconvergence_s: f64,
}

fn nan() -> f64 {
    f64::NAN
}

// serde's `skip_serializing_if` passes a reference.
#[allow(clippy::trivially_copy_pass_by_ref)]
fn is_nan(v: &f64) -> bool {
    v.is_nan()
}

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

/// The window over which locations are judged: the last 60 s of a trial.
pub const LOCATION_WINDOW_S: f64 = 60.0;

/// Location RMSE of `estimate` over `rows` after the best affine map to the
/// true distance (NaN if fewer than three rows have an estimate).
fn location_rmse(
    rows: &[crate::trial::TraceRow],
    estimate: fn(&crate::trial::TraceRow) -> Option<f64>,
) -> f64 {
    let pairs: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| estimate(r).map(|e| (e, r.x_true_mm)))
        .collect();
    metrics::location_rmse(&pairs).unwrap_or(f64::NAN)
}

/// The best possible figures for a reference (independent of the trial), in
/// the world as it ends.
pub fn best_possible(reference: &Reference, learner: &ScasmConfig) -> (f64, f64, f64) {
    let reference = reference.last();
    let s: Vec<(f64, f64)> = reference.sensor.iter().map(|&(d, o)| (o, d)).collect();
    (
        metrics::best_polynomial_rmse(&reference.action, learner.action_degree).unwrap_or(f64::NAN),
        metrics::best_polynomial_rmse(&s, learner.sensor_degree).unwrap_or(f64::NAN),
        metrics::action_error(&Polynomial::identity(), &reference.action).rmse,
    )
}

impl Figures {
    /// The figures of a finished trial (NaN where a model was never learned).
    pub fn of(outcome: &TrialOutcome, best: (f64, f64, f64)) -> Self {
        Self {
            action_rmse_mm_s: outcome.last.action_rmse_mm_s.unwrap_or(f64::NAN),
            sensor_rmse_mm: outcome.last.sensor_rmse_mm.unwrap_or(f64::NAN),
            action_best_rmse_mm_s: best.0,
            sensor_best_rmse_mm: best.1,
            action_a0_rmse_mm_s: best.2,
            consistency: outcome.last.consistency.unwrap_or(f64::NAN),
            realtime_factor: outcome.realtime_factor,
            ..Self::recovery_of(outcome, Self::localisation_of(outcome))
        }
    }

    /// `rest` with the recovery figures of the trial's first change of the
    /// world, if it had one (judged until the next change or the end).
    fn recovery_of(outcome: &TrialOutcome, rest: Self) -> Self {
        let Some(&at_s) = outcome.world_changes_s.first() else {
            return rest;
        };
        let end_s = outcome
            .world_changes_s
            .get(1)
            .copied()
            .unwrap_or(outcome.last.t_s);
        let series = |get: fn(&crate::reference::Judgement) -> Option<f64>| {
            let errors: Vec<(f64, f64)> = outcome
                .over_time
                .iter()
                .filter_map(|j| get(j).map(|e| (j.t_s, e)))
                .collect();
            Recovery::of(&errors, at_s, end_s)
        };
        let (a, s) = (series(|j| j.action_rmse_mm_s), series(|j| j.sensor_rmse_mm));
        let field =
            |r: Option<Recovery>, get: fn(&Recovery) -> f64| r.as_ref().map_or(f64::NAN, get);
        Self {
            change_before_action_rmse_mm_s: field(a, |r| r.before),
            change_peak_action_rmse_mm_s: field(a, |r| r.peak),
            change_settled_action_rmse_mm_s: field(a, |r| r.settled),
            reconvergence_action_s: field(a, |r| r.reconvergence_s),
            change_before_sensor_rmse_mm: field(s, |r| r.before),
            change_peak_sensor_rmse_mm: field(s, |r| r.peak),
            change_settled_sensor_rmse_mm: field(s, |r| r.settled),
            reconvergence_sensor_s: field(s, |r| r.reconvergence_s),
            reconvergence_s: field(a, |r| r.reconvergence_s).max(field(s, |r| r.reconvergence_s)),
            ..rest
        }
    }

    /// The location figures of a trial (the rest NaN).
    fn localisation_of(outcome: &TrialOutcome) -> Self {
        let trace = &outcome.trace;
        let end = trace.last().map_or(0.0, |r| r.t_s);
        let last = &trace[trace.partition_point(|r| r.t_s < end - LOCATION_WINDOW_S)..];
        Self {
            localisation_rmse_mm: location_rmse(last, |r| r.x_loc),
            localisation_whole_rmse_mm: location_rmse(trace, |r| r.x_loc),
            localisation_true_models_rmse_mm: location_rmse(last, |r| r.x_loc_true_mm),
            localisation_a0_rmse_mm: location_rmse(last, |r| r.x_loc_a0),
            localisation_best_poly_rmse_mm: location_rmse(last, |r| r.x_loc_best_mm),
            x_s_rmse_mm: location_rmse(last, |r| r.x_s),
            x_a_rmse_mm: location_rmse(last, |r| r.x_a),
            ..Self::filled(f64::NAN)
        }
    }

    fn map(values: &[Self], f: impl Fn(&[f64]) -> f64) -> Self {
        let field = |g: fn(&Self) -> f64| f(&values.iter().map(g).collect::<Vec<_>>());
        Self {
            action_rmse_mm_s: field(|x| x.action_rmse_mm_s),
            sensor_rmse_mm: field(|x| x.sensor_rmse_mm),
            action_best_rmse_mm_s: field(|x| x.action_best_rmse_mm_s),
            sensor_best_rmse_mm: field(|x| x.sensor_best_rmse_mm),
            action_a0_rmse_mm_s: field(|x| x.action_a0_rmse_mm_s),
            consistency: field(|x| x.consistency),
            realtime_factor: field(|x| x.realtime_factor),
            localisation_rmse_mm: field(|x| x.localisation_rmse_mm),
            localisation_whole_rmse_mm: field(|x| x.localisation_whole_rmse_mm),
            localisation_true_models_rmse_mm: field(|x| x.localisation_true_models_rmse_mm),
            localisation_a0_rmse_mm: field(|x| x.localisation_a0_rmse_mm),
            localisation_best_poly_rmse_mm: field(|x| x.localisation_best_poly_rmse_mm),
            x_s_rmse_mm: field(|x| x.x_s_rmse_mm),
            x_a_rmse_mm: field(|x| x.x_a_rmse_mm),
            change_before_action_rmse_mm_s: field(|x| x.change_before_action_rmse_mm_s),
            change_peak_action_rmse_mm_s: field(|x| x.change_peak_action_rmse_mm_s),
            change_settled_action_rmse_mm_s: field(|x| x.change_settled_action_rmse_mm_s),
            reconvergence_action_s: field(|x| x.reconvergence_action_s),
            change_before_sensor_rmse_mm: field(|x| x.change_before_sensor_rmse_mm),
            change_peak_sensor_rmse_mm: field(|x| x.change_peak_sensor_rmse_mm),
            change_settled_sensor_rmse_mm: field(|x| x.change_settled_sensor_rmse_mm),
            reconvergence_sensor_s: field(|x| x.reconvergence_sensor_s),
            reconvergence_s: field(|x| x.reconvergence_s),
        }
    }

    /// Every field `value`.
    pub fn filled(value: f64) -> Self {
        Self {
            action_rmse_mm_s: value,
            sensor_rmse_mm: value,
            action_best_rmse_mm_s: value,
            sensor_best_rmse_mm: value,
            action_a0_rmse_mm_s: value,
            consistency: value,
            realtime_factor: value,
            localisation_rmse_mm: value,
            localisation_whole_rmse_mm: value,
            localisation_true_models_rmse_mm: value,
            localisation_a0_rmse_mm: value,
            localisation_best_poly_rmse_mm: value,
            x_s_rmse_mm: value,
            x_a_rmse_mm: value,
            change_before_action_rmse_mm_s: value,
            change_peak_action_rmse_mm_s: value,
            change_settled_action_rmse_mm_s: value,
            reconvergence_action_s: value,
            change_before_sensor_rmse_mm: value,
            change_peak_sensor_rmse_mm: value,
            change_settled_sensor_rmse_mm: value,
            reconvergence_sensor_s: value,
            reconvergence_s: value,
        }
    }

    /// Mean over trials, field by field.
    pub fn mean(values: &[Self]) -> Self {
        Self::map(values, |v| v.iter().sum::<f64>() / v.len() as f64)
    }

    /// Population standard deviation over trials, field by field.
    pub fn std(values: &[Self]) -> Self {
        Self::map(values, |v| {
            let m = v.iter().sum::<f64>() / v.len() as f64;
            (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
        })
    }

    /// The paper's reported figures (15 trials on a Sony Aibo ERS-7).
    pub fn paper() -> Self {
        Self {
            action_rmse_mm_s: 29.6,
            sensor_rmse_mm: 70.4,
            action_best_rmse_mm_s: 17.2,
            sensor_best_rmse_mm: 48.8,
            action_a0_rmse_mm_s: 43.0,
            consistency: 0.08,
            ..Self::filled(f64::NAN)
        }
    }
}

/// How a trial ended. Only `Ok` trials enter a mean; every other one is counted
/// and named in every report, so none silently drops out.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum TrialStatus {
    /// The robot stayed upright and both models were learned, with finite errors.
    Ok,
    /// The robot tipped over (its world is no longer the experiment's).
    Fell,
    /// A model was never determined by the data.
    NoModel,
    /// Both models exist but an error is not finite.
    Diverged,
    /// The trial could not run; the reason.
    Error(String),
}

impl TrialStatus {
    /// The status of a finished trial: a fall first, then a missing model, then
    /// non-finite errors.
    pub fn of(outcome: &TrialOutcome) -> Self {
        let j = &outcome.last;
        if outcome.fell {
            Self::Fell
        } else if outcome.action_model.is_none() || outcome.sensor_model.is_none() {
            Self::NoModel
        } else if [j.action_rmse_mm_s, j.sensor_rmse_mm, j.consistency]
            .iter()
            .all(|v| v.is_some_and(f64::is_finite))
        {
            Self::Ok
        } else {
            Self::Diverged
        }
    }

    /// Whether the trial counts in the means.
    pub fn is_ok(&self) -> bool {
        *self == Self::Ok
    }

    /// Reads back what [`Display`](std::fmt::Display) wrote.
    pub fn parse(text: &str) -> Self {
        match text {
            "ok" => Self::Ok,
            "fell" => Self::Fell,
            "no model" => Self::NoModel,
            "diverged" => Self::Diverged,
            other => Self::Error(other.strip_prefix("error: ").unwrap_or(other).into()),
        }
    }
}

impl std::fmt::Display for TrialStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Ok => f.write_str("ok"),
            Self::Fell => f.write_str("fell"),
            Self::NoModel => f.write_str("no model"),
            Self::Diverged => f.write_str("diverged"),
            Self::Error(e) => write!(f, "error: {e}"),
        }
    }
}

/// Many trials' figures: mean and spread over the trials that ended `Ok`, and
/// the others counted and named.
#[derive(Debug, Clone, PartialEq)]
pub struct Aggregate {
    /// Trials in all.
    pub trials: usize,
    /// Mean over the `Ok` trials (NaN if there are none).
    pub mean: Figures,
    /// Population standard deviation over the `Ok` trials (NaN if none).
    pub std: Figures,
    /// The trials that did not end `Ok`: seed and status.
    pub failed: Vec<(u64, TrialStatus)>,
}

impl Aggregate {
    /// Aggregates `(seed, status, figures)` per trial.
    pub fn of(trials: &[(u64, TrialStatus, Figures)]) -> Self {
        let ok: Vec<Figures> = trials.iter().filter(|t| t.1.is_ok()).map(|t| t.2).collect();
        let (mean, std) = if ok.is_empty() {
            (Figures::filled(f64::NAN), Figures::filled(f64::NAN))
        } else {
            (Figures::mean(&ok), Figures::std(&ok))
        };
        Self {
            trials: trials.len(),
            mean,
            std,
            failed: trials
                .iter()
                .filter(|t| !t.1.is_ok())
                .map(|t| (t.0, t.1.clone()))
                .collect(),
        }
    }

    /// The localisers' figures as a small table: location RMSE over the last
    /// 60 s, after the best affine map to mm, mean +- std over the ok trials.
    pub fn describe_localisation(&self) -> String {
        let (m, s) = (&self.mean, &self.std);
        let rows = [
            (
                "filter, learned models",
                m.localisation_rmse_mm,
                s.localisation_rmse_mm,
            ),
            (
                "filter, measured (true) models",
                m.localisation_true_models_rmse_mm,
                s.localisation_true_models_rmse_mm,
            ),
            (
                "filter, best polynomials of the learner's degrees",
                m.localisation_best_poly_rmse_mm,
                s.localisation_best_poly_rmse_mm,
            ),
            (
                "filter, A0 and its section IV sensor model",
                m.localisation_a0_rmse_mm,
                s.localisation_a0_rmse_mm,
            ),
            (
                "raw x_s (learned S of each reading)",
                m.x_s_rmse_mm,
                s.x_s_rmse_mm,
            ),
            (
                "raw x_a (the learner's dead reckoning)",
                m.x_a_rmse_mm,
                s.x_a_rmse_mm,
            ),
        ];
        let mut out = String::from(
            "location RMSE, last 60 s (mm, after the best affine map):
",
        );
        for (name, mean, std) in rows {
            out.push_str(&format!("  {name:<50} {mean:7.1} +- {std:.1}\n"));
        }
        out.push_str(&format!(
            "  (the learned-model filter over the whole trial: {:.1} +- {:.1})",
            m.localisation_whole_rmse_mm, s.localisation_whole_rmse_mm
        ));
        out
    }

    /// Trials that ended `Ok`.
    pub fn ok(&self) -> usize {
        self.trials - self.failed.len()
    }

    /// "15 of 15 trials ok", or "13 of 15 trials ok; not in the means: seed 3
    /// (fell), seed 9 (no model)".
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
        s
    }

    /// The failed trials as JSON: `[{"seed": 3, "status": "fell"}, ...]`.
    pub fn failed_json(&self) -> serde_json::Value {
        self.failed
            .iter()
            .map(|(seed, status)| serde_json::json!({"seed": seed, "status": status.to_string()}))
            .collect()
    }
}

/// How the ok trials weathered the first change of the world, as a small
/// table (`None` if the world did not change): each model's error before the
/// change, at its peak after it and settled in the new world, and the
/// re-convergence time, mean +- std over the ok trials (the time over those
/// that came back, with how many did).
pub fn describe_recovery(rows: &[(u64, TrialStatus, Figures)], change: &str) -> Option<String> {
    let ok: Vec<&Figures> = rows.iter().filter(|r| r.1.is_ok()).map(|r| &r.2).collect();
    if ok
        .iter()
        .all(|f| f.change_settled_action_rmse_mm_s.is_nan())
    {
        return None;
    }
    let stats = |get: &dyn Fn(&Figures) -> f64| {
        let v: Vec<f64> = ok.iter().map(|f| get(f)).filter(|x| !x.is_nan()).collect();
        let n = v.len() as f64;
        let mean = v.iter().sum::<f64>() / n;
        let std = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
        (mean, std, v.len())
    };
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
    for (name, [before, peak, settled, back]) in models {
        let (b, p, s, r) = (stats(&before), stats(&peak), stats(&settled), stats(&back));
        out.push_str(&format!(
            "  {name:<14} {:6.1} +- {:<5.1} / {:6.1} +- {:<5.1} / {:6.1} +- {:<5.1}  back after \
             {:5.0} +- {:.0} s ({} of {} trials)\n",
            b.0,
            b.1,
            p.0,
            p.1,
            s.0,
            s.1,
            r.0,
            r.1,
            r.2,
            ok.len()
        ));
    }
    let both = stats(&|f| f.reconvergence_s);
    out.push_str(&format!(
        "  both models back after {:.0} +- {:.0} s ({} of {} trials)",
        both.0,
        both.1,
        both.2,
        ok.len()
    ));
    Some(out)
}

/// One trial's row for a summary: its status and figures (NaN figures for a
/// trial that could not run).
pub fn trial_row(
    seed: u64,
    outcome: Result<&TrialOutcome, String>,
    best: (f64, f64, f64),
) -> (u64, TrialStatus, Figures) {
    match outcome {
        Ok(o) => (seed, TrialStatus::of(o), Figures::of(o, best)),
        Err(e) => (seed, TrialStatus::Error(e), Figures::filled(f64::NAN)),
    }
}

/// A run's `summary.json`: each trial's figures and status, how many ended
/// ok and which did not, the mean and std over the ok ones, the paper's
/// figures, the learner and its parameters, and how the reference was taken.
pub fn summary_json(
    rows: &[(u64, TrialStatus, Figures)],
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
            v
        })
        .collect();
    serde_json::json!({
        "learner": learner,
        "learner_parameters": learner_parameters,
        "trials": trials,
        "trials_ok": aggregate.ok(),
        "trials_failed": aggregate.failed_json(),
        "mean": aggregate.mean,
        "std": aggregate.std,
        "paper": Figures::paper(),
        "reference": reference,
    })
}

/// The typical trial of a run: of the ok ones, the one whose action and
/// sensor errors are together nearest the run's medians (least
/// `|a / median(a) - 1| + |s / median(s) - 1|`; the first such seed on a tie).
pub fn typical_seed(rows: &[(u64, TrialStatus, Figures)]) -> Option<u64> {
    let ok: Vec<&(u64, TrialStatus, Figures)> = rows.iter().filter(|r| r.1.is_ok()).collect();
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
    pub rows: Vec<(u64, TrialStatus, Figures)>,
    /// The best polynomials' errors through the measured models.
    pub best: (f64, f64, f64),
    /// Mean and spread over the ok trials, the others named.
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
            &scenario.learner_name,
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

    fn figures(action: f64) -> Figures {
        Figures {
            action_rmse_mm_s: action,
            ..Figures::filled(1.0)
        }
    }

    #[test]
    fn failed_trials_are_counted_named_and_kept_out_of_the_mean() {
        let a = Aggregate::of(&[
            (0, TrialStatus::Ok, figures(10.0)),
            (1, TrialStatus::Fell, figures(1000.0)),
            (2, TrialStatus::Ok, figures(20.0)),
            (3, TrialStatus::NoModel, Figures::filled(f64::NAN)),
        ]);
        assert_eq!((a.trials, a.ok()), (4, 2));
        assert_eq!(a.mean.action_rmse_mm_s, 15.0);
        assert_eq!(
            a.describe(),
            "2 of 4 trials ok; not in the means: seed 1 (fell), seed 3 (no model)"
        );
        let none = Aggregate::of(&[(5, TrialStatus::Diverged, figures(1.0))]);
        assert!(none.mean.action_rmse_mm_s.is_nan());
    }

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
            row(4, 10.0, 50.0, TrialStatus::Fell),
        ];
        // Medians of the ok trials: 11 mm/s and 52 mm; trial 2 is both.
        assert_eq!(typical_seed(&rows), Some(2));
        assert_eq!(typical_seed(&rows[4..]), None);
    }

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

    #[test]
    fn statuses_read_back_as_written() {
        for s in [
            TrialStatus::Ok,
            TrialStatus::Fell,
            TrialStatus::NoModel,
            TrialStatus::Diverged,
            TrialStatus::Error("the learner refused an event".into()),
        ] {
            assert_eq!(TrialStatus::parse(&s.to_string()), s);
        }
    }
}
