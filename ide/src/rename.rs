//! Rename: whether the symbol under the cursor may be renamed, whether the new
//! name is allowed (the language decides), and the edits.

use gloc_engine::Span;

use crate::analysis::{Analysis, Context, TextEdit};
use crate::{gbasic_lang, gloc_lang, Language};

/// The span of the renamable name under the cursor and its current text.
pub fn prepare_rename(text: &str, analysis: &Analysis, offset: usize) -> Option<(Span, String)> {
    let (symbol, span) = analysis.symbol_at(offset)?;
    if !symbol.renamable {
        return None;
    }
    Some((span, text.get(span.range()).unwrap_or_default().to_string()))
}

/// The edits renaming the symbol under the cursor, `Ok(None)` when there is no
/// symbol there, or why the new name is not allowed.
pub fn rename(
    language: Language,
    text: &str,
    analysis: &Analysis,
    context: &Context,
    offset: usize,
    new_name: &str,
) -> Result<Option<Vec<TextEdit>>, String> {
    let Some((symbol, _)) = analysis.symbol_at(offset) else {
        return Ok(None);
    };
    if !symbol.renamable {
        return Err(format!("`{}` cannot be renamed", symbol.name));
    }
    let new_name = new_name.trim();
    match language {
        Language::Gloc => gloc_lang::check_new_name(symbol, new_name, analysis, text)?,
        Language::Gbasic => gbasic_lang::check_new_name(symbol, new_name, analysis, context)?,
        Language::Config => return Err("nothing to rename in gloc.toml".to_string()),
        Language::Mission | Language::MissionArgs | Language::Masterdata => {
            return Err("nothing to rename in a mission file or sensor list".to_string())
        }
    }
    Ok(Some(
        symbol
            .occurrences
            .iter()
            .map(|span| TextEdit {
                span,
                new_text: new_name.to_string(),
            })
            .collect(),
    ))
}
