//! What the CLI adds to the engine's renderer (`gloc_engine::render`): the tally of
//! errors and warnings behind its summaries and exit codes.

use gloc_compiler::Language;
pub use gloc_engine::render::SourceFile;
use gloc_engine::{Diagnostic, Severity};
use gloc_project::script::Script;

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

/// How many diagnostics are shown of a script that reads as the other language:
/// the note says what is wrong; the rest would be noise (27 for Fig. 2 read as GBASIC).
const SHOWN_WITH_LANGUAGE_NOTE: usize = 3;

/// Renders a loaded script's problems with `print` (stdout for `check`, stderr for
/// `run`), the one place every command does: a warning for an empty script; the
/// other-language note first, then only the first few diagnostics and a count of
/// the rest; else every diagnostic.
pub fn render_all(script: &Script, print: impl Fn(&str)) {
    // An empty GLOC file has its own error (E0010); an empty GBASIC file loads.
    if script.empty && !script.loaded.has_errors() {
        print(&format!(
            "{}: warning: the script is empty: it does nothing in any control cycle\n",
            script.display
        ));
    }
    let source = SourceFile::new(&script.display, &script.text);
    let diagnostics = &script.loaded.diagnostics;
    let shown = match &script.hint {
        Some(hint) => {
            print(&format!("{}: note: {hint}\n", script.display));
            SHOWN_WITH_LANGUAGE_NOTE
        }
        None => diagnostics.len(),
    };
    for diagnostic in diagnostics.iter().take(shown) {
        print(&source.render(diagnostic));
    }
    if diagnostics.len() > shown {
        let language = match script.language {
            Language::Gloc => "GLOC",
            Language::Gbasic => "GBASIC",
        };
        print(&format!(
            "{}: … and {} more problems from reading it as {language} (see the note)\n",
            script.display,
            diagnostics.len() - shown
        ));
    }
}

/// `path:line:col` of the instruction at `pc`, in the script's own text.
pub fn location_of_pc(script: &Script, pc: gloc_engine::program::Pc) -> String {
    let source = SourceFile::new(&script.display, &script.text);
    match script.loaded.span_of_pc(pc) {
        Some(span) => source.location(span.start as usize),
        None => script.display.clone(),
    }
}
