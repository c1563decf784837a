//! The one format for expected diagnostics in every test: the text itself, with each
//! diagnostic drawn under the line it starts on,
//!
//! ```text
//! dim Depth as integer
//!     ^^^^^ E2102 error: `Depth` is declared twice (help: rename one of them)
//! ```
//!
//! `^` under every character of the span (to the line's end when it goes on), `|` for an
//! empty span, then `CODE severity: message (help: …)`; a related place (a label) is a
//! `CODE note: …` under its own line. The IDE's tests write it inline (`expect![[…]]`),
//! the fixture folders beside each file (`NAME.err`); [`expect_diagnostics`] compares a
//! fixture with its `.err` and, with `GLOC_BLESS=1`, writes it instead.

use std::path::Path;

use gloc_engine::{Diagnostic, Severity, Span};

/// The text with each span drawn under its first line: `^` under every character
/// (to the line's end when the span goes on), `|` for an empty span, then the note.
pub fn annotate(text: &str, notes: &[(Span, String)]) -> String {
    let mut out = String::new();
    let mut line_start = 0;
    for line in text.split_inclusive('\n') {
        let content = line.trim_end_matches(['\n', '\r']);
        out.push_str(content);
        out.push('\n');
        let line_end = line_start + content.len();
        let mut here: Vec<&(Span, String)> = notes
            .iter()
            .filter(|(span, _)| {
                let start = span.start as usize;
                start >= line_start && (start < line_start + line.len() || start == line_end)
            })
            .collect();
        here.sort_by_key(|(span, _)| (span.start, span.end));
        for (span, note) in here {
            let start = span.start as usize;
            let end = (span.end as usize).min(line_end);
            let before = content.get(..start - line_start).unwrap_or(content);
            let column = before.chars().count();
            let width = content
                .get(start - line_start..end.max(start) - line_start)
                .unwrap_or("")
                .chars()
                .count();
            let marks = if span.is_empty() {
                "|".to_string()
            } else {
                "^".repeat(width.max(1))
            };
            out.push_str(&format!("{}{marks} {note}\n", " ".repeat(column)));
        }
        line_start += line.len();
    }
    // Spans at the very end of a text that ends with a line break (or an empty text).
    for (span, note) in notes {
        if (text.is_empty() || text.ends_with('\n')) && span.start as usize == text.len() {
            out.push_str(&format!("| {note}\n"));
        }
    }
    out
}

/// Each diagnostic as `CODE severity: message (help: …)` on its span, and each of its
/// labels as `CODE note: label` on the label's span: what [`annotate`] draws.
pub fn diagnostic_notes(diagnostics: &[Diagnostic]) -> Vec<(Span, String)> {
    let mut notes = Vec::new();
    for diagnostic in diagnostics {
        let severity = match diagnostic.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
            Severity::Note => "note",
        };
        let mut note = format!("{} {severity}: {}", diagnostic.code, diagnostic.message);
        if let Some(help) = &diagnostic.help {
            note.push_str(&format!(" (help: {help})"));
        }
        notes.push((diagnostic.span, note));
        for label in &diagnostic.labels {
            notes.push((
                label.span,
                format!("{} note: {}", diagnostic.code, label.message),
            ));
        }
    }
    notes
}

/// Compares the diagnostics of the fixture at `path` (whose text is `text`) with the
/// annotated text in `path` with the extension `err` (written by hand and reviewed);
/// with `GLOC_BLESS=1` set, writes that file instead. Panics with both texts on a
/// difference.
pub fn expect_diagnostics(path: &Path, text: &str, diagnostics: &[Diagnostic]) {
    let rendered = annotate(text, &diagnostic_notes(diagnostics));
    let expected_path = path.with_extension("err");
    if std::env::var_os("GLOC_BLESS").is_some() {
        if let Err(error) = std::fs::write(&expected_path, &rendered) {
            panic!("cannot write {}: {error}", expected_path.display());
        }
        return;
    }
    let expected = std::fs::read_to_string(&expected_path).unwrap_or_else(|error| {
        panic!(
            "{}: its expected diagnostics {} cannot be read ({error}); write them, or run \
             with GLOC_BLESS=1 and review the file",
            path.display(),
            expected_path.display()
        )
    });
    assert!(
        rendered == expected,
        "{}: the diagnostics differ from {}\n--- expected ---\n{expected}--- found ---\n{rendered}",
        path.display(),
        expected_path.display()
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_span_is_drawn_under_its_line_and_an_empty_one_as_a_bar() {
        let text = "dim a\ndim Depth as integer\n";
        let notes = vec![
            (Span::new(10, 15), "E2102 error: twice".to_string()),
            (Span::new(6, 6), "W1 warning: here".to_string()),
            (
                Span::new(text.len(), text.len()),
                "E9 error: end".to_string(),
            ),
        ];
        assert_eq!(
            annotate(text, &notes),
            "dim a\ndim Depth as integer\n| W1 warning: here\n    ^^^^^ E2102 error: twice\n| E9 error: end\n"
        );
    }
}
