//! Walk parameters, the paper's Eq. 1 interpolation between them, and the feet's
//! loci of a trot. Everything here is kinematic intent; only the physics decides
//! how fast the robot actually goes.

/// One walk: the parameters that shape every foot's path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaitParams {
    /// How far a foot travels backwards (relative to the body) during stance, m.
    /// Negative walks backwards; zero steps in place.
    pub step_length_m: f64,
    /// Apex of a foot's swing above the ground, m.
    pub step_height_m: f64,
    /// Duration of one gait cycle, s.
    pub period_s: f64,
    /// Height of the hip joints above the feet in stance, m.
    pub body_height_m: f64,
    /// Sideways offset of each foot outwards from its hip, m.
    pub stance_width_m: f64,
    /// Fraction of the cycle a foot is on the ground, in (0, 1).
    pub duty_factor: f64,
    /// Forward offset of the feet's neutral point from the hips, m (shifts the
    /// body's weight over the legs).
    pub foot_offset_m: f64,
}

impl GaitParams {
    /// `self + t (other - self)`, parameter by parameter.
    pub fn lerp(&self, other: &Self, t: f64) -> Self {
        let l = |a: f64, b: f64| a + t * (b - a);
        Self {
            step_length_m: l(self.step_length_m, other.step_length_m),
            step_height_m: l(self.step_height_m, other.step_height_m),
            period_s: l(self.period_s, other.period_s),
            body_height_m: l(self.body_height_m, other.body_height_m),
            stance_width_m: l(self.stance_width_m, other.stance_width_m),
            duty_factor: l(self.duty_factor, other.duty_factor),
            foot_offset_m: l(self.foot_offset_m, other.foot_offset_m),
        }
    }
}

/// The three parameter vectors of the paper and the nominal speeds Eq. 1 uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaitTable {
    /// `p_i`: steps in place.
    pub idle: GaitParams,
    /// `p_f`: the fastest forwards walk.
    pub fast_forwards: GaitParams,
    /// `p_b`: the fastest backwards walk.
    pub fast_backwards: GaitParams,
    /// `v_max`, mm/s: the command `p_f` stands for.
    pub v_max_mm_s: f64,
    /// `v_min`, mm/s (negative): the command `p_b` stands for.
    pub v_min_mm_s: f64,
}

impl GaitTable {
    /// Eq. 1: the parameters for command `r` (a desired velocity, mm/s).
    pub fn params_for(&self, r: f64) -> GaitParams {
        if r >= 0.0 {
            self.idle.lerp(&self.fast_forwards, r / self.v_max_mm_s)
        } else {
            self.idle.lerp(&self.fast_backwards, r / self.v_min_mm_s)
        }
    }
}

impl Default for GaitTable {
    /// An ERS-7-like trot. Step length and period change together, as on the
    /// real robot, so the command-to-speed response is not a straight line even
    /// before the physics has its say.
    ///
    /// The fast walks are as fast as the URDF's joint speed limit (6 rad/s)
    /// allows with a steady gait: a foot's swing forwards peaks at about 1.6
    /// times the stance speed, so the planned joint speeds at command +-300 are
    /// 5.9 rad/s at the hip and 6.8-7.0 at the knee (the servos' speed limit
    /// trims the knee's peak a little). Faster gaits saturated the servos for
    /// much of the swing and stumbled. Walking backwards scuffs the feet unless
    /// they lift at least about 2 cm.
    fn default() -> Self {
        let idle = GaitParams {
            step_length_m: 0.0,
            step_height_m: 0.014,
            period_s: 0.50,
            body_height_m: 0.105,
            stance_width_m: 0.012,
            duty_factor: 0.55,
            foot_offset_m: 0.0,
        };
        Self {
            idle,
            fast_forwards: GaitParams {
                step_length_m: 0.063,
                step_height_m: 0.020,
                period_s: 0.40,
                duty_factor: 0.50,
                foot_offset_m: 0.006,
                ..idle
            },
            fast_backwards: GaitParams {
                step_length_m: -0.062,
                step_height_m: 0.022,
                period_s: 0.46,
                duty_factor: 0.50,
                foot_offset_m: -0.004,
                ..idle
            },
            v_max_mm_s: 335.0,
            v_min_mm_s: -280.0,
        }
    }
}

/// A foot's target relative to its hip, in the body frame (x forwards, y left,
/// z up), m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FootTarget {
    /// Forwards of the hip.
    pub x: f64,
    /// Outwards of the hip (towards the body's side the leg is on), m.
    pub outwards: f64,
    /// Up from the hip (negative: below).
    pub z: f64,
}

/// Where a foot should be at `phase` in [0, 1) of its own cycle (0 = touch-down),
/// with `step_length_m` possibly adjusted per side for steering.
pub fn foot_target(p: &GaitParams, step_length_m: f64, phase: f64) -> FootTarget {
    let d = p.duty_factor;
    let half = 0.5 * step_length_m;
    let (x, lift) = if phase < d {
        // Stance: sweep backwards at constant speed relative to the body.
        (half - step_length_m * (phase / d), 0.0)
    } else {
        // Swing: a half-ellipse forwards, smooth at both ends.
        let s = (phase - d) / (1.0 - d);
        let ease = 0.5 - 0.5 * (core::f64::consts::PI * s).cos();
        (
            -half + step_length_m * ease,
            (core::f64::consts::PI * s).sin(),
        )
    };
    FootTarget {
        x: x + p.foot_offset_m,
        outwards: p.stance_width_m,
        z: -p.body_height_m + p.step_height_m * lift,
    }
}

/// The gait's clock: a phase that advances at the current period's rate, so that
/// a change of period never makes the feet jump.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GaitClock {
    phase: f64,
}

impl GaitClock {
    /// Advances by `dt_s` at `period_s` per cycle.
    pub fn advance(&mut self, dt_s: f64, period_s: f64) {
        self.phase = (self.phase + dt_s / period_s).fract();
    }

    /// The cycle's phase in [0, 1).
    pub fn phase(&self) -> f64 {
        self.phase
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq1_hits_the_three_vectors() {
        let t = GaitTable::default();
        assert_eq!(t.params_for(0.0), t.idle);
        let f = t.params_for(t.v_max_mm_s);
        assert!((f.step_length_m - t.fast_forwards.step_length_m).abs() < 1e-12);
        let b = t.params_for(t.v_min_mm_s);
        assert!((b.period_s - t.fast_backwards.period_s).abs() < 1e-12);
        // r = -300 extrapolates 7 % past p_b, as on the real robot.
        let e = t.params_for(-300.0);
        assert!(e.step_length_m < t.fast_backwards.step_length_m);
    }

    #[test]
    fn foot_locus_is_continuous() {
        let p = GaitTable::default().fast_forwards;
        let mut prev = foot_target(&p, p.step_length_m, 0.0);
        for k in 1..=1000 {
            let phase = f64::from(k) / 1000.0;
            let f = foot_target(&p, p.step_length_m, phase % 1.0);
            assert!(
                (f.x - prev.x).abs() < 0.002 && (f.z - prev.z).abs() < 0.002,
                "jump at {phase}"
            );
            prev = f;
        }
    }

    #[test]
    fn stance_sweeps_backwards_when_walking_forwards() {
        let p = GaitTable::default().fast_forwards;
        let a = foot_target(&p, p.step_length_m, 0.0);
        let b = foot_target(&p, p.step_length_m, 0.5 * p.duty_factor);
        assert!(b.x < a.x);
        assert!((a.z + p.body_height_m).abs() < 1e-12);
    }
}
