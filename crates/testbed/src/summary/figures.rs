//! The figures of one trial: every number `summary.json`, `sweep.csv` and the
//! leaderboard report for it, declared once.

use scasm::{Polynomial, ScasmConfig};
use serde::{Deserialize, Serialize};

use super::recovery::Recovery;
use crate::metrics;
use crate::predicted::{Band, Predicted};
use crate::reference::{Judgement, Reference};
use crate::trial::{TraceRow, TrialOutcome};

/// One figure of [`Figures`]: its name (as `summary.json`, `sweep.csv` and the
/// statistics' objects have it) and where it lives.
#[derive(Debug, Clone, Copy)]
pub struct Field {
    /// The figure's name.
    pub name: &'static str,
    /// Reads it.
    pub get: fn(&Figures) -> f64,
    /// Where it is, to write it.
    pub get_mut: fn(&mut Figures) -> &mut f64,
    /// What it is, in words (its doc comment): the book's output reference.
    pub doc: &'static str,
}

/// Declares [`Figures`] and its [`Figures::FIELDS`] from one list (a field's
/// serde attribute written `@serde(...)`, after its doc comment): a new
/// metric is one entry here (and where its value comes from, in
/// [`Figures::of`]); every table, statistic and file that lists the figures
/// reads `FIELDS`.
macro_rules! figures {
    ($( $(#[doc = $doc:literal])* $(@serde($($serde:tt)*))? $name:ident ),+ $(,)?) => {
        /// Figures of one trial, as `summary.json` has them (NaN where a figure
        /// does not apply or could not be had).
        #[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
        pub struct Figures {
            $( $(#[doc = $doc])* $(#[serde($($serde)*)])? pub $name: f64, )+
        }

        /// A test of a trial's figures: whether it ended worse than its start.
pub type WorseTest = fn(&Figures) -> bool;

impl Figures {
            /// Every figure, in `summary.json`'s order.
            pub const FIELDS: &'static [Field] = &[
                $( Field {
                    name: stringify!($name),
                    get: |f| f.$name,
                    get_mut: |f| &mut f.$name,
                    doc: concat!($($doc, "\n"),*),
                }, )+
            ];
        }
    };
}

figures! {
    /// Learned action model's RMSE after the best scale, mm/s.
    action_rmse_mm_s,
    /// Learned sensor model's RMSE after the best affine map, mm.
    sensor_rmse_mm,
    /// Best polynomial of the learner's action degree through the measured
    /// action model, mm/s.
    action_best_rmse_mm_s,
    /// Best polynomial of the learner's sensor degree through the measured
    /// sensor model, mm.
    sensor_best_rmse_mm,
    /// The identity model A0 after its best scale, mm/s: the uncalibrated
    /// action model a trial starts from.
    action_a0_rmse_mm_s,
    /// The sensor model a section IV learner builds from A0 on the trial's
    /// own frames, at the end, mm: the uncalibrated start's sensor model.
    @serde(default = "nan")
    sensor_start_rmse_mm,
    /// The trial's information floor on the action metric (see
    /// [`crate::floor`]): no unbiased learner of the learner's degrees does
    /// better on this trial's data, mm/s.
    @serde(default = "nan")
    action_crb_rmse_mm_s,
    /// The information floor on the sensor metric, mm.
    @serde(default = "nan")
    sensor_crb_rmse_mm,
    /// The likelihood's floor on the action metric: where the efficient
    /// estimator of the floor's model lands on this trial's frames (its limit
    /// with noise-free readings, and the floor's variance), mm/s. Above the
    /// floor (the metric's floor) by what fitting in the likelihood's loss
    /// rather than the metric's costs.
    @serde(default = "nan")
    action_likelihood_floor_mm_s,
    /// The likelihood's floor on the sensor metric, mm.
    @serde(default = "nan")
    sensor_likelihood_floor_mm,
    /// The information floor on the action metric with the steady process
    /// noise at its Gaussian core (`floor_steady_core_noise_mm`): about what
    /// the floor would be if a likelihood knew the noise's heavy tails; the
    /// gap to `action_crb_rmse_mm_s` is what the floor's Gaussian noise
    /// costs it, mm/s.
    @serde(default = "nan")
    action_core_floor_mm_s,
    /// The same on the sensor metric, mm.
    @serde(default = "nan")
    sensor_core_floor_mm,
    /// The learner's predicted error of its action model: the median over
    /// its posterior's draws of the metric against each draw as the truth
    /// (see [`crate::predicted`]), mm/s; NaN, and absent from JSON, for a
    /// learner that reports no posterior.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    action_predicted_mm_s,
    /// The low end of its 90 % band (the draws' 5th percentile), mm/s.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    action_predicted_low_mm_s,
    /// The high end (the 95th percentile), mm/s.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    action_predicted_high_mm_s,
    /// The uncalibrated start's action model (A0) judged by the same draws:
    /// the learner's predicted error of its start, mm/s (the median draw's).
    @serde(default = "nan", skip_serializing_if = "is_nan")
    action_start_predicted_mm_s,
    /// The share of the learner's draws by which its action model is nearer
    /// the truth than A0: its own view of whether calibrating helped (0 to 1).
    @serde(default = "nan", skip_serializing_if = "is_nan")
    action_better_than_start_share,
    /// The learner's predicted error of its sensor model, mm.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    sensor_predicted_mm,
    /// The low end of its 90 % band, mm.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    sensor_predicted_low_mm,
    /// The high end, mm.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    sensor_predicted_high_mm,
    /// The start's sensor model (section IV's, from A0) judged by the same
    /// draws, mm.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    sensor_start_predicted_mm,
    /// The share of the draws by which the sensor model is nearer the truth
    /// than the start's (0 to 1).
    @serde(default = "nan", skip_serializing_if = "is_nan")
    sensor_better_than_start_share,
    /// The reading noise the floor found in the trial's ground truth, px.
    @serde(default = "nan")
    floor_reading_noise_px,
    /// The process noise it found per frame of a steady walk, mm.
    @serde(default = "nan")
    floor_steady_noise_mm,
    /// The steady process noise's Gaussian core it found (1.4826 times the
    /// median absolute summed departure, per frame), mm.
    @serde(default = "nan")
    floor_steady_core_noise_mm,
    /// The process noise it found per frame while the gait changes over, mm.
    @serde(default = "nan")
    floor_changing_noise_mm,
    /// The location's bob about its smooth walk it found, mm.
    @serde(default = "nan")
    floor_bob_mm,
    /// The time constant of the gait's lag after a change of command it
    /// found, s.
    @serde(default = "nan")
    floor_lag_s,
    /// `| |k / b| - 1 |`.
    consistency,
    /// Simulated seconds per wall-clock second of the trial's physics.
    realtime_factor,
    /// Wall-clock seconds the learner took over the trial: its events and
    /// the queries of its models (the physics' own time is `realtime_factor`'s).
    @serde(default = "nan")
    learner_wall_s,
    /// Ground truth: the largest distance the torso went off the line of
    /// approach over the trial, forwards or backwards, mm (the heading
    /// keeper's work: it steers by what the robot sees).
    @serde(default = "nan")
    off_line_max_mm,
    /// The localiser with the learned models: location RMSE over the last 60 s
    /// after the best affine map to mm, mm.
    localisation_rmse_mm,
    /// The same over the whole trial (from the first estimate), mm.
    localisation_whole_rmse_mm,
    /// The localiser with the measured (true) models, last 60 s, mm.
    localisation_true_models_rmse_mm,
    /// The localiser with A0 and the sensor model learned from it (section
    /// IV), last 60 s, mm.
    localisation_a0_rmse_mm,
    /// The localiser with the best polynomials of the learner's degrees
    /// through the measured models (the model class's floor), last 60 s, mm.
    @serde(default = "nan")
    localisation_best_poly_rmse_mm,
    /// The learner's raw `x_s` alone, last 60 s, mm.
    x_s_rmse_mm,
    /// The learner's raw `x_a` alone, last 60 s, mm.
    x_a_rmse_mm,
    /// Seconds of the trial in which the learner, doubting its own models by
    /// its check on itself, reported older ones in their place; NaN, and
    /// absent from JSON, for a learner with no such check.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    fallback_s,
    /// The fields from here on say how the learner weathered the world's
    /// first change during the trial (see [`Recovery`]); NaN, and absent
    /// from JSON, if the world did not change. This one: the action model's
    /// error at the last judgement before the change, mm/s.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    change_before_action_rmse_mm_s,
    /// Its highest error after the change, mm/s.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    change_peak_action_rmse_mm_s,
    /// Its settled error in the changed world, mm/s.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    change_settled_action_rmse_mm_s,
    /// How long after the change its error is back within 1.2x of settled, s
    /// (NaN if it never came back).
    @serde(default = "nan", skip_serializing_if = "is_nan")
    reconvergence_action_s,
    /// The sensor model's error at the last judgement before the change, mm.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    change_before_sensor_rmse_mm,
    /// Its highest error after the change, mm.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    change_peak_sensor_rmse_mm,
    /// Its settled error in the changed world, mm.
    @serde(default = "nan", skip_serializing_if = "is_nan")
    change_settled_sensor_rmse_mm,
    /// How long after the change its error is back within 1.2x of settled, s
    /// (NaN if it never came back).
    @serde(default = "nan", skip_serializing_if = "is_nan")
    reconvergence_sensor_s,
    /// How long after the change both models are back: the later of the two,
    /// s (NaN if either never came back).
    @serde(default = "nan", skip_serializing_if = "is_nan")
    reconvergence_s,
}

fn nan() -> f64 {
    f64::NAN
}

/// Whether `measured` lies in `[low, high]`; `None` if any is NaN.
fn in_band(measured: f64, low: f64, high: f64) -> Option<bool> {
    let defined = !(measured.is_nan() || low.is_nan() || high.is_nan());
    defined.then(|| (low..=high).contains(&measured))
}

// serde's `skip_serializing_if` passes a reference.
#[allow(clippy::trivially_copy_pass_by_ref)]
fn is_nan(v: &f64) -> bool {
    v.is_nan()
}

/// One end (or the middle) of a predicted error's band, NaN if there is none.
fn band(b: Option<Band>, get: fn(&Band) -> f64) -> f64 {
    b.as_ref().map_or(f64::NAN, get)
}

/// The window over which locations are judged: the last 60 s of a trial.
pub const LOCATION_WINDOW_S: f64 = 60.0;

/// Seconds of `trace` whose frames ended with the learner falling back (a
/// frame lasts from the previous row's end to its own); NaN if the learner
/// has no check on itself.
fn fallback_s(trace: &[TraceRow]) -> f64 {
    if trace.iter().all(|r| r.falling_back.is_none()) {
        return f64::NAN;
    }
    let mut start_s = 0.0;
    let mut total = 0.0;
    for r in trace {
        if r.falling_back == Some(true) {
            total += r.t_s - start_s;
        }
        start_s = r.t_s;
    }
    total
}

/// Location RMSE of `estimate` over `rows` after the best affine map to the
/// true distance (NaN if fewer than three rows have an estimate).
fn location_rmse(rows: &[TraceRow], estimate: fn(&TraceRow) -> Option<f64>) -> f64 {
    let pairs: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| estimate(r).map(|e| (e, r.x_true_mm)))
        .collect();
    metrics::location_rmse(&pairs).unwrap_or(f64::NAN)
}

/// The best possible figures for a reference (independent of the trial), in
/// the world as it ends: the best polynomials of the learner's degrees
/// through the measured models, and A0's error.
pub fn best_possible(reference: &Reference, learner: &ScasmConfig) -> (f64, f64, f64) {
    let reference = reference.last();
    let s: Vec<(f64, f64)> = reference.sensor.iter().map(|&(d, o)| (o, d)).collect();
    (
        metrics::best_polynomial_rmse(&reference.action, learner.action_degree).unwrap_or(f64::NAN),
        metrics::best_polynomial_rmse(&s, learner.sensor_degree).unwrap_or(f64::NAN),
        metrics::action_error(&Polynomial::identity(), &reference.action).rmse,
    )
}

/// The later of two re-convergence times; NaN if either model never came
/// back (`f64::max` would return the other one).
pub fn later(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

impl Figures {
    /// The figures of a finished trial (NaN where a model was never learned).
    pub fn of(outcome: &TrialOutcome, best: (f64, f64, f64)) -> Self {
        let start = outcome.start.as_ref().and_then(|j| j.sensor_rmse_mm);
        let none = Predicted {
            action: None,
            sensor: None,
        };
        let p = outcome.predicted.as_ref();
        let learned = p.map_or(none, |p| p.learned);
        let (start_predicted, better) = p.map_or((none, (None, None)), |p| {
            (p.start.unwrap_or(none), p.better_than_start)
        });
        Self {
            action_rmse_mm_s: outcome.last.action_rmse_mm_s.unwrap_or(f64::NAN),
            sensor_rmse_mm: outcome.last.sensor_rmse_mm.unwrap_or(f64::NAN),
            action_best_rmse_mm_s: best.0,
            sensor_best_rmse_mm: best.1,
            action_a0_rmse_mm_s: best.2,
            sensor_start_rmse_mm: start.unwrap_or(f64::NAN),
            action_crb_rmse_mm_s: outcome.floor.map_or(f64::NAN, |f| f.action_rmse_mm_s),
            sensor_crb_rmse_mm: outcome.floor.map_or(f64::NAN, |f| f.sensor_rmse_mm),
            action_likelihood_floor_mm_s: outcome
                .floor
                .map_or(f64::NAN, |f| f.action_likelihood_mm_s),
            sensor_likelihood_floor_mm: outcome.floor.map_or(f64::NAN, |f| f.sensor_likelihood_mm),
            floor_reading_noise_px: outcome.floor.map_or(f64::NAN, |f| f.noise.reading_px),
            floor_steady_noise_mm: outcome.floor.map_or(f64::NAN, |f| f.noise.steady_mm),
            floor_changing_noise_mm: outcome.floor.map_or(f64::NAN, |f| f.noise.changing_mm),
            floor_bob_mm: outcome.floor.map_or(f64::NAN, |f| f.noise.bob_mm),
            floor_lag_s: outcome.floor.map_or(f64::NAN, |f| f.noise.lag_s),
            floor_steady_core_noise_mm: outcome.floor.map_or(f64::NAN, |f| f.noise.steady_core_mm),
            action_core_floor_mm_s: outcome.floor.map_or(f64::NAN, |f| f.action_core_mm_s),
            sensor_core_floor_mm: outcome.floor.map_or(f64::NAN, |f| f.sensor_core_mm),
            action_predicted_mm_s: band(learned.action, |b| b.median),
            action_predicted_low_mm_s: band(learned.action, |b| b.low),
            action_predicted_high_mm_s: band(learned.action, |b| b.high),
            sensor_predicted_mm: band(learned.sensor, |b| b.median),
            sensor_predicted_low_mm: band(learned.sensor, |b| b.low),
            sensor_predicted_high_mm: band(learned.sensor, |b| b.high),
            action_start_predicted_mm_s: band(start_predicted.action, |b| b.median),
            sensor_start_predicted_mm: band(start_predicted.sensor, |b| b.median),
            action_better_than_start_share: better.0.unwrap_or(f64::NAN),
            sensor_better_than_start_share: better.1.unwrap_or(f64::NAN),
            consistency: outcome.last.consistency.unwrap_or(f64::NAN),
            realtime_factor: outcome.realtime_factor,
            learner_wall_s: outcome.learner_wall_s,
            off_line_max_mm: outcome.off_line_max_mm,
            fallback_s: fallback_s(&outcome.trace),
            ..Self::recovery_of(outcome, Self::localisation_of(outcome))
        }
    }

    /// Whether the trial's final models are worse than the uncalibrated start
    /// it began from: the action model's error above A0's, or the sensor
    /// model's above that of the sensor model learned from A0 on the same
    /// frames (section IV). Such a trial is a result, and stays in the means.
    pub fn worse_than_start(&self) -> bool {
        self.action_worse_than_start() || self.sensor_worse_than_start()
    }

    /// Whether the measured action error is inside the learner's predicted
    /// 90 % band; `None` where either is not defined.
    pub fn action_in_band(&self) -> Option<bool> {
        in_band(
            self.action_rmse_mm_s,
            self.action_predicted_low_mm_s,
            self.action_predicted_high_mm_s,
        )
    }

    /// The same of the sensor model.
    pub fn sensor_in_band(&self) -> Option<bool> {
        in_band(
            self.sensor_rmse_mm,
            self.sensor_predicted_low_mm,
            self.sensor_predicted_high_mm,
        )
    }

    /// Whether a trial ended worse than its start, in all and by model: the
    /// name of the output column (`leaderboard.csv`, `summary.json`'s trials)
    /// that says so, and the test.
    pub const WORSE_THAN_START: [(&'static str, WorseTest); 3] = [
        ("worse_than_start", Self::worse_than_start),
        ("worse_than_start_action", Self::action_worse_than_start),
        ("worse_than_start_sensor", Self::sensor_worse_than_start),
    ];

    /// Whether the learned action model ends worse than A0.
    pub fn action_worse_than_start(&self) -> bool {
        metrics::above(self.action_rmse_mm_s, self.action_a0_rmse_mm_s)
    }

    /// Whether the learned sensor model ends worse than the one learned
    /// from A0 on the same frames.
    pub fn sensor_worse_than_start(&self) -> bool {
        metrics::above(self.sensor_rmse_mm, self.sensor_start_rmse_mm)
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
        let series = |get: fn(&Judgement) -> Option<f64>| {
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
            reconvergence_s: later(
                field(a, |r| r.reconvergence_s),
                field(s, |r| r.reconvergence_s),
            ),
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

    /// Every field `value`.
    pub fn filled(value: f64) -> Self {
        let mut f = Self::default();
        for field in Self::FIELDS {
            *(field.get_mut)(&mut f) = value;
        }
        f
    }

    /// Field by field, `f` of that field's values over `values`.
    pub fn map(values: &[Self], f: impl Fn(&[f64]) -> f64) -> Self {
        let mut out = Self::default();
        for field in Self::FIELDS {
            let v: Vec<f64> = values.iter().map(field.get).collect();
            *(field.get_mut)(&mut out) = f(&v);
        }
        out
    }

    /// The figure named `name`, if there is one.
    pub fn field(name: &str) -> Option<&'static Field> {
        Self::FIELDS.iter().find(|f| f.name == name)
    }

    /// Whether these figures are at the paper's level, each of action, sensor
    /// and consistency: the action error at most [`PAPER_LEVEL_ACTION_PCT`] %
    /// of `velocity_range_mm_s`, the sensor error at most
    /// [`PAPER_LEVEL_SENSOR_PCT`] % of `distance_range_mm`, the consistency at
    /// most [`PAPER_LEVEL_CONSISTENCY`]. A NaN figure is not.
    pub fn at_paper_level(&self, velocity_range_mm_s: f64, distance_range_mm: f64) -> [bool; 3] {
        [
            100.0 * self.action_rmse_mm_s / velocity_range_mm_s <= PAPER_LEVEL_ACTION_PCT,
            100.0 * self.sensor_rmse_mm / distance_range_mm <= PAPER_LEVEL_SENSOR_PCT,
            self.consistency <= PAPER_LEVEL_CONSISTENCY,
        ]
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

/// The paper's action error, 29.6 mm/s, as a share of its robot's velocity
/// range (600 mm/s), %: the level a learner's action model is held to.
pub const PAPER_LEVEL_ACTION_PCT: f64 = 4.9;
/// The paper's sensor error, 70.4 mm, as a share of its distance range (2400
/// mm), %.
pub const PAPER_LEVEL_SENSOR_PCT: f64 = 2.9;
/// The paper's consistency, 0.08.
pub const PAPER_LEVEL_CONSISTENCY: f64 = 0.08;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_model_that_never_came_back_makes_the_later_time_nan() {
        assert_eq!(later(20.0, 35.0), 35.0);
        assert!(later(f64::NAN, 35.0).is_nan());
        assert!(later(20.0, f64::NAN).is_nan());
    }

    #[test]
    fn every_field_is_listed_once_and_reads_what_it_writes() {
        let mut f = Figures::filled(0.0);
        for (k, field) in Figures::FIELDS.iter().enumerate() {
            *(field.get_mut)(&mut f) = k as f64;
        }
        for (k, field) in Figures::FIELDS.iter().enumerate() {
            assert_eq!((field.get)(&f), k as f64, "{}", field.name);
        }
        let json = serde_json::to_value(Figures::filled(1.0)).expect("json");
        let names: Vec<&str> = Figures::FIELDS.iter().map(|f| f.name).collect();
        let keys: Vec<&str> = json
            .as_object()
            .expect("object")
            .keys()
            .map(String::as_str)
            .collect();
        let mut sorted = names.clone();
        sorted.sort_unstable();
        let mut keys_sorted = keys.clone();
        keys_sorted.sort_unstable();
        assert_eq!(sorted, keys_sorted);
    }

    #[test]
    fn worse_than_start_is_either_model_above_its_start() {
        let f = |a: f64, s: f64| Figures {
            action_rmse_mm_s: a,
            action_a0_rmse_mm_s: 25.0,
            sensor_rmse_mm: s,
            sensor_start_rmse_mm: 300.0,
            ..Figures::filled(1.0)
        };
        assert!(!f(10.0, 50.0).worse_than_start());
        assert!(f(30.0, 50.0).worse_than_start());
        assert!(f(10.0, 400.0).worse_than_start());
        // The start's error up to the last bits of the sums is the start's.
        assert!(!f(25.0 * (1.0 + 4.0 * f64::EPSILON), 50.0).worse_than_start());
        assert!(f(25.001, 50.0).worse_than_start());
    }
}
