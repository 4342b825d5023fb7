//! The `design` behaviour: the paper's walk (the same holds and turning
//! round) with each command's magnitude drawn from an optimal design for
//! the action model instead of uniformly.
//!
//! The action model is a polynomial of degree `d` in the command, judged by
//! its root mean square error over the paper's 31 evenly spaced commands
//! (section VI). Fitted by least squares to speeds measured at commands
//! drawn from a distribution `w`, its average prediction variance over those
//! commands is proportional to `trace(L M(w)^-1)`, with `M(w)` the design's
//! information matrix (the mean of `f(c) f(c)^T`, `f(c) = (1, c, ..., c^d)`)
//! and `L` the same mean over the 31 commands. The distribution minimising
//! it is the I-optimal design (Atkinson, Donev and Tobias, *Optimum
//! Experimental Designs*, ch. 10), found here by the multiplicative
//! algorithm over commands at every 1 % of the range. It is symmetric; each
//! phase draws from its own half (a zero command half as often as in the
//! design, since both halves hold it). For degree 4 it holds the extremes
//! 25 % of a phase's time, 0.64 of the maximum 48 % and stands still 27 %.
//!
//! What it does not do: it does not look at the models learned so far (the
//! design is the same for every model of the degree), and it treats every
//! second at a command as worth the same, whereas a change of command is
//! followed by a transient the learners do not model (book: Behaviours).

use nalgebra::{DMatrix, DVector};

/// How many degrees richer than the action model the design's polynomial is
/// by default: chosen on development seeds 100-129 among 0, 2 and 4 (book:
/// Behaviours). A design for the model's own degree puts every command at
/// `degree + 1` points and teaches fastest early, but its fit misses
/// between them; one for a richer model spreads the commands.
pub const EXTRA_DEGREE: usize = 4;
/// The richest extra degree a run may ask for.
pub const MAX_EXTRA_DEGREE: usize = 8;

/// The metric's commands: 31 evenly spaced over `[-1, 1]` (of the maximum).
const METRIC_COMMANDS: usize = 31;
/// Candidate commands: every 1 % of `[-1, 1]`.
const CANDIDATES: usize = 201;
/// Iterations of the multiplicative algorithm.
const ITERATIONS: usize = 4000;
/// Support points lighter than this are dropped; nearer than
/// [`MERGE_WITHIN`] are merged.
const LIGHTEST: f64 = 1e-3;
/// See [`LIGHTEST`].
const MERGE_WITHIN: f64 = 0.05;

/// `(1, c, ..., c^degree)`.
pub(crate) fn basis(c: f64, degree: usize) -> DVector<f64> {
    DVector::from_iterator(degree + 1, (0..=degree).map(|k| c.powi(k as i32)))
}

/// `L`: the mean of `f(c) f(c)^T` over the metric's 31 commands, whose
/// `trace(L M^-1)` is a fit's average prediction variance over them.
pub(crate) fn metric_matrix(degree: usize) -> DMatrix<f64> {
    let n = degree + 1;
    let mut l = DMatrix::zeros(n, n);
    for k in 0..METRIC_COMMANDS {
        let g = basis(-1.0 + 2.0 * k as f64 / (METRIC_COMMANDS - 1) as f64, degree);
        l += &g * g.transpose() / METRIC_COMMANDS as f64;
    }
    l
}

/// The I-optimal design's support over `[-1, 1]`: each command and its
/// share of the time, in increasing order of command.
pub fn i_optimal(degree: usize) -> Vec<(f64, f64)> {
    let n = degree + 1;
    let even = |k: usize, count: usize| -1.0 + 2.0 * k as f64 / (count - 1) as f64;
    let f: Vec<DVector<f64>> = (0..CANDIDATES)
        .map(|k| basis(even(k, CANDIDATES), degree))
        .collect();
    let l = metric_matrix(degree);
    let mut w = vec![1.0 / CANDIDATES as f64; CANDIDATES];
    for _ in 0..ITERATIONS {
        let mut m = DMatrix::zeros(n, n);
        for (fk, wk) in f.iter().zip(&w) {
            m += fk * fk.transpose() * *wk;
        }
        let Some(mi) = m.try_inverse() else { break };
        let a = &mi * &l * &mi;
        let trace = (&l * &mi).trace();
        for (fk, wk) in f.iter().zip(w.iter_mut()) {
            *wk *= (fk.transpose() * &a * fk)[(0, 0)] / trace;
        }
        let total: f64 = w.iter().sum();
        w.iter_mut().for_each(|v| *v /= total);
    }
    // Neighbouring candidates share an optimum between them: merge them.
    let mut support: Vec<(f64, f64)> = Vec::new();
    for (k, &wk) in w.iter().enumerate().filter(|(_, v)| **v >= LIGHTEST) {
        let c = even(k, CANDIDATES);
        match support.last_mut() {
            Some((at, share)) if c - *at < MERGE_WITHIN => {
                *at = (*at * *share + c * wk) / (*share + wk);
                *share += wk;
            }
            _ => support.push((c, wk)),
        }
    }
    let total: f64 = support.iter().map(|s| s.1).sum();
    support.iter().map(|&(c, s)| (c, s / total)).collect()
}

/// One phase's draw from the I-optimal design for `degree` ([`i_optimal`],
/// [`one_phase`]), found once per degree in a run and shared by its trials
/// (it is the same every time, and finding it costs about a tenth of a
/// second).
pub fn phase_draw(degree: usize) -> Vec<(f64, f64)> {
    use std::collections::BTreeMap;
    use std::sync::{Mutex, OnceLock};
    /// Each phase's draw (magnitude, probability) by degree.
    type Found = Mutex<BTreeMap<usize, Vec<(f64, f64)>>>;
    static FOUND: OnceLock<Found> = OnceLock::new();
    let found = FOUND.get_or_init(|| Mutex::new(BTreeMap::new()));
    if let Some(draw) = found.lock().ok().and_then(|m| m.get(&degree).cloned()) {
        return draw;
    }
    let draw = one_phase(&i_optimal(degree));
    if let Ok(mut m) = found.lock() {
        m.insert(degree, draw.clone());
    }
    draw
}

/// One phase's draw from the symmetric `design`: magnitudes (fractions of
/// the maximum) and their probabilities, a zero command counted half.
pub fn one_phase(design: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let half: Vec<(f64, f64)> = design
        .iter()
        .filter(|(c, _)| *c >= -1e-9)
        .map(|&(c, s)| {
            if c.abs() < 1e-9 {
                (0.0, 0.5 * s)
            } else {
                (c, s)
            }
        })
        .collect();
    let total: f64 = half.iter().map(|h| h.1).sum();
    half.iter().map(|&(c, s)| (c, s / total)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The design's average prediction variance over the metric's commands.
    fn i_criterion(design: &[(f64, f64)], degree: usize) -> f64 {
        let n = degree + 1;
        let mut m = DMatrix::zeros(n, n);
        for &(c, s) in design {
            let f = basis(c, degree);
            m += &f * f.transpose() * s;
        }
        let mi = m.try_inverse().expect("a design that identifies the model");
        (0..METRIC_COMMANDS)
            .map(|k| {
                let g = basis(-1.0 + 2.0 * k as f64 / 30.0, degree);
                (g.transpose() * &mi * &g)[(0, 0)]
            })
            .sum::<f64>()
            / METRIC_COMMANDS as f64
    }

    #[test]
    fn the_design_beats_the_uniform_draw_and_every_nearby_design() {
        for degree in 1..=8 {
            let design = i_optimal(degree);
            assert!(design.len() > degree, "degree {degree}: {design:?}");
            let total: f64 = design.iter().map(|s| s.1).sum();
            assert!((total - 1.0).abs() < 1e-12);
            let best = i_criterion(&design, degree);
            let uniform: Vec<(f64, f64)> = (0..CANDIDATES)
                .map(|k| (-1.0 + 2.0 * k as f64 / 200.0, 1.0 / CANDIDATES as f64))
                .collect();
            assert!(best < i_criterion(&uniform, degree), "degree {degree}");
            // Moving a little weight between any two support points, or
            // moving a point, makes it worse (a local optimum at least).
            for i in 0..design.len() {
                for j in 0..design.len() {
                    if i == j {
                        continue;
                    }
                    let mut other = design.clone();
                    let d = 0.01 * other[i].1;
                    other[i].1 -= d;
                    other[j].1 += d;
                    assert!(
                        i_criterion(&other, degree) >= best - 1e-6,
                        "degree {degree}"
                    );
                }
                let mut moved = design.clone();
                moved[i].0 = (moved[i].0 * 0.97).clamp(-1.0, 1.0);
                if moved[i].0 != design[i].0 {
                    assert!(
                        i_criterion(&moved, degree) >= best - 1e-6,
                        "degree {degree}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_richest_design_a_run_may_ask_for_is_found() {
        // The default action degree, 4, plus the most a run may add.
        let degree = 4 + MAX_EXTRA_DEGREE;
        let design = i_optimal(degree);
        assert!(design.len() > degree, "{design:?}");
        assert!(design.iter().all(|(c, s)| c.abs() <= 1.0 && *s > 0.0));
    }

    #[test]
    fn the_design_is_symmetric_and_a_phase_draws_from_its_half() {
        let design = i_optimal(4);
        for (&(a, sa), &(b, sb)) in design.iter().zip(design.iter().rev()) {
            assert!((a + b).abs() < 1e-6 && (sa - sb).abs() < 1e-6, "{design:?}");
        }
        let phase = one_phase(&design);
        assert!(phase.iter().all(|(c, _)| (0.0..=1.0).contains(c)));
        assert!((phase.iter().map(|p| p.1).sum::<f64>() - 1.0).abs() < 1e-12);
        assert_eq!(phase.last().map(|p| p.0), Some(1.0), "{phase:?}");
    }
}
