//! The learners a run can name, and the default: the list a scenario's
//! `learner.name` is checked against (it needs nothing else of the learners).

/// The learner a run uses unless told otherwise.
pub const DEFAULT: &str = "scasm";

/// Each learner's name and what it is.
pub const LEARNERS: [(&str, &str); 4] = [
    (
        "scasm-paper",
        "SCASM exactly as the paper has it: every reading its own point of the sensor fit",
    ),
    (
        "scasm",
        "SCASM with the sensor fit's readings averaged in windows (learner.sensor_window, 5)",
    ),
    (
        "scasm-eiv",
        "SCASM whose sensor fit corrects for the reading noise, estimated from the readings: \
         no errors-in-variables bias",
    ),
    (
        "batch-ml",
        "maximum likelihood over the whole trial: path, A and the forward sensor model jointly, \
         started from scasm-eiv, its own last solution and the readings' pinhole path",
    ),
];

/// The learners' names, in the order above.
pub fn names() -> impl Iterator<Item = &'static str> {
    LEARNERS.iter().map(|l| l.0)
}
