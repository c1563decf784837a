//! The GLOC language: [`parse`] (never fails), [`print`] (canonical text) and
//! [`check`] (the safety checker, which builds the resolved [`Program`]).
//!
//! [`Program`]: crate::program::Program

pub mod ast;
mod cfg;
mod checker;
pub mod identity;
mod parser;
mod printer;

use std::fmt;
use std::sync::Arc;

use crate::diagnostic::Diagnostic;
use crate::program::{Pc, Program};
use crate::sensors::SensorList;

pub use checker::{MAX_LABELS, MAX_MEMORY, MAX_REGISTERS};

/// The result of [`parse`]: a tree for every line and the syntax diagnostics.
#[derive(Clone, Debug, Default)]
pub struct Parsed {
    pub file: ast::File,
    pub diagnostics: Vec<Diagnostic>,
}

/// Parses GLOC text. Never fails; problems are diagnostics. A text over
/// [`MAX_SOURCE_BYTES`] is not read at all: one E0013 error says so.
pub fn parse(text: &str) -> Parsed {
    if let Some(diagnostic) = source_too_large(text) {
        return Parsed {
            file: ast::File::default(),
            diagnostics: vec![diagnostic],
        };
    }
    let (file, diagnostics) = parser::parse_file(text);
    Parsed { file, diagnostics }
}

/// The largest script (GLOC or GBASIC) gloc reads, in bytes. A glider script
/// is a few kilobytes. GBASIC has a lower cap of its own
/// (`gloc_compiler::MAX_GBASIC_BYTES`): its trees cost more per source byte.
pub const MAX_SOURCE_BYTES: usize = 16 << 20;

/// The most lines a script (GLOC or GBASIC) may have. Memory grows with lines more
/// than with bytes (each line is a tree node, a table row and, when it is wrong, a
/// diagnostic): checking a 16 MB GLOC file of 2.8 million `yield` lines took 550 MB,
/// 8 million bad lines 2.4 GB, and the language server holds about 600 bytes a line
/// (a 700,000-line document: 423 MB). At 2^19 lines the worst measured stays under
/// 500 MB in the server too (README, limits).
pub const MAX_SOURCE_LINES: usize = 1 << 19;

/// The diagnostic code of a script over [`MAX_SOURCE_BYTES`] or [`MAX_SOURCE_LINES`].
pub const SOURCE_TOO_LARGE: &str = crate::codes::gloc::SOURCE_TOO_LARGE;

/// E0013 when `text` is over [`MAX_SOURCE_BYTES`] or [`MAX_SOURCE_LINES`] (for both
/// languages).
pub fn source_too_large(text: &str) -> Option<Diagnostic> {
    source_over(text, MAX_SOURCE_BYTES)
}

/// E0013 when `text` is over `max_bytes` bytes or [`MAX_SOURCE_LINES`] lines: the one
/// wording of the size limits, which GBASIC's lower byte cap uses too.
pub fn source_over(text: &str, max_bytes: usize) -> Option<Diagnostic> {
    let megabytes = |bytes: usize| bytes as f64 / (1 << 20) as f64;
    if text.len() > max_bytes {
        return Some(
            Diagnostic::error(
                SOURCE_TOO_LARGE,
                crate::diagnostic::Span::default(),
                format!(
                    "the script is {:.1} MB; gloc reads scripts of at most {} MB",
                    megabytes(text.len()),
                    megabytes(max_bytes)
                ),
            )
            .with_help("a glider script is a few kilobytes: is this the right file?"),
        );
    }
    // A last line without a line end counts too.
    let lines = text.bytes().filter(|byte| *byte == b'\n').count()
        + usize::from(!text.is_empty() && !text.ends_with('\n'));
    (lines > MAX_SOURCE_LINES).then(|| {
        Diagnostic::error(
            SOURCE_TOO_LARGE,
            crate::diagnostic::Span::default(),
            format!(
                "the script has {lines} lines; gloc reads scripts of at most {MAX_SOURCE_LINES} lines"
            ),
        )
        .with_help("a glider script is a few hundred lines: is this the right file?")
    })
}

/// Prints a file canonically (`\n` line ends, a final newline).
pub fn print(file: &ast::File) -> String {
    printer::print_file(file)
}

/// `text` as a GLOC string literal (the one quoter: the printer and the GBASIC
/// compiler's code generator both use it); [`parse`] reads it back as `text`.
pub fn quote(text: &str) -> String {
    let mut quoted = String::new();
    printer::write_quoted(&mut quoted, text);
    quoted
}

/// What a caller knows that the checker cannot see.
#[derive(Clone, Debug, Default)]
pub struct CheckOptions {
    /// Loops with a known trip count (the GBASIC compiler's `for` loops).
    pub loop_bounds: Vec<LoopBound>,
    /// The list the file's `# sensors: CRC` line names, when the caller found it
    /// (a `.cac` file); the embedded list is known without it. See [`identity`].
    pub written_for: Option<Arc<SensorList>>,
}

/// Control jumps back to `label` from inside its loop at most
/// `max_iterations` times each time the loop is entered. The label names the
/// loop header (the first instruction of the loop); nested loops each need
/// their own bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoopBound {
    pub label: u32,
    pub max_iterations: u64,
}

/// The result of [`check`].
#[derive(Clone, Debug)]
pub struct Checked {
    /// `Some` exactly when no diagnostic is an error.
    pub program: Option<Arc<Program>>,
    /// The parse diagnostics and the checker's, sorted by position.
    pub diagnostics: Vec<Diagnostic>,
    pub stats: Stats,
}

/// Sizes of the script and its worst case per control cycle.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// `nregs`.
    pub registers: u32,
    /// `nblbs`.
    pub labels: u32,
    /// `nmem`.
    pub memory: u32,
    /// Lines after the header (what `ninstr` counts: labels included).
    pub statements: u32,
    /// Executable instructions (labels not counted).
    pub instructions: u32,
    /// `None` when errors prevented the control-flow analysis.
    pub worst_case: Option<WorstCase>,
}

/// The most instructions a control cycle can execute (labels are not executed
/// and do not count; the `yield` that ends the cycle does).
#[derive(Clone, Debug, PartialEq)]
pub struct WorstCase {
    /// The first cycle, from pc 0.
    pub from_start: Bound,
    /// Each reachable `yield` (its pc), and the worst cycle that starts after it.
    pub from_yields: Vec<(Pc, Bound)>,
    /// The largest of all the above.
    pub max: Bound,
    /// The most output bytes one cycle can produce (printed or left pending), each
    /// value counted at its widest (24 characters) and each item with its separator.
    pub output_bytes: Bound,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Bound {
    Finite(u64),
    /// A loop without a `yield` (and without a known bound) lies on the way.
    Unbounded,
}

impl Bound {
    fn plus(self, amount: u64) -> Bound {
        match self {
            Bound::Finite(value) => Bound::Finite(value.saturating_add(amount)),
            Bound::Unbounded => Bound::Unbounded,
        }
    }

    fn plus_bound(self, other: Bound) -> Bound {
        match other {
            Bound::Finite(amount) => self.plus(amount),
            Bound::Unbounded => Bound::Unbounded,
        }
    }

    fn times(self, factor: u64) -> Bound {
        match self {
            Bound::Finite(value) => Bound::Finite(value.saturating_mul(factor)),
            Bound::Unbounded => Bound::Unbounded,
        }
    }
}

impl fmt::Display for Bound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Bound::Finite(value) => write!(f, "{value}"),
            Bound::Unbounded => f.write_str("unbounded"),
        }
    }
}

/// Validates a parsed file against its header and the sensor list and builds
/// the program. The diagnostics include the parse diagnostics.
pub fn check(parsed: &Parsed, sensors: &SensorList, options: &CheckOptions) -> Checked {
    checker::check_parsed(parsed, sensors, options)
}
