//! The `launch` request: its attributes, read and checked for their form here, mapped
//! onto the project layer's one `Overrides` (the settings a launch may override:
//! `mission`, `masterdata`, `cycleBudget`, `sensorCache`), which `gloc_project`
//! resolves over the nearest gloc.toml and checks in the CLI's words; then the inputs'
//! kinds are checked and the world is loaded into a [`Debugger`].

use std::io;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use serde_json::Value;

use gloc_project::{Overrides, Surface};

use crate::debugger::{Debugger, HistoryConfig};
use crate::error::{DebugError, DebugResult};
use crate::world::{self, LaunchConfig, World};

/// The launch attributes the adapter accepts (`editors/vscode/package.json` declares
/// the same names; a test keeps them in step).
pub const LAUNCH_ATTRIBUTES: &[&str] = &[
    "program",
    "mission",
    "masterdata",
    "profile",
    "seed",
    "stopOnEntry",
    "cycleBudget",
    "maxCycles",
    "history",
    "token",
    "replay",
    "sensorCache",
];

/// The most snapshots the `history` launch attribute may ask for. A snapshot is the
/// whole simulation (about 14 KB with Fig. 2's mission), so 4,096 are about 60 MB;
/// `"history": 1000000000` grew by 400 MB in 450,000 cycles and without end.
const MAX_HISTORY_SNAPSHOTS: u64 = 4096;

#[derive(Debug, Default, Deserialize, Serialize, Clone)]
#[serde(default, rename_all = "camelCase")]
pub struct LaunchArguments {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub program: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mission: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub masterdata: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profile: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stop_on_entry: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cycle_budget: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_cycles: Option<u64>,
    /// `true`/`false`, or the number of snapshots to keep (0 = off).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub history: Option<Value>,
    /// The session token of `gloc dap --port` (never echoed back).
    #[serde(skip_serializing)]
    pub token: Option<String>,
    /// Recorded data to step through instead of simulating: one path or a list
    /// (a CSV file, or glider logs: a deployment, flight and science merged).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub replay: Option<Value>,
    /// The folder searched first for the glider logs' sensor lists (`<crc>.cac`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensor_cache: Option<String>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(default)]
pub struct RestartArguments {
    /// The new launch configuration; absent (or `null`) keeps the last one.
    pub arguments: Option<LaunchArguments>,
}

impl LaunchArguments {
    /// The settings this launch overrides, as the project layer takes them from every
    /// front end (an empty path means "the default", as the editors send it).
    pub fn overrides(&self) -> Overrides {
        Overrides {
            masterdata: given_path(&self.masterdata),
            cycle_budget: self.cycle_budget,
            mission: given_path(&self.mission),
            sensor_cache: given_path(&self.sensor_cache),
            ..Overrides::new(Surface::Launch)
        }
    }

    /// What the launch runs: the script, the overrides, and what is no setting.
    pub fn config(&self) -> DebugResult<LaunchConfig> {
        let program = self
            .program
            .clone()
            .filter(|program| !program.trim().is_empty())
            .ok_or_else(|| {
                DebugError::launch(
                    "the launch configuration needs `program`: the .gbas or .gloc script to debug",
                )
            })?;
        Ok(LaunchConfig {
            program: PathBuf::from(program),
            overrides: self.overrides(),
            profile: given_path(&self.profile),
            seed: self.seed,
            max_cycles: self.max_cycles,
            replay: replay_paths(self.replay.as_ref())?,
        })
    }

    /// The reverse history asked for: on by default, off with `false` or 0.
    pub fn history(&self) -> DebugResult<Option<HistoryConfig>> {
        match &self.history {
            None | Some(Value::Null) | Some(Value::Bool(true)) => Ok(Some(HistoryConfig::default())),
            Some(Value::Bool(false)) => Ok(None),
            Some(Value::Number(number)) => match number.as_u64() {
                Some(0) => Ok(None),
                Some(count) if count <= MAX_HISTORY_SNAPSHOTS => Ok(Some(HistoryConfig {
                    max_snapshots: usize::try_from(count).unwrap_or(usize::MAX).max(2),
                    ..HistoryConfig::default()
                })),
                _ => Err(DebugError::launch(format!(
                    "`history` must be true, false or a number of snapshots from 1 to {MAX_HISTORY_SNAPSHOTS}, not {number}"
                ))),
            },
            Some(_) => Err(DebugError::launch(
                "`history` must be true, false or a positive number of snapshots",
            )),
        }
    }
}

/// Loads what `arguments` name into a debugger paused at cycle 0: the attributes
/// checked for their form, the settings resolved by the project layer (a launch
/// refuses what `gloc run` refuses, in the same words), the inputs checked for their
/// kind before anything reads them. An error of loading them, which may quote what a
/// file holds, goes through `shown` (the session blanks quotes out over TCP); the
/// others name attributes and paths only.
pub fn launch(
    arguments: &LaunchArguments,
    shown: impl FnOnce(DebugError) -> DebugError,
) -> DebugResult<Debugger<World>> {
    let config = arguments.config()?;
    let history = arguments.history()?;
    let settings = world::resolve(&config)?;
    check_input(&config.program, "program", &["gbas", "gloc"])?;
    // Files that exist are checked for their kind before anything reads them; a
    // missing one is reported by the project layer, naming where its path came from.
    if let Some(mission) = settings.mission.as_ref().filter(|m| m.value.exists()) {
        check_input(&mission.value, "mission", &["mi"])?;
    }
    if let Some(profile) = &config.profile {
        check_input(profile, "profile", &["csv"])?;
    }
    if let Some(masterdata) = settings.masterdata.as_ref().filter(|m| m.value.exists()) {
        // Real sensor lists are called `masterdata` or `*.cac`: no extension rule.
        check_input(&masterdata.value, "masterdata", &[])?;
    }
    let (world, info) = world::launch_with(&config, &settings).map_err(shown)?;
    Ok(Debugger::new(world, info, history))
}

/// A path attribute as given, `None` when absent or blank.
fn given_path(value: &Option<String>) -> Option<PathBuf> {
    value
        .as_deref()
        .filter(|text| !text.trim().is_empty())
        .map(PathBuf::from)
}

/// `replay`: a path, a list of paths, or empty (`""`, `[]`, `null`: simulate).
fn replay_paths(value: Option<&Value>) -> DebugResult<Vec<PathBuf>> {
    const FORM: &str = "`replay` must be a path or a list of paths (a CSV file or glider logs)";
    let paths: Vec<&str> = match value {
        None | Some(Value::Null) => Vec::new(),
        Some(Value::String(path)) => vec![path.as_str()],
        Some(Value::Array(items)) => items
            .iter()
            .map(|item| item.as_str().ok_or_else(|| DebugError::launch(FORM)))
            .collect::<Result<_, _>>()?,
        Some(_) => return Err(DebugError::launch(FORM)),
    };
    Ok(paths
        .into_iter()
        .filter(|path| !path.trim().is_empty())
        .map(PathBuf::from)
        .collect())
}

/// A launch input must be a regular file (no FIFO, device or folder) with one of the
/// extensions its kind uses, so that no attribute makes the adapter read an arbitrary
/// file as a script or a mission. The message names the path only.
fn check_input(path: &Path, kind: &str, extensions: &[&str]) -> DebugResult<()> {
    let shown = path.display();
    let metadata = std::fs::metadata(path).map_err(|error| {
        DebugError::launch(format!(
            "cannot read the {kind} {shown}: {}",
            io_reason(&error)
        ))
    })?;
    if !metadata.is_file() {
        return Err(DebugError::launch(format!(
            "the {kind} {shown} is not a regular file (a folder, FIFO or device)"
        )));
    }
    let extension = path
        .extension()
        .and_then(|extension| extension.to_str())
        .unwrap_or("");
    if !extensions.is_empty()
        && !extensions
            .iter()
            .any(|known| extension.eq_ignore_ascii_case(known))
    {
        let known: Vec<String> = extensions.iter().map(|known| format!(".{known}")).collect();
        return Err(DebugError::launch(format!(
            "the {kind} {shown} is not a {} file; `{kind}` takes {}",
            known.join(" or "),
            known.join(" or ")
        )));
    }
    Ok(())
}

/// An IO error without the OS's error number.
fn io_reason(error: &io::Error) -> String {
    match error.kind() {
        io::ErrorKind::NotFound => "no such file".into(),
        io::ErrorKind::PermissionDenied => "permission denied".into(),
        _ => error.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn arguments(value: Value) -> LaunchArguments {
        serde_json::from_value(value).expect("launch arguments")
    }

    #[test]
    fn settings_attributes_become_the_project_layers_overrides() {
        let given = arguments(json!({
            "program": "a.gbas",
            "mission": "m.mi",
            "masterdata": "",
            "cycleBudget": 77,
            "sensorCache": "cache",
            "seed": 3,
        }));
        let overrides = given.overrides();
        assert_eq!(overrides.surface, Surface::Launch);
        assert_eq!(overrides.mission, Some(PathBuf::from("m.mi")));
        // Blank is the default, as editors send it.
        assert_eq!(overrides.masterdata, None);
        assert_eq!(overrides.cycle_budget, Some(77));
        assert_eq!(overrides.sensor_cache, Some(PathBuf::from("cache")));
        let config = given.config().expect("a program");
        assert_eq!(config.program, PathBuf::from("a.gbas"));
        assert_eq!(config.seed, Some(3));
        assert_eq!(config.overrides.mission, overrides.mission);
        assert_eq!(config.overrides.cycle_budget, Some(77));
    }

    #[test]
    fn the_form_of_each_attribute_is_checked_with_what_to_write() {
        let missing = arguments(json!({ "program": "  " })).config();
        assert!(
            matches!(missing, Err(DebugError::Launch(message)) if message.contains("needs `program`"))
        );
        let replay = arguments(json!({ "program": "a.gbas", "replay": [1] })).config();
        assert!(
            matches!(replay, Err(DebugError::Launch(message)) if message.starts_with("`replay` must be"))
        );
        let history = arguments(json!({ "history": 5000 })).history();
        assert!(
            matches!(history, Err(DebugError::Launch(message)) if message.contains("from 1 to 4096"))
        );
        assert_eq!(arguments(json!({ "history": 0 })).history(), Ok(None));
        let kept = arguments(json!({ "history": 1 })).history();
        assert_eq!(
            kept.map(|history| history.map(|h| h.max_snapshots)),
            Ok(Some(2))
        );
    }
}
