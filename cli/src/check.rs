//! `gloc check FILE…`: parse and check each file, print every diagnostic
//! rustc-style, and with `--stats` the sizes and worst case per cycle.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use anyhow::Context;
use gloc_engine::gloc::{self, Bound, CheckOptions, Stats};
use gloc_engine::sensors::{load_sensor_file, SensorList, SensorOrder};

use crate::render::{SourceFile, Tally};

pub fn main(args: crate::CheckArgs) -> anyhow::Result<ExitCode> {
    let mut tally = Tally::default();
    let settings = crate::settings::resolve(
        args.files.first().map(PathBuf::as_path),
        crate::settings::Flags {
            masterdata: args.masterdata.as_deref(),
            sensor_order: args.sensor_order,
            ..Default::default()
        },
    )?;
    let sensors = match &settings.masterdata {
        Some(path) => match load_sensors(path, settings.sensor_order, &mut tally)? {
            Some(list) => list,
            None => return Ok(ExitCode::FAILURE),
        },
        None => SensorList::embedded(),
    };
    for path in &args.files {
        let display = path.display().to_string();
        let text = match gloc_engine::files::read_text(path, gloc_engine::files::SCRIPT) {
            Ok(text) => text,
            Err(error) => {
                println!("{display}: error: cannot read the file: {error}");
                tally.errors += 1;
                continue;
            }
        };
        if gloc_compiler::Language::of_path(path) == gloc_compiler::Language::Gbasic {
            check_gbas(&display, &text, &sensors, args.stats, &mut tally);
            continue;
        }
        let source = SourceFile::new(&display, &text);
        let parsed = gloc::parse(&text);
        let options = CheckOptions {
            written_for: written_for(&text, path, &settings, &sensors),
            ..CheckOptions::default()
        };
        let checked = gloc::check(&parsed, &sensors, &options);
        for diagnostic in &checked.diagnostics {
            print!("{}", source.render(diagnostic));
        }
        tally.add(&checked.diagnostics);
        if args.stats {
            let program = checked.program.as_deref();
            print_stats(&source, &checked.stats, &|pc| {
                program.map_or(0, |program| program.line(pc))
            });
        }
    }
    if tally.errors > 0 || tally.warnings > 0 {
        println!(
            "{} error{}, {} warning{}",
            tally.errors,
            if tally.errors == 1 { "" } else { "s" },
            tally.warnings,
            if tally.warnings == 1 { "" } else { "s" }
        );
    }
    Ok(if tally.errors > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// The list a GLOC file's `# sensors: CRC` line names, when it is a third list:
/// `<crc>.cac` beside the script, beside the active list, or in the sensor cache
/// (`gloc_engine::gloc::identity::find_written_for`).
pub fn written_for(
    text: &str,
    script: &Path,
    settings: &crate::settings::Settings,
    active: &SensorList,
) -> Option<Arc<SensorList>> {
    let folders = gloc::identity::list_folders(
        Some(script),
        settings.masterdata.as_deref(),
        settings.sensor_cache.as_deref(),
    );
    gloc::identity::find_written_for(text, active, &folders)
}

/// The active sensor list of resolved settings: the masterdata file they name (see
/// [`load_sensors`]) or the embedded list. One place for `run`, `batch`, `compile` and
/// the replay.
pub fn active_sensors(
    settings: &crate::settings::Settings,
    tally: &mut Tally,
) -> anyhow::Result<Option<SensorList>> {
    match &settings.masterdata {
        Some(path) => load_sensors(path, settings.sensor_order, tally),
        None => Ok(Some(SensorList::embedded())),
    }
}

/// Loads `--masterdata`: prints its diagnostics; `None` when it has errors.
pub fn load_sensors(
    path: &Path,
    order: SensorOrder,
    tally: &mut Tally,
) -> anyhow::Result<Option<SensorList>> {
    let loaded = load_sensor_file(path, order)
        .with_context(|| format!("cannot read the sensor list `{}`", path.display()))?;
    let display = path.display().to_string();
    let source = SourceFile::new(&display, &loaded.text);
    for diagnostic in &loaded.diagnostics {
        print!("{}", source.render(diagnostic));
    }
    let before = tally.errors;
    tally.add(&loaded.diagnostics);
    Ok((tally.errors == before).then_some(loaded.list))
}

/// GBASIC files are compiled in memory and their GLOC checked (with the `for`
/// loop bounds the compiler knows); diagnostics point at the GBASIC text.
fn check_gbas(display: &str, text: &str, sensors: &SensorList, stats: bool, tally: &mut Tally) {
    let loaded = gloc_compiler::load_script(
        text,
        gloc_compiler::Language::Gbasic,
        sensors,
        &gloc_compiler::LoadOptions::default(),
    );
    let source = SourceFile::new(display, text);
    for diagnostic in &loaded.diagnostics {
        print!("{}", source.render(diagnostic));
    }
    tally.add(&loaded.diagnostics);
    if stats {
        if let Some(checked_stats) = &loaded.stats {
            print_stats(&source, checked_stats, &|pc| {
                loaded.line_of_pc(pc).unwrap_or(0)
            });
        }
    }
}

fn print_stats(
    source: &SourceFile,
    stats: &Stats,
    line_of_pc: &dyn Fn(gloc_engine::program::Pc) -> u32,
) {
    println!("{}:", source.path);
    println!("  registers     {}", stats.registers);
    println!("  labels        {}", stats.labels);
    println!("  memory        {}", stats.memory);
    println!(
        "  instructions  {} (ninstr; {} executable, labels excluded)",
        stats.statements, stats.instructions
    );
    let Some(worst) = &stats.worst_case else {
        println!("  worst case    not computed (fix the errors first)");
        return;
    };
    let per_cycle = match worst.max {
        Bound::Finite(count) => format!("{count} instructions per cycle"),
        Bound::Unbounded => "unbounded (a loop without `yield` lies on the way)".to_string(),
    };
    println!("  worst case    {per_cycle}");
    println!("    {:<30} {}", "from the start", worst.from_start);
    for (pc, bound) in &worst.from_yields {
        let line = line_of_pc(*pc);
        println!(
            "    {:<30} {bound}",
            format!("after the yield on line {line}")
        );
    }
    let output = match worst.output_bytes {
        Bound::Finite(bytes) => format!("at most {bytes} bytes per cycle"),
        Bound::Unbounded => "unbounded (a loop without `yield` writes)".to_string(),
    };
    println!("  output        {output}");
}
