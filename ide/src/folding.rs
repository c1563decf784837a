//! Folding: label sections and blocks that end on a later line than they start.

use gloc_engine::Span;

use crate::analysis::Analysis;

/// The foldable regions; a region within one line is not one.
pub fn folding_ranges(text: &str, analysis: &Analysis) -> Vec<Span> {
    analysis
        .folds
        .iter()
        .copied()
        .filter(|span| crosses_a_line_break(text, *span))
        .collect()
}

/// Whether `span` holds a line break (`\n`, `\r\n` or a lone `\r`, the breaks
/// the editor counts); a `\r` whose `\n` lies past the span ends no line.
fn crosses_a_line_break(text: &str, span: Span) -> bool {
    let bytes = text.as_bytes();
    let end = (span.end as usize).min(bytes.len());
    (span.start as usize..end).any(|at| match bytes[at] {
        b'\n' => true,
        b'\r' => bytes.get(at + 1) != Some(&b'\n'),
        _ => false,
    })
}
