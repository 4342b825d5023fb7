//! Tables of results as text: the paper's comparison table of a run (on the
//! console and on its page), and any table as aligned text or Markdown.

use testbed::reference::MeasuredModels;
use testbed::summary::{Aggregate, Figures};

/// A run's figures beside the paper's, as rows of text (for the console, the
/// page and the README): led by the ratio to the best possible polynomial.
pub fn results_table(
    aggregate: &Aggregate,
    models: &MeasuredModels,
) -> (Vec<String>, Vec<Vec<String>>) {
    let (mean, std) = (&aggregate.mean, &aggregate.std);
    let (velocity_range, distance_range) =
        (models.velocity_range_mm_s(), models.distance_range_mm());
    let header = [
        "figure",
        "learned / best poly (ours / paper)",
        "ours (mean +- std)",
        "median [p10, p90] (median / best)",
        "paper",
        "best poly (ours / paper)",
        "information floor, RMS (learned / floor by RMS; per trial median, p90)",
        "A0 (ours / paper)",
    ]
    .map(String::from)
    .to_vec();
    let paper = Figures::paper();
    let ours = |m: f64, s: f64, range: f64| {
        format!(
            "{m:.1} +- {s:.1} ({:.1} % of {range:.0})",
            100.0 * m / range
        )
    };
    let pair = |a: f64, b: f64| format!("{a:.1} / {b:.1}");
    let tail = |get: fn(&Figures) -> f64, decimals: usize| {
        format!(
            "{:.d$} [{:.d$}, {:.d$}]",
            get(&aggregate.median),
            get(&aggregate.p10),
            get(&aggregate.p90),
            d = decimals
        )
    };
    let ratio = |a: f64, best_a: f64, b: f64, best_b: f64| {
        format!("{:.2}x / {:.2}x", a / best_a, b / best_b)
    };
    let rows = vec![
        vec![
            "action RMSE (mm/s)".into(),
            ratio(
                mean.action_rmse_mm_s,
                mean.action_best_rmse_mm_s,
                paper.action_rmse_mm_s,
                paper.action_best_rmse_mm_s,
            ),
            ours(mean.action_rmse_mm_s, std.action_rmse_mm_s, velocity_range),
            format!(
                "{} ({:.2}x)",
                tail(|f| f.action_rmse_mm_s, 1),
                aggregate.median.action_rmse_mm_s / mean.action_best_rmse_mm_s
            ),
            format!("{:.1} (4.9 % of 600)", paper.action_rmse_mm_s),
            pair(mean.action_best_rmse_mm_s, paper.action_best_rmse_mm_s),
            aggregate.floor.action.cell(),
            pair(mean.action_a0_rmse_mm_s, paper.action_a0_rmse_mm_s),
        ],
        vec![
            "sensor RMSE (mm)".into(),
            ratio(
                mean.sensor_rmse_mm,
                mean.sensor_best_rmse_mm,
                paper.sensor_rmse_mm,
                paper.sensor_best_rmse_mm,
            ),
            ours(mean.sensor_rmse_mm, std.sensor_rmse_mm, distance_range),
            format!(
                "{} ({:.2}x)",
                tail(|f| f.sensor_rmse_mm, 1),
                aggregate.median.sensor_rmse_mm / mean.sensor_best_rmse_mm
            ),
            format!("{:.1} +- 13.9 (2.9 % of 2400)", paper.sensor_rmse_mm),
            pair(mean.sensor_best_rmse_mm, paper.sensor_best_rmse_mm),
            aggregate.floor.sensor.cell(),
            "-".into(),
        ],
        vec![
            "consistency".into(),
            "-".into(),
            format!("{:.3} +- {:.3}", mean.consistency, std.consistency),
            tail(|f| f.consistency, 3),
            format!("{:.2} +- 0.06", paper.consistency),
            "-".into(),
            "-".into(),
            "-".into(),
        ],
    ];
    (header, rows)
}

/// The width the console's headline keeps within, in columns.
pub const CONSOLE_COLUMNS: usize = 100;

/// A run's figures beside the paper's, narrow enough for a
/// [`CONSOLE_COLUMNS`]-column terminal: each figure's mean (and share of the
/// range), the paper's, whether it is at the paper's level, and the ratio to
/// the best polynomial of the learner's degrees (the paper's beside it).
pub fn headline(aggregate: &Aggregate, models: &MeasuredModels) -> String {
    let mean = &aggregate.mean;
    let paper = Figures::paper();
    let (v, d) = (models.velocity_range_mm_s(), models.distance_range_mm());
    let level = mean.at_paper_level(v, d);
    let yes = |ok: bool| if ok { "yes" } else { "no" }.to_string();
    let pct = |x: f64, range: f64| format!("{:.1} %", 100.0 * x / range);
    let header = [
        "figure",
        "ours",
        "of range",
        "paper",
        "of range",
        "at paper level",
        "/ best poly (paper)",
    ]
    .map(String::from)
    .to_vec();
    let rows = vec![
        vec![
            "action RMSE (mm/s)".into(),
            format!("{:.1}", mean.action_rmse_mm_s),
            pct(mean.action_rmse_mm_s, v),
            format!("{:.1}", paper.action_rmse_mm_s),
            "4.9 %".into(),
            yes(level[0]),
            format!(
                "{:.2}x ({:.2}x)",
                mean.action_rmse_mm_s / mean.action_best_rmse_mm_s,
                paper.action_rmse_mm_s / paper.action_best_rmse_mm_s
            ),
        ],
        vec![
            "sensor RMSE (mm)".into(),
            format!("{:.1}", mean.sensor_rmse_mm),
            pct(mean.sensor_rmse_mm, d),
            format!("{:.1}", paper.sensor_rmse_mm),
            "2.9 %".into(),
            yes(level[1]),
            format!(
                "{:.2}x ({:.2}x)",
                mean.sensor_rmse_mm / mean.sensor_best_rmse_mm,
                paper.sensor_rmse_mm / paper.sensor_best_rmse_mm
            ),
        ],
        vec![
            "consistency".into(),
            format!("{:.3}", mean.consistency),
            "-".into(),
            format!("{:.2}", paper.consistency),
            "-".into(),
            yes(level[2]),
            "-".into(),
        ],
    ];
    let mut out = text(&header, &rows);
    let (a, s) = (&aggregate.floor.action, &aggregate.floor.sensor);
    let (la, ls) = (
        &aggregate.floor.action_likelihood,
        &aggregate.floor.sensor_likelihood,
    );
    let floor = if a.n == 0 && s.n == 0 {
        "no trial has an information floor".to_string()
    } else {
        format!(
            "the information floor, the least error the data allow, by RMS over the trials: \
             action {:.1} mm/s (the error {:.2}x it by RMS; per trial median {:.2}x, p90 \
             {:.2}x), sensor {:.1} mm ({:.2}x; {:.2}x, {:.2}x); the likelihood's floor, where \
             maximum likelihood of the floor's model lands: action {:.1} mm/s ({:.2}x), sensor \
             {:.1} mm ({:.2}x)",
            a.floor_rms,
            a.rms,
            a.median,
            a.p90,
            s.floor_rms,
            s.rms,
            s.median,
            s.p90,
            la.floor_rms,
            la.rms,
            ls.floor_rms,
            ls.rms
        )
    };
    out += &wrap(
        &format!("(means over the ok trials; {floor})"),
        CONSOLE_COLUMNS,
    );
    out
}

/// `text` broken at spaces into lines of at most `width` columns (a word
/// longer than that stands on its own line); a line's indentation is kept,
/// and its continuation lines get the same.
pub fn wrap(text: &str, width: usize) -> String {
    let mut out = String::new();
    for paragraph in text.lines() {
        let indent: String = paragraph
            .chars()
            .take_while(|c| c.is_whitespace())
            .collect();
        let mut line = indent.clone();
        for word in paragraph.split_whitespace() {
            let empty = line.len() == indent.len();
            if !empty && line.chars().count() + 1 + word.chars().count() > width {
                out += &line;
                out.push('\n');
                line.clone_from(&indent);
            } else if !empty {
                line.push(' ');
            }
            line += word;
        }
        out += &line;
        out.push('\n');
    }
    out
}

/// The table as aligned text, one line per row (the first column left-aligned,
/// the others right-aligned).
pub fn text(header: &[String], rows: &[Vec<String>]) -> String {
    let widths: Vec<usize> = (0..header.len())
        .map(|c| {
            std::iter::once(header)
                .chain(rows.iter().map(Vec::as_slice))
                .map(|r| r.get(c).map_or(0, |s| s.chars().count()))
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut out = String::new();
    for row in std::iter::once(header).chain(rows.iter().map(Vec::as_slice)) {
        let cells: Vec<String> = row
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(i, (c, &w))| {
                if i == 0 {
                    format!("{c:<w$}")
                } else {
                    format!("{c:>w$}")
                }
            })
            .collect();
        out.push_str(cells.join("  ").trim_end());
        out.push('\n');
    }
    out
}

/// The table as Markdown.
pub fn markdown(header: &[String], rows: &[Vec<String>]) -> String {
    let line = |cells: &[String]| format!("| {} |\n", cells.join(" | "));
    let mut out = line(header);
    out.push_str(&line(&vec!["---".to_string(); header.len()]));
    for r in rows {
        out.push_str(&line(r));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_aligns_columns_and_markdown_has_a_rule() {
        let header = vec!["a".to_string(), "bb".to_string()];
        let rows = vec![vec!["long".to_string(), "1".to_string()]];
        assert_eq!(text(&header, &rows), "a     bb\nlong   1\n");
        assert_eq!(
            markdown(&header, &rows),
            "| a | bb |\n| --- | --- |\n| long | 1 |\n"
        );
    }
}
