//! Learners side by side: every learner on every scenario of a suite and every
//! seed, each world recorded once and fed to all the learners, judged by the
//! paper's protocol. A leaderboard row per (learner, scenario, seed), and a
//! summary per (learner, scenario): mean and spread over the seeds, the ratio
//! to the best possible polynomial, and the failed trials counted.

pub mod leaderboard;
pub mod run;
pub mod suite;

pub use leaderboard::{
    Cell, Entry, LeaderboardError, below_paper, cells, merge_entries, read_leaderboard_csv,
    summary_table, write_leaderboard_csv,
};
pub use run::{Benchmark, shard_worlds};
pub use suite::{SUITE_DIR, SuiteScenario, load_suite, with_behaviours};
