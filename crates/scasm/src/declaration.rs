//! How a learner declares itself to a host: its name, what it is, the
//! settings it reads (the shared ones of [`SHARED`] it uses, and its own, each
//! with a type, default, range and a line of doc) and how it is built from
//! them. A host lists, checks, records and sweeps settings from these
//! declarations alone; a new learner is one [`Declaration`] beside its
//! algorithm and one line in the host's registry (the testbed's
//! `learners/registry.rs`).

use std::boxed::Box;
use std::format;
use std::string::String;
use std::vec::Vec;

use crate::config::ScasmConfig;
use crate::learner::CalibrationLearner;
use crate::mode::Mode;

/// A setting's type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A finite real number.
    Number,
    /// A whole number (degrees, counts).
    Count,
}

/// One setting a learner reads: the key (after `learner.` for a shared one,
/// after `learner.<name>.` for a learner's own), its type, default, range and
/// what it does.
#[derive(Debug, Clone, PartialEq)]
pub struct Setting {
    /// The key, e.g. `gamma` or `solve_every_s`.
    pub key: String,
    /// Its type.
    pub kind: Kind,
    /// Its default.
    pub default: f64,
    /// The smallest value allowed.
    pub min: f64,
    /// Whether `min` itself is excluded.
    pub min_open: bool,
    /// The largest value allowed (inclusive; infinity for none).
    pub max: f64,
    /// One line on what it does.
    pub doc: String,
}

impl Setting {
    /// A setting of `kind` in `[min, max]` (or `(min, max]` if `min_open`).
    pub fn new(
        key: &str,
        kind: Kind,
        default: f64,
        (min, min_open, max): (f64, bool, f64),
        doc: &str,
    ) -> Self {
        Self {
            key: key.into(),
            kind,
            default,
            min,
            min_open,
            max,
            doc: doc.into(),
        }
    }

    /// The allowed range, as written in docs and errors: `(0, 1]`, `1..=8`.
    pub fn range(&self) -> String {
        match self.kind {
            Kind::Count if self.max.is_finite() => format!("{}..={}", self.min, self.max),
            Kind::Count => format!("{}..", self.min),
            Kind::Number => format!(
                "{}{}, {}]",
                if self.min_open { "(" } else { "[" },
                self.min,
                if self.max.is_finite() {
                    format!("{}", self.max)
                } else {
                    "inf".into()
                }
            )
            .replace("inf]", "inf)"),
        }
    }

    /// `value` if it is of this setting's type and in its range.
    pub fn check(&self, value: f64) -> Result<f64, String> {
        if !value.is_finite() {
            return Err(format!("{value} is not finite"));
        }
        if self.kind == Kind::Count && value.fract() != 0.0 {
            return Err(format!("{value} is not a whole number"));
        }
        let above_min = if self.min_open {
            value > self.min
        } else {
            value >= self.min
        };
        if above_min && value <= self.max {
            Ok(value)
        } else {
            Err(format!("{value} must be in {}", self.range()))
        }
    }
}

/// The values of a learner's own settings in force, in its declared order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Values(pub Vec<(String, f64)>);

impl Values {
    /// The value of `key` (NaN if it is not one: declarations and builders
    /// are written together, and a unit test builds every learner).
    pub fn get(&self, key: &str) -> f64 {
        self.0
            .iter()
            .find(|(k, _)| k == key)
            .map_or(f64::NAN, |(_, v)| *v)
    }

    /// The value of a count `key`.
    pub fn count(&self, key: &str) -> usize {
        self.get(key) as usize
    }
}

/// What a learner is built from: the shared settings, its own in force, and
/// what it learns (both models, or one from the other given).
#[derive(Debug, Clone)]
pub struct BuildContext {
    /// The shared settings (`learner.gamma`, the degrees, ...).
    pub shared: ScasmConfig,
    /// Its own settings in force.
    pub own: Values,
    /// What is learned from what.
    pub mode: Mode,
}

/// A learner a host can own and send between threads.
pub type BoxedLearner = Box<dyn CalibrationLearner + Send>;

/// A learner, as a host sees it before building one.
#[derive(Debug, Clone, Copy)]
pub struct Declaration {
    /// Its name on command lines and in reports.
    pub name: &'static str,
    /// One line on what it is.
    pub about: &'static str,
    /// The shared settings it reads (keys of [`SHARED`]).
    pub shared: &'static [&'static str],
    /// Its own settings (`learner.<name>.<key>`).
    pub settings: fn() -> Vec<Setting>,
    /// Whether it can learn one model from the other given (the paper's
    /// sections IV and V), not only both at once.
    pub one_sided: bool,
    /// Builds one, for one trial.
    pub build: fn(&BuildContext) -> Result<BoxedLearner, String>,
}

impl Declaration {
    /// Its own settings' defaults.
    pub fn defaults(&self) -> Values {
        Values(
            (self.settings)()
                .into_iter()
                .map(|s| (s.key, s.default))
                .collect(),
        )
    }
}

/// A shared setting: its declaration and where it lives in [`ScasmConfig`].
#[derive(Debug, Clone, Copy)]
pub struct SharedSetting {
    /// The key after `learner.`.
    pub key: &'static str,
    /// Its type.
    pub kind: Kind,
    /// `(min, min_open, max)`.
    pub range: (f64, bool, f64),
    /// One line on what it does.
    pub doc: &'static str,
    /// Reads it.
    pub get: fn(&ScasmConfig) -> f64,
    /// Writes it (the value already checked against its range).
    pub set: fn(&mut ScasmConfig, f64),
}

impl SharedSetting {
    /// Its declaration, with the default from `defaults` (which a host
    /// scales to its robot).
    pub fn setting(&self, defaults: &ScasmConfig) -> Setting {
        Setting::new(
            self.key,
            self.kind,
            (self.get)(defaults),
            self.range,
            self.doc,
        )
    }
}

const MAX_DEGREE: f64 = crate::MAX_REGRESSORS as f64;

/// The settings several learners share, as `learner.<key>`: SCASM's
/// hyper-parameters, which the batch learner's online start reads too.
pub const SHARED: [SharedSetting; 10] = [
    SharedSetting {
        key: "gamma",
        kind: Kind::Number,
        range: (0.0, true, 1.0),
        doc: "forgetting factor per reading: point k of n weighs gamma^(n-k)",
        get: |c| c.gamma,
        set: |c, v| c.gamma = v,
    },
    SharedSetting {
        key: "beta",
        kind: Kind::Number,
        range: (0.0, false, 1.0),
        doc: "pull of x_a towards x_s at each reading",
        get: |c| c.beta,
        set: |c, v| c.beta = v,
    },
    SharedSetting {
        key: "t_start",
        kind: Kind::Number,
        range: (0.0, false, f64::INFINITY),
        doc: "ramp-up, s: only S learns before it, A from it, dead reckoning with A from twice it",
        get: |c| c.t_start_s,
        set: |c, v| c.t_start_s = v,
    },
    SharedSetting {
        key: "sensor_degree",
        kind: Kind::Count,
        range: (1.0, false, MAX_DEGREE),
        doc: "degree of the sensor model S (pixels -> location)",
        get: |c| c.sensor_degree as f64,
        set: |c, v| c.sensor_degree = v as usize,
    },
    SharedSetting {
        key: "action_degree",
        kind: Kind::Count,
        range: (1.0, false, MAX_DEGREE - 1.0),
        doc: "degree of the action model A (command -> velocity)",
        get: |c| c.action_degree as f64,
        set: |c, v| c.action_degree = v as usize,
    },
    SharedSetting {
        key: "sensor_window",
        kind: Kind::Count,
        range: (1.0, false, crate::config::MAX_SENSOR_WINDOW as f64),
        doc: "readings averaged into each point of the sensor fit (1: the paper's)",
        get: |c| c.sensor_window as f64,
        set: |c, v| c.sensor_window = v as usize,
    },
    SharedSetting {
        key: "forward_degree",
        kind: Kind::Count,
        range: (1.0, false, MAX_DEGREE),
        doc: "degree of the forward sensor model obs ~ g(x) a batch learner fits",
        get: |c| c.forward_degree as f64,
        set: |c, v| c.forward_degree = v as usize,
    },
    SharedSetting {
        key: "action_prior",
        kind: Kind::Number,
        range: (0.0, false, f64::INFINITY),
        doc: "strength k of the prior that A is nearly linear: its coefficients of degree >= 2 \
              (commands / command_scale) ~ N(0, (command_scale / k)^2); 0: none (the paper's)",
        get: |c| c.action_prior,
        set: |c, v| c.action_prior = v,
    },
    SharedSetting {
        key: "action_highpass",
        kind: Kind::Number,
        range: (0.0, false, f64::INFINITY),
        doc: "time constant, s, of the high-pass both sides of the action fit go through, so a \
              distance lost in a stall fades from it; 0: none (the paper's Eq. 5)",
        get: |c| c.action_highpass_s,
        set: |c, v| c.action_highpass_s = v,
    },
    SharedSetting {
        key: "action_robust",
        kind: Kind::Number,
        range: (0.0, false, f64::INFINITY),
        doc: "a point of the action fit whose residual is beyond this many residual standard \
              deviations is weighed down (Huber's); 0: least squares (the paper's)",
        get: |c| c.action_robust,
        set: |c, v| c.action_robust = v,
    },
];

/// The shared setting `key` (after `learner.`).
pub fn shared(key: &str) -> Option<&'static SharedSetting> {
    SHARED.iter().find(|s| s.key == key)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_read_as_written_and_check_what_they_say() {
        let gamma = shared("gamma").map(|s| s.setting(&ScasmConfig::default()));
        let gamma = gamma
            .as_ref()
            .map(|g| (g.range(), g.check(0.0), g.check(1.0)));
        assert_eq!(
            gamma.map(|(r, zero, one)| (r, zero.is_err(), one.is_ok())),
            Some(("(0, 1]".into(), true, true))
        );
        let degree = Setting::new("d", Kind::Count, 3.0, (1.0, false, 8.0), "");
        assert_eq!(degree.range(), "1..=8");
        assert!(degree.check(2.5).is_err() && degree.check(9.0).is_err());
        assert!(degree.check(f64::NAN).is_err() && degree.check(8.0).is_ok());
        let open = Setting::new("s", Kind::Number, 1.0, (0.0, true, f64::INFINITY), "");
        assert_eq!(open.range(), "(0, inf)");
    }

    #[test]
    fn every_shared_setting_reads_back_what_it_wrote() {
        for s in &SHARED {
            let mut c = ScasmConfig::default();
            let v = if s.kind == Kind::Count { 2.0 } else { 0.5 };
            (s.set)(&mut c, v);
            assert_eq!((s.get)(&c), v, "{}", s.key);
        }
    }
}
