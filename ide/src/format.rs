//! Formatting: the canonical text, and the one edit that gets there replacing
//! only the lines that change (so the cursor stays put elsewhere).

use std::panic::{catch_unwind, AssertUnwindSafe};

use gloc_engine::Span;

use crate::analysis::TextEdit;
use crate::{gbasic_lang, gloc_lang, Language};

/// The canonical form of the text (formatting never loses text: GLOC lines that
/// do not parse are kept verbatim), or `None` for a gloc.toml or when the
/// formatter panicked.
pub fn format(language: Language, text: &str) -> Option<String> {
    catch_unwind(AssertUnwindSafe(|| match language {
        Language::Gloc => gloc_lang::format(text),
        Language::Gbasic => gbasic_lang::format(text),
        Language::Config => None,
    }))
    .ok()
    .flatten()
}

/// The edits that format the text: none when it is already formatted, one
/// covering the changed lines otherwise; `None` when it cannot be formatted.
/// A CRLF text keeps its line ends.
pub fn formatting(language: Language, text: &str) -> Option<Vec<TextEdit>> {
    let formatted = format(language, text)?;
    let formatted = if text.contains("\r\n") {
        formatted.replace("\r\n", "\n").replace('\n', "\r\n")
    } else {
        formatted
    };
    if formatted == text {
        return Some(Vec::new());
    }
    let old_lines: Vec<&str> = text.split_inclusive('\n').collect();
    let new_lines: Vec<&str> = formatted.split_inclusive('\n').collect();
    let common_prefix = old_lines
        .iter()
        .zip(&new_lines)
        .take_while(|(old, new)| old == new)
        .count();
    let common_suffix = old_lines[common_prefix..]
        .iter()
        .rev()
        .zip(new_lines[common_prefix..].iter().rev())
        .take_while(|(old, new)| old == new)
        .count();
    let start: usize = old_lines[..common_prefix]
        .iter()
        .map(|line| line.len())
        .sum();
    let end: usize = text.len()
        - old_lines[old_lines.len() - common_suffix..]
            .iter()
            .map(|line| line.len())
            .sum::<usize>();
    let new_text = new_lines[common_prefix..new_lines.len() - common_suffix].concat();
    Some(vec![TextEdit {
        span: Span::new(start, end),
        new_text,
    }])
}
