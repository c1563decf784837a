//! The flags several subcommands share, defined once: what they mean, how they are
//! bounded, and how they become the project layer's [`Overrides`].

use std::path::PathBuf;

use clap::Args;
use gloc_project::{Overrides, Surface};

/// The flags `gloc run` and `gloc batch` share for the mission, the sensor list and the
/// budget (one definition, so both parse and bound them alike).
#[derive(Args, Debug)]
pub struct FlightArgs {
    /// Per-cycle instruction budget, 1 to 1,000,000,000; default: gloc.toml's, else 10,000
    /// (a script that runs longer traps with "cycle overrun").
    #[arg(long, value_name = "N", value_parser = gloc_project::settings::parse_cycle_budget)]
    pub cycle_budget: Option<u64>,
    /// Mission file (`.mi`); default: gloc.toml's, else the embedded Fig. 2 mission.
    #[arg(long, value_name = "M.mi")]
    pub mission: Option<PathBuf>,
    #[command(flatten)]
    pub sensors: SensorListArgs,
    /// A folder searched first for the mission's `.ma` files, before `mafiles/` beside
    /// `missions/` and the mission's own folder; default: gloc.toml's `mafiles`.
    #[arg(long, value_name = "DIR")]
    pub mafiles: Option<PathBuf>,
}

impl FlightArgs {
    /// The settings these flags override (the rest from gloc.toml or the defaults).
    pub fn overrides(&self) -> Overrides {
        self.sensors.overrides(Overrides {
            cycle_budget: self.cycle_budget,
            mission: self.mission.clone(),
            mafiles: self.mafiles.clone(),
            ..Overrides::new(Surface::Cli)
        })
    }
}

/// The sensor list flags `check`, `compile`, `run`, `batch` and `forecast` share: which
/// list, and how a masterdata file's sensors are numbered.
#[derive(Args, Debug)]
pub struct SensorListArgs {
    /// The sensor list (masterdata or `.cac`/`.ccc`); default: gloc.toml's, else the
    /// embedded 2008 list.
    #[arg(long, value_name = "FILE")]
    pub masterdata: Option<PathBuf>,
    /// How a masterdata file's sensors are numbered: `file` or `sorted` (firmware 2014+);
    /// default: gloc.toml's, else `file`.
    #[arg(long, value_name = "ORDER", value_parser = gloc_project::settings::parse_sensor_order)]
    pub sensor_order: Option<gloc_engine::sensors::SensorOrder>,
}

impl SensorListArgs {
    /// `overrides` with the sensor list these flags give.
    pub fn overrides(&self, overrides: Overrides) -> Overrides {
        Overrides {
            masterdata: self.masterdata.clone(),
            sensor_order: self.sensor_order,
            ..overrides
        }
    }
}
