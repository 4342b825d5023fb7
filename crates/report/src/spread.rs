//! A chart of categories: per category (a scenario, say), each series' (a
//! learner's) median as a dot with a bar from its 10th to its 90th
//! percentile, category names on the axis, on a log scale (ratios read
//! evenly above and below 1).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use testbed::benchmark::Cell;
use testbed::summary::Figures;

use crate::ReportError;
use crate::plot::{Drawing, FONT, colours, register_font};

/// Pixel size of a spread chart.
pub const SIZE: (u32, u32) = (960, 560);

/// A median and the spread around it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    /// The median.
    pub median: f64,
    /// The bar's lower end (the 10th percentile).
    pub low: f64,
    /// The bar's upper end (the 90th percentile).
    pub high: f64,
}

/// Colours of the series, in order (Okabe and Ito).
const PALETTE: [RGBColor; 6] = [
    colours::BLUE,
    colours::RED,
    colours::GREEN,
    colours::ORANGE,
    colours::PURPLE,
    colours::BLACK,
];

/// The chart: per category, each series' [`Spread`] side by side.
#[derive(Debug, Clone, PartialEq)]
pub struct SpreadChart {
    /// The caption.
    pub title: String,
    /// The y axis' title.
    pub y_label: String,
    /// The categories' names, along x.
    pub categories: Vec<String>,
    /// Per series, its name and per category its spread (`None` where it has
    /// none).
    pub series: Vec<(String, Vec<Option<Spread>>)>,
    /// A dashed horizontal line at this value (1 for a ratio to the best).
    pub reference: Option<f64>,
}

impl SpreadChart {
    /// The y range over every finite positive value (and the reference),
    /// widened by a quarter either side on the log scale.
    fn y_range(&self) -> (f64, f64) {
        let values = self
            .series
            .iter()
            .flat_map(|(_, s)| s.iter().flatten())
            .flat_map(|s| [s.median, s.low, s.high])
            .chain(self.reference)
            .filter(|v| v.is_finite() && *v > 0.0);
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
        if lo > hi {
            (0.1, 10.0)
        } else {
            (lo / 1.25, hi * 1.25)
        }
    }
}

impl Drawing for SpreadChart {
    const SIZE: (u32, u32) = SIZE;

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let _ = register_font();
        root.fill(&WHITE)?;
        let n = self.categories.len().max(1) as f64;
        let (x0, x1) = (-0.5, n - 0.5);
        let (y0, y1) = self.y_range();
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, (FONT, 22))
            .margin(16)
            .x_label_area_size(40)
            .y_label_area_size(76)
            .build_cartesian_2d(x0..x1, (y0..y1).log_scale())?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(0)
            .x_label_formatter(&|_| String::new())
            .y_desc(&self.y_label)
            .y_label_formatter(&|v| format!("{v:.1}"))
            .label_style((FONT, 15))
            .axis_desc_style((FONT, 17))
            .max_light_lines(0)
            .bold_line_style(RGBColor(225, 225, 225))
            .draw()?;
        // The categories' names under their columns.
        for (i, name) in self.categories.iter().enumerate() {
            let (px, py) = chart.backend_coord(&(i as f64, y0));
            let style = TextStyle::from((FONT, 16).into_font())
                .pos(plotters::style::text_anchor::Pos::new(
                    plotters::style::text_anchor::HPos::Center,
                    plotters::style::text_anchor::VPos::Top,
                ))
                .color(&BLACK);
            root.draw(&Text::new(name.clone(), (px, py + 10), style))?;
        }
        if let Some(r) = self.reference {
            chart.draw_series(DashedLineSeries::new(
                [(x0, r), (x1, r)],
                8,
                5,
                colours::GREY.stroke_width(1),
            ))?;
        }
        let m = self.series.len().max(1) as f64;
        let width = 0.7 / m;
        for (k, (name, spreads)) in self.series.iter().enumerate() {
            let colour = PALETTE[k % PALETTE.len()];
            let offset = (k as f64 - (m - 1.0) / 2.0) * width;
            let points: Vec<(f64, Spread)> = spreads
                .iter()
                .enumerate()
                .filter_map(|(i, s)| s.map(|s| (i as f64 + offset, s)))
                .filter(|(_, s)| [s.median, s.low, s.high].iter().all(|v| *v > 0.0))
                .collect();
            chart.draw_series(points.iter().map(|&(x, s)| {
                ErrorBar::new_vertical(x, s.low, s.median, s.high, colour.stroke_width(2), 8)
            }))?;
            chart
                .draw_series(
                    points
                        .iter()
                        .map(|&(x, s)| Circle::new((x, s.median), 4, colour.filled())),
                )?
                .label(name)
                .legend(move |(x, y)| Circle::new((x + 10, y), 4, colour.filled()));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .label_font((FONT, 15))
            .background_style(WHITE.mix(0.9))
            .border_style(RGBColor(180, 180, 180))
            .draw()?;
        Ok(())
    }
}

/// The benchmark's figure of one error: per scenario (in `scenarios`'
/// order), each learner's (in `learners`') median `ratio` with its 10th to
/// 90th percentile, as `<dir>/<stem>.png` and `.svg`; returns `stem`.
pub fn save_ratios(
    dir: &Path,
    stem: &str,
    what: &str,
    cells: &[Cell],
    learners: &[String],
    scenarios: &[String],
    ratio: fn(&Cell, &Figures) -> f64,
) -> Result<String, ReportError> {
    let series = learners
        .iter()
        .map(|l| {
            let spreads = scenarios
                .iter()
                .map(|s| {
                    let c = cells.iter().find(|c| &c.learner == l && &c.scenario == s)?;
                    let a = &c.aggregate;
                    Some(Spread {
                        median: ratio(c, &a.median),
                        low: ratio(c, &a.p10),
                        high: ratio(c, &a.p90),
                    })
                })
                .collect();
            (l.clone(), spreads)
        })
        .collect();
    SpreadChart {
        title: format!("{what} error / best possible polynomial (median, p10-p90)"),
        y_label: "ratio (1 = the best possible; log scale)".into(),
        categories: scenarios.to_vec(),
        series,
        reference: Some(1.0),
    }
    .save(&dir.join(stem))?;
    Ok(stem.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spread_chart_draws_with_category_names_and_survives_missing_cells() {
        let chart = SpreadChart {
            title: "Sensor error / best possible polynomial".into(),
            y_label: "ratio".into(),
            categories: vec!["default".into(), "slippery_floor".into()],
            series: vec![
                (
                    "scasm".into(),
                    vec![
                        Some(Spread {
                            median: 2.4,
                            low: 1.6,
                            high: 5.4,
                        }),
                        None,
                    ],
                ),
                (
                    "batch-ml".into(),
                    vec![
                        Some(Spread {
                            median: 1.3,
                            low: 1.1,
                            high: 2.1,
                        }),
                        Some(Spread {
                            median: f64::NAN,
                            low: 1.0,
                            high: 1.2,
                        }),
                    ],
                ),
            ],
            reference: Some(1.0),
        };
        register_font().expect("font");
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
            chart.draw(&root).expect("draws");
            root.present().expect("presents");
        }
        assert!(svg.contains("slippery_floor"), "the category is named");
        assert!(svg.contains("batch-ml"), "the legend names the series");
        // Log scale from 1.0 / 1.25 to 5.4 * 1.25.
        assert_eq!(chart.y_range(), (0.8, 6.75));
    }
}
