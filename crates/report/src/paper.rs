//! The paper's figures 2a, 2b, 3, 6, 7a, 7b and 8, drawn from a training run's
//! own data: its demonstrations, its trials and the measured models; and,
//! beyond the paper, the localiser's estimates over the typical trial.

use std::path::Path;

use plotters::chart::SeriesLabelPosition;
use plotters::style::RGBColor;
use scasm::Polynomial;
use testbed::demos::{CONSTANT_COMMAND, DemoRun, Demos};
use testbed::metrics;
use testbed::reference::MeasuredModels;
use testbed::trial::{TraceRow, TrialOutcome};

use crate::ReportError;
use crate::plot::{Chart, Drawing, Mark, Series, colours};

/// What the figures are drawn from.
#[derive(Debug, Clone, Copy)]
pub struct RunData<'a> {
    /// The measured (reference) models.
    pub measured: &'a MeasuredModels,
    /// The finished trials.
    pub trials: &'a [TrialOutcome],
    /// The section IV and V demonstrations.
    pub demos: &'a Demos,
    /// Best possible errors: action polynomial (mm/s), sensor polynomial (mm).
    pub best: (f64, f64),
    /// The learned polynomials' degrees: action, sensor.
    pub degrees: (usize, usize),
}

/// One figure: its file stem and what it shows.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// The file name without extension (`fig2a`, ...).
    pub stem: &'static str,
    /// The chart.
    pub chart: Chart,
}

/// The index of the typical trial: the one with the median final sensor error.
pub fn typical_trial(trials: &[TrialOutcome]) -> Option<usize> {
    let mut order: Vec<(f64, usize)> = trials
        .iter()
        .enumerate()
        .map(|(i, t)| (t.last.sensor_rmse_mm.unwrap_or(f64::INFINITY), i))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    order.get(order.len().saturating_sub(1) / 2).map(|p| p.1)
}

/// Every figure the data allow (figures of a model never learned are left out).
pub fn figures(data: &RunData) -> Vec<Figure> {
    let typical = typical_trial(data.trials).map(|i| &data.trials[i]);
    [
        Some(fig2a(&data.demos.constant_walk)),
        Some(fig2b(&data.demos.sensor_from_a0)),
        fig3(&data.demos.action_from_rough_sensor),
        typical.map(fig6),
        typical.and_then(|t| fig7a(t, data.measured)),
        typical.and_then(|t| fig7b(t, data.measured)),
        Some(fig8(data.trials, data.best, data.degrees)),
        change(data.trials),
        typical.and_then(localisation),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// Writes every figure as `<stem>.png` and `<stem>.svg` in `dir`; returns them.
pub fn write_figures(dir: &Path, data: &RunData) -> Result<Vec<Figure>, ReportError> {
    let figs = figures(data);
    for f in &figs {
        f.chart.save(&dir.join(f.stem))?;
    }
    Ok(figs)
}

/// `n` points of `f` evenly over `[lo, hi]`.
fn curve(lo: f64, hi: f64, n: usize, f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let x = lo + (hi - lo) * i as f64 / (n - 1) as f64;
            (x, f(x))
        })
        .collect()
}

fn readings(trace: &[TraceRow]) -> impl Iterator<Item = (&TraceRow, f64)> {
    trace.iter().filter_map(|r| r.obs_px.map(|o| (r, o)))
}

fn obs_span(trace: &[TraceRow]) -> (f64, f64) {
    readings(trace).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (_, o)| {
        (a.min(o), b.max(o))
    })
}

/// The run's sensor model over the readings it saw, if it has one.
fn sensor_curve(run: &DemoRun, label: &str, mark: Mark, colour: RGBColor) -> Option<Series> {
    let s = run.sensor?;
    let (lo, hi) = obs_span(&run.trace);
    Some(Series::new(
        label,
        mark,
        colour,
        curve(lo, hi, 100, |o| s.eval(o)),
    ))
}

fn fig2a(walk: &DemoRun) -> Figure {
    let mut series = vec![Series::new(
        "observations",
        Mark::Plus,
        colours::BLUE,
        readings(&walk.trace).map(|(r, o)| (o, r.t_s)).collect(),
    )];
    series.extend(sensor_curve(
        walk,
        "best-fit cubic",
        Mark::Dashed,
        colours::RED,
    ));
    Figure {
        stem: "fig2a",
        chart: Chart {
            title: format!("Fig. 2a: walking forwards at constant command {CONSTANT_COMMAND}"),
            x_label: "beacon height (px)".into(),
            y_label: "time (s)".into(),
            series,
            legend: SeriesLabelPosition::UpperLeft,
        },
    }
}

fn fig2b(run: &DemoRun) -> Figure {
    let points = |forwards: bool| {
        readings(&run.trace)
            .filter(|(r, _)| (r.command >= 0.0) == forwards)
            .filter_map(|(r, o)| r.x_a.map(|x| (o, x)))
            .collect()
    };
    let mut series = vec![
        Series::new("walking forwards", Mark::Plus, colours::BLUE, points(true)),
        Series::new(
            "walking backwards",
            Mark::Cross,
            colours::ORANGE,
            points(false),
        ),
    ];
    series.extend(sensor_curve(
        run,
        "best-fit cubic (to all data)",
        Mark::Line,
        colours::BLACK,
    ));
    Figure {
        stem: "fig2b",
        chart: Chart {
            title: "Fig. 2b: S learned from the identity action model A0, one cycle".into(),
            x_label: "beacon height (px)".into(),
            y_label: "x_a(t) by A0 (command x s)".into(),
            series,
            legend: SeriesLabelPosition::LowerRight,
        },
    }
}

/// The learned path `x(0) + sum A(c) dt` at each frame of `trace`.
fn dead_reckoned(trace: &[TraceRow], a: &Polynomial, x0: f64) -> Vec<(f64, f64)> {
    let mut t_prev = 0.0;
    let mut x = x0;
    let mut path = vec![(0.0, x0)];
    for r in trace {
        x += a.eval(r.command) * (r.t_s - t_prev);
        t_prev = r.t_s;
        path.push((r.t_s, x));
    }
    path
}

fn fig3(run: &DemoRun) -> Option<Figure> {
    let (a, x0) = run.action.zip(run.action_start)?;
    let observations = run
        .trace
        .iter()
        .filter_map(|r| r.obs_px.and(r.x_s).map(|x| (r.t_s, x)))
        .collect();
    Some(Figure {
        stem: "fig3",
        chart: Chart {
            title: "Fig. 3: A learned from a rough S, one cycle".into(),
            x_label: "time (s)".into(),
            y_label: "x_s(t) by the rough S (s of the constant walk)".into(),
            series: vec![
                Series::new("observations", Mark::Plus, colours::BLUE, observations),
                Series::new(
                    "learned action model",
                    Mark::Line,
                    colours::RED,
                    dead_reckoned(&run.trace, &a, x0),
                ),
            ],
            legend: SeriesLabelPosition::UpperRight,
        },
    })
}

fn fig6(trial: &TrialOutcome) -> Figure {
    let x_s = trial
        .trace
        .iter()
        .filter_map(|r| r.obs_px.and(r.x_s).map(|x| (r.t_s, x)))
        .collect();
    let x_a = trial
        .trace
        .iter()
        .filter_map(|r| r.x_a.map(|x| (r.t_s, x)))
        .collect();
    Figure {
        stem: "fig6",
        chart: Chart {
            title: format!(
                "Fig. 6: x_a(t) and x_s(t) while learning both (seed {})",
                trial.seed
            ),
            x_label: "time (s)".into(),
            y_label: "x(t) (learned units)".into(),
            series: vec![
                Series::new("x_s(t) = S(obs)", Mark::Plus, colours::BLUE, x_s),
                Series::new("x_a(t), dead reckoning", Mark::Line, colours::RED, x_a),
            ],
            legend: SeriesLabelPosition::LowerRight,
        },
    }
}

/// `(t, estimate)` pairs mapped to mm by the best affine map onto the true
/// distance over the whole trial (the location metric's gauge), with the map's
/// slope.
fn in_mm(
    trace: &[TraceRow],
    estimate: impl Fn(&TraceRow) -> Option<f64>,
) -> Option<(Vec<(f64, f64)>, f64)> {
    let pairs: Vec<(f64, f64)> = trace
        .iter()
        .filter_map(|r| estimate(r).map(|e| (e, r.x_true_mm)))
        .collect();
    let map = metrics::best_polynomial(&pairs, 1)?;
    let points = trace
        .iter()
        .filter_map(|r| estimate(r).map(|e| (r.t_s, map.eval(e))))
        .collect();
    Some((points, map.coeffs()[1]))
}

fn localisation(trial: &TrialOutcome) -> Option<Figure> {
    let trace = &trial.trace;
    let (filtered, slope) = in_mm(trace, |r| r.x_loc)?;
    let band: Vec<f64> = trace
        .iter()
        .filter(|r| r.x_loc.is_some())
        .map(|r| 2.0 * r.x_loc_std.unwrap_or(0.0) * slope.abs())
        .collect();
    let lower: Vec<(f64, f64)> = filtered
        .iter()
        .zip(&band)
        .map(|(&(t, x), b)| (t, x - b))
        .collect();
    let upper: Vec<f64> = filtered
        .iter()
        .zip(&band)
        .map(|(&(_, x), b)| x + b)
        .collect();
    let (raw, _) = in_mm(trace, |r| r.obs_px.and(r.x_s))?;
    let truth = trace.iter().map(|r| (r.t_s, r.x_true_mm)).collect();
    Some(Figure {
        stem: "localisation",
        chart: Chart {
            title: format!(
                "Localisation with the learned models (seed {}), in mm after the best affine map",
                trial.seed
            ),
            x_label: "time (s)".into(),
            y_label: "distance to the beacon (mm)".into(),
            series: vec![
                Series::new("filter +- 2 std", Mark::Band(upper), colours::BLUE, lower),
                Series::new("raw x_s = S(obs)", Mark::Plus, colours::GREY, raw),
                Series::new("true distance", Mark::Line, colours::BLACK, truth),
                Series::new(
                    "filter (learned A and S)",
                    Mark::Line,
                    colours::BLUE,
                    filtered,
                ),
            ],
            legend: SeriesLabelPosition::UpperRight,
        },
    })
}

fn fig7a(trial: &TrialOutcome, measured: &MeasuredModels) -> Option<Figure> {
    let a = trial.action_model?;
    let std: Vec<f64> = measured.action.iter().map(|m| m.std_mm_s).collect();
    Some(Figure {
        stem: "fig7a",
        chart: action_chart(
            &format!("Fig. 7a: action model (seed {}), best scale", trial.seed),
            &measured.reference().action,
            Some(std),
            Some(a),
        ),
    })
}

fn fig7b(trial: &TrialOutcome, measured: &MeasuredModels) -> Option<Figure> {
    let s = trial.sensor_model?;
    Some(Figure {
        stem: "fig7b",
        chart: sensor_chart(
            &format!(
                "Fig. 7b: sensor model (seed {}), best affine map",
                trial.seed
            ),
            &measured.reference().sensor,
            Some(s),
        ),
    })
}

/// The action model against the measured one (`(command, velocity)` points,
/// with their standard deviations if known): the learned model, if any,
/// after the action metric's best scale.
pub fn action_chart(
    title: &str,
    measured: &[(f64, f64)],
    std: Option<Vec<f64>>,
    learned: Option<Polynomial>,
) -> Chart {
    let (lo, hi) = span(measured.iter().map(|m| m.0));
    let mut series = vec![match std {
        Some(std) => Series::new(
            "measured (stopwatch, +- 1 std)",
            Mark::ErrorBars(std),
            colours::BLUE,
            measured.to_vec(),
        ),
        None => Series::new(
            "measured (stopwatch)",
            Mark::Dot,
            colours::BLUE,
            measured.to_vec(),
        ),
    }];
    if let Some(a) = learned {
        let k = metrics::action_error(&a, measured).scale;
        series.push(Series::new(
            "learned",
            Mark::Line,
            colours::RED,
            curve(lo, hi, 121, |c| k * a.eval(c)),
        ));
    }
    Chart {
        title: title.into(),
        x_label: "action command".into(),
        y_label: "velocity towards the beacon (mm/s)".into(),
        series,
        legend: SeriesLabelPosition::UpperLeft,
    }
}

/// The sensor model against the measured one (`(distance, reading)`
/// points): the learned model, if any, after the sensor metric's best affine
/// map.
pub fn sensor_chart(title: &str, measured: &[(f64, f64)], learned: Option<Polynomial>) -> Chart {
    let (lo, hi) = span(measured.iter().map(|m| m.1));
    let mut series = vec![Series::new(
        "measured (tape measure)",
        Mark::Dot,
        colours::BLUE,
        measured.iter().map(|&(d, o)| (o, d)).collect(),
    )];
    if let Some(s) = learned {
        let fit = metrics::sensor_error(&s, measured);
        series.push(Series::new(
            "learned",
            Mark::Line,
            colours::RED,
            curve(lo, hi, 100, |o| fit.offset + fit.scale * s.eval(o)),
        ));
    }
    Chart {
        title: title.into(),
        x_label: "beacon height (px)".into(),
        y_label: "distance to the beacon (mm)".into(),
        series,
        legend: SeriesLabelPosition::UpperRight,
    }
}

fn span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    })
}

/// Mean and standard deviation over trials of one error at each judging time
/// (trials without that model at that time are left out).
fn over_trials(
    trials: &[TrialOutcome],
    get: impl Fn(&testbed::reference::Judgement) -> Option<f64>,
) -> Vec<(f64, f64, f64)> {
    let n = trials.iter().map(|t| t.over_time.len()).max().unwrap_or(0);
    (0..n)
        .filter_map(|i| {
            let values: Vec<(f64, f64)> = trials
                .iter()
                .filter_map(|t| t.over_time.get(i))
                .filter_map(|j| get(j).map(|v| (j.t_s, v)))
                .filter(|v| v.1.is_finite())
                .collect();
            let m = values.len() as f64;
            (m > 0.0).then(|| {
                let mean = values.iter().map(|v| v.1).sum::<f64>() / m;
                let var = values.iter().map(|v| (v.1 - mean).powi(2)).sum::<f64>() / m;
                (values[0].0, mean, var.sqrt())
            })
        })
        .collect()
}

fn fig8(trials: &[TrialOutcome], best: (f64, f64), degrees: (usize, usize)) -> Figure {
    let mut series = errors_over_time(trials, 0.0);
    let t_end = trials
        .iter()
        .flat_map(|t| t.over_time.last())
        .map(|j| j.t_s)
        .fold(0.0, f64::max);
    series.extend([
        Series::new(
            &format!("best degree-{} action model", degrees.0),
            Mark::Dashed,
            colours::BLUE,
            vec![(0.0, best.0), (t_end, best.0)],
        ),
        Series::new(
            &format!("best degree-{} sensor model", degrees.1),
            Mark::Dashed,
            colours::RED,
            vec![(0.0, best.1), (t_end, best.1)],
        ),
    ]);
    Figure {
        stem: "fig8",
        chart: Chart {
            title: format!(
                "Fig. 8: error over time, mean +- std of {} trials",
                trials.len()
            ),
            x_label: "time (s)".into(),
            y_label: "error (action mm/s, sensor mm)".into(),
            series,
            legend: SeriesLabelPosition::UpperRight,
        },
    }
}

/// Each model's error from `from_s` on, mean (line) +- std (band) over the
/// trials, and a grey line at each change of the world.
fn errors_over_time(trials: &[TrialOutcome], from_s: f64) -> Vec<Series> {
    let after = |v: Vec<(f64, f64, f64)>| -> Vec<(f64, f64, f64)> {
        v.into_iter().filter(|p| p.0 >= from_s).collect()
    };
    let action = after(over_trials(trials, |j| j.action_rmse_mm_s));
    let sensor = after(over_trials(trials, |j| j.sensor_rmse_mm));
    let band = |v: &[(f64, f64, f64)], colour| {
        Series::new(
            "",
            Mark::Band(v.iter().map(|p| p.1 + p.2).collect()),
            colour,
            v.iter().map(|p| (p.0, (p.1 - p.2).max(0.0))).collect(),
        )
    };
    let mean = |v: &[(f64, f64, f64)]| v.iter().map(|p| (p.0, p.1)).collect();
    let top = action
        .iter()
        .chain(&sensor)
        .map(|p| p.1 + p.2)
        .fold(0.0, f64::max);
    let changes = trials.first().map_or(&[][..], |t| &t.world_changes_s[..]);
    let mut series = vec![
        band(&action, colours::BLUE),
        band(&sensor, colours::RED),
        Series::new(
            "learned action model (mm/s)",
            Mark::Line,
            colours::BLUE,
            mean(&action),
        ),
        Series::new(
            "learned sensor model (mm)",
            Mark::Line,
            colours::RED,
            mean(&sensor),
        ),
    ];
    for (i, &at_s) in changes.iter().enumerate() {
        series.push(Series::new(
            if i == 0 { "the world changes" } else { "" },
            Mark::Dashed,
            colours::GREY,
            vec![(at_s, 0.0), (at_s, top)],
        ));
    }
    series
}

/// The errors across the first change of the world, from 100 s before it.
fn change(trials: &[TrialOutcome]) -> Option<Figure> {
    let at_s = *trials.first()?.world_changes_s.first()?;
    Some(Figure {
        stem: "change",
        chart: Chart {
            title: format!(
                "Across the world's change at {at_s:.0} s, mean +- std of {} trials",
                trials.len()
            ),
            x_label: "time (s)".into(),
            y_label: "error (action mm/s, sensor mm)".into(),
            series: errors_over_time(trials, (at_s - 100.0).max(0.0)),
            legend: SeriesLabelPosition::UpperRight,
        },
    })
}

/// What each figure shows (the page's captions).
pub fn caption(stem: &str) -> &'static str {
    match stem {
        "fig2a" => {
            "Fig. 2a. Readings against time while walking forwards at one constant command, with the best-fit cubic of time on reading: a sensor model in seconds of this walk (section IV)."
        }
        "fig2b" => {
            "Fig. 2b. Readings against x_a dead-reckoned by the identity action model A0 over one cycle (+ forwards, x backwards), with the cubic fitted to all of them. A0 is wrong, so forwards and backwards disagree; the cubic still has the right shape."
        }
        "fig3" => {
            "Fig. 3. x_s = S(obs) by the rough S of Fig. 2a over one cycle, with the piecewise-linear path of the action model learned from it: slope A(C(t)), x(0) from the fit (section V)."
        }
        "fig6" => {
            "Fig. 6. x_s (+) and x_a (line) over the typical trial (median final sensor error) while both models learn: they come into agreement."
        }
        "fig7a" => {
            "Fig. 7a. Measured velocity per command (stopwatch protocol, +- 1 std) and the typical trial's learned action model after its best scale."
        }
        "fig7b" => {
            "Fig. 7b. Measured distance per reading (stand-and-read protocol) and the typical trial's learned sensor model after its best affine map."
        }
        "localisation" => {
            "Localisation (beyond the paper): over the typical trial, the true distance, the localiser's estimate with the learner's models as they were at each moment (with +- 2 std), and the raw x_s of each reading, each mapped to mm by its best affine map."
        }
        "fig8" => {
            "Fig. 8. Errors of the learned models every 5 s, mean and std over the trials, with the best possible polynomial of each model's degree (dashed)."
        }
        "change" => {
            "The world changes (beyond the paper): the learned models' errors from 100 s before the world's first change, mean and std over the trials, each judged against the measured models of the world in force at the time."
        }
        _ => "",
    }
}
