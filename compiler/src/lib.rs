//! gloc-compiler: GBASIC, the paper's BASIC-like language, compiled to GLOC text.
//!
//! Stages: [`parser::parse`] (never fails) → [`check::check`] (types and names) →
//! [`codegen::generate`] (the paper's numbering scheme) → optionally
//! [`optimize::optimize`] → GLOC text plus a [`SourceMap`]. Pure: no IO, no threads.

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

pub mod analysis;
pub mod ast;
pub mod builtins;
pub mod check;
pub mod codegen;
pub mod codes;
pub mod expression;
pub mod ir;
pub mod lexer;
pub mod loader;

pub mod optimize;
pub mod parser;
pub mod source_map;
pub mod typed;

use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::Diagnostic;

pub use analysis::{analyze, Analysis, Block, SensorAccess, SymbolInfo, SymbolKind};
pub use codegen::{ForBound, Storage};

pub use loader::{
    load_script, source_too_large, Language, LoadOptions, LoadedScript, MAX_GBASIC_BYTES,
};
pub use source_map::{ConstantValue, Origin, SourceMap};

/// Whether GBASIC is compiled with the optimizer (`-O`): the argument of every
/// function that loads a script for a front end (a named choice, not a bare `bool`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Optimization {
    /// As written: what the debugger and the checker load, so lines map one to one.
    #[default]
    Plain,
    /// `-O`: what `gloc run` and `gloc batch` fly by default.
    Optimized,
}

impl Optimization {
    /// `true` for [`Optimization::Optimized`].
    pub fn enabled(self) -> bool {
        self == Optimization::Optimized
    }
}

/// The most diagnostics one pass (the parser, the checker) keeps: a file with
/// millions of wrong lines would otherwise hold millions of messages (4 million
/// undeclared `x=1` took 2 GB). The rest are counted and summed up in one E2011.
pub const MAX_DIAGNOSTICS: usize = 1000;

/// A pass's count of diagnostics past [`MAX_DIAGNOSTICS`].
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Suppressed {
    count: usize,
    last: gloc_engine::Span,
}

impl Suppressed {
    /// Keeps `diagnostic` while the pass has fewer than [`MAX_DIAGNOSTICS`], else counts it.
    pub(crate) fn push(&mut self, diagnostics: &mut Vec<Diagnostic>, diagnostic: Diagnostic) {
        if diagnostics.len() < MAX_DIAGNOSTICS {
            diagnostics.push(diagnostic);
        } else {
            self.count += 1;
            self.last = self.last.max(diagnostic.span);
        }
    }

    /// Adds the one E2011 that sums up what was not kept, at the last of them.
    pub(crate) fn finish(self, diagnostics: &mut Vec<Diagnostic>) {
        if self.count > 0 {
            diagnostics.push(
                Diagnostic::error(
                    codes::TOO_MANY_DIAGNOSTICS,
                    self.last,
                    format!(
                        "{} more diagnostics not shown (the first {MAX_DIAGNOSTICS} are listed)",
                        self.count
                    ),
                )
                .with_help("fix the first ones: the rest often follow from them"),
            );
        }
    }
}

/// How to compile.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CompileOptions {
    /// Whether the optimizer runs (`-O`).
    pub optimization: Optimization,
}

/// Register, label and instruction counts of one build (for `-O` figures).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct CodeStats {
    /// GLOC lines after the header (labels included, as `ninstr` counts).
    pub lines: u32,
    /// Executable instructions (label lines not counted).
    pub instructions: u32,
    pub registers: u32,
    pub labels: u32,
    pub memory: u32,
}

/// What compiling GBASIC yields beside its GLOC.
#[derive(Clone, Debug)]
pub struct GbasicBuild {
    /// Compiled GLOC → GBASIC.
    pub source_map: SourceMap,
    /// The compiler's size figures.
    pub stats: CodeStats,
}

/// The result of compiling GBASIC; diagnostics always point into the GBASIC text.
#[derive(Clone, Debug, Default)]
pub struct Compiled {
    pub diagnostics: Vec<Diagnostic>,
    /// `None` exactly when a diagnostic is an error.
    pub code: Option<CompiledCode>,
}

/// What a GBASIC program without errors compiles to.
#[derive(Clone, Debug)]
pub struct CompiledCode {
    pub gloc_text: String,
    /// Its source map and sizes, which the loaded script keeps.
    pub build: GbasicBuild,
    /// Trip counts of `for` loops with constant limits, keyed by the GLOC label of
    /// the loop's test, for the GLOC checker.
    pub for_bounds: Vec<ForBound>,
    /// The sensors the program stores, in order of first `stores`, taken before `-O`
    /// (which drops unreachable stores), so a log's or replay's columns do not depend
    /// on `-O`.
    pub stored_sensors: Vec<SensorId>,
}

impl Compiled {
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }
}

/// Compiles a GBASIC program against a sensor list.
pub fn compile(text: &str, sensors: &SensorList, options: &CompileOptions) -> Compiled {
    let parser::Parsed {
        program,
        diagnostics,
    } = parser::parse(text);
    let checked = check::check(&program, sensors);
    // The tree is not needed past the checker: not kept beside the code.
    drop(program);
    let check::Checked {
        program,
        symbols,
        diagnostics: check_diagnostics,
    } = checked;
    let mut diagnostics = diagnostics;
    diagnostics.extend(check_diagnostics);
    compile_checked(text, diagnostics, program, &symbols, sensors, options)
}

/// The code generation half of [`compile`], for callers that already parsed and
/// checked the text (the language server's analysis does, and compiles only once):
/// `diagnostics` are the parser's and the checker's; the typed `program` is dropped
/// once the code is generated.
pub(crate) fn compile_checked(
    text: &str,
    mut diagnostics: Vec<Diagnostic>,
    program: typed::Program,
    symbols: &typed::Symbols,
    sensors: &SensorList,
    options: &CompileOptions,
) -> Compiled {
    diagnostics.sort_by_key(|diagnostic| (diagnostic.span.start, diagnostic.span.end));
    if diagnostics.iter().any(Diagnostic::is_error) {
        return Compiled {
            diagnostics,
            ..Compiled::default()
        };
    }
    let generated = codegen::generate(&program, symbols);
    // The typed tree is not needed past code generation: not kept beside the code.
    drop(program);
    let mut code = generated.code;
    code.sensor_list = stated_list(sensors);
    let mut for_bounds = generated.for_bounds;
    let mut stored_sensors: Vec<SensorId> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for instr in &code.instrs {
        if let ir::Instr::StoreS { sensor, .. } = instr {
            if seen.insert(*sensor) {
                stored_sensors.push(SensorId(*sensor));
            }
        }
    }
    let mut label_renumbering = None;
    if options.optimization.enabled() {
        match optimize::optimize(&mut code, &for_bounds) {
            Some(optimized) => {
                for_bounds = optimized.for_bounds;
                label_renumbering = Some(optimized.labels);
            }
            None => diagnostics.push(
                Diagnostic::warning(
                    codes::NOT_OPTIMIZED,
                    gloc_engine::Span::default(),
                    format!(
                        "the program is too large for `-O` ({} instructions × {} registers, \
                         the optimizer's limit is {} bits of liveness): compiled without it",
                        code.instrs.len(),
                        code.register_count,
                        optimize::MAX_LIVENESS_BITS
                    ),
                )
                .with_help("split the program; a glider script is a few hundred lines"),
            ),
        }
    }
    if let Some(diagnostic) = too_large(&code) {
        diagnostics.push(diagnostic);
        return Compiled {
            diagnostics,
            ..Compiled::default()
        };
    }
    let mut source_map = SourceMap::build(&code, &generated.storage, symbols, text);
    if options.optimization.enabled() {
        // Register reuse gives a scalar's register to other values wherever the
        // variable is dead, so no register can be named for it; arrays keep their
        // memory cells.
        source_map
            .variables
            .retain(|variable| matches!(variable.storage, Storage::Memory { .. }));
    }
    if let Some(renumbering) = label_renumbering {
        // A label nothing jumps to is gone after `-O`.
        source_map
            .labels
            .retain_mut(|label| match renumbering.get(&ir::Lbl(label.number)) {
                Some(new) => {
                    label.number = new.0;
                    true
                }
                None => false,
            });
    }
    let stats = CodeStats {
        lines: code.instrs.len() as u32,
        instructions: code
            .instrs
            .iter()
            .filter(|instr| !matches!(instr, ir::Instr::Label(_)))
            .count() as u32,
        registers: code.register_count,
        labels: code.label_count,
        memory: code.memory_size,
    };
    Compiled {
        diagnostics,
        code: Some(CompiledCode {
            gloc_text: code.to_gloc(),
            build: GbasicBuild { source_map, stats },
            for_bounds,
            stored_sensors,
        }),
    }
}

/// The CRC the compiled GLOC states in its `# sensors:` line: the active list's,
/// when it is not the embedded list. Decision: the embedded list's output carries
/// no line, so that the paper's Fig. 3 still compiles to its Fig. 2 byte for byte;
/// such a file checked against another list gets one W0114 warning, not a silent
/// pass. A masterdata file has no CRC the glider would recognise: no line either.
fn stated_list(sensors: &SensorList) -> Option<String> {
    sensors
        .crc()
        .filter(|crc| *crc != gloc_engine::sensors::EMBEDDED_CRC)
        .map(str::to_string)
}

/// GLOC's loader limits (registers, labels, memory); a program beyond them is refused
/// here with a GBASIC diagnostic rather than later with a GLOC one.
fn too_large(code: &ir::Code) -> Option<Diagnostic> {
    const MAX_REGISTERS: u32 = 1 << 16;
    const MAX_LABELS: u32 = 1 << 20;
    const MAX_MEMORY: u32 = 1 << 20;
    let what = if code.register_count > MAX_REGISTERS {
        format!(
            "{} registers (the limit is {MAX_REGISTERS})",
            code.register_count
        )
    } else if code.label_count > MAX_LABELS {
        format!("{} labels (the limit is {MAX_LABELS})", code.label_count)
    } else if code.memory_size > MAX_MEMORY {
        format!(
            "{} memory cells (the limit is {MAX_MEMORY})",
            code.memory_size
        )
    } else {
        return None;
    };
    Some(
        Diagnostic::error(
            codes::TOO_LARGE,
            gloc_engine::Span::default(),
            format!("the program needs {what}"),
        )
        .with_help("split the program or use smaller arrays; `-O` reuses registers"),
    )
}
