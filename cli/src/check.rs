//! `gloc check FILE…`: parse and check each file, print every diagnostic
//! rustc-style, and with `--stats` the sizes and worst case per cycle. Scripts
//! (`.gloc`, `.gbas`), missions (`.mi` with the `.ma` files they load, `.ma` alone)
//! and sensor lists (a file named `masterdata*`, `.cac`, `.ccc`) are told apart by
//! their names; a mission is read by `gloc_mission` as `gloc run` and the editor read it.

use std::collections::hash_map::Entry;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use gloc_compiler::Optimization;
use gloc_engine::gloc::{Bound, Stats};
use gloc_engine::sensors::SensorList;
use gloc_project::config::Config;
use gloc_project::sensors::load_sensor_list_file;
use gloc_project::settings::{Origin, Settings, Sourced};
use gloc_project::{Overrides, Surface};

use crate::render::{SourceFile, Tally};

pub fn main(args: crate::CheckArgs) -> anyhow::Result<ExitCode> {
    let mut tally = Tally::default();
    let overrides = args.sensors.overrides(Overrides {
        cycle_budget: args.cycle_budget,
        mafiles: args.mafiles.clone(),
        ..Overrides::new(Surface::Cli)
    });
    // The exit code of files that could not be checked (unreadable, or not a script).
    let mut not_checked = None;
    let mut shown = std::collections::HashSet::new();
    // Each file is checked with its own project's settings (the nearest gloc.toml above
    // it), resolved once per project: `gloc check a/x.gloc b/y.gloc` with a gloc.toml in
    // each folder applies each to its own files.
    let mut projects: HashMap<Option<PathBuf>, Option<Project>> = HashMap::new();
    for path in &args.files {
        let project = match projects.entry(Config::find(path)) {
            Entry::Occupied(entry) => entry.into_mut(),
            Entry::Vacant(entry) => entry.insert(Project::resolve(path, &overrides, &mut tally)?),
        };
        let Some(Project {
            settings,
            sensors,
            options,
        }) = project
        else {
            // The project's sensor list has errors (printed when it was read).
            not_checked = not_checked.max(Some(crate::exit::ERRORS));
            continue;
        };
        let (settings, sensors, options) = (&*settings, &*sensors, &*options);
        match FileKind::of(path) {
            FileKind::Script => {}
            FileKind::Mission | FileKind::Args => {
                match check_mission(path, options, sensors, &mut shown, &mut tally) {
                    Ok(()) => {}
                    Err(error) => {
                        outln!("error: {error}");
                        not_checked = not_checked.max(Some(crate::exit::UNREADABLE));
                    }
                }
                continue;
            }
            FileKind::SensorList => {
                let origin = Sourced {
                    value: path.clone(),
                    origin: Origin::File(path.clone()),
                };
                match load_sensor_list_file(&origin, settings.sensor_order) {
                    Ok(loaded) => {
                        let _ = crate::loading::print_list(loaded, &mut tally);
                    }
                    Err(error) => {
                        outln!("error: {error}");
                        not_checked = not_checked.max(Some(crate::exit::of_project(&error)));
                    }
                }
                continue;
            }
        }
        let script =
            match gloc_project::script::load_script(path, sensors, settings, Optimization::Plain) {
                Ok(script) => script,
                Err(error) => {
                    outln!("error: {error}");
                    not_checked = not_checked.max(Some(crate::exit::of_project(&error)));
                    continue;
                }
            };
        let source = SourceFile::new(&script.display, &script.text);
        crate::render::render_all(&script, |text| out!("{text}"));
        tally.add(&script.loaded.diagnostics);
        if args.stats {
            if let Some(checked_stats) = &script.loaded.stats {
                print_stats(&source, checked_stats, &|pc| {
                    script.loaded.line_of_pc(pc).unwrap_or(0)
                });
            }
        }
    }
    if tally.errors > 0 || tally.warnings > 0 {
        outln!(
            "{} error{}, {} warning{}",
            tally.errors,
            if tally.errors == 1 { "" } else { "s" },
            tally.warnings,
            if tally.warnings == 1 { "" } else { "s" }
        );
    }
    Ok(if let Some(code) = not_checked {
        crate::exit::code(code)
    } else if tally.errors > 0 {
        crate::exit::code(crate::exit::ERRORS)
    } else {
        ExitCode::SUCCESS
    })
}

/// One project's resolved settings, its active sensor list and how its missions are read.
struct Project {
    settings: Settings,
    sensors: SensorList,
    options: gloc_mission::LoadOptions,
}

impl Project {
    /// The project of `path` (the nearest gloc.toml above it); `None` when its sensor
    /// list has errors (printed).
    fn resolve(
        path: &Path,
        overrides: &Overrides,
        tally: &mut Tally,
    ) -> anyhow::Result<Option<Project>> {
        let settings = Settings::resolve(Some(path), overrides.clone())?;
        let Some(sensors) = crate::loading::active_sensors(&settings, tally)? else {
            return Ok(None);
        };
        let options = gloc_project::simulation::mission_options(&settings, &sensors);
        Ok(Some(Project {
            settings,
            sensors,
            options,
        }))
    }
}

/// What `gloc check` makes of a file, by its name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FileKind {
    Script,
    Mission,
    Args,
    SensorList,
}

impl FileKind {
    /// A name with `masterdata` in it (`masterdata`, `masterdata.mi`, `x.masterdata`)
    /// is a sensor list whatever its extension (real masterdata files are named so);
    /// then by extension.
    fn of(path: &Path) -> FileKind {
        let name = path
            .file_name()
            .map(|name| name.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        let extension = gloc_engine::files::extension(path).unwrap_or_default();
        if name.contains("masterdata") {
            return FileKind::SensorList;
        }
        match extension.as_str() {
            "mi" => FileKind::Mission,
            "ma" => FileKind::Args,
            "cac" | "ccc" => FileKind::SensorList,
            _ => FileKind::Script,
        }
    }
}

/// Checks a `.mi` (with its `.ma` files) or a `.ma` alone and prints each problem
/// once per run: a `.ma` that several missions load is reported once.
fn check_mission(
    path: &Path,
    options: &gloc_mission::LoadOptions,
    sensors: &SensorList,
    shown: &mut std::collections::HashSet<String>,
    tally: &mut Tally,
) -> std::io::Result<()> {
    let mission = match FileKind::of(path) {
        FileKind::Args => {
            gloc_mission::Mission::load_args_file(path, options, &mut gloc_mission::Disk)
        }
        _ => gloc_mission::Mission::load_with_options(path, options, &mut gloc_mission::Disk),
    };
    // A file that cannot be read is exit code 3, as for scripts.
    if let Some(unreadable) = mission.diagnostics.iter().find(|entry| {
        entry.file == 0 && entry.diagnostic.code == gloc_engine::codes::mission::CANNOT_READ_MISSION
    }) {
        return Err(std::io::Error::other(unreadable.diagnostic.message.clone()));
    }
    let checks = mission.check(sensors);
    for entry in mission.diagnostics.iter().chain(&checks) {
        let Some(source) = mission.sources.get(entry.file) else {
            continue;
        };
        // One problem per place: a `.ma` reached as `missions/../mafiles/x.ma` and
        // named as `mafiles/x.ma` is one file.
        let real = std::fs::canonicalize(&source.path).unwrap_or_else(|_| source.path.clone());
        let key = format!(
            "{}:{}:{}:{}",
            real.display(),
            entry.diagnostic.span.start,
            entry.diagnostic.code,
            entry.diagnostic.message
        );
        if shown.insert(key) {
            let display = source.path.display().to_string();
            print!(
                "{}",
                SourceFile::new(&display, &source.text).render(&entry.diagnostic)
            );
            tally.add(std::slice::from_ref(&entry.diagnostic));
        }
    }
    Ok(())
}

fn print_stats(
    source: &SourceFile,
    stats: &Stats,
    line_of_pc: &dyn Fn(gloc_engine::program::Pc) -> u32,
) {
    outln!("{}:", source.path);
    outln!("  registers     {}", stats.registers);
    outln!("  labels        {}", stats.labels);
    outln!("  memory        {}", stats.memory);
    outln!(
        "  instructions  {} (ninstr; {} executable, labels excluded)",
        stats.statements,
        stats.instructions
    );
    let Some(worst) = &stats.worst_case else {
        outln!("  worst case    not computed (fix the errors first)");
        return;
    };
    let per_cycle = match worst.max {
        Bound::Finite(count) => format!("{count} instructions per cycle"),
        Bound::Unbounded => "unbounded (a loop without `yield` lies on the way)".to_string(),
    };
    outln!("  worst case    {per_cycle}");
    outln!("    {:<30} {}", "from the start", worst.from_start);
    for (pc, bound) in &worst.from_yields {
        let line = line_of_pc(*pc);
        outln!(
            "    {:<30} {bound}",
            format!("after the yield on line {line}")
        );
    }
    let output = match worst.output_bytes {
        Bound::Finite(bytes) => format!("at most {bytes} bytes per cycle"),
        Bound::Unbounded => "unbounded (a loop without `yield` writes)".to_string(),
    };
    outln!("  output        {output}");
}
