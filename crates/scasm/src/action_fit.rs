//! Learning the action model from location estimates (the paper's Eq. 5): a
//! linear regression of `x_s(t_k)` on `V_i(t_k) = integral_0^t C(s)^i ds`,
//! `i = 0..d` (`V_0 = t`), with intercept `x(0)`. Commands are normalised by a
//! fixed scale so that `|C / scale| <= 1` and every `V_i` grows no faster than `t`.
//!
//! With a prior (`ScasmConfig::action_prior`, strength `k > 0`) the fit is the
//! maximum a posteriori one: each coefficient of degree 2 and above, in
//! normalised command units, is `~ N(0, (scale / k)^2)`. Weighed against the
//! fit's residual noise `sigma` (estimated from the fit itself: its weighted
//! residual sum of squares over its weighted points less its unknowns), each
//! is one pseudo-observation `b_i = 0` of weight `sigma k / scale`. A quartic
//! fitted to the first seconds' few commands swings wildly between and beyond
//! them; the prior keeps it near a line until the data say otherwise.
//!
//! Two defences against stretches where the world departs from any `A(C)`
//! (a walk that stalls for seconds, say), beyond the paper:
//! - **A high-pass** (`ScasmConfig::action_highpass_s`, time constant `tau > 0`):
//!   both sides of Eq. 5 go through the same first-order high-pass,
//!   `y - L(y)` with `L` an exponential mean of time constant `tau`. The
//!   model `x = x(0) + sum_i b_i V_i` is linear, so the filtered data obey
//!   `x - L(x) = sum_i b_i (V_i - L(V_i))` with no intercept (pinned at 0 by
//!   a pseudo-observation). A distance lost in a stall, which in Eq. 5 offsets
//!   every later point until it is forgotten, fades from the filtered data
//!   within a few `tau`. `x(0)` is then `L(x) - sum_i b_i L(V_i)`.
//! - **A robust weight** (`ScasmConfig::action_robust`, `c > 0`): a point
//!   whose residual against the fit so far exceeds `c` times the fit's
//!   residual standard deviation is weighed `c sigma / |residual|` (Huber's),
//!   so a stretch the fit cannot explain moves it less.
//!
//! Neither does much alone: the high-pass keeps the stall's own points, and in
//! Eq. 5 every point after a stall is as far off as the stall's, so a robust
//! weight cannot tell them apart. Together, the high-passed residuals are large
//! only during the stall and the few `tau` after it, and those are weighed down.

use crate::polynomial::Polynomial;
use crate::wls::{IncrementalWls, MAX_COLS};

/// The pseudo-observation weight that pins the high-passed fit's intercept at 0.
const PINNED_INTERCEPT: f64 = 1e6;

/// Points the robust weight waits for (in forgetting-weighted residual degrees
/// of freedom) before it trusts the fit's residual spread.
const ROBUST_AFTER_DOF: f64 = 10.0;

/// The running integrals `V_i` and the fit of locations on them.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct ActionFit {
    wls: IncrementalWls,
    degree: usize,
    command_scale: f64,
    /// The prior's strength (0: none).
    #[cfg_attr(feature = "serde", serde(default))]
    prior: f64,
    /// `V_i = integral_0^t (C / command_scale)^i ds`, `i = 0..=degree`.
    integrals: [f64; MAX_COLS],
    /// The high-pass's time constant, s (0: none, the paper's Eq. 5).
    #[cfg_attr(feature = "serde", serde(default))]
    highpass_s: f64,
    /// The robust weight's threshold in residual standard deviations (0: none).
    #[cfg_attr(feature = "serde", serde(default))]
    robust: f64,
    /// The high-pass's means `L(V_i)` and, last, `L(x)`, and the time of the
    /// last point (`None` before the first).
    #[cfg_attr(feature = "serde", serde(default))]
    means: [f64; MAX_COLS],
    #[cfg_attr(feature = "serde", serde(default))]
    mean_x: f64,
    #[cfg_attr(feature = "serde", serde(default))]
    last_t: Option<f64>,
    /// The fit's solution after the last point (intercept, then the
    /// coefficients in normalised command units).
    #[cfg_attr(feature = "serde", serde(default))]
    solution: Option<[f64; MAX_COLS]>,
}

impl ActionFit {
    /// An empty fit of an action model of the given degree (its `degree + 1`
    /// regressors are at most MAX_REGRESSORS), forgetting factor, command
    /// scale and prior strength (0: none; see the module's doc).
    pub(crate) fn new(degree: usize, gamma: f64, command_scale: f64, prior: f64) -> Self {
        Self {
            wls: IncrementalWls::new(degree + 1, gamma),
            degree,
            command_scale,
            prior,
            integrals: [0.0; MAX_COLS],
            highpass_s: 0.0,
            robust: 0.0,
            means: [0.0; MAX_COLS],
            mean_x: 0.0,
            last_t: None,
            solution: None,
        }
    }

    /// The same fit with the high-pass of time constant `highpass_s` and the
    /// robust weight of threshold `robust` (each 0: none; see the module's doc).
    pub(crate) fn robust(mut self, highpass_s: f64, robust: f64) -> Self {
        self.highpass_s = highpass_s;
        self.robust = robust;
        self
    }

    /// Accounts for `command` held for `dt_s` seconds.
    pub(crate) fn integrate(&mut self, command: f64, dt_s: f64) {
        let u = command / self.command_scale;
        let mut p = 1.0;
        for v in &mut self.integrals[..=self.degree] {
            *v += p * dt_s;
            p *= u;
        }
    }

    /// Adds the location estimate `x_s` at the current time.
    pub(crate) fn add(&mut self, x_s: f64) {
        let n = self.degree + 1;
        let (v, y) = if self.highpass_s > 0.0 {
            // V_0 is the time.
            let t = self.integrals[0];
            let share = self
                .last_t
                .map_or(1.0, |t0| -libm::expm1(-(t - t0) / self.highpass_s));
            self.last_t = Some(t);
            let mut v = [0.0; MAX_COLS];
            for ((vi, m), &x) in v
                .iter_mut()
                .zip(&mut self.means)
                .zip(&self.integrals)
                .take(n)
            {
                *m += share * (x - *m);
                *vi = x - *m;
            }
            self.mean_x += share * (x_s - self.mean_x);
            (v, x_s - self.mean_x)
        } else {
            (self.integrals, x_s)
        };
        let weight = self.robust_weight(&v[..n], y);
        self.wls.add_weighted(&v[..n], y, weight);
        self.solution = match self.ridge() {
            Some(ridge) => self.wls.solve_with_ridge(&ridge),
            None => self.wls.solve(),
        };
    }

    /// The robust weight of the point `(v, y)` against the fit so far (1
    /// without one, and until the fit's residual spread is measured).
    fn robust_weight(&self, v: &[f64], y: f64) -> f64 {
        let dof = self.wls.weight() - (self.degree + 2) as f64;
        let Some(b) = self
            .solution
            .filter(|_| self.robust > 0.0 && dof > ROBUST_AFTER_DOF)
        else {
            return 1.0;
        };
        let predicted = b[0] + v.iter().zip(&b[1..]).map(|(vi, bi)| vi * bi).sum::<f64>();
        let residual = libm::fabs(y - predicted);
        let limit = self.robust * libm::sqrt(self.wls.residual_ss() / dof);
        if residual > limit {
            limit / residual
        } else {
            1.0
        }
    }

    /// The prior's pseudo-observation weights, per column of the fit
    /// (intercept, `V_0..V_d`); `None` without a prior, for a line (which the
    /// prior leaves alone) and while the fit has no residual degrees of
    /// freedom to measure its noise by (the fit is then least squares').
    /// With the high-pass, the intercept's pseudo-observation pins it at 0.
    fn ridge(&self) -> Option<[f64; MAX_COLS]> {
        let unknowns = (self.degree + 2) as f64;
        let dof = self.wls.weight() - unknowns;
        let mut ridge = [0.0; MAX_COLS];
        let pinned = self.highpass_s > 0.0;
        if pinned {
            ridge[0] = PINNED_INTERCEPT;
        }
        if self.prior == 0.0 || self.degree < 2 || dof <= 0.0 {
            return pinned.then_some(ridge);
        }
        let sigma = libm::sqrt(self.wls.residual_ss() / dof);
        let w = sigma * self.prior / self.command_scale;
        for r in &mut ridge[3..=self.degree + 1] {
            *r = w;
        }
        Some(ridge)
    }

    /// The fitted action model (command -> location units per second) in raw
    /// command units, and the fitted start location `x(0)`; `None` while the
    /// data do not determine them.
    pub(crate) fn model(&self) -> Option<(Polynomial, f64)> {
        let b = self.solution?;
        let mut coeffs = [0.0; MAX_COLS];
        let mut scale_pow = 1.0;
        for (c, &bi) in coeffs[..=self.degree]
            .iter_mut()
            .zip(&b[1..=self.degree + 1])
        {
            *c = bi / scale_pow;
            scale_pow *= self.command_scale;
        }
        let model = Polynomial::new(&coeffs[..=self.degree]).filter(Polynomial::is_finite)?;
        let start = if self.highpass_s > 0.0 {
            let n = self.degree + 1;
            self.mean_x
                - self.means[..n]
                    .iter()
                    .zip(&b[1..])
                    .map(|(m, bi)| m * bi)
                    .sum::<f64>()
        } else {
            b[0]
        };
        Some((model, start))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `f` fed a walk over `commands`, each held for `per_command` readings at
    /// 20 Hz: the location from `x(0) = 100` at velocity `v(t, C)` (`t` the
    /// frame's start), read with a small deterministic wobble (so that the fit
    /// has residual noise to weigh its prior by) and `off(k)` added at reading
    /// `k` (from 1).
    fn feed(
        mut f: ActionFit,
        commands: &[f64],
        per_command: u32,
        v: impl Fn(f64, f64) -> f64,
        off: impl Fn(u32) -> f64,
    ) -> ActionFit {
        let (mut x, mut k) = (100.0, 0u32);
        for &c in commands {
            for _ in 0..per_command {
                let t = f64::from(k) * 0.05;
                f.integrate(c, 0.05);
                x += v(t, c) * 0.05;
                k += 1;
                f.add(x + off(k) + 3.0 * libm::sin(f64::from(k) * 1.7));
            }
        }
        f
    }

    /// Commands held in turn, spread over the range without a pattern.
    fn spread(n: u32) -> Vec<f64> {
        (0..n)
            .map(|i| 300.0 * libm::sin(f64::from(i) * 2.39))
            .collect()
    }

    /// The largest error of `f`'s A against `curve` over the commands from
    /// -300 to 300 in steps of `step`.
    fn worst(f: &ActionFit, curve: impl Fn(f64) -> f64, step: usize) -> f64 {
        let (a, _) = f.model().expect("determined");
        (-300..=300)
            .step_by(step)
            .map(|c| libm::fabs(a.eval(f64::from(c)) - curve(f64::from(c))))
            .fold(0.0, f64::max)
    }

    /// A fit of degree 4 with no forgetting over `commands`, each held for 2 s.
    fn fit(prior: f64, commands: &[f64], v: impl Fn(f64) -> f64) -> ActionFit {
        feed(
            ActionFit::new(4, 1.0, 300.0, prior),
            commands,
            40,
            |_, c| v(c),
            |_| 0.0,
        )
    }

    #[test]
    fn no_prior_needs_as_many_commands_as_unknowns_and_the_prior_fills_in_a_line() {
        let line = |c: f64| 0.8 * c + 20.0;
        // Two command levels cannot determine a quartic by least squares...
        assert!(
            fit(0.0, &[100.0, -200.0, 100.0, -200.0], line)
                .model()
                .is_none()
        );
        // ...but with the prior they determine it as nearly the line through them.
        let (a, _) = fit(10.0, &[100.0, -200.0, 100.0, -200.0], line)
            .model()
            .expect("the prior determines the fit");
        for c in [-300.0, -100.0, 0.0, 200.0, 300.0] {
            assert!((a.eval(c) - line(c)).abs() < 5.0, "A({c}) = {}", a.eval(c));
        }
    }

    #[test]
    fn plentiful_data_outweigh_the_prior() {
        // A curved response seen at many commands: the prior (a line) is
        // outweighed, and the fit follows the curve.
        let curve = |c: f64| 0.5 * c + 0.002 * c * c - 1e-8 * c * c * c * c;
        let commands = spread(200);
        let (a, _) = fit(10.0, &commands, curve).model().expect("determined");
        let (ls, _) = fit(0.0, &commands, curve).model().expect("determined");
        for c in [-300.0, -150.0, 0.0, 150.0, 300.0] {
            // The curve's departure from a line is about 180 mm/s at the ends.
            assert!((a.eval(c) - curve(c)).abs() < 3.0, "A({c}) = {}", a.eval(c));
            assert!(
                (ls.eval(c) - curve(c)).abs() < 3.0,
                "LS({c}) = {}",
                ls.eval(c)
            );
        }
    }

    /// The curve of [`plentiful_data_outweigh_the_prior`] walked over 150 s
    /// of commands held 3 s each (20 Hz, forgetting 0.999 a reading, prior
    /// 10), except that for 12 s from `stall_s` the robot stalls: it walks at
    /// a third of `v(C)`, as a trot fallen into a slow mode does. Returns the
    /// fit's largest error over the command range at the end.
    fn stalled(stall_s: f64, highpass_s: f64, robust: f64) -> f64 {
        let curve = |c: f64| 0.5 * c + 0.002 * c * c - 1e-8 * c * c * c * c;
        let stalls = |t: f64| (stall_s..stall_s + 12.0).contains(&t);
        let f = feed(
            ActionFit::new(4, 0.999, 300.0, 10.0).robust(highpass_s, robust),
            &spread(50),
            60,
            |t, c| if stalls(t) { curve(c) / 3.0 } else { curve(c) },
            |_| 0.0,
        );
        worst(&f, curve, 25)
    }

    /// Eq. 5 bends A to explain the distance a stall lost; neither defence
    /// alone does much (the high-pass leaves the stall's own points in, and
    /// in Eq. 5 every later point is as far off as they are, so a robust
    /// weight cannot tell them apart); together they do.
    fn check_stall(stall_s: f64) {
        let plain = stalled(stall_s, 0.0, 0.0);
        let high_passed = stalled(stall_s, 5.0, 0.0);
        let robust = stalled(stall_s, 0.0, 1.5);
        let both = stalled(stall_s, 5.0, 1.5);
        assert!(plain > 10.0, "Eq. 5 after a stall: off by {plain:.1} mm/s");
        assert!(
            both < 0.5 * plain.min(high_passed).min(robust),
            "high-passed and robust {both:.1} mm/s, against Eq. 5's {plain:.1}, the \
             high-passed {high_passed:.1} and the robust {robust:.1}"
        );
    }

    #[test]
    fn a_stall_mid_trial_fades_from_the_high_passed_robust_fit() {
        check_stall(60.0);
    }

    #[test]
    fn a_stall_near_the_end_moves_the_high_passed_robust_fit_less() {
        check_stall(120.0);
    }

    #[test]
    fn without_a_stall_the_high_passed_robust_fit_finds_the_curve_and_the_start() {
        let curve = |c: f64| 0.5 * c + 0.002 * c * c - 1e-8 * c * c * c * c;
        let f = feed(
            ActionFit::new(4, 1.0, 300.0, 10.0).robust(5.0, 1.5),
            &spread(200),
            40,
            |_, c| curve(c),
            |_| 0.0,
        );
        let (a, x0) = f.model().expect("determined");
        for c in [-300.0, -150.0, 0.0, 150.0, 300.0] {
            assert!((a.eval(c) - curve(c)).abs() < 3.0, "A({c}) = {}", a.eval(c));
        }
        assert!((x0 - 100.0).abs() < 5.0, "x(0) = {x0}");
    }

    #[test]
    fn a_burst_of_wild_points_moves_the_robust_fit_less() {
        // Clean data, then 2 s of readings 400 mm off (a camera fooled, say).
        let curve = |c: f64| 0.8 * c + 20.0 + 0.001 * c * c;
        let run = |robust: f64| {
            let f = feed(
                ActionFit::new(2, 0.999, 300.0, 0.0).robust(5.0, robust),
                &spread(40),
                60,
                |_, c| curve(c),
                |k| {
                    if (1500..1540).contains(&k) {
                        400.0
                    } else {
                        0.0
                    }
                },
            );
            worst(&f, curve, 50)
        };
        let (plain, robust) = (run(0.0), run(1.5));
        assert!(
            robust < 0.5 * plain,
            "robust {robust:.2} against least squares' {plain:.2} mm/s"
        );
    }
}
