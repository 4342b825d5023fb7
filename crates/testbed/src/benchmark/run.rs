//! Running a benchmark: its learners resolved, one reference per distinct
//! world, the (scenario, seed) worlds of a shard, each simulated once and fed
//! to every learner, and the leaderboard's entries.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Mutex;

use crate::benchmark::leaderboard::Entry;
use crate::benchmark::suite::SuiteScenario;
use crate::experiment::{self, Job};
use crate::learners;
use crate::reference::{self, MeasuredModels};
use crate::summary;

/// A benchmark ready to run: the suite, the learners, the seeds, and the
/// measured models of each distinct world of the suite.
#[derive(Debug)]
pub struct Benchmark {
    /// The scenarios.
    pub suite: Vec<SuiteScenario>,
    /// The learners as named (a Rust learner's name or `exec:COMMAND`).
    pub specs: Vec<String>,
    /// The names they report under, in the same order.
    pub learners: Vec<String>,
    /// The seeds.
    pub seeds: Vec<u64>,
    /// The measured models, by reference key.
    pub references: BTreeMap<String, MeasuredModels>,
}

impl Benchmark {
    /// Resolves `specs` (a program is started once here, to read its hello)
    /// and measures, or reads from `cache`, one reference per distinct world
    /// of `suite`, saying each as it comes.
    pub fn new(
        suite: Vec<SuiteScenario>,
        specs: Vec<String>,
        seeds: Vec<u64>,
        cache: &Path,
        say: &dyn Fn(&str),
    ) -> Result<Self, String> {
        let learners = specs
            .iter()
            .map(|spec| learners::resolve(spec).map(|l| l.name().to_string()))
            .collect::<Result<_, _>>()?;
        let mut references = BTreeMap::new();
        for s in &suite {
            let key = s.scenario.reference_key();
            if let std::collections::btree_map::Entry::Vacant(slot) = references.entry(key) {
                say(&format!(
                    "reference models for {} ({})...",
                    s.name,
                    slot.key()
                ));
                let models = reference::measured_models(&s.scenario, Some(cache))
                    .map_err(|e| format!("{}: {e}", s.name))?;
                slot.insert(models);
            }
        }
        Ok(Self {
            suite,
            specs,
            learners,
            seeds,
            references,
        })
    }

    /// The measured models of scenario `s`.
    pub fn models(&self, s: &SuiteScenario) -> &MeasuredModels {
        &self.references[&s.scenario.reference_key()]
    }

    /// `summary.json` of a benchmark: the seeds, each learner as named (a
    /// program's command too) with the settings it ran with on each
    /// scenario, and per (learner, scenario) the counts of trials and the
    /// statistics of every figure over the ok ones.
    pub fn summary_json(&self, entries: &[Entry]) -> serde_json::Value {
        let learners: Vec<serde_json::Value> = self
            .specs
            .iter()
            .zip(&self.learners)
            .map(|(spec, name)| {
                let on: serde_json::Map<String, serde_json::Value> = self
                    .suite
                    .iter()
                    .map(|s| (s.name.clone(), learners::parameters(spec, &s.scenario)))
                    .collect();
                serde_json::json!({"name": name, "spec": spec, "parameters": on})
            })
            .collect();
        let cells: Vec<serde_json::Value> =
            crate::benchmark::cells(entries, &self.learners, &self.names())
                .into_iter()
                .map(|c| {
                    let a = &c.aggregate;
                    let mut cell = serde_json::Map::new();
                    cell.insert("learner".into(), c.learner.clone().into());
                    cell.insert("scenario".into(), c.scenario.clone().into());
                    cell.insert("trials".into(), a.trials.into());
                    cell.insert("trials_ok".into(), a.ok().into());
                    cell.insert("trials_failed".into(), a.failed.len().into());
                    cell.insert(
                        "trials_worse_than_start".into(),
                        a.worse_than_start.len().into(),
                    );
                    cell.extend(a.statistics_json());
                    serde_json::Value::Object(cell)
                })
                .collect();
        serde_json::json!({
            "seeds": self.seeds,
            "scenarios": self.names(),
            "learners": learners,
            "cells": cells,
        })
    }

    /// The scenarios' names, in order.
    pub fn names(&self) -> Vec<String> {
        self.suite.iter().map(|s| s.name.clone()).collect()
    }

    /// Every `(scenario index, seed)` world of shard `k` of `n`.
    pub fn worlds(&self, k: usize, n: usize) -> Vec<(usize, u64)> {
        shard_worlds(self.suite.len(), &self.seeds, k, n)
    }

    /// How many simulations `worlds` take: one each, but one per learner
    /// for a scenario whose behaviour steers by the learner
    /// ([`experiment::steered`]).
    pub fn simulations(&self, worlds: &[(usize, u64)]) -> usize {
        worlds
            .iter()
            .map(|&(i, _)| {
                if experiment::steered(&self.suite[i].scenario) {
                    self.specs.len()
                } else {
                    1
                }
            })
            .sum()
    }

    /// Runs every learner on `worlds`, each world simulated once (once per
    /// learner for a behaviour that steers by it), calling
    /// `done` as each trial finishes; the entries, in the benchmark's order.
    pub fn run(&self, worlds: &[(usize, u64)], done: &(dyn Fn() + Sync)) -> Vec<Entry> {
        // (scenario index, learner index, job)
        let mut jobs: Vec<(usize, usize, Job<'_>)> = Vec::new();
        for &(i, seed) in worlds {
            let s = &self.suite[i];
            for (l, spec) in self.specs.iter().enumerate() {
                let job = Job {
                    scenario: &s.scenario,
                    models: self.models(s),
                    seed,
                    learner: spec,
                };
                jobs.push((i, l, job));
            }
        }
        let only: Vec<Job<'_>> = jobs.iter().map(|(.., j)| *j).collect();
        let entries = Mutex::new(Vec::new());
        experiment::run_jobs(&only, &|i, result| {
            let (scenario, learner, job) = &jobs[i];
            let best = summary::best_possible(&job.models.reference(), &job.scenario.learner);
            let (seed, status, figures) =
                summary::trial_row(job.seed, result.as_ref().map_err(|e| e.to_string()), best);
            if let Ok(mut v) = entries.lock() {
                v.push(Entry {
                    // The name it reports under, resolved once in `new`.
                    learner: self.learners[*learner].clone(),
                    scenario: self.suite[*scenario].name.clone(),
                    seed,
                    status,
                    figures,
                });
            }
            done();
        });
        let mut entries = entries.into_inner().unwrap_or_else(|p| p.into_inner());
        self.sort(&mut entries);
        entries
    }

    /// Sorts entries by scenario, then learner, then seed.
    pub fn sort(&self, entries: &mut [Entry]) {
        entries.sort_by_key(|e| {
            (
                self.suite.iter().position(|s| s.name == e.scenario),
                self.learners.iter().position(|l| *l == e.learner),
                e.seed,
            )
        });
    }

    /// Refuses merged entries that are not among this benchmark's learners
    /// and scenarios (its tables could not show them).
    pub fn check_merged(&self, entries: &[Entry]) -> Result<(), String> {
        match entries.iter().find(|e| {
            !self.suite.iter().any(|s| s.name == e.scenario) || !self.learners.contains(&e.learner)
        }) {
            Some(e) => Err(format!(
                "{} on {} seed {} is not among --learners {} and --scenarios {}; merge with the \
                 flags the shards ran with",
                e.learner,
                e.scenario,
                e.seed,
                self.learners.join(","),
                self.names().join(",")
            )),
            None => Ok(()),
        }
    }

    /// The velocity and distance ranges of scenario `name`'s measured models.
    pub fn ranges(&self, name: &str) -> (f64, f64) {
        self.suite
            .iter()
            .find(|s| s.name == name)
            .map(|s| self.models(s))
            .map_or((f64::NAN, f64::NAN), |m| {
                (m.velocity_range_mm_s(), m.distance_range_mm())
            })
    }
}

/// Shard `k` of `n` of a benchmark's worlds, `(scenario index, seed)` in
/// scenario-major order: every `n`-th from the `k`-th. A world is never split,
/// so it is still simulated once for all its learners; shards are disjoint
/// and together cover every world.
pub fn shard_worlds(scenarios: usize, seeds: &[u64], k: usize, n: usize) -> Vec<(usize, u64)> {
    (0..scenarios)
        .flat_map(|s| seeds.iter().map(move |&seed| (s, seed)))
        .enumerate()
        .filter(|(i, _)| i % n == k - 1)
        .map(|(_, w)| w)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn world_shards_are_disjoint_and_cover_every_world() {
        let seeds = [3, 4, 5, 6, 7];
        for n in 1..=4 {
            let mut all: Vec<(usize, u64)> = (1..=n)
                .flat_map(|k| shard_worlds(3, &seeds, k, n))
                .collect();
            all.sort_unstable();
            assert_eq!(all, shard_worlds(3, &seeds, 1, 1), "{n} shards");
            assert_eq!(all.len(), 15);
        }
    }
}
