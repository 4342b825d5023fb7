//! What made a run: the package's version, the git commit (and whether the tree
//! had uncommitted changes) and the command line, recorded in every run
//! directory beside its settings.

use serde::{Deserialize, Serialize};

/// Where a run came from.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Provenance {
    /// The testbed's version.
    pub version: String,
    /// `git rev-parse HEAD` in the working directory, if it is a git checkout.
    pub git_commit: Option<String>,
    /// Whether that checkout had uncommitted changes to tracked files.
    pub git_dirty: Option<bool>,
    /// The command line, as given.
    pub command: String,
}

impl Provenance {
    /// The running program's provenance.
    pub fn current() -> Self {
        let git = |args: &[&str]| {
            std::process::Command::new("git")
                .args(args)
                .output()
                .ok()
                .filter(|o| o.status.success())
                .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        };
        let git_commit = git(&["rev-parse", "HEAD"]);
        let git_dirty = git_commit
            .as_ref()
            .and(git(&["status", "--porcelain", "--untracked-files=no"]))
            .map(|s| !s.is_empty());
        Self {
            version: env!("CARGO_PKG_VERSION").into(),
            git_commit,
            git_dirty,
            command: std::env::args().collect::<Vec<_>>().join(" "),
        }
    }

    /// One line for a file's header.
    pub fn describe(&self) -> String {
        format!(
            "testbed {}, commit {}{}",
            self.version,
            self.git_commit.as_deref().unwrap_or("unknown"),
            if self.git_dirty == Some(true) {
                " (with uncommitted changes)"
            } else {
                ""
            }
        )
    }
}
