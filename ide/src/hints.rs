//! Inlay hints: the cycle costs the analysis placed, those inside a range.

use crate::analysis::{Analysis, Hint};

/// The hints placed between `first` and `last` (bytes, both included).
pub fn inlay_hints(analysis: &Analysis, first: usize, last: usize) -> Vec<Hint> {
    analysis
        .hints
        .iter()
        .filter(|hint| hint.offset >= first && hint.offset <= last)
        .cloned()
        .collect()
}
