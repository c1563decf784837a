//! What several subcommands load the same way: the active sensor list (or one a flag
//! names), and the script to fly or replay (the paper's Fig. 2 script when none is
//! given), each with its diagnostics printed. The subcommands depend on this module,
//! never on each other.

use std::path::Path;

use gloc_engine::sensors::{SensorList, SensorOrder};
use gloc_project::script::Script;
use gloc_project::sensors::{load_sensor_list, load_sensor_list_file, LoadedSensors};
use gloc_project::settings::{Origin, Settings, Sourced};

use crate::render::{SourceFile, Tally};

/// The paper's Fig. 2, the script `gloc run` uses when none is given.
pub const FIG2: &str = include_str!("../../examples/fig2.gloc");

/// Loads the script (`.gloc`, or `.gbas` compiled in memory; the Fig. 2 script when
/// `path` is `None`), printing its diagnostics to stderr.
pub fn load_script(
    path: Option<&Path>,
    sensors: &SensorList,
    settings: &Settings,
    optimization: gloc_compiler::Optimization,
) -> anyhow::Result<Script> {
    let script = match path {
        Some(path) => gloc_project::script::load_script(path, sensors, settings, optimization)?,
        None => gloc_project::script::load_text(
            None,
            "fig2.gloc".to_string(),
            FIG2.to_string(),
            gloc_compiler::Language::Gloc,
            sensors,
            settings,
            optimization,
        ),
    };
    crate::render::render_all(&script, |text| eprint!("{text}"));
    Ok(script)
}

/// The active sensor list of resolved settings (`gloc_project::sensors`), its
/// diagnostics printed; `None` when it has errors. One place for every subcommand.
pub fn active_sensors(
    settings: &Settings,
    tally: &mut Tally,
) -> anyhow::Result<Option<SensorList>> {
    let loaded = load_sensor_list(settings)?;
    Ok(print_list(loaded, tally))
}

/// Loads a sensor list a flag names outside the settings (`reindex --to/--from`):
/// prints its diagnostics; `None` when it has errors.
pub fn load_sensors(
    path: &Path,
    flag: &'static str,
    order: SensorOrder,
    tally: &mut Tally,
) -> anyhow::Result<Option<SensorList>> {
    let loaded = load_sensor_list_file(
        &Sourced {
            value: path.to_path_buf(),
            origin: Origin::Flag(flag),
        },
        order,
    )?;
    Ok(print_list(loaded, tally))
}

pub fn print_list(loaded: LoadedSensors, tally: &mut Tally) -> Option<SensorList> {
    let display = loaded
        .path
        .as_deref()
        .map(|path| path.display().to_string())
        .unwrap_or_default();
    let source = SourceFile::new(&display, &loaded.text);
    for diagnostic in &loaded.diagnostics {
        out!("{}", source.render(diagnostic));
    }
    tally.add(&loaded.diagnostics);
    match loaded.errors() {
        // Errors the diagnostics above did not show (a file without sensors).
        Some(error)
            if !loaded
                .diagnostics
                .iter()
                .any(gloc_engine::Diagnostic::is_error) =>
        {
            outln!("error: {error}");
            tally.errors += 1;
            None
        }
        Some(_) => None,
        None => Some(loaded.list),
    }
}
