//! An online learner that knows how sure it is. It reports its own models,
//! learned online as ever; what it believes the robot's true responses could
//! be, given every event it has seen, is the likelihood's (`batch-ml-lag`'s
//! model: the path, a lagged response to each command and a forward sensor
//! model, with the process and reading noises), by the Laplace approximation
//! at its maximum, solved once, when a host asks. The posterior over the
//! truth depends on the data and the model of them, not on which estimate
//! is reported: judging the online models against its draws counts both
//! the noise and how far the online estimate is from the likeliest one.
//!
//! The likelihood's solve starts from the online learner's own path and
//! models (and the readings' pinhole path), and its solution is put in the
//! online learner's units (the affine map that best takes its path onto the
//! online path), so that the draws are in the units of the models reported.

use std::vec;
use std::vec::Vec;

use crate::batch::{BatchMl, BatchMlConfig};
use crate::config::{ScasmConfig, SensorFit};
use crate::error::EventError;
use crate::learner::{CalibrationLearner, Event};
use crate::polynomial::Polynomial;
use crate::posterior::Posterior;
use crate::scasm::Scasm;

/// An online SCASM learner with the lagged likelihood's posterior (see the
/// module's documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Believed {
    learner: Scasm,
    /// Every event the learner took, in order, for the likelihood.
    events: Vec<Event>,
    /// The learner's dead-reckoned location at each frame boundary (the
    /// first at time 0): its units, which the posterior's draws are put in.
    path: Vec<f64>,
    /// The likelihood's settings: `batch-ml-lag`'s, with the online
    /// learner's own as its start and units.
    likelihood: BatchMlConfig,
}

impl Believed {
    /// `learner` (simultaneous), its posterior that of `batch-ml-lag`'s
    /// likelihood started from a learner with its settings.
    pub fn new(learner: Scasm) -> Self {
        Self {
            likelihood: BatchMlConfig {
                online: ScasmConfig {
                    sensor_fit: SensorFit::Corrected,
                    ..learner.params().config()
                },
                ..BatchMlConfig::lagged()
            },
            learner,
            events: Vec::new(),
            path: vec![0.0],
        }
    }

    /// The online learner.
    pub fn learner(&self) -> &Scasm {
        &self.learner
    }
}

impl CalibrationLearner for Believed {
    fn name(&self) -> &str {
        self.learner.name()
    }

    fn handle(&mut self, event: Event) -> Result<(), EventError> {
        self.learner.handle(event)?;
        self.events.push(event);
        let x = self.learner.x_a().unwrap_or(0.0);
        match event {
            Event::Command { .. } => self.path.push(x),
            Event::Reading { .. } => {
                if let Some(last) = self.path.last_mut() {
                    *last = x;
                }
            }
        }
        Ok(())
    }

    fn action_model(&self) -> Option<Polynomial> {
        self.learner.action_model()
    }

    fn sensor_model(&self) -> Option<Polynomial> {
        self.learner.sensor_model()
    }

    fn x_a(&self) -> Option<f64> {
        self.learner.x_a()
    }

    fn x_s(&self) -> Option<f64> {
        self.learner.x_s()
    }

    fn falling_back(&self) -> Option<bool> {
        self.learner.falling_back()
    }

    fn posterior(&self, draws: usize) -> Option<Posterior> {
        // One solve, at the last reading: the events so far are the trial.
        let end_s = self.events.iter().rev().find_map(|e| match e {
            Event::Reading { t_s, .. } => Some(*t_s),
            Event::Command { .. } => None,
        })?;
        // Solving every 10 s of the trial, as `batch-ml-lag` does, gave the
        // same bands to within 4 % (ERS-7, development seeds 100-129) at
        // seven times the cost: the posterior's own solve, of a richer
        // action model, starts from the solution either way.
        let params = BatchMlConfig {
            solve_every_s: end_s,
            ..self.likelihood
        }
        .validate()
        .ok()?;
        let mut batch = BatchMl::new(params);
        for event in &self.events {
            // The learner took each of them; the batch learner's online
            // learner checks events alike.
            batch.handle(*event).ok()?;
        }
        batch.posterior_in_units_of(draws, Some(&self.path))
    }
}
