//! A recording walked again: a world that answers each frame with the one it
//! recorded, as long as it is asked for the same command at the same time,
//! and refuses, saying where, as soon as it is not. Walking a recording again
//! with the behaviour that made it checks that the behaviour is what the
//! recording says it was (it read nothing but the recorded readings).

use super::{FrameRecord, Sensed, World, WorldError};

/// The frames of a recording, to be walked again in order.
#[derive(Debug, Clone)]
pub struct Replayed {
    frames: Vec<FrameRecord>,
    next: usize,
}

impl Replayed {
    /// The world of `frames` (a recording's, in order).
    pub fn new(frames: Vec<FrameRecord>) -> Self {
        Self { frames, next: 0 }
    }
}

impl World for Replayed {
    fn frame_period_s(&self) -> f64 {
        self.frames.first().map_or(f64::NAN, |f| f.dt_s)
    }

    fn step_frame(&mut self, t_s: f64, command: f64) -> Result<Sensed, WorldError> {
        let k = self.next;
        let Some(frame) = self.frames.get(k) else {
            return Err(WorldError::Departed(format!(
                "asked for frame {k} at {t_s} s, and it holds {} frames",
                self.frames.len()
            )));
        };
        if frame.t_s.to_bits() != t_s.to_bits() {
            return Err(WorldError::Departed(format!(
                "frame {k} starts at {} s in the recording, and was asked for at {t_s} s",
                frame.t_s
            )));
        }
        if frame.command.to_bits() != command.to_bits() {
            return Err(WorldError::Departed(format!(
                "at {t_s} s (frame {k}) the behaviour commands {command}, and the recording \
                 walked {}",
                frame.command
            )));
        }
        self.next += 1;
        Ok(Sensed {
            obs_px: frame.obs_px,
            truth: frame.truth,
        })
    }
}
