//! Heatmaps of a sweep: the mean action and sensor errors over two swept
//! settings (gamma x beta by default), one picture per value of the others.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use testbed::sweep::CombinationSummary;

use crate::ReportError;
use crate::plot::{FONT, SIZE, draw_error, encode_png, register_font};
use crate::write_atomic;

/// One panel: a value per cell of a grid of two settings.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// The panel's caption.
    pub title: String,
    /// The x setting and its values, left to right.
    pub x: (String, Vec<String>),
    /// The y setting and its values, bottom to top.
    pub y: (String, Vec<String>),
    /// `cells[j][i]` at `(x[i], y[j])`; `None` where no run finished.
    pub cells: Vec<Vec<Option<f64>>>,
}

impl Grid {
    fn range(&self) -> (f64, f64) {
        self.cells
            .iter()
            .flatten()
            .flatten()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            })
    }

    /// The lowest cell, `(i, j)`.
    fn best(&self) -> Option<(usize, usize)> {
        let mut best: Option<(f64, usize, usize)> = None;
        for (j, row) in self.cells.iter().enumerate() {
            for (i, v) in row.iter().enumerate() {
                if let Some(v) = v.filter(|v| v.is_finite()) {
                    if best.is_none_or(|b| v < b.0) {
                        best = Some((v, i, j));
                    }
                }
            }
        }
        best.map(|b| (b.1, b.2))
    }

    fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let (nx, ny) = (self.x.1.len(), self.y.1.len());
        let mut chart = ChartBuilder::on(area)
            .caption(&self.title, (FONT, 19))
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(64)
            // plotters' integer ranges include their end: 0..n-1 gives n segments.
            .build_cartesian_2d(
                (0..nx.saturating_sub(1)).into_segmented(),
                (0..ny.saturating_sub(1)).into_segmented(),
            )?;
        let label = |values: &[String], v: &SegmentValue<usize>| match v {
            SegmentValue::CenterOf(i) => values.get(*i).cloned().unwrap_or_default(),
            _ => String::new(),
        };
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(&self.x.0)
            .y_desc(&self.y.0)
            .x_labels(nx)
            .y_labels(ny)
            .x_label_formatter(&|v| label(&self.x.1, v))
            .y_label_formatter(&|v| label(&self.y.1, v))
            .label_style((FONT, 15))
            .axis_desc_style((FONT, 16))
            .draw()?;
        let (lo, hi) = self.range();
        let best = self.best();
        for (j, row) in self.cells.iter().enumerate() {
            for (i, v) in row.iter().enumerate() {
                let corners = [
                    (SegmentValue::Exact(i), SegmentValue::Exact(j)),
                    (SegmentValue::Exact(i + 1), SegmentValue::Exact(j + 1)),
                ];
                let centre = (SegmentValue::CenterOf(i), SegmentValue::CenterOf(j));
                let v = v.filter(|v| v.is_finite());
                let fill = v.map_or(RGBColor(200, 200, 200), |v| ramp(unit(v, lo, hi)));
                chart.draw_series(std::iter::once(Rectangle::new(
                    corners.clone(),
                    fill.filled(),
                )))?;
                if best == Some((i, j)) {
                    chart.draw_series(std::iter::once(Rectangle::new(
                        corners,
                        BLACK.stroke_width(3),
                    )))?;
                }
                let text = v.map_or("no run".to_string(), |v| format!("{v:.1}"));
                let ink = if luminance(fill) > 0.5 { BLACK } else { WHITE };
                let style = TextStyle::from((FONT, 17).into_font())
                    .color(&ink)
                    .pos(Pos::new(HPos::Center, VPos::Center));
                chart.draw_series(std::iter::once(Text::new(text, centre, style)))?;
            }
        }
        Ok(())
    }
}

fn unit(v: f64, lo: f64, hi: f64) -> f64 {
    if hi > lo { (v - lo) / (hi - lo) } else { 0.0 }
}

/// Viridis, reversed: low errors are bright yellow, high ones dark purple.
fn ramp(t: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (253.0, 231.0, 37.0),
        (94.0, 201.0, 98.0),
        (33.0, 145.0, 140.0),
        (59.0, 82.0, 139.0),
        (68.0, 1.0, 84.0),
    ];
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let k = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - k as f64;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    let mix = |p: f64, q: f64| (p + (q - p) * f).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

fn luminance(c: RGBColor) -> f64 {
    (0.299 * f64::from(c.0) + 0.587 * f64::from(c.1) + 0.114 * f64::from(c.2)) / 255.0
}

/// Draws panels side by side into `<stem>.png` and `<stem>.svg`.
pub fn save_panels(stem: &Path, heading: &str, panels: &[Grid]) -> Result<(), ReportError> {
    register_font()?;
    let size = (SIZE.0 / 2 * panels.len().max(1) as u32 + 80, SIZE.1);
    let mut svg = String::new();
    draw_panels(
        SVGBackend::with_string(&mut svg, size).into_drawing_area(),
        heading,
        panels,
    )?;
    write_atomic(&stem.with_extension("svg"), svg.as_bytes())?;
    let mut rgb = vec![0u8; (size.0 * size.1 * 3) as usize];
    draw_panels(
        BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area(),
        heading,
        panels,
    )?;
    write_atomic(&stem.with_extension("png"), &encode_png(&rgb, size)?)
}

fn draw_panels<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    heading: &str,
    panels: &[Grid],
) -> Result<(), ReportError>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(draw_error)?;
    let root = root.titled(heading, (FONT, 21)).map_err(draw_error)?;
    for (area, grid) in root
        .split_evenly((1, panels.len().max(1)))
        .iter()
        .zip(panels)
    {
        grid.draw(area).map_err(draw_error)?;
    }
    root.present().map_err(draw_error)
}

/// The two settings a sweep's heatmaps span: `learner.beta` across and
/// `learner.gamma` up if both vary, else the first two that vary.
pub fn heatmap_axes(keys: &[String], summary: &[CombinationSummary]) -> Option<(usize, usize)> {
    let varies: Vec<usize> = (0..keys.len())
        .filter(|&k| values_of(summary, k).len() > 1)
        .collect();
    let find = |name: &str| varies.iter().copied().find(|&k| keys[k] == name);
    match (find("learner.beta"), find("learner.gamma")) {
        (Some(x), Some(y)) => Some((x, y)),
        _ => (varies.len() >= 2).then(|| (varies[0], varies[1])),
    }
}

/// The distinct values of setting `k`, in numeric order where they are numbers.
fn values_of(summary: &[CombinationSummary], k: usize) -> Vec<String> {
    let mut v: Vec<String> = Vec::new();
    for c in summary {
        if let Some((_, value)) = c.settings.get(k) {
            if !v.contains(value) {
                v.push(value.clone());
            }
        }
    }
    v.sort_by(|a, b| match (a.parse::<f64>(), b.parse::<f64>()) {
        (Ok(x), Ok(y)) => x.total_cmp(&y),
        _ => a.cmp(b),
    });
    v
}

/// Writes one picture of mean action and sensor error per combination of the
/// settings other than the two it spans, as `heatmap[-key-value...].{png,svg}`
/// in `dir`. Returns their stems (none if fewer than two settings vary).
pub fn write_sweep_heatmaps(
    dir: &Path,
    keys: &[String],
    summary: &[CombinationSummary],
) -> Result<Vec<PathBuf>, ReportError> {
    let Some((xk, yk)) = heatmap_axes(keys, summary) else {
        return Ok(Vec::new());
    };
    let (xs, ys) = (values_of(summary, xk), values_of(summary, yk));
    let mut groups: BTreeMap<Vec<(String, String)>, Vec<&CombinationSummary>> = BTreeMap::new();
    for c in summary {
        let rest = c
            .settings
            .iter()
            .enumerate()
            .filter(|(k, _)| *k != xk && *k != yk)
            .map(|(_, s)| s.clone())
            .collect();
        groups.entry(rest).or_default().push(c);
    }
    let mut stems = Vec::new();
    for (rest, members) in groups {
        let cell = |metric: fn(&CombinationSummary) -> f64| -> Vec<Vec<Option<f64>>> {
            ys.iter()
                .map(|y| {
                    xs.iter()
                        .map(|x| {
                            members
                                .iter()
                                .find(|c| c.settings[xk].1 == *x && c.settings[yk].1 == *y)
                                .filter(|c| c.runs_ok > 0)
                                .map(|c| metric(c))
                        })
                        .collect()
                })
                .collect()
        };
        let grid = |title: &str, metric| Grid {
            title: title.into(),
            x: (keys[xk].clone(), xs.clone()),
            y: (keys[yk].clone(), ys.clone()),
            cells: cell(metric),
        };
        let panels = [
            grid("mean action error (mm/s)", |c| c.mean.action_rmse_mm_s),
            grid("mean sensor error (mm)", |c| c.mean.sensor_rmse_mm),
        ];
        let suffix: String = rest
            .iter()
            .map(|(k, v)| format!("-{}-{}", k.trim_start_matches("learner."), v))
            .collect();
        let heading = if rest.is_empty() {
            "Sweep: mean errors (lowest outlined)".to_string()
        } else {
            let at: Vec<String> = rest.iter().map(|(k, v)| format!("{k} = {v}")).collect();
            format!("Sweep at {}: mean errors (lowest outlined)", at.join(", "))
        };
        let stem = dir.join(format!("heatmap{suffix}"));
        save_panels(&stem, &heading, &panels)?;
        stems.push(stem);
    }
    Ok(stems)
}

#[cfg(test)]
mod tests {
    use super::*;
    use testbed::summary::Figures;

    fn summary() -> (Vec<String>, Vec<CombinationSummary>) {
        let keys: Vec<String> = ["learner.gamma", "learner.t_start", "learner.beta"]
            .map(String::from)
            .to_vec();
        let mut out = Vec::new();
        for g in ["0.999", "0.99"] {
            for t in ["20"] {
                for b in ["0.1", "0.01", "0.0333"] {
                    let mut mean = Figures::filled(1.0);
                    mean.action_rmse_mm_s = g.parse::<f64>().unwrap_or(0.0) * 100.0;
                    mean.sensor_rmse_mm = b.parse::<f64>().unwrap_or(0.0) * 1000.0;
                    out.push(CombinationSummary {
                        settings: vec![
                            ("learner.gamma".into(), g.into()),
                            ("learner.t_start".into(), t.into()),
                            ("learner.beta".into(), b.into()),
                        ],
                        runs_ok: usize::from(!(g == "0.99" && b == "0.1")),
                        runs_failed: usize::from(g == "0.99" && b == "0.1"),
                        runs_worse_than_start: 0,
                        runs_worse_than_start_by_model: (0, 0),
                        mean,
                        std: Figures::filled(0.0),
                        quantiles: [mean; 3],
                        counted: Figures::filled(1.0),
                    });
                }
            }
        }
        (keys, out)
    }

    #[test]
    fn gamma_goes_up_beta_across_in_numeric_order() {
        let (keys, s) = summary();
        assert_eq!(heatmap_axes(&keys, &s), Some((2, 0)));
        assert_eq!(values_of(&s, 2), ["0.01", "0.0333", "0.1"]);
        assert_eq!(values_of(&s, 0), ["0.99", "0.999"]);
        // Without gamma and beta, the first two settings that vary.
        let other: Vec<String> = ["a", "b", "c"].map(String::from).to_vec();
        assert_eq!(heatmap_axes(&other, &s), Some((0, 2)));
        assert_eq!(heatmap_axes(&keys[..1], &s[..1]), None);
    }

    #[test]
    fn one_picture_per_other_setting_with_empty_cells_marked() {
        let (keys, s) = summary();
        let dir = std::env::temp_dir().join(format!("heatmap-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let stems = write_sweep_heatmaps(&dir, &keys, &s).expect("drawn");
        assert_eq!(stems, [dir.join("heatmap-t_start-20")]);
        let svg = std::fs::read_to_string(dir.join("heatmap-t_start-20.svg")).expect("svg");
        // The run-less cell says so; the others show their values.
        assert!(svg.contains("no run"));
        assert!(svg.contains("99.9") && svg.contains("33.3"));
        assert!(dir.join("heatmap-t_start-20.png").exists());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn the_ramp_runs_from_bright_to_dark() {
        assert!(luminance(ramp(0.0)) > 0.7);
        assert!(luminance(ramp(1.0)) < 0.2);
        assert_eq!(ramp(-1.0), ramp(0.0));
        assert_eq!(ramp(2.0), ramp(1.0));
    }
}
