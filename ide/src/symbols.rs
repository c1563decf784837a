//! Document symbols: every defined label, variable, array and constant, with
//! its whole defining line or section and the name itself.

use gloc_engine::Span;

use crate::analysis::{Analysis, SymbolKind};

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DocumentSymbol {
    pub name: String,
    pub kind: SymbolKind,
    pub detail: Option<String>,
    /// The whole definition (line or label section).
    pub extent: Span,
    /// The defining name.
    pub selection: Span,
}

/// The symbols defined in the document (a label only jumped to is not one).
pub fn document_symbols(analysis: &Analysis) -> Vec<DocumentSymbol> {
    analysis
        .symbols
        .iter()
        .filter_map(|symbol| {
            let definition = symbol.occurrences.definition?;
            Some(DocumentSymbol {
                name: symbol.name.clone(),
                kind: symbol.kind,
                detail: (!symbol.detail.is_empty()).then(|| symbol.detail.clone()),
                extent: symbol.extent.cover(definition),
                selection: definition,
            })
        })
        .collect()
}
