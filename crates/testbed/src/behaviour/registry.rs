//! The training behaviours a run can name (`--behaviour NAME`, setting
//! `behaviour.name`; `--behaviour list` prints them): each a declaration of
//! its name, what it does and how a trial builds it. Every behaviour is told
//! the same [`BehaviourConfig`] (the paper's turning thresholds, the largest
//! command, how long a command is held, the action model's degree) and draws
//! from the trial's behaviour stream of random numbers; it sees the robot's
//! readings, never the ground truth.

use rand_chacha::ChaCha8Rng;

use super::paper::Draw;
use super::{Behaviour, BehaviourConfig, Phase, TrainingBehaviour};

/// A behaviour a run can name.
#[derive(Debug, Clone, Copy)]
pub struct Declaration {
    /// Its name.
    pub name: &'static str,
    /// What it does, in a line.
    pub doc: &'static str,
    /// The behaviour for a trial, starting forwards.
    pub build: fn(BehaviourConfig, ChaCha8Rng) -> Box<dyn Behaviour>,
    /// What of `config` beyond the paper's thresholds, the largest command
    /// and the hold (which the world's own key holds) this behaviour's
    /// commands depend on, as text: two scenarios whose keys are equal walk
    /// the same (see [`crate::experiment::world_key`]).
    pub key: fn(&BehaviourConfig) -> String,
    /// Whether it steers by the learner's models
    /// ([`Behaviour::consult`]): its trial then
    /// runs with the learner in the loop, and a recorded world is shared
    /// only by runs of the same learner with the same settings.
    pub steered: bool,
}

/// The behaviour a run uses unless told otherwise.
pub const DEFAULT: &str = "paper";

/// Every behaviour, the default first.
pub const BEHAVIOURS: [Declaration; 3] = [
    Declaration {
        name: "paper",
        doc: "the paper's (section II): commands drawn uniformly from [0, max] forwards and \
              [-max, 0] backwards, each held 3 s, turning round when the beacon looks too big \
              or too small",
        build: |config, rng| Box::new(TrainingBehaviour::new(config, rng, Phase::Forwards)),
        key: |_| "paper".into(),
        steered: false,
    },
    Declaration {
        name: "design",
        doc: "the paper's walk with each command's magnitude drawn from the I-optimal design (the \
              least average prediction variance over the paper's 31 commands) for a polynomial \
              behaviour.design_extra_degree degrees above the action model's, not uniformly",
        build: |config, rng| {
            let draw = Draw::Design(super::design::phase_draw(
                config.action_degree + config.design_extra_degree,
            ));
            Box::new(TrainingBehaviour::drawing(
                config,
                draw,
                rng,
                Phase::Forwards,
            ))
        },
        key: |config| {
            format!(
                "design/{}",
                config.action_degree + config.design_extra_degree
            )
        },
        steered: false,
    },
    Declaration {
        name: "explore",
        doc: "the paper's walk with each command chosen, when due, to lower the action model's \
              average prediction variance the most (sequential I-optimal design for the design's \
              polynomial) given the commands walked so far and how long the learner's current \
              models say the hold would last; runs with the learner in the loop",
        build: |config, rng| {
            let explorer =
                super::explore::Explorer::new(config.action_degree + config.design_extra_degree);
            Box::new(TrainingBehaviour::drawing(
                config,
                Draw::Explore(Box::new(explorer)),
                rng,
                Phase::Forwards,
            ))
        },
        key: |config| {
            format!(
                "explore/{}",
                config.action_degree + config.design_extra_degree
            )
        },
        steered: true,
    },
];

/// The behaviour named `name`, or an error listing them.
pub fn resolve(name: &str) -> Result<&'static Declaration, String> {
    BEHAVIOURS.iter().find(|b| b.name == name).ok_or_else(|| {
        format!(
            "no behaviour `{name}`: one of {} (--behaviour list)",
            names().collect::<Vec<_>>().join(", ")
        )
    })
}

/// Every behaviour's name.
pub fn names() -> impl Iterator<Item = &'static str> {
    BEHAVIOURS.iter().map(|b| b.name)
}

/// Every behaviour, a line each: its name and what it does.
pub fn describe() -> String {
    BEHAVIOURS
        .iter()
        .map(|b| {
            let default = if b.name == DEFAULT {
                " (the default)"
            } else {
                ""
            };
            format!("{:<8} {}{default}\n", b.name, b.doc)
        })
        .collect()
}

/// The behaviour `config` names, for a trial whose behaviour stream is `rng`.
pub fn build(config: BehaviourConfig, rng: ChaCha8Rng) -> Result<Box<dyn Behaviour>, String> {
    Ok((resolve(config.name)?.build)(config, rng))
}
