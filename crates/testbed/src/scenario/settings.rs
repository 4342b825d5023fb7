//! Settings applied to a scenario: one `key=value`, a scenario file's
//! tables, the command line's in order, a learner's own settings, scheduled
//! changes of the world, and the scenario written back as `config.toml`.

use std::path::Path;

use quadsim::SimConfig;
use scasm::declaration::Values;

use crate::scenario::data::{Change, Scenario, SettingError};
use crate::scenario::table::{Kind, SETTINGS, number, setting_keys, unknown};

impl Scenario {
    /// Applies `key=value`, or changes nothing and says which key is wrong.
    pub fn set(&mut self, assignment: &str) -> Result<(), SettingError> {
        let mut changed = self.clone();
        changed.apply(assignment)?;
        *self = changed;
        Ok(())
    }

    /// [`Scenario::paper`] with the robot of `urdf` (default: the shipped one),
    /// then a scenario file's settings (if any), then `key=value` settings in
    /// order: what a command line asks for. The robot is chosen first wherever
    /// it is set (`robot.*` settings reset the world to the robot's scale, see
    /// [`quadsim::RobotScale`]), so other settings always apply on top of it.
    pub fn from_settings(
        urdf: Option<&Path>,
        file: Option<&Path>,
        settings: &[String],
    ) -> Result<Self, SettingError> {
        let mut scenario = Self::paper().map_err(|e| SettingError::File {
            file: "assets/ers7.urdf".into(),
            reason: e.to_string(),
        })?;
        if let Some(path) = urdf {
            scenario.set(&format!("robot.urdf={}", path.display()))?;
        }
        if let Some(path) = file {
            let text =
                quadsim::files::read_text(path, quadsim::files::SETTINGS_LIMIT).map_err(|e| {
                    SettingError::File {
                        file: path.display().to_string(),
                        reason: e.to_string(),
                    }
                })?;
            scenario.apply_toml(&path.display().to_string(), &text)?;
        }
        // The robot first, then the trial (a blanked interval is checked
        // against the trial's length), then the rest, each in the order given.
        let mut ordered: Vec<&String> = settings.iter().collect();
        ordered.sort_by_key(|s| {
            let key = s.split('=').next().unwrap_or("").trim();
            // The learner is named before its own settings are set.
            (
                section_rank(key.split('.').next().unwrap_or("")),
                key != "learner.name",
            )
        });
        for s in ordered {
            scenario.set(s)?;
        }
        Ok(scenario)
    }

    /// Applies a scenario file's settings (TOML: `[section]` tables of
    /// `key = value`, the same keys as [`Scenario::set`]), all or nothing.
    pub fn apply_toml(&mut self, file: &str, text: &str) -> Result<(), SettingError> {
        let file_error = |reason: String| SettingError::File {
            file: file.into(),
            reason,
        };
        let table: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| file_error(e.to_string()))?;
        let mut changed = self.clone();
        // The robot first (it resets the world to its scale), then the trial
        // (a blanked interval is checked against its length), then the rest.
        let mut ordered: Vec<(&String, &toml::Value)> = table.iter().collect();
        ordered.sort_by_key(|(section, _)| section_rank(section));
        for (section, entries) in ordered {
            if section == "change" {
                changed.add_changes(file, entries)?;
                continue;
            }
            let toml::Value::Table(entries) = entries else {
                return Err(file_error(format!(
                    "`{section}` must be a [section] of settings"
                )));
            };
            // A learner's own settings are a table within (`[learner.batch-ml]`);
            // the learner is named first, so that a program's settings are known.
            let mut flat: Vec<(String, &toml::Value)> = Vec::new();
            for (key, value) in entries {
                match value {
                    toml::Value::Table(inner) => {
                        flat.extend(
                            inner
                                .iter()
                                .map(|(k, v)| (format!("{section}.{key}.{k}"), v)),
                        );
                    }
                    v => flat.push((format!("{section}.{key}"), v)),
                }
            }
            flat.sort_by_key(|(full, _)| full != "learner.name");
            for (full, value) in flat {
                // Every learner setting but its name is a number.
                let kind = SETTINGS
                    .iter()
                    .find(|e| e.key == full)
                    .map(|e| e.kind)
                    .or_else(|| full.starts_with("learner.").then_some(Kind::Number));
                let value = match (value, kind) {
                    (toml::Value::String(text), Some(Kind::Text) | None) => text.clone(),
                    (toml::Value::Integer(i), Some(Kind::Number | Kind::Count) | None) => {
                        i.to_string()
                    }
                    (toml::Value::Float(f), Some(Kind::Number | Kind::Count) | None) => {
                        f.to_string()
                    }
                    (other, Some(Kind::Text)) => {
                        return Err(file_error(format!(
                            "`{full}` must be a string, is {}",
                            other.type_str()
                        )));
                    }
                    (other, _) => {
                        return Err(file_error(format!(
                            "`{full}` must be a number, is {}",
                            other.type_str()
                        )));
                    }
                };
                changed.apply(&format!("{full}={value}"))?;
            }
        }
        *self = changed;
        Ok(())
    }

    /// Adds a scenario file's `[[change]]` entries (an array of tables with
    /// `at_s`, `key` and `value`) after the changes already scheduled.
    fn add_changes(&mut self, file: &str, entries: &toml::Value) -> Result<(), SettingError> {
        let bad = |reason: String| SettingError::File {
            file: file.into(),
            reason,
        };
        let toml::Value::Array(list) = entries else {
            return Err(bad(
                "`change` must be an array of tables: [[change]] with at_s, key and value".into(),
            ));
        };
        for entry in list {
            let mut entry = entry.clone();
            // The value as `--set` writes it, whatever its TOML type.
            if let Some(t) = entry.as_table_mut() {
                if let Some(v) = t.get("value").cloned() {
                    let text = match v {
                        toml::Value::String(s) => s,
                        other => other.to_string(),
                    };
                    t.insert("value".into(), toml::Value::String(text));
                }
                if let Some(toml::Value::Integer(i)) = t.get("at_s").cloned() {
                    t.insert("at_s".into(), toml::Value::Float(i as f64));
                }
            }
            let change: Change = entry
                .try_into()
                .map_err(|e: toml::de::Error| bad(format!("[[change]]: {}", e.message())))?;
            self.changes.push(change);
        }
        self.worlds().map(|_| ())
    }

    /// The world as it starts and after each scheduled change: `(from s,
    /// settings)`, the first from 0. Says which change cannot be made: a time
    /// outside the trial or out of order, an unknown key or a bad value, or a
    /// setting that cannot change during a run.
    pub fn worlds(&self) -> Result<Vec<(f64, SimConfig)>, SettingError> {
        let mut world = self.clone();
        world.changes.clear();
        let mut out = vec![(0.0, world.sim)];
        for c in &self.changes {
            let fail = |reason: String| SettingError::Change {
                key: c.key.clone(),
                at_s: c.at_s,
                reason,
            };
            if !(c.at_s > 0.0 && c.at_s < self.duration_s) {
                return Err(fail(format!(
                    "outside the trial: must be in (0, {}) s",
                    self.duration_s
                )));
            }
            if c.at_s < out.last().map_or(0.0, |w| w.0) {
                return Err(fail("changes must be in time order".into()));
            }
            let (before, settings) = (world.sim, world.to_toml());
            world
                .set(&format!("{}={}", c.key, c.value))
                .map_err(|e| fail(e.to_string()))?;
            let mut rest = world.clone();
            rest.sim = before;
            if rest.to_toml() != settings {
                return Err(fail(
                    "not part of the world: it cannot change during a run".into(),
                ));
            }
            before
                .check_live_change(&world.sim)
                .map_err(|e| fail(e.to_string()))?;
            out.push((c.at_s, world.sim));
        }
        Ok(out)
    }

    /// The scenario of the world after change `i` (0: as it starts), with no
    /// changes: what the reference of that world is measured on.
    pub fn world(&self, i: usize) -> Result<Scenario, SettingError> {
        let worlds = self.worlds()?;
        let mut s = self.clone();
        s.changes.clear();
        s.sim = worlds.get(i).map_or(s.sim, |w| w.1);
        Ok(s)
    }

    /// The changes, as `at:key=value;...` (for keys and logs).
    pub fn changes_text(&self) -> String {
        self.changes
            .iter()
            .map(|c| format!("{}:{}={}", c.at_s, c.key, c.value))
            .collect::<Vec<_>>()
            .join(";")
    }

    fn apply(&mut self, assignment: &str) -> Result<(), SettingError> {
        let (key, value) = assignment
            .split_once('=')
            .ok_or_else(|| SettingError::Malformed(assignment.into()))?;
        let (key, value) = (key.trim(), value.trim());
        let bad = |reason: String| SettingError::BadValue {
            key: key.into(),
            reason,
        };
        if let Some(entry) = SETTINGS.iter().find(|e| e.key == key) {
            (entry.set)(self, value).map_err(bad)?;
        } else if let Some(name) = key.strip_prefix("learner.") {
            match name.split_once('.') {
                None => {
                    let shared = scasm::declaration::shared(name).ok_or_else(|| unknown(key))?;
                    let v = shared
                        .setting(&self.learner)
                        .check(number(value).map_err(bad)?)
                        .map_err(bad)?;
                    (shared.set)(&mut self.learner, v);
                }
                Some((learner, own)) => {
                    let v = number(value).map_err(bad)?;
                    self.set_own(learner, own, v).map_err(bad)?;
                }
            }
        } else {
            return Err(unknown(key));
        }
        // Catch range errors at the door, naming the key.
        self.learner.validate().map_err(|e| bad(e.to_string()))?;
        self.sim.validate().map_err(|e| bad(e.to_string()))?;
        // A setting may also make a scheduled change impossible (a trial
        // shorter than it, say).
        self.worlds()?;
        Ok(())
    }

    /// Sets `learner.<learner>.<key>`: a setting that learner declares, in
    /// its range.
    fn set_own(&mut self, learner: &str, key: &str, value: f64) -> Result<(), String> {
        let found = crate::learners::registry::named(learner).ok_or_else(|| {
            format!(
                "no learner is called `{learner}`; known: {} (a program's settings follow \
                 learner.name=exec:... or --learner exec:...)",
                crate::learners::registry::names()
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })?;
        let settings = found.settings();
        let setting = settings.iter().find(|s| s.key == key).ok_or_else(|| {
            let keys: Vec<&str> = settings.iter().map(|s| s.key.as_str()).collect();
            format!(
                "learner `{learner}` has no setting `{key}`; its settings: {}",
                if keys.is_empty() {
                    "none of its own (it reads the shared learner.* ones)".into()
                } else {
                    keys.join(", ")
                }
            )
        })?;
        let v = setting.check(value)?;
        self.learner_own
            .insert(format!("learner.{learner}.{key}"), v);
        Ok(())
    }

    /// The values of `learner`'s own settings in this scenario: each as set,
    /// or its default.
    pub fn own_settings(&self, learner: &crate::learners::registry::Learner) -> Values {
        Values(
            learner
                .settings()
                .into_iter()
                .map(|s| {
                    let full = format!("learner.{}.{}", learner.name(), s.key);
                    let v = self.learner_own.get(&full).copied().unwrap_or(s.default);
                    (s.key, v)
                })
                .collect(),
        )
    }

    /// The value of a setting, as a scenario file writes it.
    pub fn get(&self, key: &str) -> Option<toml::Value> {
        if let Some(entry) = SETTINGS.iter().find(|e| e.key == key) {
            return Some((entry.get)(self));
        }
        let name = key.strip_prefix("learner.")?;
        match name.split_once('.') {
            None => {
                let s = scasm::declaration::shared(name)?;
                let v = (s.get)(&self.learner);
                Some(match s.kind {
                    scasm::declaration::Kind::Count => toml::Value::Integer(v as i64),
                    scasm::declaration::Kind::Number => toml::Value::Float(v),
                })
            }
            Some((learner, own)) => {
                let learner = crate::learners::registry::named(learner)?;
                let s = learner.settings().into_iter().find(|s| s.key == own)?;
                let v = self.learner_own.get(key).copied().unwrap_or(s.default);
                Some(match s.kind {
                    scasm::declaration::Kind::Count => toml::Value::Integer(v as i64),
                    scasm::declaration::Kind::Number => toml::Value::Float(v),
                })
            }
        }
    }

    /// The keys a run records: every setting, the scenario's learner's own
    /// settings, and any other learner's set.
    pub fn recorded_keys(&self) -> Vec<String> {
        let mut keys: Vec<String> = setting_keys().collect();
        if let Ok(learner) = crate::learners::registry::resolve(&self.learner_name) {
            for s in learner.settings() {
                keys.push(format!("learner.{}.{}", learner.name(), s.key));
            }
        }
        for k in self.learner_own.keys() {
            if !keys.contains(k) {
                keys.push(k.clone());
            }
        }
        keys
    }

    /// Every setting as a scenario file (TOML): what a run records as its
    /// `config.toml`, and what `--config` reads back to the same scenario. The
    /// default robot's `robot.file` is left out.
    pub fn to_toml(&self) -> String {
        let mut table = toml::Table::new();
        for key in self.recorded_keys() {
            let Some(value) = self.get(&key) else {
                continue;
            };
            // robot.urdf is recorded as robot.file.
            if key == "robot.urdf" || (key == "robot.file" && self.robot_file.is_none()) {
                continue;
            }
            // `learner.batch-ml.gamma` is `[learner.batch-ml] gamma = ...`.
            let path: Vec<&str> = key.split('.').collect();
            insert_at(&mut table, &path, value);
        }
        if !self.changes.is_empty() {
            let list = self
                .changes
                .iter()
                .map(|c| {
                    let mut t = toml::Table::new();
                    t.insert("at_s".into(), toml::Value::Float(c.at_s));
                    t.insert("key".into(), toml::Value::String(c.key.clone()));
                    let value = c
                        .value
                        .parse::<f64>()
                        .map_or_else(|_| toml::Value::String(c.value.clone()), toml::Value::Float);
                    t.insert("value".into(), value);
                    toml::Value::Table(t)
                })
                .collect();
            table.insert("change".into(), toml::Value::Array(list));
        }
        toml::to_string(&table).unwrap_or_default()
    }
}

/// The order settings are applied in, by section: the robot first (it resets
/// the world to its scale), then the trial (a blanked interval is checked
/// against its length), then the rest, and a file's `[[change]]`s last (each
/// changes the world as the rest made it); a stable sort keeps the given
/// order within each.
fn section_rank(section: &str) -> u8 {
    match section {
        "robot" => 0,
        "trial" => 1,
        "change" => 3,
        _ => 2,
    }
}

/// Puts `value` at `path` (`["learner", "batch-ml", "gamma"]`) in nested tables.
fn insert_at(table: &mut toml::Table, path: &[&str], value: toml::Value) {
    match path {
        [] => {}
        [last] => {
            table.insert((*last).into(), value);
        }
        [first, rest @ ..] => {
            let entry = table
                .entry(*first)
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            if let toml::Value::Table(inner) = entry {
                insert_at(inner, rest, value);
            }
        }
    }
}
