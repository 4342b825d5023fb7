//! Every random stream comes from one master seed, split into named streams, so
//! that adding noise somewhere never changes the robot's choices elsewhere.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// The independent random streams of one trial.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stream {
    /// The training behaviour's choice of commands.
    Behaviour = 1,
    /// Noise added to the camera's readings.
    SensorNoise = 2,
    /// Perturbations of the world (start pose, terrain, ...).
    World = 3,
}

/// The random generator of `stream` under master seed `seed`.
pub fn rng(seed: u64, stream: Stream) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream as u64);
    rng
}
