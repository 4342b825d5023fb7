//! Sweeps: the grid, deterministic shards that merge into exactly the rows of one
//! unsharded sweep, resuming, and refusing what does not fit.

use std::sync::OnceLock;

use testbed::experiment;
use testbed::reference::MeasuredModels;
use testbed::scenario::Scenario;
use testbed::summary::{self, Figures, TrialStatus};
use testbed::sweep::{self, Axis, Results, Row, Run};

fn setup() -> &'static (Scenario, MeasuredModels) {
    static SETUP: OnceLock<(Scenario, MeasuredModels)> = OnceLock::new();
    SETUP.get_or_init(|| {
        let mut scenario = Scenario::paper().expect("scenario");
        scenario.set("trial.duration=12").expect("valid");
        let cache = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("reference-cache");
        let models =
            testbed::reference::measured_models(&scenario, Some(&cache)).expect("measured");
        (scenario, models)
    })
}

fn grid() -> Vec<Run> {
    let axes = [
        Axis::parse("learner.gamma", "0.99,0.999").expect("list"),
        Axis::parse("learner.t_start", "2:2:4").expect("range"),
    ];
    sweep::runs(&axes, &[0, 1])
}

fn run_all(runs: &[Run]) -> Results {
    let (base, models) = setup();
    let mut results = Results::new(vec!["learner.gamma".into(), "learner.t_start".into()]);
    for run in runs {
        let scenario = run.scenario(base).expect("valid");
        let (_, outcome) = experiment::run_one(&scenario, models, run.seed).expect("trial");
        let best = summary::best_possible(&models.reference(), &scenario.learner);
        results.insert(Row {
            run: run.clone(),
            figures: Figures::of(&outcome, best),
            status: TrialStatus::of(&outcome),
        });
    }
    results
}

fn temp_dir(name: &str) -> std::path::PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("dir");
    d
}

#[test]
fn the_grid_is_every_combination_times_every_seed() {
    let runs = grid();
    assert_eq!(runs.len(), 2 * 2 * 2);
    let keys: std::collections::BTreeSet<String> = runs.iter().map(Run::key).collect();
    assert_eq!(keys.len(), runs.len(), "run keys must be unique");
    assert!(keys.contains("learner.gamma=0.999;learner.t_start=4;seed=1"));
}

#[test]
fn shards_are_disjoint_and_cover_the_grid() {
    let runs = grid();
    for n in 1..=5 {
        let mut all: Vec<String> = (1..=n)
            .flat_map(|k| sweep::shard(runs.clone(), k, n))
            .map(|r| r.key())
            .collect();
        all.sort();
        let mut expected: Vec<String> = runs.iter().map(Run::key).collect();
        expected.sort();
        assert_eq!(all, expected, "{n} shards");
    }
}

#[test]
fn sharded_runs_merge_into_the_unsharded_rows() {
    let runs = grid();
    let whole = temp_dir("sweep-whole");
    run_all(&runs).write(&whole).expect("write");
    let merged_dir = temp_dir("sweep-merged");
    let mut merged: Option<Results> = None;
    for k in 1..=3 {
        let dir = temp_dir(&format!("sweep-shard-{k}"));
        run_all(&sweep::shard(runs.clone(), k, 3))
            .write(&dir)
            .expect("write");
        let r = Results::read(&dir).expect("read").expect("exists");
        match &mut merged {
            None => merged = Some(r),
            Some(m) => m.merge(r).expect("same settings"),
        }
    }
    merged.expect("shards").write(&merged_dir).expect("write");
    // Every column but the wall-clock times must agree to the bit.
    let read = |d: &std::path::Path| -> Vec<String> {
        let text = std::fs::read_to_string(d.join("sweep.csv")).expect("csv");
        let header: Vec<&str> = text.lines().next().expect("header").split(',').collect();
        let skip: Vec<usize> = ["realtime_factor", "learner_wall_s"]
            .iter()
            .map(|w| header.iter().position(|c| c == w).expect("column"))
            .collect();
        text.lines()
            .map(|l| {
                let cells: Vec<&str> = l.split(',').collect();
                cells
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| !skip.contains(i))
                    .map(|(_, c)| *c)
                    .collect::<Vec<_>>()
                    .join(",")
            })
            .collect()
    };
    assert_eq!(read(&whole), read(&merged_dir));
}

#[test]
fn a_resumed_sweep_skips_what_is_done_and_reads_back_exactly() {
    let runs = grid();
    let dir = temp_dir("sweep-resume");
    let first = run_all(&runs[..3]);
    first.write(&dir).expect("write");
    let back = Results::read(&dir).expect("read").expect("exists");
    assert!(runs[..3].iter().all(|r| back.has(r)));
    assert!(!runs[3..].iter().any(|r| back.has(r)));
    // What was read back writes out to the same bytes.
    let again = temp_dir("sweep-resume-again");
    back.write(&again).expect("write");
    assert_eq!(
        std::fs::read_to_string(dir.join("sweep.csv")).expect("csv"),
        std::fs::read_to_string(again.join("sweep.csv")).expect("csv")
    );
    back.write_summary(&dir).expect("summary");
    let summary = std::fs::read_to_string(dir.join("sweep_summary.csv")).expect("summary");
    assert!(
        summary
            .starts_with("learner.gamma,learner.t_start,runs_ok,runs_failed,runs_worse_than_start,runs_worse_than_start_action,runs_worse_than_start_sensor,action_rmse_mm_s_mean,action_rmse_mm_s_std,action_rmse_mm_s_median,action_rmse_mm_s_p10,action_rmse_mm_s_p90,action_rmse_mm_s_n,")
    );
}

#[test]
fn bad_values_shards_and_foreign_results_are_refused() {
    assert!(Axis::parse("learner.gamma", "0.9,,0.99").is_err());
    assert!(Axis::parse("learner.t_start", "10:0:40").is_err());
    assert!(Axis::parse("learner.t_start", "40:10:10").is_err());
    assert_eq!(
        Axis::parse("learner.t_start", "10:10:40")
            .expect("range")
            .values,
        ["10", "20", "30", "40"]
    );
    for bad in ["0/3", "4/3", "x/3", "3"] {
        assert!(sweep::parse_shard(bad).is_err(), "{bad}");
    }
    let run = Run {
        settings: vec![("learner.gama".into(), "0.9".into())],
        seed: 0,
    };
    assert!(run.scenario(&setup().0).is_err());
    let dir = temp_dir("sweep-foreign");
    std::fs::write(dir.join("sweep.csv"), "a,b,c\n1,2,3\n").expect("write");
    assert!(Results::read(&dir).is_err());
}
