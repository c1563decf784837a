//! One loader for both languages, used by `gloc check`, `gloc run`, the language
//! server and the debug adapter: text in, a runnable `Program` out, with every
//! diagnostic pointing into the script's own text. GBASIC is compiled in memory and
//! its GLOC checked with the loop bounds the compiler knows; a GLOC diagnostic on
//! compiled code is moved to the GBASIC line it came from.

use std::path::Path;
use std::sync::Arc;

use gloc_engine::gloc::{self, CheckOptions, LoopBound, Stats};
use gloc_engine::program::{Pc, Program};
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::TrapKind;
use gloc_engine::{Diagnostic, LineIndex, Span};

use crate::{
    compile, CompileOptions, Compiled, CompiledCode, GbasicBuild, Optimization, SourceMap,
};

/// Which of the two languages a script is in. The one such type: the CLI, the
/// debugger and the loader use it as it is, and the editor's document kind
/// (`gloc_ide::Language`) is built from it beside its non-script documents.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Language {
    Gbasic,
    Gloc,
}

impl Language {
    /// By file extension, in any case: `gbas`, `gbasic` or `bas` is GBASIC, `gloc`
    /// is GLOC; any other is neither.
    pub fn of_extension(extension: &str) -> Option<Language> {
        match extension.to_ascii_lowercase().as_str() {
            "gbas" | "gbasic" | "bas" => Some(Language::Gbasic),
            "gloc" => Some(Language::Gloc),
            _ => None,
        }
    }

    /// By the path's extension ([`Language::of_extension`]); a file with any other
    /// extension, or none, is read as GLOC.
    pub fn of_path(path: &Path) -> Language {
        path.extension()
            .and_then(|extension| extension.to_str())
            .and_then(Language::of_extension)
            .unwrap_or(Language::Gloc)
    }
}

/// The largest GBASIC script gloc reads, in bytes: lower than GLOC's 16 MB
/// (`gloc_engine::gloc::MAX_SOURCE_BYTES`) because a GBASIC source byte costs more:
/// tokens, a tree, a typed tree and the code compiled from it. The worst measured
/// (README, limits: chains `a+a+…`) took 310 MB to check at 2 MB and 538 MB in the
/// language server (two million semantic tokens); 1 MB is still two hundred times the
/// largest real script.
pub const MAX_GBASIC_BYTES: usize = 1 << 20;

/// E0013 when a script of `language` is over its size limits (bytes, lines): the one
/// check the loader, the GBASIC parser and the editor's features all make.
pub fn source_too_large(text: &str, language: Language) -> Option<Diagnostic> {
    match language {
        Language::Gloc => gloc::source_too_large(text),
        Language::Gbasic => gloc::source_over(text, MAX_GBASIC_BYTES),
    }
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// Whether GBASIC is compiled with `-O`.
    pub optimization: Optimization,
    /// The per-cycle instruction budget the script will run under: a worst case per
    /// cycle above it is reported as a warning. `None`: the machine's default.
    pub cycle_budget: Option<u64>,
}

impl From<Optimization> for LoadOptions {
    /// A load with `optimization` under the machine's default budget.
    fn from(optimization: Optimization) -> LoadOptions {
        LoadOptions {
            optimization,
            cycle_budget: None,
        }
    }
}

#[derive(Clone, Debug, Default)]
pub struct LoadedScript {
    /// `Some` exactly when no diagnostic is an error.
    pub program: Option<Arc<Program>>,
    /// The GLOC that was checked (the compiled text for GBASIC, the script for GLOC).
    pub gloc_text: Option<String>,
    /// All point into the script's own text, sorted by position.
    pub diagnostics: Vec<Diagnostic>,
    /// The GLOC checker's figures (worst case per cycle and sizes).
    pub stats: Option<Stats>,
    /// GBASIC that compiled: what the compiler adds to its GLOC.
    pub gbasic: Option<GbasicBuild>,
    /// The sensors the script stores, in order of first `stores`: the program's for
    /// GLOC, the unoptimized code's for GBASIC, so `-O` never changes the columns of a
    /// log or a replay's `--out`.
    pub stored_sensors: Vec<SensorId>,
}

impl LoadedScript {
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }

    /// Compiled GLOC → GBASIC, for a GBASIC script that compiled.
    pub fn source_map(&self) -> Option<&SourceMap> {
        self.gbasic.as_ref().map(|build| &build.source_map)
    }

    /// The span in the script's own text of the instruction at `pc` (for traps and
    /// the debugger).
    pub fn span_of_pc(&self, pc: Pc) -> Option<Span> {
        match self.source_map() {
            Some(map) => map.origin_of_pc(pc.0).map(|origin| origin.span()),
            None => self.program.as_ref().map(|program| program.span(pc)),
        }
    }

    /// A trap described for the script's author. Compiled GBASIC checks array
    /// indices by reading memory address -1 when an index is outside its array (no
    /// other compiled access can reach a negative address), so that trap is named
    /// for what it is.
    pub fn trap_message(&self, kind: &TrapKind) -> String {
        match kind {
            TrapKind::MemoryOutOfBounds { address: -1, .. } if self.gbasic.is_some() => {
                "array index out of bounds".to_string()
            }
            _ => kind.to_string(),
        }
    }

    /// The 1-based line in the script's own text of the instruction at `pc`.
    pub fn line_of_pc(&self, pc: Pc) -> Option<u32> {
        match self.source_map() {
            Some(map) => map.origin_of_pc(pc.0).map(|origin| origin.line),
            None => self.program.as_ref().map(|program| program.line(pc)),
        }
    }

    /// [`LoadedScript::line_of_pc`] of every pc of the program, in one pass.
    pub fn lines_of_pcs(&self) -> Vec<Option<u32>> {
        let Some(program) = &self.program else {
            return Vec::new();
        };
        let count = program.instrs.len();
        match self.source_map() {
            Some(map) => map
                .origins_of_pcs(count)
                .map(|origin| origin.map(|origin| origin.line))
                .collect(),
            None => (0..count)
                .map(|pc| Some(program.line(Pc(pc as u32))))
                .collect(),
        }
    }
}

pub fn load_script(
    text: &str,
    language: Language,
    sensors: &SensorList,
    options: &LoadOptions,
) -> LoadedScript {
    load_script_written_for(text, language, sensors, options, None)
}

/// As [`load_script`], for a GLOC file whose `# sensors: CRC` line names a list the
/// caller found (`<crc>.cac`), so that its indices are verified by name against
/// `sensors` ([`gloc::identity`]). GBASIC names sensors by name: it ignores it.
pub fn load_script_written_for(
    text: &str,
    language: Language,
    sensors: &SensorList,
    options: &LoadOptions,
    written_for: Option<Arc<SensorList>>,
) -> LoadedScript {
    match language {
        Language::Gloc => {
            let check_options = CheckOptions {
                written_for,
                ..CheckOptions::default()
            };
            let checked = gloc::check(&gloc::parse(text), sensors, &check_options);
            let mut diagnostics = checked.diagnostics;
            if let Some(warning) = budget_warning(&checked.stats, options, Span::default()) {
                diagnostics.push(warning);
            }
            LoadedScript {
                stored_sensors: checked
                    .program
                    .as_ref()
                    .map(|program| program.stored_sensors.clone())
                    .unwrap_or_default(),
                program: checked.program,
                gloc_text: Some(text.to_string()),
                diagnostics,
                stats: Some(checked.stats),
                gbasic: None,
            }
        }
        Language::Gbasic => load_gbasic(text, sensors, options),
    }
}

fn load_gbasic(text: &str, sensors: &SensorList, options: &LoadOptions) -> LoadedScript {
    let load = |optimization| {
        load_compiled(
            text,
            compile(text, sensors, &CompileOptions { optimization }),
            sensors,
            options,
        )
    };
    let loaded = load(options.optimization);
    if !options.optimization.enabled() {
        return loaded;
    }
    // Constant folding can turn a loop's exit test into a jump: `n = 10` then `loop
    // while n < 25` folds to a loop without a way out, which the GLOC checker refuses
    // (E0111) although the plain code only warns (W0111) and traps at run time when
    // the cycle budget runs out. `-O` must not change whether a program compiles, so
    // such a program keeps its plain code and the proof becomes a warning.
    let endless: Vec<Span> = loaded
        .diagnostics
        .iter()
        .filter(|diagnostic| diagnostic.code == gloc_engine::codes::gloc::LOOP_WITHOUT_YIELD)
        .map(|diagnostic| diagnostic.span)
        .collect();
    if endless.is_empty() {
        return loaded;
    }
    let mut plain = load(Optimization::Plain);
    if plain.has_errors() {
        return loaded;
    }
    for span in endless {
        plain.diagnostics.push(
            Diagnostic::warning(
                crate::codes::ENDLESS_AFTER_FOLDING,
                span,
                "`-O` proved this loop never ends and never yields: its exit condition is \
                 always the same, so it would hang the control cycle (the vehicle's script \
                 traps when the cycle budget runs out); the program is compiled without `-O`",
            )
            .with_help("add a `yield` inside the loop, or change what the exit condition tests"),
        );
    }
    plain
        .diagnostics
        .sort_by_key(|diagnostic| (diagnostic.span.start, diagnostic.span.end));
    plain
}

/// The GLOC half of loading a GBASIC script: check the compiled code (with the
/// `for` loop bounds) and move its findings onto GBASIC lines.
pub(crate) fn load_compiled(
    text: &str,
    compiled: Compiled,
    sensors: &SensorList,
    options: &LoadOptions,
) -> LoadedScript {
    let Some(code) = compiled.code else {
        return LoadedScript {
            diagnostics: compiled.diagnostics,
            ..LoadedScript::default()
        };
    };
    let CompiledCode {
        gloc_text,
        build,
        for_bounds,
        stored_sensors,
    } = code;
    let check_options = CheckOptions {
        loop_bounds: for_bounds
            .iter()
            .map(|bound| LoopBound {
                label: bound.header.0,
                max_iterations: bound.trip_count,
            })
            .collect(),
        written_for: None,
    };
    let mut checked = gloc::check(&gloc::parse(&gloc_text), sensors, &check_options);
    // Compiled GLOC is written for `sensors` by construction: whether it states the
    // list (a masterdata file has no CRC to state) says nothing about its indices.
    checked
        .diagnostics
        .retain(|diagnostic| !gloc::identity::CODES.contains(&diagnostic.code));
    let gloc_index = LineIndex::new(&gloc_text);
    let mut diagnostics = compiled.diagnostics;
    for diagnostic in checked.diagnostics {
        diagnostics.push(translate(
            diagnostic,
            text,
            &gloc_text,
            &gloc_index,
            &build.source_map,
        ));
    }
    let end_of_text = Span::new(text.len(), text.len());
    if let Some(warning) = budget_warning(&checked.stats, options, end_of_text) {
        diagnostics.push(warning);
    }
    diagnostics.sort_by_key(|diagnostic| (diagnostic.span.start, diagnostic.span.end));
    LoadedScript {
        program: checked.program,
        gloc_text: Some(gloc_text),
        diagnostics,
        stats: Some(checked.stats),
        gbasic: Some(build),
        stored_sensors,
    }
}

/// Moves a diagnostic on the compiled GLOC to the GBASIC line it came from (the
/// whole statement line: a GLOC finding such as unreachable code or a loop without
/// `yield` is about statements, not about the literal an instruction loads). Its
/// fixes edit GLOC, so they are dropped.
fn translate(
    mut diagnostic: Diagnostic,
    script: &str,
    gloc_text: &str,
    index: &LineIndex,
    map: &SourceMap,
) -> Diagnostic {
    let gloc_line = index.line_col(gloc_text, diagnostic.span.start as usize).0 as u32;
    let script_lines = LineIndex::new(script);
    let to_script = |span: Span| {
        let line = index.line_col(gloc_text, span.start as usize).0 as u32;
        let Some(origin) = map.origin_of_gloc_line(line) else {
            return Span::default();
        };
        let line_index = script_lines.line_of(origin.start as usize);
        let start = script_lines.line_start(line_index).unwrap_or(0);
        let end = script_lines
            .line_start(line_index + 1)
            .unwrap_or(script.len())
            .min(script.len());
        let text = script.get(start..end).unwrap_or("");
        // The statement without its comment (the lexer knows a `'` in a string).
        let code = crate::lexer::lex(text)
            .iter()
            .find(|token| token.kind == crate::lexer::TokenKind::Comment)
            .map_or(text, |comment| &text[..comment.span.start as usize]);
        let leading = code.len() - code.trim_start().len();
        Span::new(start + leading, start + code.trim_end().len().max(leading))
    };
    diagnostic.span = to_script(diagnostic.span);
    for label in &mut diagnostic.labels {
        label.span = to_script(label.span);
    }
    diagnostic.fixes.clear();
    if diagnostic.code == gloc_engine::codes::gloc::LOOP_MAY_OVERRUN
        || diagnostic.code == gloc_engine::codes::gloc::LOOP_WITHOUT_YIELD
    {
        // The GLOC help speaks of loop bounds; in GBASIC those come from `for`.
        diagnostic.help = Some(
            "add a `yield` inside the loop (a `for` loop with constant limits counts as bounded)"
                .to_string(),
        );
    }
    diagnostic.message = format!("{} (compiled GLOC line {gloc_line})", diagnostic.message);
    diagnostic
}

fn budget_warning(stats: &Stats, options: &LoadOptions, span: Span) -> Option<Diagnostic> {
    let budget = options.cycle_budget?;
    match stats.worst_case.as_ref()?.max {
        gloc::Bound::Finite(worst) if worst > budget => Some(
            Diagnostic::warning(
                crate::codes::OVER_BUDGET,
                span,
                format!(
                    "a control cycle may execute {worst} instructions, more than the budget of {budget}"
                ),
            )
            .with_help("add a `yield` inside long loops, or raise the budget"),
        ),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_extension_table_for_every_front_end() {
        use std::path::Path;
        for gbasic in ["a.gbas", "b.GBAS", "c.gbasic", "d.bas"] {
            assert_eq!(
                Language::of_path(Path::new(gbasic)),
                Language::Gbasic,
                "{gbasic}"
            );
        }
        for gloc in ["fig2.gloc", "x.GLOC", "notes.txt", "no_extension", "gbas"] {
            assert_eq!(Language::of_path(Path::new(gloc)), Language::Gloc, "{gloc}");
        }
        assert_eq!(Language::of_extension("txt"), None);
        assert_eq!(Language::of_extension("Gloc"), Some(Language::Gloc));
    }

    /// A finding on the compiled GLOC lands on its GBASIC statement, the whole of
    /// it: a `'` inside a string starts no comment.
    #[test]
    fn a_quote_in_a_string_does_not_cut_the_translated_span() {
        // "label: a\n" (9 bytes) + "yield\n" (6) + "goto a\n" (7): the unreachable
        // `print "it's"` runs from byte 22 to 34, with or without a comment after it.
        for text in [
            "label: a\nyield\ngoto a\nprint \"it's\"\n",
            "label: a\nyield\ngoto a\nprint \"it's\" ' never runs\n",
        ] {
            let loaded = load_script(
                text,
                Language::Gbasic,
                &SensorList::embedded(),
                &LoadOptions::default(),
            );
            let unreachable = loaded
                .diagnostics
                .iter()
                .find(|diagnostic| diagnostic.code == "W0112")
                .expect("the print is unreachable");
            assert_eq!(unreachable.span, Span::new(22, 34), "{text:?}");
        }
    }
}
