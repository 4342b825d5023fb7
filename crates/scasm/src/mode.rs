//! What a learner learns from what: both models at once, or one from the
//! other given (the paper's sections IV, V and VI).

use crate::polynomial::Polynomial;

/// What is learned from what.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Mode {
    /// Both models at once, each from the other (section VI, Fig. 4).
    Simultaneous,
    /// S from one constant action: regress readings on time (Fig. 2a). The
    /// learned S is in "seconds of this walk".
    SensorFromConstantAction,
    /// S from a given action model, by dead reckoning (section IV).
    SensorFromAction(Polynomial),
    /// A from a given sensor model (section V, Eq. 5).
    ActionFromSensor(Polynomial),
}
