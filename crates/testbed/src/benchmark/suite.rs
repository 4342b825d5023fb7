//! A benchmark's suite: the named scenario files of a directory, each on top
//! of the paper's scenario.

use std::path::{Path, PathBuf};

use crate::scenario::{Scenario, SettingError};

/// The shipped suite's directory, relative to the repository's root.
pub const SUITE_DIR: &str = "assets/scenarios/suite";

/// A named scenario of a suite.
#[derive(Debug, Clone)]
pub struct SuiteScenario {
    /// Its name (the file's stem).
    pub name: String,
    /// The file it came from.
    pub file: PathBuf,
    /// The scenario.
    pub scenario: Scenario,
}

/// The scenario files in `dir` (`*.toml`, by name), each on top of the paper's
/// scenario, then `settings` on top of each; only those named in `only` if it is
/// not empty (an unknown name is an error that lists the known ones).
pub fn load_suite(
    dir: &Path,
    only: &[String],
    settings: &[String],
) -> Result<Vec<SuiteScenario>, SettingError> {
    let file_error = |reason: String| SettingError::File {
        file: dir.display().to_string(),
        reason,
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| file_error(e.to_string()))?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    let name_of = |p: &Path| {
        p.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let known: Vec<String> = files.iter().map(|p| name_of(p)).collect();
    if let Some(unknown) = only.iter().find(|n| !known.contains(n)) {
        return Err(file_error(format!(
            "no scenario `{unknown}`; the suite has {}",
            known.join(", ")
        )));
    }
    files
        .into_iter()
        .filter(|p| only.is_empty() || only.contains(&name_of(p)))
        .map(|file| {
            let scenario = Scenario::from_settings(None, Some(&file), settings)?;
            Ok(SuiteScenario {
                name: name_of(&file),
                file,
                scenario,
            })
        })
        .collect()
}

/// `suite` with a behaviour axis: each scenario once per behaviour of
/// `behaviours` (`behaviour.name` set on top of it), named
/// `SCENARIO+BEHAVIOUR`; `suite` itself if `behaviours` is empty. An unknown
/// behaviour is an error that lists the known ones.
pub fn with_behaviours(
    suite: Vec<SuiteScenario>,
    behaviours: &[String],
) -> Result<Vec<SuiteScenario>, SettingError> {
    if behaviours.is_empty() {
        return Ok(suite);
    }
    let mut out = Vec::new();
    for s in &suite {
        for b in behaviours {
            let mut scenario = s.scenario.clone();
            scenario.set(&format!("behaviour.name={b}"))?;
            out.push(SuiteScenario {
                name: format!("{}+{}", s.name, scenario.behaviour_name),
                file: s.file.clone(),
                scenario,
            });
        }
    }
    Ok(out)
}
