//! A benchmark's leaderboard for people: the summary table (console,
//! `leaderboard.md` and `index.html`), its notes (failed trials, learners
//! below the paper's level) and the spread figures of the ratios to the best
//! possible polynomials.

use std::path::Path;

use testbed::benchmark::{self, Benchmark, Entry};

use crate::ReportError;
use crate::page::Page;
use crate::{spread, table};

/// Writes `leaderboard.md`, the two spread figures and `index.html` in `out`
/// for `entries` of `bench`; returns what the console shows (the table and
/// the notes).
pub fn write(
    out: &Path,
    bench: &Benchmark,
    entries: &[Entry],
    wide: bool,
) -> Result<String, ReportError> {
    let names = bench.names();
    let cells = benchmark::cells(entries, &bench.learners, &names);
    let (header, rows) = benchmark::summary_table(&cells);
    let misses = benchmark::below_paper(&cells, &|name| bench.ranges(name));
    let failed: Vec<String> = entries
        .iter()
        .filter(|e| !e.status.is_ok())
        .map(|e| {
            format!(
                "{} on {} seed {} ({})",
                e.learner, e.scenario, e.seed, e.status
            )
        })
        .collect();
    let (first, end) = (
        bench.seeds.first().copied().unwrap_or(0),
        bench.seeds.last().map_or(0, |s| s + 1),
    );
    let notes = vec![
        format!(
            "{} learners x {} scenarios x seeds {first}..{end}, {} s trials; the figures are means \
             over each cell's ok trials (+- their std); ratios are to the best polynomial through \
             the measured model (quartic action, cubic sensor).",
            bench.learners.len(),
            bench.suite.len(),
            bench
                .suite
                .first()
                .map_or(f64::NAN, |s| s.scenario.duration_s)
        ),
        if failed.is_empty() {
            "Every trial finished ok.".into()
        } else {
            format!("Trials not ok (not in any mean): {}.", failed.join("; "))
        },
        if misses.is_empty() {
            "Every learner is at the paper's level (action <= 4.9 %, sensor <= 2.9 % of range, \
             consistency <= 0.08) on every scenario."
                .into()
        } else {
            format!("Below the paper's level: {}.", misses.join("; "))
        },
    ];
    let markdown = format!(
        "{}\n\n{}",
        table::markdown(&header, &rows),
        notes.join("\n\n")
    );
    let md = out.join("leaderboard.md");
    testbed::output::write_atomic(&md, markdown.as_bytes()).map_err(|source| ReportError::Io {
        path: md.display().to_string(),
        source,
    })?;
    // The figures: each learner's median ratio to the best polynomial, and
    // its 10th to 90th percentile, per scenario.
    let figures = vec![
        (
            spread::save_ratios(
                out,
                "leaderboard-action",
                "Action",
                &cells,
                &bench.learners,
                &names,
                |c, f| c.action_ratio_of(f),
            )?,
            "Each learner's action error over the best quartic's per scenario: the median \
             (dot) and the 10th to 90th percentile (bar) over the seeds."
                .to_string(),
        ),
        (
            spread::save_ratios(
                out,
                "leaderboard-sensor",
                "Sensor",
                &cells,
                &bench.learners,
                &names,
                |c, f| c.sensor_ratio_of(f),
            )?,
            "Each learner's sensor error over the best cubic's per scenario: the median (dot) \
             and the 10th to 90th percentile (bar) over the seeds."
                .to_string(),
        ),
    ];
    let console = if wide {
        format!(
            "\n{}\n{}",
            table::text(&header, &rows),
            notes[1..].join("\n")
        )
    } else {
        format!(
            "\n{}\n{}",
            compact(&cells),
            table::wrap(&notes[1..].join("\n"), table::CONSOLE_COLUMNS)
        )
    };
    Page {
        title: "Learners side by side".into(),
        paragraphs: notes,
        header,
        rows,
        figures,
    }
    .write(&out.join("index.html"))?;
    Ok(console)
}

/// The leaderboard narrow enough for a terminal: per scenario and learner,
/// the mean errors and their ratios to the best polynomials, the consistency,
/// and the trials worse than their start and ok.
fn compact(cells: &[benchmark::Cell]) -> String {
    let header = [
        "scenario",
        "learner",
        "action mm/s",
        "/ best",
        "sensor mm",
        "/ best",
        "consistency",
        "worse",
        "ok",
    ]
    .map(String::from)
    .to_vec();
    let rows: Vec<Vec<String>> = cells
        .iter()
        .map(|c| {
            let (a, m) = (&c.aggregate, &c.aggregate.mean);
            vec![
                c.scenario.clone(),
                c.learner.clone(),
                format!("{:.1}", m.action_rmse_mm_s),
                format!("{:.2}x", c.action_ratio()),
                format!("{:.1}", m.sensor_rmse_mm),
                format!("{:.2}x", c.sensor_ratio()),
                format!("{:.3}", m.consistency),
                format!("{}", a.worse_than_start.len()),
                format!("{}/{}", a.ok(), a.trials),
            ]
        })
        .collect();
    table::text(&header, &rows)
}
