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
}

/// The flags a subcommand was given; `None` where the user gave none.
#[derive(Debug, Default)]
pub struct Flags<'a> {
    pub masterdata: Option<&'a Path>,
    pub cycle_budget: Option<u64>,
    pub mission: Option<&'a Path>,
    pub sensor_order: Option<SensorOrder>,
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
    })
}

/// Parses `--sensor-order` (clap's value parser).
pub fn parse_sensor_order(name: &str) -> Result<SensorOrder, String> {
    SensorOrder::from_name(name).ok_or_else(|| format!("expected {}", SensorOrder::NAMES))
}
