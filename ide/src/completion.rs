//! Completion: the candidates at a cursor, from the language's adapter.

use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::analysis::{Analysis, Completion, Context};
use crate::{gbasic_lang, gloc_lang, Language};

/// The candidates at `offset` (none when the core panicked: a completion list
/// is never worth a crash).
pub fn completions(
    language: Language,
    text: &str,
    offset: usize,
    analysis: &Analysis,
    context: &Context,
) -> Vec<Completion> {
    catch_unwind(AssertUnwindSafe(|| match language {
        Language::Gloc => gloc_lang::completions(text, offset, analysis, context),
        Language::Gbasic => gbasic_lang::completions(text, offset, analysis, context),
        Language::Config => Vec::new(),
    }))
    .unwrap_or_default()
}
