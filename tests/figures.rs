//! The section IV and V demonstrations behave as the paper describes, and a run's
//! figures and page are written whole, with drawn text, from its own data.

use std::sync::OnceLock;

use scasm::Polynomial;
use testbed::demos::{self, Demos};
use testbed::experiment;
use testbed::metrics;
use testbed::reference::MeasuredModels;
use testbed::scenario::Scenario;

fn setup() -> &'static (Scenario, MeasuredModels, Demos) {
    static SETUP: OnceLock<(Scenario, MeasuredModels, Demos)> = OnceLock::new();
    SETUP.get_or_init(|| {
        let scenario = Scenario::paper().expect("scenario");
        let cache = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("reference-cache");
        let models =
            testbed::reference::measured_models(&scenario, Some(&cache)).expect("measured");
        let demos = demos::run_demos(&scenario, &models, 0).expect("demos");
        (scenario, models, demos)
    })
}

/// Whether `p` rises (or falls, if not `increasing`) over each twentieth of `[lo, hi]`.
fn monotone(p: &Polynomial, lo: f64, hi: f64, increasing: bool) -> bool {
    (0..20).all(|i| {
        let x = lo + (hi - lo) * i as f64 / 20.0;
        let step = (hi - lo) / 20.0;
        (p.eval(x + step) > p.eval(x)) == increasing
    })
}

fn obs_range(models: &MeasuredModels) -> (f64, f64) {
    let obs: Vec<f64> = models.sensor.iter().map(|s| s.obs_px).collect();
    (
        obs.iter().copied().fold(f64::INFINITY, f64::min),
        obs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    )
}

#[test]
fn the_constant_walk_learns_time_as_a_rising_function_of_the_reading() {
    let (_, models, demos) = setup();
    let walk = &demos.constant_walk;
    let s = walk.sensor.expect("a cubic was fitted");
    let (lo, hi) = obs_range(models);
    // Walking towards the beacon, readings grow with time.
    assert!(monotone(&s, lo, hi, true), "S = {:?}", s.coeffs());
    // The walk went from beyond the far end to the near end of the test range.
    let first = walk.trace.iter().find_map(|r| r.obs_px).expect("readings");
    let last = walk
        .trace
        .iter()
        .rev()
        .find_map(|r| r.obs_px)
        .expect("readings");
    assert!(
        first <= lo + 1.5 && last >= hi,
        "readings {first:.1} -> {last:.1} px"
    );
    // The fitted S is an affine image of distance up to the cubic's misfit: it
    // is a sensor model already (section IV), in seconds of this walk.
    let err = metrics::sensor_error(&s, &models.reference().sensor).rmse;
    assert!(
        err < 120.0,
        "constant-walk S misses distance by {err:.1} mm"
    );
}

#[test]
fn one_cycle_covers_the_range_both_ways() {
    let (_, models, demos) = setup();
    for run in [&demos.sensor_from_a0, &demos.action_from_rough_sensor] {
        let forwards = run.trace.iter().filter(|r| r.command > 0.0).count();
        let backwards = run.trace.iter().filter(|r| r.command < 0.0).count();
        assert!(
            forwards > 40 && backwards > 40,
            "{forwards} / {backwards} frames"
        );
        let near = models.sensor[0].distance_mm;
        let far = models.sensor[models.sensor.len() - 1].distance_mm;
        let closest = run
            .trace
            .iter()
            .map(|r| r.x_true_mm)
            .fold(f64::INFINITY, f64::min);
        let farthest = run.trace.iter().map(|r| r.x_true_mm).fold(0.0, f64::max);
        assert!(
            closest < near + 150.0 && farthest > far - 150.0,
            "{closest:.0}..{farthest:.0} mm"
        );
    }
}

#[test]
fn s_from_a0_has_the_right_shape_and_a_from_the_rough_s_tracks_it() {
    let (_, models, demos) = setup();
    let (lo, hi) = obs_range(models);
    // A0 is wrong, yet S is "qualitatively reasonable" (Fig. 2b): after its best
    // affine map it explains most of the measured distances' spread (R^2 >=
    // 0.9), it rises from the far end of the range to the near end, and it
    // flattens as the beacon nears. It need not be monotone everywhere: A0 is
    // worst at small backwards commands, where this robot hardly moves, and
    // the cubic bends to fit the far end's distorted x_a.
    let s = demos.sensor_from_a0.sensor.expect("S learned");
    let reference = models.reference().sensor;
    let err = metrics::sensor_error(&s, &reference).rmse;
    let d: Vec<f64> = reference.iter().map(|p| p.0).collect();
    let mean_d = d.iter().sum::<f64>() / d.len() as f64;
    let sd_d = (d.iter().map(|x| (x - mean_d).powi(2)).sum::<f64>() / d.len() as f64).sqrt();
    let explained = 1.0 - (err / sd_d).powi(2);
    assert!(
        explained >= 0.9,
        "S from A0 misses distance by {err:.0} mm of {sd_d:.0} (R^2 {explained:.3})"
    );
    assert!(s.eval(hi) > s.eval(lo), "S does not rise over the range");
    let slope = |x: f64| s.eval(x + 0.5) - s.eval(x - 0.5);
    assert!(slope(lo + 2.0) > 2.0 * slope(hi - 2.0), "no flattening");
    // Fig. 3: the learned A's piecewise-linear path explains most of x_s's
    // variation over the cycle (R^2 >= 0.9; the rest is reading noise through
    // the rough S, largest where S extrapolates past the constant walk's
    // readings).
    let run = &demos.action_from_rough_sensor;
    let a = run.action.expect("A learned");
    let mut x = run.action_start.expect("x(0) learned");
    let (mut t_prev, mut residual, mut spread, mut n) = (0.0, 0.0, Vec::new(), 0.0);
    for r in &run.trace {
        x += a.eval(r.command) * (r.t_s - t_prev);
        t_prev = r.t_s;
        if let (Some(_), Some(x_s)) = (r.obs_px, r.x_s) {
            residual += (x_s - x).powi(2);
            spread.push(x_s);
            n += 1.0;
        }
    }
    let rms = (residual / n).sqrt();
    let mean = spread.iter().sum::<f64>() / n;
    let sd = (spread.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
    let r_squared = 1.0 - (rms / sd).powi(2);
    assert!(
        r_squared >= 0.9,
        "path misses x_s by {rms:.3} against a spread of {sd:.3} (R^2 {r_squared:.3})"
    );
}

#[test]
fn a_run_writes_the_papers_seven_figures_the_localisation_and_its_page() {
    let (scenario, models, demos) = setup();
    let mut scenario = scenario.clone();
    scenario.duration_s = 50.0;
    let trials: Vec<_> = experiment::run_trials(&scenario, models, &[0, 1], &|_| {})
        .into_iter()
        .map(|(_, r)| r.expect("trial").1)
        .collect();
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("figures-run");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let data = report::paper::RunData {
        measured: models,
        trials: &trials,
        demos,
        best: (10.0, 30.0),
        degrees: (4, 3),
    };
    let figures = report::paper::write_figures(&dir, &data).expect("figures");
    let stems: Vec<&str> = figures.iter().map(|f| f.stem).collect();
    assert_eq!(
        stems,
        [
            "fig2a",
            "fig2b",
            "fig3",
            "fig6",
            "fig7a",
            "fig7b",
            "fig8",
            "localisation"
        ]
    );
    for f in &figures {
        assert!(
            f.chart.series.iter().all(|s| !s.points.is_empty()),
            "{} has an empty series",
            f.stem
        );
        let png = std::fs::read(dir.join(format!("{}.png", f.stem))).expect("png");
        let decoder = png::Decoder::new(std::io::Cursor::new(png));
        let info = decoder.read_info().expect("a PNG").info().clone();
        assert_eq!((info.width, info.height), report::plot::SIZE);
        let svg = std::fs::read_to_string(dir.join(format!("{}.svg", f.stem))).expect("svg");
        assert!(svg.contains(&f.chart.x_label) && svg.contains(&f.chart.y_label));
    }
    let page = report::page::Page {
        title: "t".into(),
        figures: figures
            .iter()
            .map(|f| (f.stem.to_string(), String::new()))
            .collect(),
        ..Default::default()
    };
    page.write(&dir.join("index.html")).expect("page");
    let html = std::fs::read_to_string(dir.join("index.html")).expect("html");
    for f in &figures {
        assert!(html.contains(&format!("src=\"{}.png\"", f.stem)));
    }
    assert!(!std::fs::read_dir(&dir).expect("dir").any(|e| {
        e.expect("entry")
            .path()
            .extension()
            .is_some_and(|x| x == "tmp")
    }));

    // Had the world changed at 30 s, Fig. 8 and a figure across the change
    // would mark it, the latter from 100 s before it (here: from the start).
    let changed: Vec<_> = trials
        .iter()
        .cloned()
        .map(|mut t| {
            t.world_changes_s = vec![30.0];
            t
        })
        .collect();
    let figures = report::paper::figures(&report::paper::RunData {
        trials: &changed,
        ..data
    });
    let stems: Vec<&str> = figures.iter().map(|f| f.stem).collect();
    assert_eq!(&stems[6..], ["fig8", "change", "localisation"]);
    for f in &figures[6..8] {
        let marker = f
            .chart
            .series
            .iter()
            .find(|s| s.label == "the world changes")
            .expect("the change is marked");
        assert!(marker.points.iter().all(|p| p.0 == 30.0), "{}", f.stem);
    }
}
