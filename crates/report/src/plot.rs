//! Line and scatter charts as data ([`Chart`]), drawn the same way to PNG and to
//! SVG with a bundled font, so text renders on a machine with no system fonts.

use std::path::Path;

/// Where a chart's legend goes (plotters' own type).
pub use plotters::prelude::SeriesLabelPosition;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::{ReportError, write_atomic};

/// Pixel size of every chart.
pub const SIZE: (u32, u32) = (800, 560);

/// The font every chart's text is drawn in (DejaVu Sans, bundled).
pub(crate) const FONT: &str = "sans-serif";
static FONT_BYTES: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

/// Registers the bundled font with plotters as "sans-serif" (once per process);
/// drawing text with plotters needs it.
pub fn register_font() -> Result<(), ReportError> {
    static REGISTERED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(ReportError::Draw("the bundled font does not parse".into()))
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, PartialEq)]
pub enum Mark {
    /// A solid line through the points.
    Line,
    /// A dashed line through the points.
    Dashed,
    /// A `+` at each point.
    Plus,
    /// A `x` at each point.
    Cross,
    /// A filled dot at each point.
    Dot,
    /// A dot at each point with a vertical bar of plus or minus this much.
    ErrorBars(Vec<f64>),
    /// A shaded band between the points (lower edge) and these values (upper edge).
    Band(Vec<f64>),
}

/// One series of a chart.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Its legend entry (none if empty).
    pub label: String,
    /// How it is drawn.
    pub mark: Mark,
    /// Its colour.
    pub colour: RGBColor,
    /// Its points, `(x, y)`.
    pub points: Vec<(f64, f64)>,
}

impl Series {
    /// A series of `points` drawn as `mark`.
    pub fn new(label: &str, mark: Mark, colour: RGBColor, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            mark,
            colour,
            points,
        }
    }
}

/// A chart: title, axis titles, series and the legend's corner.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// The caption.
    pub title: String,
    /// The x axis' title, with units.
    pub x_label: String,
    /// The y axis' title, with units.
    pub y_label: String,
    /// The series, drawn in order.
    pub series: Vec<Series>,
    /// Where the legend goes.
    pub legend: SeriesLabelPosition,
}

/// Colours that stay apart for colour-blind readers (Okabe and Ito).
pub mod colours {
    use plotters::style::RGBColor;
    /// Blue.
    pub const BLUE: RGBColor = RGBColor(0, 114, 178);
    /// Vermillion.
    pub const RED: RGBColor = RGBColor(213, 94, 0);
    /// Bluish green.
    pub const GREEN: RGBColor = RGBColor(0, 158, 115);
    /// Orange.
    pub const ORANGE: RGBColor = RGBColor(230, 159, 0);
    /// Reddish purple.
    pub const PURPLE: RGBColor = RGBColor(204, 121, 167);
    /// Near black.
    pub const BLACK: RGBColor = RGBColor(30, 30, 30);
    /// Grey.
    pub const GREY: RGBColor = RGBColor(120, 120, 120);
}

impl Chart {
    /// The range of x and y over every finite point (and band edge), padded by 4 %.
    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let mut xs = Vec::new();
        let mut ys = Vec::new();
        for s in &self.series {
            for (i, &(x, y)) in s.points.iter().enumerate() {
                xs.push(x);
                ys.push(y);
                match &s.mark {
                    Mark::Band(upper) => ys.extend(upper.get(i)),
                    Mark::ErrorBars(half) => {
                        if let Some(h) = half.get(i) {
                            ys.extend([y - h, y + h]);
                        }
                    }
                    _ => {}
                }
            }
        }
        (padded(&xs), padded(&ys))
    }
}

impl Drawing for Chart {
    const SIZE: (u32, u32) = SIZE;

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        // A font that does not parse shows up as the text's own drawing error.
        let _ = register_font();
        root.fill(&WHITE)?;
        let ((x0, x1), (y0, y1)) = self.ranges();
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, (FONT, 22))
            .margin(16)
            .x_label_area_size(52)
            .y_label_area_size(76)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style((FONT, 15))
            .axis_desc_style((FONT, 17))
            .max_light_lines(0)
            .bold_line_style(RGBColor(225, 225, 225))
            .draw()?;
        let mut labelled = false;
        for s in &self.series {
            let colour = s.colour;
            let line = colour.stroke_width(2);
            let pts = s
                .points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite());
            let anno = match &s.mark {
                Mark::Line => chart.draw_series(LineSeries::new(pts, line))?,
                Mark::Dashed => chart.draw_series(DashedLineSeries::new(pts, 10, 6, line))?,
                Mark::Plus => chart.draw_series(pts.map(|p| {
                    EmptyElement::at(p)
                        + PathElement::new(vec![(-4, 0), (4, 0)], colour.stroke_width(1))
                        + PathElement::new(vec![(0, -4), (0, 4)], colour.stroke_width(1))
                }))?,
                Mark::Cross => chart.draw_series(pts.map(|p| Cross::new(p, 3, colour)))?,
                Mark::Dot => chart.draw_series(pts.map(|p| Circle::new(p, 3, colour.filled())))?,
                Mark::ErrorBars(half) => {
                    chart.draw_series(s.points.iter().zip(half).map(|(&(x, y), &h)| {
                        ErrorBar::new_vertical(x, y - h, y, y + h, colour.filled(), 6)
                    }))?
                }
                Mark::Band(upper) => {
                    let mut edge: Vec<(f64, f64)> = s.points.clone();
                    edge.extend(s.points.iter().zip(upper).rev().map(|(&(x, _), &u)| (x, u)));
                    edge.retain(|p| p.0.is_finite() && p.1.is_finite());
                    chart.draw_series(std::iter::once(Polygon::new(edge, colour.mix(0.18))))?
                }
            };
            if !s.label.is_empty() {
                labelled = true;
                let a = anno.label(&s.label);
                let thin = colour.stroke_width(1);
                match &s.mark {
                    Mark::Line => {
                        a.legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], line))
                    }
                    Mark::Dashed => a.legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new([(0, 0), (7, 0)], line)
                            + PathElement::new([(13, 0), (20, 0)], line)
                    }),
                    Mark::Plus => a.legend(move |(x, y)| {
                        EmptyElement::at((x + 10, y))
                            + PathElement::new([(-4, 0), (4, 0)], thin)
                            + PathElement::new([(0, -4), (0, 4)], thin)
                    }),
                    Mark::Cross => a.legend(move |(x, y)| Cross::new((x + 10, y), 3, colour)),
                    Mark::Dot | Mark::ErrorBars(_) => {
                        a.legend(move |(x, y)| Circle::new((x + 10, y), 3, colour.filled()))
                    }
                    Mark::Band(_) => a.legend(move |(x, y)| {
                        Rectangle::new([(x, y - 5), (x + 20, y + 5)], colour.mix(0.25).filled())
                    }),
                };
            }
        }
        if labelled {
            chart
                .configure_series_labels()
                .position(self.legend.clone())
                .label_font((FONT, 15))
                .background_style(WHITE.mix(0.9))
                .border_style(RGBColor(180, 180, 180))
                .draw()?;
        }
        Ok(())
    }
}

/// A picture drawn the same way on any plotters backend, and written as PNG
/// and SVG by [`Drawing::save`], the one place pictures become files.
pub trait Drawing {
    /// Its size in pixels.
    const SIZE: (u32, u32);

    /// Draws it on `root`.
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>;

    /// Writes `<stem>.svg` and `<stem>.png`, each whole or not at all.
    fn save(&self, stem: &Path) -> Result<(), ReportError> {
        register_font()?;
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, Self::SIZE).into_drawing_area();
            self.draw(&root).map_err(draw_error)?;
            root.present().map_err(draw_error)?;
        }
        write_atomic(&stem.with_extension("svg"), svg.as_bytes())?;
        write_atomic(&stem.with_extension("png"), &self.png()?)
    }

    /// It as PNG bytes (what [`Drawing::save`] writes, and what a Rerun
    /// recording shows).
    fn png(&self) -> Result<Vec<u8>, ReportError> {
        register_font()?;
        let size = Self::SIZE;
        let mut rgb = vec![0u8; (size.0 * size.1 * 3) as usize];
        {
            let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
            self.draw(&root).map_err(draw_error)?;
            root.present().map_err(draw_error)?;
        }
        encode_png(&rgb, size)
    }
}

/// `[min, max]` of the finite values, padded by 4 % (a unit interval if none).
pub(crate) fn padded(values: &[f64]) -> (f64, f64) {
    let (lo, hi) = values
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if lo > hi {
        return (0.0, 1.0);
    }
    let pad = if hi > lo {
        0.04 * (hi - lo)
    } else {
        0.5 * lo.abs().max(1.0)
    };
    (lo - pad, hi + pad)
}

pub(crate) fn draw_error<E: std::error::Error + Send + Sync>(
    e: DrawingAreaErrorKind<E>,
) -> ReportError {
    ReportError::Draw(e.to_string())
}

/// An RGB buffer as PNG bytes: the workspace's one PNG encoder.
pub fn encode_png(rgb: &[u8], (w, h): (u32, u32)) -> Result<Vec<u8>, ReportError> {
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, w, h);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder
            .write_header()
            .map_err(|e| ReportError::Draw(e.to_string()))?;
        writer
            .write_image_data(rgb)
            .map_err(|e| ReportError::Draw(e.to_string()))?;
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn render(chart: &Chart) -> Vec<u8> {
        register_font().expect("font");
        let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
        {
            let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
            chart.draw(&root).expect("drawn");
            root.present().expect("presented");
        }
        rgb
    }

    fn chart(title: &str, points: Vec<(f64, f64)>) -> Chart {
        Chart {
            title: title.into(),
            x_label: "x (m)".into(),
            y_label: "y (s)".into(),
            series: vec![Series::new("data", Mark::Line, colours::BLUE, points)],
            legend: SeriesLabelPosition::UpperRight,
        }
    }

    #[test]
    fn text_is_drawn_with_the_bundled_font() {
        let line = vec![(0.0, 0.0), (1.0, 1.0)];
        let plain = render(&chart("", line.clone()));
        let titled = render(&chart("Fig. 0: a title", line));
        // The caption's glyphs darken pixels in the band above the plot.
        let band = |rgb: &[u8]| {
            rgb[..(SIZE.0 * 40 * 3) as usize]
                .iter()
                .filter(|&&v| v < 128)
                .count()
        };
        assert_eq!(band(&plain), 0);
        assert!(band(&titled) > 100, "{} dark pixels", band(&titled));
    }

    #[test]
    fn non_finite_points_are_skipped_not_fatal() {
        let rgb = render(&chart(
            "t",
            vec![
                (0.0, f64::NAN),
                (1.0, 2.0),
                (f64::INFINITY, 3.0),
                (2.0, 1.0),
            ],
        ));
        assert!(rgb.iter().any(|&v| v < 128));
        let empty = render(&chart("t", vec![]));
        assert!(empty.iter().any(|&v| v < 128));
    }

    #[test]
    fn ranges_are_padded_and_never_empty() {
        assert_eq!(padded(&[]), (0.0, 1.0));
        assert_eq!(padded(&[f64::NAN]), (0.0, 1.0));
        let (lo, hi) = padded(&[2.0, 2.0]);
        assert!(lo < 2.0 && hi > 2.0);
        let (lo, hi) = padded(&[0.0, 10.0]);
        assert!((lo + 0.4).abs() < 1e-12 && (hi - 10.4).abs() < 1e-12);
    }
}
