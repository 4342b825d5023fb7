//! One picture of the live run: the world around the robot, what its camera sees
//! with the measured extent, the learned models beside the measured ones, and the
//! numbers of the moment.

use plotters::chart::SeriesLabelPosition;
use plotters::prelude::*;
use report::plot::{Chart, Mark, Series, colours};
use scasm::CalibrationLearner;
use testbed::behaviour::Phase;
use testbed::metrics;
use testbed::reference::MeasuredModels;
use testbed::trial::{TraceRow, TrialRunner};

use crate::scene;

/// The picture's size, px.
pub const SIZE: (u32, u32) = (1280, 800);
const TOP_H: u32 = 470;
const SCENE_W: u32 = 800;

/// The run's state of the moment, as the dashboard shows it.
pub struct Moment<'a> {
    pub runner: &'a TrialRunner,
    pub learner: &'a dyn CalibrationLearner,
    pub models: &'a MeasuredModels,
    pub last: Option<TraceRow>,
    pub seed: u64,
    pub realtime: f64,
}

/// Draws the dashboard into an RGB buffer of [`SIZE`].
pub fn render(m: &Moment) -> Result<Vec<u8>, String> {
    let mut rgb = vec![255u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        let e = |e: DrawingAreaErrorKind<_>| e.to_string();
        root.fill(&WHITE).map_err(e)?;
        let (top, bottom) = root.split_vertically(TOP_H);
        let (world, right) = top.split_horizontally(SCENE_W);
        scene::draw(&world, m.runner.sim()).map_err(e)?;
        for (area, title, x) in [
            (&world, "the robot and the beacon (live physics)", 12),
            (&right, "head camera: band and measured extent", 16),
        ] {
            let font = ("sans-serif", 18).into_font();
            area.draw(&Text::new(title, (x, 10), font)).map_err(e)?;
        }
        status(&right, m).map_err(e)?;
        let panels = bottom.split_evenly((1, 2));
        action_chart(m).draw(&panels[0]).map_err(e)?;
        sensor_chart(m).draw(&panels[1]).map_err(e)?;
        root.present().map_err(e)?;
    }
    // The camera's image, scaled up whole pixels, blitted under the panel title.
    let intr = m.runner.sim().config().camera.intrinsics;
    let (w, h) = (intr.width_px, intr.height_px);
    let scale = ((SIZE.0 - SCENE_W - 32) / w).min(320 / h).max(1);
    let camera = m.runner.sim().camera_image();
    let (img, (iw, ih)) = report::upscale_rgb(&camera, (w, h), scale);
    let (x0, y0) = (SCENE_W + 16, 40);
    for row in 0..ih.min(SIZE.1 - y0) {
        let d = 3 * ((y0 + row) * SIZE.0 + x0) as usize;
        let s = 3 * (row * iw) as usize;
        let n = 3 * iw.min(SIZE.0 - x0) as usize;
        rgb[d..d + n].copy_from_slice(&img[s..s + n]);
    }
    Ok(rgb)
}

fn status<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    m: &Moment,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let num = |v: Option<f64>, unit: &str| v.map_or("-".to_string(), |v| format!("{v:.1} {unit}"));
    let row = m.last;
    let phase = match m.runner.behaviour().phase() {
        Phase::Forwards => "forwards",
        Phase::Backwards => "backwards",
    };
    let reference = m.models.reference();
    let judged = reference.judge(row.map_or(0.0, |r| r.t_s), m.learner);
    let lines = [
        format!(
            "t = {:.1} s   seed {}   {:.1}x real time",
            row.map_or(0.0, |r| r.t_s),
            m.seed,
            m.realtime
        ),
        format!(
            "command {}   ({phase})",
            num(row.map(|r| r.command), "mm/s")
        ),
        format!("reading {}", num(row.and_then(|r| r.obs_px), "px")),
        format!(
            "x_a {}   x_s {}   (learned units)",
            num(row.and_then(|r| r.x_a), ""),
            num(row.and_then(|r| r.x_s), "")
        ),
        format!(
            "true distance {}  (never shown to the learner)",
            num(row.map(|r| r.x_true_mm), "mm")
        ),
        format!(
            "errors now: action {}, sensor {}",
            num(judged.action_rmse_mm_s, "mm/s"),
            num(judged.sensor_rmse_mm, "mm")
        ),
    ];
    for (i, l) in lines.iter().enumerate() {
        area.draw(&Text::new(
            l.clone(),
            (16, 368 + 17 * i as i32),
            ("sans-serif", 14).into_font(),
        ))?;
    }
    Ok(())
}

fn action_chart(m: &Moment) -> Chart {
    let measured = m.models.reference().action;
    let mut series = vec![Series::new(
        "measured",
        Mark::Dot,
        colours::BLUE,
        measured.clone(),
    )];
    if let Some(a) = m.learner.action_model() {
        let k = metrics::action_error(&a, &measured).scale;
        let (lo, hi) = measured
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.1), b.max(p.1))
            });
        let span = hi - lo;
        series.push(Series::new(
            "learned (best scale)",
            Mark::Line,
            colours::RED,
            (-30..=30)
                .map(|i| {
                    let c = 10.0 * f64::from(i);
                    (c, k * a.eval(c))
                })
                .filter(|p| p.1 > lo - 0.5 * span && p.1 < hi + 0.5 * span)
                .collect(),
        ));
    }
    Chart {
        title: "action model".into(),
        x_label: "command".into(),
        y_label: "velocity (mm/s)".into(),
        series,
        legend: SeriesLabelPosition::UpperLeft,
    }
}

fn sensor_chart(m: &Moment) -> Chart {
    let measured = m.models.reference().sensor;
    let mut series = vec![Series::new(
        "measured",
        Mark::Dot,
        colours::BLUE,
        measured.iter().map(|&(d, o)| (o, d)).collect(),
    )];
    if let (Some(s), Some(near), Some(far)) =
        (m.learner.sensor_model(), measured.first(), measured.last())
    {
        let fit = metrics::sensor_error(&s, &measured);
        let (lo, hi) = (far.1, near.1);
        let span = far.0 - near.0;
        series.push(Series::new(
            "learned (best affine map)",
            Mark::Line,
            colours::RED,
            (0..=60)
                .map(|i| {
                    let o = lo + (hi - lo) * f64::from(i) / 60.0;
                    (o, fit.offset + fit.scale * s.eval(o))
                })
                // An early model can be wild: keep the measured range in view.
                .filter(|p| p.1 > near.0 - 0.5 * span && p.1 < far.0 + 0.5 * span)
                .collect(),
        ));
    }
    Chart {
        title: "sensor model".into(),
        x_label: "beacon height (px)".into(),
        y_label: "distance (mm)".into(),
        series,
        legend: SeriesLabelPosition::UpperRight,
    }
}
