//! A SCASM learner's check on itself, from nothing but its own models and the
//! inputs it has seen: each model must still be monotone over the inputs it
//! is used on (the command range for A, the readings of its fit's points for
//! S), as a walk's response and a camera's reading of a beacon are. A
//! coupling whose model has turned back on itself has learned something
//! false; until it passes again, the learner reports the last models that
//! passed instead.

use crate::polynomial::Polynomial;

/// Points at which a model's monotonicity is checked across its inputs' range.
const CHECK_POINTS: usize = 33;

/// How far a model may turn back on itself over its inputs' range, as a
/// fraction of the range of its values there, and still count as monotone
/// (a fitted polynomial wiggles a little where the response is flat).
pub const TURN_TOLERANCE: f64 = 0.01;

/// The self-check's setting.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SelfCheck {
    /// How long (s) models must pass the check, reading after reading,
    /// before the learner may fall back on them.
    pub good_after_s: f64,
}

/// The smallest closed range holding every value seen.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Span {
    lo: f64,
    hi: f64,
}

impl Span {
    pub(crate) fn of(x: f64) -> Self {
        Self { lo: x, hi: x }
    }

    pub(crate) fn widened(self, x: f64) -> Self {
        Self {
            lo: self.lo.min(x),
            hi: self.hi.max(x),
        }
    }
}

/// How far `model` turns back on itself over `lo..=hi`: the largest move
/// against its overall direction (end against start) between two checked
/// points, as a fraction of its values' range there. 0 for a monotone model,
/// a constant one or an empty range; infinite for one that is not finite
/// there.
pub fn turn_back(model: &Polynomial, lo: f64, hi: f64) -> f64 {
    if hi <= lo {
        return 0.0;
    }
    let at = |i: usize| {
        let u = i as f64 / (CHECK_POINTS - 1) as f64;
        model.eval(lo + u * (hi - lo))
    };
    let sign = if at(CHECK_POINTS - 1) >= at(0) {
        1.0
    } else {
        -1.0
    };
    let (mut least, mut most) = (f64::INFINITY, f64::NEG_INFINITY);
    // The furthest the model has gone in its direction so far, and the
    // largest fall behind it.
    let (mut best, mut worst_fall) = (f64::NEG_INFINITY, 0.0_f64);
    for i in 0..CHECK_POINTS {
        let v = at(i);
        if !v.is_finite() {
            return f64::INFINITY;
        }
        least = least.min(v);
        most = most.max(v);
        best = best.max(sign * v);
        worst_fall = worst_fall.max(best - sign * v);
    }
    if most > least {
        worst_fall / (most - least)
    } else {
        0.0
    }
}

/// A pair of models: the action model, then the sensor model.
pub type Models = (Polynomial, Polynomial);

/// The check's memory: the inputs' ranges, the last good models, the models
/// waiting to prove good, and the models reported while the check fails.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Guard {
    check: SelfCheck,
    commands: Option<Span>,
    readings: Option<Span>,
    /// Models that passed every check for `good_after_s` after they were taken.
    good: Option<Models>,
    /// Models that passed, when they were taken (s), and every check since.
    pending: Option<(f64, Models)>,
    /// Whether the last check failed.
    failing: bool,
    /// The good models reported in the learner's place while it fails.
    fallback: Option<Models>,
    /// How many times the learner has fallen back.
    fallbacks: u32,
}

impl Guard {
    /// A check of models over at least the commands `-command_scale..=command_scale`.
    pub(crate) fn new(check: SelfCheck, command_scale: f64) -> Self {
        Self {
            check,
            commands: Some(Span::of(-command_scale).widened(command_scale)),
            readings: None,
            good: None,
            pending: None,
            failing: false,
            fallback: None,
            fallbacks: 0,
        }
    }

    pub(crate) fn saw_command(&mut self, command: f64) {
        self.commands = Some(
            self.commands
                .map_or(Span::of(command), |s| s.widened(command)),
        );
    }

    /// A reading S is fitted to (a point of its fit, the mean of a window).
    pub(crate) fn saw_reading(&mut self, obs_px: f64) {
        self.readings = Some(
            self.readings
                .map_or(Span::of(obs_px), |s| s.widened(obs_px)),
        );
    }

    /// Whether both models are monotone over their inputs.
    fn passes(&self, (action, sensor): &Models) -> bool {
        let ok = |m: &Polynomial, span: Option<Span>| {
            span.is_none_or(|s| turn_back(m, s.lo, s.hi) <= TURN_TOLERANCE)
        };
        ok(action, self.commands) && ok(sensor, self.readings)
    }

    /// Checks the learner's `models` at `t_s`. Passing, they are reported
    /// as they are, and the waiting models become the good ones once they
    /// have passed for `good_after_s`, `models` waiting in their place.
    /// Failing, the waiting models are dropped, and from the first failed
    /// check until the next pass the good models are reported instead, if
    /// they pass over the inputs seen by then.
    pub(crate) fn check(&mut self, t_s: f64, models: Models) {
        if self.passes(&models) {
            self.failing = false;
            self.fallback = None;
            match self.pending {
                Some((taken_s, _)) if t_s - taken_s < self.check.good_after_s => {}
                _ => {
                    if let Some((_, m)) = self.pending.take() {
                        self.good = Some(m);
                    }
                    self.pending = Some((t_s, models));
                }
            }
            return;
        }
        self.pending = None;
        if !core::mem::replace(&mut self.failing, true) {
            self.fallback = self.good.filter(|g| self.passes(g));
            if self.fallback.is_some() {
                self.fallbacks += 1;
            }
        }
    }

    /// The models to report in the learner's place, while it fails.
    pub(crate) fn fallback(&self) -> Option<Models> {
        self.fallback
    }

    /// How many times the learner has fallen back.
    pub(crate) fn fallbacks(&self) -> u32 {
        self.fallbacks
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(c: &[f64]) -> Polynomial {
        Polynomial::new(c).expect("a polynomial")
    }

    #[test]
    fn a_monotone_model_does_not_turn_back_either_way() {
        assert_eq!(turn_back(&poly(&[10.0, 0.9, 1e-4]), -300.0, 300.0), 0.0);
        assert_eq!(turn_back(&poly(&[10.0, -0.9, 1e-4]), -300.0, 300.0), 0.0);
    }

    #[test]
    fn a_model_that_turns_back_at_its_end_is_seen() {
        // Rises to c = 150, then falls: 0.9 c - 0.003 c^2.
        let m = poly(&[0.0, 0.9, -0.003]);
        let turn = turn_back(&m, -300.0, 300.0);
        assert!(turn > 0.1, "{turn}");
        // Over the commands before the turn it is monotone.
        assert!(turn_back(&m, -300.0, 100.0) < 1e-12);
    }

    #[test]
    fn a_small_wiggle_is_within_the_tolerance() {
        // c^3 - 0.03 c turns back between c = -0.1 and 0.1 by 0.2 %
        // of its range over [-1, 1].
        let m = poly(&[0.0, -0.03, 0.0, 1.0]);
        let turn = turn_back(&m, -1.0, 1.0);
        assert!(turn > 0.0 && turn <= TURN_TOLERANCE, "{turn}");
    }

    #[test]
    fn good_models_are_those_that_passed_for_the_set_time() {
        let line = |k: f64| poly(&[0.0, k]);
        let bad = (poly(&[0.0, 0.9, -0.003]), line(1.0));
        let mut g = Guard::new(SelfCheck { good_after_s: 10.0 }, 300.0);
        g.saw_command(-300.0);
        g.saw_command(300.0);
        g.check(0.0, (line(1.0), line(1.0)));
        g.check(5.0, (line(2.0), line(1.0)));
        g.check(6.0, bad);
        assert_eq!(g.fallback(), None, "nothing has passed for 10 s yet");
        g.check(7.0, (line(3.0), line(1.0)));
        g.check(17.0, (line(4.0), line(1.0)));
        g.check(18.0, (line(5.0), line(1.0)));
        assert_eq!(
            g.fallback(),
            None,
            "passing models are reported as they are"
        );
        g.check(19.0, bad);
        assert_eq!(g.fallback(), Some((line(3.0), line(1.0))));
        g.check(20.0, bad);
        assert_eq!(g.fallbacks(), 1, "one failure, however long");
        // The models waiting when the check failed never become good.
        g.check(21.0, (line(6.0), line(1.0)));
        assert_eq!(g.fallback(), None);
        g.check(31.0, (line(7.0), line(1.0)));
        g.check(32.0, bad);
        assert_eq!(g.fallback(), Some((line(6.0), line(1.0))));
    }
}
