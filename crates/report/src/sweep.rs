//! A sweep's results for people: the best combination, the paper's
//! constants beside it, and the runs that did not finish ok or ended worse
//! than their start.

use std::fmt::Write;

use testbed::summary::Figures;
use testbed::sweep::{CombinationSummary, Results};

/// The combination with the lowest sum of relative errors (action over the
/// velocity range, sensor over the 2.4 m distance range), among those whose
/// every run finished ok if there are any such.
pub fn best(results: &Results, velocity_range: f64) -> Option<CombinationSummary> {
    let score = |m: &Figures| m.action_rmse_mm_s / velocity_range + m.sensor_rmse_mm / 2400.0;
    results
        .summary()
        .into_iter()
        .filter(|g| g.runs_ok > 0 && score(&g.mean).is_finite())
        .min_by(|a, b| {
            (a.runs_failed > 0)
                .cmp(&(b.runs_failed > 0))
                .then(score(&a.mean).total_cmp(&score(&b.mean)))
        })
}

/// What the console shows of a sweep: the runs not ok, those worse than
/// their start, the best combination and the paper's constants. `base` is
/// the learner settings of the sweep's base scenario (the values of the
/// settings no axis sweeps).
pub fn describe(results: &Results, velocity_range: f64, base: &scasm::ScasmConfig) -> String {
    let mut out = String::new();
    let Some(g) = best(results, velocity_range) else {
        return "no combination finished with both models learned\n".into();
    };
    let failed: Vec<String> = results
        .rows()
        .filter(|r| !r.status.is_ok())
        .map(|r| format!("{} ({})", r.run.key(), r.status))
        .collect();
    if !failed.is_empty() {
        let _ = writeln!(
            out,
            "\n{} runs did not finish ok and are not in any mean: {}",
            failed.len(),
            failed.join("; ")
        );
    }
    let worse: Vec<String> = results
        .rows()
        .filter(|r| r.status.is_ok() && r.figures.worse_than_start())
        .map(|r| r.run.key())
        .collect();
    if !worse.is_empty() {
        let _ = writeln!(
            out,
            "\n{} runs ended worse than their uncalibrated start (in the means): {}",
            worse.len(),
            worse.join("; ")
        );
    }
    let named: Vec<String> = g.settings.iter().map(|(k, v)| format!("{k}={v}")).collect();
    let _ = writeln!(
        out,
        "\nbest combination (lowest sum of relative errors; {} runs ok, {} failed, {} worse than \
         their start): {}",
        g.runs_ok,
        g.runs_failed,
        g.runs_worse_than_start,
        named.join(", ")
    );
    let [median, _, p90] = &g.quantiles;
    let _ = writeln!(
        out,
        "  action {:.1} mm/s (median {:.1}, p90 {:.1}), sensor {:.1} mm (median {:.1}, p90 {:.1}), \
         consistency {:.3}",
        g.mean.action_rmse_mm_s,
        median.action_rmse_mm_s,
        p90.action_rmse_mm_s,
        g.mean.sensor_rmse_mm,
        median.sensor_rmse_mm,
        p90.sensor_rmse_mm,
        g.mean.consistency
    );
    let constants = scasm::ScasmConfig::paper();
    // Each constant: the paper's value, and the base scenario's.
    let paper = [
        ("learner.gamma", constants.gamma, base.gamma),
        ("learner.beta", constants.beta, base.beta),
        ("learner.t_start", constants.t_start_s, base.t_start_s),
    ];
    let near = |x: f64, paper: f64| (x - paper).abs() <= 1e-3 * paper;
    // Only a sweep over one of the paper's constants has them to compare.
    if !results
        .keys()
        .iter()
        .any(|k| paper.iter().any(|p| p.0 == k))
    {
        return out;
    }
    // A combination is the paper's when every constant is, swept or not.
    let is_paper = |g: &CombinationSummary| {
        paper.iter().all(
            |&(key, value, in_base)| match g.settings.iter().find(|(k, _)| k == key) {
                Some((_, v)) => v.parse::<f64>().is_ok_and(|x| near(x, value)),
                None => near(in_base, value),
            },
        )
    };
    // To four decimals, without trailing zeros (beta 1/30 as 0.0333).
    let short = |v: f64| {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    };
    let named: Vec<String> = paper
        .iter()
        .map(|(k, v, _)| format!("{k}={}", short(*v)))
        .collect();
    let _ = write!(
        out,
        "paper's constants, the first values it tried ({})",
        named.join(", ")
    );
    // Writing to a String cannot fail.
    let _ = match results
        .summary()
        .into_iter()
        .find(|g| is_paper(g) && g.runs_ok > 0)
    {
        Some(g) => writeln!(
            out,
            " ({} runs ok, {} failed):\n  action {:.1} mm/s, sensor {:.1} mm, consistency {:.3}",
            g.runs_ok,
            g.runs_failed,
            g.mean.action_rmse_mm_s,
            g.mean.sensor_rmse_mm,
            g.mean.consistency
        ),
        None => writeln!(out, ": not in this sweep"),
    };
    out
}
