//! Semantic tokens: each classified piece of text as a highlight type and
//! modifiers (read-only sensors and constants, sensor writes, registers).

use gloc_engine::sensors::Access;
use gloc_engine::Span;

use crate::analysis::{Analysis, Context, TokenKind};

/// Highlight types, in the order of the server's legend (`TokenType as u32`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TokenType {
    Keyword,
    /// A GLOC header directive.
    Macro,
    Function,
    Variable,
    Number,
    String,
    Comment,
    Operator,
    /// A sensor.
    Property,
    Label,
}

impl TokenType {
    /// Every type, in legend order.
    pub const ALL: [TokenType; 10] = [
        TokenType::Keyword,
        TokenType::Macro,
        TokenType::Function,
        TokenType::Variable,
        TokenType::Number,
        TokenType::String,
        TokenType::Comment,
        TokenType::Operator,
        TokenType::Property,
        TokenType::Label,
    ];
}

/// Modifier bits, in the order of the server's legend.
pub mod modifiers {
    pub const READONLY: u32 = 1;
    pub const MODIFICATION: u32 = 2;
    pub const DEFAULT_LIBRARY: u32 = 4;
    pub const REGISTER: u32 = 8;
    /// Every modifier's name, bit 0 first.
    pub const NAMES: [&str; 4] = ["readonly", "modification", "defaultLibrary", "register"];
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HighlightedToken {
    pub span: Span,
    pub token_type: TokenType,
    /// A set of `modifiers` bits.
    pub modifiers: u32,
}

/// Every token, sorted by start, not overlapping.
pub fn semantic_tokens<'a>(
    analysis: &'a Analysis,
    context: &'a Context,
) -> impl Iterator<Item = HighlightedToken> + 'a {
    highlighted(&analysis.tokens, context)
}

/// The tokens that start within `span` (a binary search: no walk over the rest).
pub fn semantic_tokens_within<'a>(
    analysis: &'a Analysis,
    context: &'a Context,
    span: Span,
) -> impl Iterator<Item = HighlightedToken> + 'a {
    let tokens = &analysis.tokens;
    let first = tokens.partition_point(|token| token.span.start < span.start);
    let last = tokens
        .partition_point(|token| token.span.start < span.end)
        .max(first);
    highlighted(&tokens[first..last], context)
}

fn highlighted<'a>(
    tokens: &'a [crate::analysis::Token],
    context: &'a Context,
) -> impl Iterator<Item = HighlightedToken> + 'a {
    tokens.iter().map(move |token| {
        let read_only = token
            .sensor
            .and_then(|id| context.sensors.get(id))
            .is_some_and(|sensor| sensor.access() == Access::ReadOnly);
        let (token_type, modifiers) = style(token.kind, read_only);
        HighlightedToken {
            span: token.span,
            token_type,
            modifiers,
        }
    })
}

fn style(kind: TokenKind, read_only_sensor: bool) -> (TokenType, u32) {
    use modifiers::*;
    let read_only = if read_only_sensor { READONLY } else { 0 };
    match kind {
        TokenKind::Keyword => (TokenType::Keyword, 0),
        TokenKind::Directive => (TokenType::Macro, 0),
        TokenKind::Function => (TokenType::Function, DEFAULT_LIBRARY),
        TokenKind::Variable => (TokenType::Variable, 0),
        TokenKind::Constant => (TokenType::Variable, READONLY),
        TokenKind::Register => (TokenType::Variable, REGISTER),
        TokenKind::Number => (TokenType::Number, 0),
        TokenKind::String => (TokenType::String, 0),
        TokenKind::Comment => (TokenType::Comment, 0),
        TokenKind::Operator => (TokenType::Operator, 0),
        TokenKind::SensorRead => (TokenType::Property, DEFAULT_LIBRARY | read_only),
        TokenKind::SensorWrite => (TokenType::Property, DEFAULT_LIBRARY | MODIFICATION),
        TokenKind::Label => (TokenType::Label, 0),
    }
}
