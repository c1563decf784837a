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

/// The progress bar of a long command on a terminal's stderr (`None` elsewhere, so a
/// pipe or a log gets no control characters): `doing` what, `len` `units` in all.
pub fn progress_bar(len: u64, doing: &str, units: &str) -> Option<indicatif::ProgressBar> {
    use std::io::IsTerminal;
    std::io::stderr().is_terminal().then(|| {
        let bar = indicatif::ProgressBar::new(len);
        bar.set_style(
            indicatif::ProgressStyle::with_template(&progress_template(doing, units))
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        bar
    })
}

/// The template of [`progress_bar`].
fn progress_template(doing: &str, units: &str) -> String {
    format!("{{spinner}} {doing} [{{bar:40}}] {{pos}}/{{len}} {units} ({{eta}} left)")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_progress_template_is_indicatifs() {
        // The template `gloc batch` wrote out before there was one function for both.
        let batch = progress_template("flying", "missions");
        assert_eq!(
            batch,
            "{spinner} flying [{bar:40}] {pos}/{len} missions ({eta} left)"
        );
        for template in [batch, progress_template("simulating", "cycles")] {
            assert!(indicatif::ProgressStyle::with_template(&template).is_ok());
        }
    }
}
