//! The plugin interface between a host (a simulator, a real robot) and a
//! calibration learner. The host drives; the learner reacts to timestamped events
//! and can be asked for its current models and location estimates at any time.

use crate::error::EventError;
use crate::polynomial::Polynomial;
#[cfg(feature = "std")]
use crate::posterior::Posterior;

/// Something that happened, in the host's time (seconds from the start of the run).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Event {
    /// `command` was in force from `t_s` to `t_s + dt_s`. Commands arrive back to
    /// back: each starts where the previous one ended (the first at time 0).
    Command {
        /// Start of the interval, s.
        t_s: f64,
        /// Length of the interval, s (> 0).
        dt_s: f64,
        /// The walk command, in the robot's command units.
        command: f64,
    },
    /// A beacon reading taken at `t_s`, which must be the end of the last command
    /// interval (the learner's clock).
    Reading {
        /// When it was taken, s.
        t_s: f64,
        /// The beacon's height in the image, px (> 0).
        obs_px: f64,
    },
}

/// A learner of action and sensor models from commands and readings alone.
///
/// A host feeds events in time order with [`handle`](Self::handle); a refused event
/// returns an error and leaves the learner exactly as it was. Models are in the
/// learner's own units: the sensor model maps pixels to a location, the action
/// model maps a command to that location's rate of change per second.
///
/// ```
/// use scasm::{CalibrationLearner, Event, Scasm};
///
/// let mut learner: Box<dyn CalibrationLearner> = Box::new(Scasm::default());
/// let dt_s = 0.05;
/// for k in 0..100 {
///     let t_s = f64::from(k) * dt_s;
///     learner.handle(Event::Command { t_s, dt_s, command: 150.0 })?;
///     // A robot walking towards a beacon sees it grow.
///     let distance_mm = 3000.0 - 150.0 * (t_s + dt_s);
///     learner.handle(Event::Reading { t_s: t_s + dt_s, obs_px: 38_400.0 / distance_mm })?;
/// }
/// assert!(learner.sensor_model().is_some());
/// assert!(learner.handle(Event::Reading { t_s: 1.0, obs_px: 20.0 }).is_err()); // the past
/// # Ok::<(), scasm::EventError>(())
/// ```
pub trait CalibrationLearner {
    /// A short name for reports and command lines: its declaration's, or
    /// the variant its settings make it.
    fn name(&self) -> &str;
    /// Takes one event, or refuses it and changes nothing.
    fn handle(&mut self, event: Event) -> Result<(), EventError>;
    /// The current action model (command -> location units per second), if any yet.
    fn action_model(&self) -> Option<Polynomial>;
    /// The current sensor model (pixels -> location units), if any yet.
    fn sensor_model(&self) -> Option<Polynomial>;
    /// The location by dead reckoning with the action model in use (`x_a`).
    fn x_a(&self) -> Option<f64>;
    /// The location the sensor model gave for the latest reading (`x_s`).
    fn x_s(&self) -> Option<f64>;
    /// Why the learner can no longer take part, if it cannot: a learner in
    /// another process that died, broke its protocol or stopped answering.
    /// Once it fails, its events are refused ([`EventError::Failed`]) and its
    /// queries answer `None`; a host ends the trial and reports this reason.
    /// A learner in the host's own process never fails (the default).
    fn failure(&self) -> Option<&str> {
        None
    }
    /// Whether the learner, by a check on itself, doubts its own current
    /// models and reports older ones in their place (see
    /// [`crate::Scasm::with_self_check`]); `None` for a learner that does not
    /// check itself (the default).
    fn falling_back(&self) -> Option<bool> {
        None
    }
    /// `draws` draws from the learner's posterior over the robot's true
    /// responses given what it has seen, in the units of its models; the
    /// same draws for the same events (seeded from nothing else). `None`
    /// for a learner that does not know how sure it is (the default), or
    /// has no models yet.
    #[cfg(feature = "std")]
    fn posterior(&self, draws: usize) -> Option<Posterior> {
        let _ = draws;
        None
    }
}
