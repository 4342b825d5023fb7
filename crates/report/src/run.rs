//! A run's results for people: the console's tables and text (`train`,
//! `replay`), and a training run's figures and index.html.

use std::path::Path;

use testbed::demos::Demos;
use testbed::provenance::Provenance;
use testbed::reference::MeasuredModels;
use testbed::scenario::Scenario;
use testbed::summary::RunSummary;
use testbed::trial::TrialOutcome;

use crate::ReportError;
use crate::page::Page;
use crate::paper::{self, RunData};
use crate::table;

/// What the console shows of a run. By default a headline that fits a
/// [`table::CONSOLE_COLUMNS`]-column terminal: each figure beside the paper's
/// and whether it is at the paper's level, and how many trials finished ok
/// and which did not. With `wide`, the whole results table (judged in the
/// world as it ends), the measured models, the localisation table and the
/// recovery after any change, as `index.html` and `summary.json` hold them.
pub fn console(
    run: &RunSummary,
    models: &MeasuredModels,
    scenario: &Scenario,
    wide: bool,
) -> String {
    let aggregate = &run.aggregate;
    let recovery = aggregate.describe_recovery(&scenario.changes_text());
    if !wide {
        let mut out = format!(
            "\n{}\n{}",
            table::headline(aggregate, models.last()),
            table::wrap(&aggregate.describe(), table::CONSOLE_COLUMNS)
        );
        if let Some(text) = recovery {
            out += &format!("\n{}", table::wrap(&text, table::CONSOLE_COLUMNS));
        }
        return out;
    }
    let (header, rows) = table::results_table(aggregate, models.last());
    let mut out = format!(
        "\n{}\n{}\n{}\n\n{}\n",
        table::text(&header, &rows),
        aggregate.describe(),
        models.describe(&scenario.stopwatch()),
        aggregate.describe_localisation()
    );
    if let Some(text) = recovery {
        out += &format!("\n{text}\n");
    }
    out
}

/// A training run's figures (PNG and SVG) and `index.html` beside them, in
/// `out`: the paper's figures over the ok trials, and the results table.
/// Returns how many figures were written.
pub fn write_page(
    out: &Path,
    scenario: &Scenario,
    models: &MeasuredModels,
    run: &RunSummary,
    ok_trials: &[TrialOutcome],
    demos: &Demos,
    made_by: &Provenance,
) -> Result<usize, ReportError> {
    let data = RunData {
        measured: models.last(),
        trials: ok_trials,
        demos,
        best: (run.best.0, run.best.1),
        degrees: (
            scenario.learner.action_degree,
            scenario.learner.sensor_degree,
        ),
    };
    let figures = paper::write_figures(out, &data)?;
    let (header, rows) = table::results_table(&run.aggregate, models.last());
    let page = Page {
        title: "Self-calibration on the simulated quadruped".into(),
        paragraphs: vec![
            format!(
                "{} trials of {:.0} s (seeds {}..{}), learner {}, mode {:?}. Each figure links to its SVG.",
                run.rows.len(),
                scenario.duration_s,
                scenario.seeds.0,
                scenario.seeds.1,
                testbed::learners::display_name(&scenario.learner_name),
                scenario.mode
            ),
            format!(
                "{}; the means and figures are over the ok trials.",
                run.aggregate.describe()
            ),
            format!(
                "The {} (cache key {}).",
                models.describe(&scenario.stopwatch()),
                scenario.reference_key()
            ),
            format!("Made by {}.", made_by.describe()),
        ],
        header,
        rows,
        figures: figures
            .iter()
            .map(|f| (f.stem.to_string(), paper::caption(f.stem).to_string()))
            .collect(),
    };
    page.write(&out.join("index.html"))?;
    Ok(figures.len())
}
