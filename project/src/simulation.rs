//! The simulation of a project: its mission (the settings' `.mi`, or the embedded
//! Fig. 2 mission), a temperature profile, and the simulator configured from the
//! settings (seed, cycle budget, `[simulator]` constants). The CLI's `run` and `batch`
//! and the debugger build their simulations here, through [`prepare`], and `forecast`
//! through [`prepare_unscripted`] (no script): the one place a flight is assembled and the
//! mission checked against the list and the script.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gloc_compiler::LoadedScript;
use gloc_engine::diagnostic::Diagnostic;
use gloc_engine::program::Program;
use gloc_engine::sensors::SensorList;
use gloc_mission::mission::MissionDiagnostic;
use gloc_sim::{default_mission, Mission, SimConfig, Simulation, TemperatureProfile};

use crate::error::{ErrorKind, ProjectError};
use crate::settings::{Origin, Settings, Sourced};

/// The settings' mission, read with its `.ma` files. A mission file that cannot be
/// read is an error naming where its path came from (`gloc.toml:2:11: cannot read the
/// mission `nosuch.mi`: …`); a mission with errors is returned with its diagnostics
/// (`Mission::has_errors`). The sensor list's masterdata gives the behavior table.
pub fn load_mission(settings: &Settings, sensors: &SensorList) -> Result<Mission, ProjectError> {
    let Some(Sourced {
        value: path,
        origin,
    }) = &settings.mission
    else {
        return Ok(default_mission());
    };
    let text = read_text(path, gloc_engine::files::MISSION, "the mission", origin)?;
    Ok(Mission::load_text(
        path,
        text,
        &mission_options(settings, sensors),
        &mut gloc_mission::Disk,
    ))
}

/// Reads `what` (`the mission`) at `path`, at most `limit`; one that cannot be read is
/// an error naming where its path came from.
fn read_text(
    path: &Path,
    limit: gloc_engine::files::Limit,
    what: &str,
    origin: &Origin,
) -> Result<String, ProjectError> {
    gloc_engine::files::read_text(path, limit).map_err(|error| {
        ProjectError::new(
            ErrorKind::Unreadable,
            Some(origin.clone()),
            format!("cannot read {what} `{}`: {error}", path.display()),
        )
    })
}

/// How the settings' missions are read, for every front end: their `.ma` files found
/// through `--mafiles` / gloc.toml's `mafiles` first, their behaviors from the active
/// sensor list's masterdata (else the embedded release table).
pub fn mission_options(settings: &Settings, sensors: &SensorList) -> gloc_mission::LoadOptions {
    gloc_mission::LoadOptions {
        mafiles: settings.mafiles.clone(),
        table: Some(gloc_mission::behaviors::BehaviorTable::for_sensors(sensors)),
    }
}

/// Reads a temperature profile CSV (`depth_m,temp_degC`); `origin` names the flag or
/// attribute that gave it.
pub fn load_profile(path: &Path, origin: Origin) -> Result<TemperatureProfile, ProjectError> {
    let text = read_text(path, gloc_engine::files::PROFILE, "the profile", &origin)?;
    TemperatureProfile::from_csv(path, &text)
        .map_err(|error| ProjectError::new(ErrorKind::Invalid, None, error.to_string()))
}

/// What a flight adds to the settings: the seed, the profile, and constants swept on
/// top of the settings' (a `gloc batch` variant).
#[derive(Clone, Debug, Default)]
pub struct Flight {
    pub seed: Option<u64>,
    pub profile: Option<TemperatureProfile>,
    pub simulator: Vec<(String, f64)>,
}

impl Flight {
    /// A flight with `seed` and the profile read from `profile`, a path given by
    /// `origin` (a flag, a launch attribute): how `gloc run`, the debugger and
    /// `gloc.run` set a single flight up.
    pub fn read(
        seed: Option<u64>,
        profile: Option<&Path>,
        origin: Origin,
    ) -> Result<Flight, ProjectError> {
        Ok(Flight {
            seed,
            profile: profile.map(|path| load_profile(path, origin)).transpose()?,
            simulator: Vec::new(),
        })
    }
}

/// The simulator's configuration: the defaults, then the settings' budget and
/// constants, then the flight's. Front ends set a flight up through [`prepare`] or
/// [`prepare_unscripted`], which call this and return the configuration with the
/// simulation.
fn sim_config(settings: &Settings, flight: Flight) -> Result<SimConfig, ProjectError> {
    let defaults = SimConfig::default();
    let mut config = SimConfig {
        seed: flight.seed.unwrap_or(defaults.seed),
        profile: flight.profile,
        cycle_budget: settings.cycle_budget.value.get(),
        ..defaults
    };
    for (name, value) in settings.simulator.iter().chain(&flight.simulator) {
        // The names were checked against the same table when they were read.
        if !config.set(name, *value) {
            return Err(ProjectError::new(
                ErrorKind::Setting,
                None,
                format!("`{name}` is not a simulator setting"),
            ));
        }
    }
    Ok(config)
}

/// The simulation of `program` on `mission`.
fn build_simulation(
    mission: &Mission,
    sensors: Arc<SensorList>,
    program: Option<Arc<Program>>,
    config: &SimConfig,
) -> Result<Simulation, ProjectError> {
    Simulation::new(mission, sensors, program, config)
        .map_err(|error| ProjectError::new(ErrorKind::Invalid, None, error.to_string()))
}

/// What every flight of one script on one mission shares.
#[derive(Clone, Copy)]
pub struct Plan<'a> {
    pub settings: &'a Settings,
    pub sensors: &'a Arc<SensorList>,
    pub mission: &'a Mission,
    pub script: &'a LoadedScript,
    /// The script's program (`script.program`, which a plan requires).
    pub program: &'a Arc<Program>,
}

/// A warning found while a flight was prepared, for the front end to show where it
/// belongs.
#[derive(Clone, Debug)]
pub enum Warning {
    /// The simulator's own, one line each (a mission setting it cannot honour, …).
    Simulator(String),
    /// On the mission's files (S0106, the S012x checks), against `mission.sources`.
    Mission(MissionDiagnostic),
    /// On the script: S0107, stores to `sci_ruhp_behs` in a mission without a hook.
    Script(Diagnostic),
}

/// A simulation ready to fly and what preparing it found.
pub struct Prepared {
    pub simulation: Simulation,
    pub warnings: Vec<Warning>,
    /// The configuration it was built with: a caller that flies more like it
    /// (a forecast's members, each from the glider's logged state) builds them
    /// from this.
    pub config: SimConfig,
}

/// A mission flown without a script (`gloc forecast` and the Python package's
/// forecast fly the glider's own mission from its logs), as [`prepare_unscripted`]
/// found it. Each front end reports a mission with errors its own way.
pub enum Unscripted {
    /// The mission has errors (its diagnostics say which); nothing was prepared.
    MissionErrors(Mission),
    /// The mission, and its flight prepared from the settings alone (boxed: a
    /// simulation is large).
    Ready {
        mission: Mission,
        prepared: Box<Prepared>,
    },
}

/// The set-up of a mission flown without a script: the settings' mission loaded
/// (as [`load_mission`]) and, when it has no errors, the simulator configured from
/// the settings, the simulation built and the mission checked against the sensor
/// list, as [`prepare`] does for `gloc run`. Each track of a forecast is then flown
/// from this configuration and the logs' state.
pub fn prepare_unscripted(
    settings: &Settings,
    sensors: &Arc<SensorList>,
) -> Result<Unscripted, ProjectError> {
    let mission = load_mission(settings, sensors)?;
    if mission.has_errors() {
        return Ok(Unscripted::MissionErrors(mission));
    }
    let prepared = prepare_flight(settings, sensors, &mission, None, Flight::default())?;
    Ok(Unscripted::Ready {
        mission,
        prepared: Box::new(prepared),
    })
}

/// Prepares one flight of `plan`: the simulator configured from the settings and the
/// flight, the simulation built, and the mission checked against the sensor list and
/// the script (S0106, S0107, S0120–S0127). `gloc run`, `gloc batch` and the debugger
/// all start here, so they warn alike.
pub fn prepare(plan: &Plan<'_>, flight: Flight) -> Result<Prepared, ProjectError> {
    prepare_flight(
        plan.settings,
        plan.sensors,
        plan.mission,
        Some((plan.script, plan.program)),
        flight,
    )
}

/// [`prepare`] and [`prepare_unscripted`]: one flight, with or without a script.
fn prepare_flight(
    settings: &Settings,
    sensors: &Arc<SensorList>,
    mission: &Mission,
    script: Option<(&LoadedScript, &Arc<Program>)>,
    flight: Flight,
) -> Result<Prepared, ProjectError> {
    let config = sim_config(settings, flight)?;
    let simulation = build_simulation(
        mission,
        sensors.clone(),
        script.map(|(_, program)| program.clone()),
        &config,
    )?;
    let mut warnings: Vec<Warning> = simulation
        .warnings()
        .iter()
        .cloned()
        .map(Warning::Simulator)
        .collect();
    warnings.extend(mission.check(sensors).into_iter().map(Warning::Mission));
    if let Some((script, program)) = script {
        let unhooked: Vec<_> = mission
            .unhooked_stores(sensors, program)
            .into_iter()
            .filter_map(|pc| script.span_of_pc(pc))
            .collect();
        if let Some(warning) = mission.unhooked_store_warning(&unhooked) {
            warnings.push(Warning::Script(warning));
        }
    }
    Ok(Prepared {
        simulation,
        warnings,
        config,
    })
}

/// The control cycles that fly `seconds` of mission time: `u_cycle_time` plus the
/// mean overrun, for `gloc run`, `gloc batch` and the Python package alike.
pub fn cycles_for(seconds: f64, simulation: &Simulation) -> u64 {
    (seconds / simulation.mean_cycle_period()).ceil() as u64
}

/// The mission's path as the settings give it (for messages), `None` when embedded.
pub fn mission_path(settings: &Settings) -> Option<&PathBuf> {
    settings.mission.as_ref().map(|sourced| &sourced.value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_mission_from_gloc_toml_names_gloc_toml_and_says_it_cannot_be_read() {
        let settings = crate::settings::test_settings("mission = \"nosuch.mi\"\n");
        let error = load_mission(&settings, &SensorList::embedded()).expect_err("missing");
        // `mission = ` is 10 characters: the value starts in column 11.
        crate::error::assert_unreadable(
            &error,
            "/p/gloc.toml:1:11: cannot read the mission `/p/nosuch.mi`: ",
        );
    }

    #[test]
    fn the_budget_and_constants_of_the_settings_reach_the_simulator() {
        let settings =
            crate::settings::test_settings("cycle_budget = 77\n[simulator]\ndrag_cd0 = 0.3\n");
        let sim = sim_config(
            &settings,
            Flight {
                seed: Some(9),
                ..Flight::default()
            },
        )
        .expect("valid");
        assert_eq!(sim.cycle_budget, 77);
        assert_eq!(sim.seed, 9);
        assert_eq!(sim.flight.drag_cd0, 0.3);
        assert_eq!(
            load_mission(&settings, &SensorList::embedded()).map(|m| m.has_errors()),
            Ok(false)
        );
    }
}
