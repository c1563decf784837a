//! Go to definition, find references and document highlights: the symbol
//! whose definition or use covers the cursor.

use gloc_engine::Span;

use crate::analysis::Analysis;

/// Where the symbol under the cursor is defined.
pub fn definition(analysis: &Analysis, offset: usize) -> Option<Span> {
    let (symbol, _) = analysis.symbol_at(offset)?;
    symbol.occurrences.definition
}

/// Every use of the symbol under the cursor, its definition first when
/// `include_declaration`.
pub fn references(
    analysis: &Analysis,
    offset: usize,
    include_declaration: bool,
) -> Option<Vec<Span>> {
    let (symbol, _) = analysis.symbol_at(offset)?;
    Some(if include_declaration {
        symbol.occurrences.iter().collect()
    } else {
        symbol.occurrences.references.clone()
    })
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HighlightKind {
    /// The definition.
    Write,
    /// A use.
    Read,
}

/// The occurrences of the symbol under the cursor, the definition marked as a write.
pub fn highlights(analysis: &Analysis, offset: usize) -> Option<Vec<(Span, HighlightKind)>> {
    let (symbol, _) = analysis.symbol_at(offset)?;
    let definition = symbol
        .occurrences
        .definition
        .iter()
        .map(|span| (*span, HighlightKind::Write));
    let uses = symbol
        .occurrences
        .references
        .iter()
        .map(|span| (*span, HighlightKind::Read));
    Some(definition.chain(uses).collect())
}
