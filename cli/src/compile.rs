//! `gloc compile FILE.gbas [-o OUT.gloc] [-O] [--emit-map]`, and the script loader
//! `gloc check` and `gloc run` share for `.gloc` and `.gbas` files.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use gloc_compiler::{compile, CompileOptions, Language, Optimization};
use gloc_project::settings::Settings;
use gloc_project::{Overrides, Surface};

use crate::render::Tally;

pub fn main(args: crate::CompileArgs) -> anyhow::Result<ExitCode> {
    let mut tally = Tally::default();
    let settings = Settings::resolve(
        Some(&args.file),
        args.sensors.overrides(Overrides::new(Surface::Cli)),
    )?;
    let Some(sensors) = crate::loading::active_sensors(&settings, &mut tally)? else {
        return Ok(crate::exit::code(crate::exit::ERRORS));
    };
    // `gloc compile` compiles GBASIC whatever the file is called.
    let text = gloc_project::script::read_script(&args.file)?;
    let display = args.file.display().to_string();
    let script = gloc_project::script::load_text(
        Some(&args.file),
        display.clone(),
        text,
        Language::Gbasic,
        &sensors,
        &settings,
        args.optimization(),
    );
    let loaded = &script.loaded;
    crate::render::render_all(&script, |text| eprint!("{text}"));
    tally.add(&loaded.diagnostics);
    // The compiled GLOC must also pass the GLOC checker (a loop with neither `yield`
    // nor a way out is refused there); its findings are shown on the GBASIC lines.
    let (false, Some(gloc_text), Some(build)) =
        (loaded.has_errors(), &loaded.gloc_text, &loaded.gbasic)
    else {
        eprintln!(
            "{display}: {} error{}: no GLOC written",
            tally.errors,
            if tally.errors == 1 { "" } else { "s" }
        );
        return Ok(crate::exit::code(crate::exit::ERRORS));
    };
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| args.file.with_extension("gloc"));
    let map_path = map_path(&output);
    let mut outputs = vec![crate::output::Output {
        flag: "-o",
        path: &output,
    }];
    if args.emit_map {
        outputs.push(crate::output::Output {
            flag: "--emit-map",
            path: &map_path,
        });
    }
    let inputs: Vec<&Path> = std::iter::once(args.file.as_path())
        .chain(settings.input_paths())
        .collect();
    crate::output::check_outputs(&inputs, &outputs)?;
    crate::output::write_atomically(&output, gloc_text.as_bytes())
        .map_err(|error| crate::output::write_error(error, "the GLOC", &output))?;
    if args.emit_map {
        crate::output::write_atomically(&map_path, build.source_map.to_json().as_bytes())
            .map_err(|error| crate::output::write_error(error, "the source map", &map_path))?;
    }
    let stats = build.stats;
    eprintln!(
        "{display} → {}: {} lines ({} instructions), {} registers, {} labels{}",
        output.display(),
        stats.lines,
        stats.instructions,
        stats.registers,
        stats.labels,
        if stats.memory > 0 {
            format!(", {} memory cells", stats.memory)
        } else {
            String::new()
        }
    );
    if args.optimization().enabled() {
        // What -O bought: the same program built without the optimizer. Its
        // errors, if any, were already reported by the optimized build.
        let unoptimized = compile(
            &script.text,
            &sensors,
            &CompileOptions {
                optimization: Optimization::Plain,
            },
        );
        if let Some(before) = unoptimized.code.map(|code| code.build.stats) {
            eprintln!(
                "{display}: -O: {} → {} instructions, {} → {} registers (unoptimized → optimized)",
                before.instructions, stats.instructions, before.registers, stats.registers
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// `OUT.gloc` → `OUT.map.json`.
fn map_path(output: &Path) -> PathBuf {
    let mut name = output
        .file_stem()
        .map(|stem| stem.to_os_string())
        .unwrap_or_default();
    name.push(".map.json");
    output.with_file_name(name)
}
