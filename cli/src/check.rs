//! `gloc check FILE…`: parse and check each file, print every diagnostic
//! rustc-style, and with `--stats` the sizes and worst case per cycle.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use gloc_engine::gloc::{Bound, Stats};
use gloc_engine::sensors::{SensorList, SensorOrder};
use gloc_project::sensors::{load_sensor_list, load_sensor_list_file, LoadedSensors};
use gloc_project::settings::{Origin, Settings, Sourced};
use gloc_project::{Overrides, Surface};

use crate::render::{SourceFile, Tally};

pub fn main(args: crate::CheckArgs) -> anyhow::Result<ExitCode> {
    let mut tally = Tally::default();
    let settings = Settings::resolve(
        args.files.first().map(PathBuf::as_path),
        Overrides {
            masterdata: args.masterdata.clone(),
            cycle_budget: args.cycle_budget,
            sensor_order: args.sensor_order,
            ..Overrides::new(Surface::Cli)
        },
    )?;
    let Some(sensors) = active_sensors(&settings, &mut tally)? else {
        return Ok(crate::exit::code(crate::exit::ERRORS));
    };
    // The exit code of files that could not be checked (unreadable, or not a script).
    let mut not_checked = None;
    for path in &args.files {
        let script = match gloc_project::script::load_script(path, &sensors, &settings, false) {
            Ok(script) => script,
            Err(error) => {
                outln!("error: {error}");
                not_checked = not_checked.max(Some(crate::exit::of_project(&error)));
                continue;
            }
        };
        let source = SourceFile::new(&script.display, &script.text);
        crate::compile::render_all(&script, |text| out!("{text}"));
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

fn print_list(loaded: LoadedSensors, tally: &mut Tally) -> Option<SensorList> {
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
