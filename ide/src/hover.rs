//! Hover: what the token under the cursor is (a sensor's documentation, a
//! symbol's kind, type and use count, or a keyword's, instruction's or
//! built-in's description), as markdown with the span it covers.

use gloc_engine::Span;

use crate::analysis::{Analysis, Context, SymbolKind, TokenKind};
use crate::{lang, Language};

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HoverInfo {
    pub markdown: String,
    /// The token the text is about.
    pub span: Span,
}

pub fn hover(
    language: Language,
    text: &str,
    analysis: &Analysis,
    context: &Context,
    offset: usize,
) -> Option<HoverInfo> {
    if language == Language::Masterdata {
        let (span, markdown) = crate::masterdata::hover(text, offset)?;
        return Some(HoverInfo { markdown, span });
    }
    if let Some(kind) = language.mission_file() {
        let (span, markdown) = crate::mission::hover(kind, text, offset, &context.sensors)?;
        return Some(HoverInfo { markdown, span });
    }
    let token = analysis.token_at(offset)?;
    let word = text.get(token.span.range()).unwrap_or_default();
    let markdown = match token.kind {
        TokenKind::SensorRead | TokenKind::SensorWrite => {
            lang::sensor_markdown(&context.sensors, token.sensor?)
        }
        TokenKind::Label | TokenKind::Variable | TokenKind::Constant => {
            let (symbol, _) = analysis.symbol_at(offset)?;
            let what = match symbol.kind {
                SymbolKind::Label => "label",
                SymbolKind::Variable => "variable",
                SymbolKind::Array => "array",
                SymbolKind::Constant => "constant",
                SymbolKind::Sensor => "sensor",
                SymbolKind::Behavior => "behavior",
            };
            let uses = symbol.occurrences.references.len();
            let mut text = format!("{what} `{}`", symbol.name);
            if !symbol.detail.is_empty() {
                text.push_str(&format!(": {}", symbol.detail));
            }
            text.push_str(&format!(
                "\n\n{uses} use{}",
                if uses == 1 { "" } else { "s" }
            ));
            if symbol.occurrences.definition.is_none() {
                text.push_str("; never defined");
            }
            text
        }
        _ => lang::word_markdown(language, word, token.kind)?,
    };
    Some(HoverInfo {
        markdown,
        span: token.span,
    })
}
