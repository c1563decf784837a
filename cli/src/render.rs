//! What the CLI adds to the engine's renderer (`gloc_engine::render`): the tally of
//! errors and warnings behind its summaries and exit codes.

pub use gloc_engine::render::SourceFile;
use gloc_engine::{Diagnostic, Severity};

/// Counts of errors and warnings, for summaries and exit codes.
#[derive(Clone, Copy, Debug, Default)]
pub struct Tally {
    pub errors: usize,
    pub warnings: usize,
}

impl Tally {
    pub fn add(&mut self, diagnostics: &[Diagnostic]) {
        for diagnostic in diagnostics {
            match diagnostic.severity {
                Severity::Error => self.errors += 1,
                Severity::Warning => self.warnings += 1,
                Severity::Note => {}
            }
        }
    }
}
