//! How a trial ended: only `Ok` trials enter the statistics, every other one is
//! counted and named.

use crate::trial::TrialOutcome;

/// How a trial ended. Only `Ok` trials enter a mean; every other one is counted
/// and named in every report, so none silently drops out.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum TrialStatus {
    /// The robot stayed upright and both models were learned, with finite errors.
    Ok,
    /// The robot tipped over (its world is no longer the experiment's), by
    /// `at_s` (s into the trial, the end of the frame it tipped in) when
    /// that is known.
    Fell {
        /// When, s.
        at_s: Option<f64>,
    },
    /// The physics blew up (see [`quadsim::QuadrupedSim::blew_up_at_s`]):
    /// the solver, not the robot or the learner, ended the trial; by `at_s`
    /// (s into the trial, the end of the frame it blew up in) when that is
    /// known.
    BlewUp {
        /// When, s.
        at_s: Option<f64>,
    },
    /// A model was never determined by the data.
    NoModel,
    /// Both models exist but an error is not finite.
    Diverged,
    /// The trial could not run; the reason.
    Error(String),
}

impl TrialStatus {
    /// The status of a finished trial: a blow-up first (it usually throws the
    /// robot over too), then a fall, then a missing model, then non-finite
    /// errors.
    pub fn of(outcome: &TrialOutcome) -> Self {
        let j = &outcome.last;
        if let Some(at_s) = outcome.blew_up_at_s {
            Self::BlewUp { at_s: Some(at_s) }
        } else if let Some(at_s) = outcome.fell_at_s {
            Self::Fell { at_s: Some(at_s) }
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
        let dated = |prefix: &str| {
            let at = text.strip_prefix(prefix)?.strip_suffix(" s")?;
            at.parse::<f64>().ok()
        };
        match text {
            "ok" => Self::Ok,
            "fell" => Self::Fell { at_s: None },
            "physics blew up" => Self::BlewUp { at_s: None },
            "no model" => Self::NoModel,
            "diverged" => Self::Diverged,
            _ => {
                if let Some(at_s) = dated("fell at ") {
                    Self::Fell { at_s: Some(at_s) }
                } else if let Some(at_s) = dated("physics blew up at ") {
                    Self::BlewUp { at_s: Some(at_s) }
                } else {
                    Self::Error(text.strip_prefix("error: ").unwrap_or(text).into())
                }
            }
        }
    }
}

impl std::fmt::Display for TrialStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Ok => f.write_str("ok"),
            Self::Fell { at_s: None } => f.write_str("fell"),
            // To the hundredth of a second (frames come every 50 ms).
            Self::Fell { at_s: Some(t) } => write!(f, "fell at {t:.2} s"),
            Self::BlewUp { at_s: None } => f.write_str("physics blew up"),
            Self::BlewUp { at_s: Some(t) } => write!(f, "physics blew up at {t:.2} s"),
            Self::NoModel => f.write_str("no model"),
            Self::Diverged => f.write_str("diverged"),
            Self::Error(e) => write!(f, "error: {e}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statuses_read_back_as_written() {
        for s in [
            TrialStatus::Ok,
            TrialStatus::Fell { at_s: None },
            TrialStatus::Fell { at_s: Some(260.1) },
            TrialStatus::BlewUp { at_s: None },
            TrialStatus::BlewUp { at_s: Some(0.05) },
            TrialStatus::NoModel,
            TrialStatus::Diverged,
            TrialStatus::Error("the learner refused an event".into()),
        ] {
            assert_eq!(TrialStatus::parse(&s.to_string()), s);
        }
    }
}
