//! # scasm: Simultaneous Calibration of Action and Sensor Models
//!
//! The learner of Stronger & Stone's "Simultaneous Calibration of Action and
//! Sensor Models on a Mobile Robot": from walk commands, timestamps and beacon
//! readings alone, a robot learns at once its action model (command -> velocity)
//! and its sensor model (beacon height in pixels -> distance), each from the other.
//!
//! The crate knows nothing of physics or simulators. A host (the testbed, or a
//! real robot) drives any [`CalibrationLearner`] with [`Event`]s; [`Scasm`] is the
//! paper's learner. With default features off it needs neither the standard
//! library nor an allocator, so it can run on board.
//!
//! Numerics: each model is an incremental exponentially weighted least-squares fit
//! (Eq. 2-7) kept in square-root (QR) form with internally normalised inputs; it
//! gives the batch weighted least-squares solution in O(1) time and memory per
//! point, and reports "not yet" (`None`) while the data do not determine a model.
//!
//! ```
//! use scasm::{CalibrationLearner, Event, Scasm, ScasmConfig, Mode};
//!
//! let params = ScasmConfig { gamma: 0.999, ..Default::default() }.validate()?;
//! let mut learner = Scasm::new(params, Mode::Simultaneous)?;
//! learner.handle(Event::Command { t_s: 0.0, dt_s: 0.05, command: 120.0 })?;
//! learner.handle(Event::Reading { t_s: 0.05, obs_px: 21.5 })?;
//! assert!(learner.sensor_model().is_none()); // one reading determines no cubic
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![cfg_attr(not(feature = "std"), no_std)]
#![warn(missing_docs)]

mod action_fit;
#[cfg(feature = "std")]
mod batch;
mod config;
#[cfg(feature = "std")]
pub mod declaration;
mod eiv_fit;
mod error;
mod learner;
mod mode;
mod poly_fit;
mod polynomial;
#[cfg(feature = "std")]
mod posterior;
mod scasm;
pub mod self_check;
#[cfg(feature = "std")]
mod variants;
mod wls;

/// Most regressors one fit can have: a sensor model of degree up to this, an
/// action model of degree up to one less (its regressors are `V_0..V_d`).
pub const MAX_REGRESSORS: usize = 8;

#[cfg(feature = "std")]
pub use batch::{
    BATCH_ML, BATCH_ML_LAG, BatchMl, BatchMlConfig, BatchMlParams, Believed, KeepStart,
};
pub use config::{MAX_SENSOR_WINDOW, ScasmConfig, ScasmParams, SensorFit};
pub use error::{ConfigError, EventError};
pub use learner::{CalibrationLearner, Event};
pub use mode::Mode;
pub use polynomial::{MAX_COEFFS, Polynomial};
#[cfg(feature = "std")]
pub use posterior::{Draw, Posterior};
pub use scasm::Scasm;
pub use self_check::SelfCheck;
#[cfg(feature = "std")]
pub use variants::{SCASM, SCASM_EIV, SCASM_PAPER};

#[cfg(test)]
mod proptests;
