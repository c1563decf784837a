//! The one renderer of diagnostics, below every front end (the CLI, the debugger's
//! launch errors and output, the language server's messages), so one diagnostic
//! reads the same everywhere. Rendered for a terminal, rustc-style but with a
//! `path:line:col: severity[CODE]: message` header so editors and `grep`
//! can jump to it:
//!
//! ```text
//! bad.gloc:5:10: error[E0101]: register r8 is out of range: `nregs 8` allows r0 to r7
//!   |
//! 5 | loadi 1,r8
//!   |         ^^
//!   = help: raise `nregs` to 9 or use a lower register
//! ```
//!
//! Hand-written because the crates made for this (annotate-snippets,
//! codespan-reporting) put the location on a separate `-->` line and cannot
//! produce that header; the rest is forty lines.

use crate::{Diagnostic, LineIndex, Span};

/// `text` with every control character but tab and line break shown as U+FFFD:
/// a message quotes the source (`unknown instruction `…``), and the bytes of a
/// binary file must not reach a terminal as escape sequences.
pub fn printable(text: &str) -> String {
    text.replace(
        |c: char| c.is_control() && c != '\t' && c != '\n',
        "\u{FFFD}",
    )
}

/// A source text prepared for rendering many diagnostics.
pub struct SourceFile<'a> {
    pub path: &'a str,
    pub text: &'a str,
    line_index: LineIndex,
}

impl<'a> SourceFile<'a> {
    pub fn new(path: &'a str, text: &'a str) -> SourceFile<'a> {
        SourceFile {
            path,
            text,
            line_index: LineIndex::new(text),
        }
    }

    /// The `path:line:col` of a byte offset.
    pub fn location(&self, offset: usize) -> String {
        let (line, column) = self.line_index.line_col(self.text, offset);
        format!("{}:{line}:{column}", self.path)
    }

    /// The first line of a report, `path:line:col: severity[CODE]: message`, without
    /// a newline: what a one-line surface (an output event, a message) shows.
    pub fn headline(&self, diagnostic: &Diagnostic) -> String {
        format!(
            "{}: {}[{}]: {}",
            self.location(diagnostic.span.start as usize),
            diagnostic.severity,
            diagnostic.code,
            printable(&diagnostic.message)
        )
    }

    /// The full report for one diagnostic, ending with a newline.
    pub fn render(&self, diagnostic: &Diagnostic) -> String {
        let mut out = self.headline(diagnostic);
        out.push('\n');
        let mut snippets: Vec<(Span, char, &str)> = vec![(diagnostic.span, '^', "")];
        snippets.extend(
            diagnostic
                .labels
                .iter()
                .map(|label| (label.span, '-', label.message.as_str())),
        );
        let width = snippets
            .iter()
            .map(|(span, _, _)| self.line_number(span.start as usize).to_string().len())
            .max()
            .unwrap_or(1);
        let gutter = " ".repeat(width);
        out.push_str(&format!("{gutter} |\n"));
        for (span, marker, message) in snippets {
            self.snippet(&mut out, span, marker, message, width);
        }
        if let Some(help) = &diagnostic.help {
            out.push_str(&format!("{gutter} = help: {}\n", printable(help)));
        }
        out
    }

    fn line_number(&self, offset: usize) -> usize {
        self.line_index.line_col(self.text, offset).0
    }

    /// One source line with markers under the span (and a label message).
    fn snippet(&self, out: &mut String, span: Span, marker: char, message: &str, width: usize) {
        let start = (span.start as usize).min(self.text.len());
        let line = self.line_index.line_of(start);
        let line_start = self.line_index.line_start(line).unwrap_or(0);
        let line_end = self.text[line_start..]
            .find('\n')
            .map_or(self.text.len(), |at| line_start + at);
        let source_line = self.text[line_start..line_end].trim_end_matches('\r');
        // Very long lines (binary garbage) are cut to keep the report readable.
        let shown: String = source_line.chars().take(200).collect();
        let shown = printable(&shown);
        let mut prefix = String::new();
        for (at, character) in source_line.char_indices() {
            if line_start + at >= start {
                break;
            }
            prefix.push(if character == '\t' { '\t' } else { ' ' });
        }
        // A span may start at the line end (`\r`, `\n`): never let `end` fall below `start`.
        let end = (span.end as usize)
            .min(line_start + source_line.len())
            .max(start);
        let marked = self
            .text
            .get(start..end)
            .map_or(0, |text| text.chars().count());
        let markers: String = std::iter::repeat_n(marker, marked.max(1)).collect();
        out.push_str(&format!("{:>width$} | {shown}\n", line + 1));
        let tail = if message.is_empty() {
            String::new()
        } else {
            format!(" {}", printable(message))
        };
        out.push_str(&format!(
            "{} | {prefix}{markers}{tail}\n",
            " ".repeat(width)
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_header_source_line_caret_and_help() {
        let text = "nregs 1\nloadi 1,r8\n";
        let source = SourceFile::new("a.gloc", text);
        let diagnostic =
            Diagnostic::error("E0101", Span::new(16, 18), "register r8 is out of range")
                .with_label(Span::new(6, 7), "declared here")
                .with_help("raise `nregs`");
        assert_eq!(
            source.render(&diagnostic),
            "a.gloc:2:9: error[E0101]: register r8 is out of range
  |
2 | loadi 1,r8
  |         ^^
1 | nregs 1
  |       - declared here
  = help: raise `nregs`
"
        );
    }

    #[test]
    fn spans_at_line_ends_and_past_the_text_do_not_panic() {
        let text = "loadi 1,r0\r\nyield";
        let source = SourceFile::new("b.gloc", text);
        for (start, end) in [(10, 11), (11, 12), (12, 12), (17, 40), (100, 200)] {
            let rendered = source.render(&Diagnostic::warning("W0000", Span::new(start, end), "x"));
            assert!(rendered.contains('^'), "{rendered}");
        }
    }
}
