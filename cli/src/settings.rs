//! Settings shared by every subcommand: a command-line flag wins over the
//! nearest `gloc.toml` above the script (or the current folder), which wins over
//! the built-in default. The language server and the debugger read the same file.

use std::path::{Path, PathBuf};

use gloc_engine::config::Config;
use gloc_engine::sensors::SensorOrder;

/// What the flags and `gloc.toml` together say.
#[derive(Debug, Default)]
pub struct Settings {
    pub masterdata: Option<PathBuf>,
    pub cycle_budget: Option<u64>,
    pub mission: Option<PathBuf>,
    pub sensor_order: SensorOrder,
    /// Simulator constants: `[simulator]` of gloc.toml, then the `--sim` flags (so
    /// that applied in order, a flag wins).
    pub simulator: Vec<(String, f64)>,
    /// The `gloc.toml` that was read, if any (an input no output may overwrite).
    pub config_path: Option<PathBuf>,
    /// The folder searched first for a glider log's sensor list (`--sensor-cache`, `sensor_cache`).
    pub sensor_cache: Option<PathBuf>,
}

impl Settings {
    /// The files these settings name (masterdata, mission, gloc.toml).
    pub fn input_paths(&self) -> impl Iterator<Item = &Path> {
        [&self.masterdata, &self.mission, &self.config_path]
            .into_iter()
            .flatten()
            .map(PathBuf::as_path)
    }
}

/// The flags a subcommand was given; `None` where the user gave none.
#[derive(Debug, Default)]
pub struct Flags<'a> {
    pub masterdata: Option<&'a Path>,
    pub cycle_budget: Option<u64>,
    pub mission: Option<&'a Path>,
    pub sensor_order: Option<SensorOrder>,
    pub simulator: &'a [(String, f64)],
    pub sensor_cache: Option<&'a Path>,
}

/// Finds `gloc.toml` upward from `anchor` (a script; the current folder when
/// `None`) and fills in what the flags leave open. A bad `gloc.toml` is an
/// error naming its file, line and column.
pub fn resolve(anchor: Option<&Path>, flags: Flags<'_>) -> anyhow::Result<Settings> {
    let config = match anchor {
        Some(script) => Config::discover(script)?,
        None => {
            let here = std::env::current_dir().unwrap_or_else(|_| PathBuf::from("."));
            match Config::find(&here) {
                Some(path) => Config::load(&path)?,
                None => Config::default(),
            }
        }
    };
    Ok(Settings {
        config_path: config.path.clone(),
        masterdata: flags
            .masterdata
            .map(Path::to_path_buf)
            .or(config.masterdata),
        cycle_budget: flags.cycle_budget.or(config.cycle_budget),
        mission: flags.mission.map(Path::to_path_buf).or(config.mission),
        sensor_order: flags
            .sensor_order
            .or(config.sensor_order)
            .unwrap_or_default(),
        simulator: config
            .simulator
            .into_iter()
            .chain(flags.simulator.iter().cloned())
            .collect(),
        sensor_cache: flags
            .sensor_cache
            .map(Path::to_path_buf)
            .or(config.sensor_cache),
    })
}

/// Parses `--sim NAME=VALUE` (clap's value parser), checked as gloc.toml's
/// `[simulator]` entries are.
pub fn parse_simulator_setting(text: &str) -> Result<(String, f64), String> {
    let (name, value) = text
        .split_once('=')
        .ok_or_else(|| format!("`{text}` is not NAME=VALUE, e.g. `dive_rate=0.2`"))?;
    let (name, value) = (name.trim(), value.trim());
    let number: f64 = value
        .parse()
        .map_err(|_| format!("`{value}` is not a number (in `{text}`)"))?;
    gloc_engine::config::check_simulator_setting(name, number)?;
    Ok((name.to_string(), number))
}

/// Parses `--cycle-budget` (clap's value parser), checked as gloc.toml's is.
pub fn parse_cycle_budget(text: &str) -> Result<u64, String> {
    let budget: u64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a whole number of instructions"))?;
    gloc_engine::config::check_cycle_budget(budget)
}

/// Parses `--sensor-order` (clap's value parser).
pub fn parse_sensor_order(name: &str) -> Result<SensorOrder, String> {
    SensorOrder::from_name(name).ok_or_else(|| format!("expected {}", SensorOrder::NAMES))
}
