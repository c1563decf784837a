//! `gloc compile FILE.gbas [-o OUT.gloc] [-O] [--emit-map]`, and the script loader
//! `gloc check` and `gloc run` share for `.gloc` and `.gbas` files.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use gloc_compiler::{compile, load_script, CompileOptions, Language, LoadOptions, LoadedScript};
use gloc_engine::sensors::SensorList;

use crate::render::{SourceFile, Tally};

pub fn main(args: crate::CompileArgs) -> anyhow::Result<ExitCode> {
    let mut tally = Tally::default();
    let settings = crate::settings::resolve(
        Some(&args.file),
        crate::settings::Flags {
            masterdata: args.masterdata.as_deref(),
            sensor_order: args.sensor_order,
            ..Default::default()
        },
    )?;
    let Some(sensors) = crate::check::active_sensors(&settings, &mut tally)? else {
        return Ok(ExitCode::FAILURE);
    };
    let text = gloc_engine::files::read_text(&args.file, gloc_engine::files::SCRIPT)
        .with_context(|| format!("cannot read the GBASIC file `{}`", args.file.display()))?;
    let display = args.file.display().to_string();
    let loaded = load_script(
        &text,
        Language::Gbasic,
        &sensors,
        &LoadOptions {
            optimize: args.optimize,
            cycle_budget: None,
        },
    );
    let source = SourceFile::new(&display, &text);
    for diagnostic in &loaded.diagnostics {
        eprint!("{}", source.render(diagnostic));
    }
    tally.add(&loaded.diagnostics);
    // The compiled GLOC must also pass the GLOC checker (a loop with neither `yield`
    // nor a way out is refused there); its findings are shown on the GBASIC lines.
    let (false, Some(gloc_text), Some(source_map)) =
        (loaded.has_errors(), &loaded.gloc_text, &loaded.source_map)
    else {
        eprintln!(
            "{display}: {} error{}: no GLOC written",
            tally.errors,
            if tally.errors == 1 { "" } else { "s" }
        );
        return Ok(ExitCode::FAILURE);
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
        crate::output::write_atomically(&map_path, source_map.to_json().as_bytes())
            .map_err(|error| crate::output::write_error(error, "the source map", &map_path))?;
    }
    if let Some(stats) = loaded.compile_stats {
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
        if args.optimize {
            // What -O bought: the same program built without the optimizer. Its
            // errors, if any, were already reported by the optimized build.
            let unoptimized = compile(&text, &sensors, &CompileOptions { optimize: false });
            if let Some(before) = unoptimized.stats {
                eprintln!(
                    "{display}: -O: {} → {} instructions, {} → {} registers (unoptimized → optimized)",
                    before.instructions, stats.instructions, before.registers, stats.registers
                );
            }
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

/// Reads and loads a `.gloc` or `.gbas` script for `gloc check` / `gloc run`, and
/// renders its diagnostics (to stderr). The script is always returned so the caller
/// can tell errors (no program) from success.
pub struct CliScript {
    pub display: String,
    pub text: String,
    pub loaded: LoadedScript,
}

impl CliScript {
    /// Renders every diagnostic with `print` (stdout for `check`, stderr for `run`).
    pub fn render_all(&self, print: impl Fn(&str)) {
        let source = SourceFile::new(&self.display, &self.text);
        for diagnostic in &self.loaded.diagnostics {
            print(&source.render(diagnostic));
        }
    }

    /// `path:line:col` of the instruction at `pc`, in the script's own text.
    pub fn location_of_pc(&self, pc: gloc_engine::program::Pc) -> String {
        let source = SourceFile::new(&self.display, &self.text);
        match self.loaded.span_of_pc(pc) {
            Some(span) => source.location(span.start as usize),
            None => self.display.clone(),
        }
    }
}

pub fn read_script(
    path: &Path,
    sensors: &SensorList,
    settings: &crate::settings::Settings,
    options: &LoadOptions,
) -> anyhow::Result<CliScript> {
    let text = gloc_engine::files::read_text(path, gloc_engine::files::SCRIPT)
        .with_context(|| format!("cannot read the script `{}`", path.display()))?;
    // `gloc run` checks a `# sensors:` line as `gloc check` does.
    let written_for = crate::check::written_for(&text, path, settings, sensors);
    let loaded = gloc_compiler::loader::load_script_written_for(
        &text,
        Language::of_path(path),
        sensors,
        options,
        written_for,
    );
    Ok(CliScript {
        display: path.display().to_string(),
        text,
        loaded,
    })
}
