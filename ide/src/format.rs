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
        Language::Config | Language::Masterdata => None,
        Language::Mission | Language::MissionArgs => crate::mission::format(text),
    }))
    .ok()
    .flatten()
}

/// The edits that format the text: none when it is already formatted, one
/// covering the changed lines otherwise; `None` when it cannot be formatted.
/// A CRLF text keeps its line ends.
pub fn formatting(language: Language, text: &str) -> Option<Vec<TextEdit>> {
    let formatted = with_line_ends_of(text, format(language, text)?);
    if formatted == text {
        return Some(Vec::new());
    }
    let old_lines: Vec<&str> = text.split_inclusive('\n').collect();
    let new_lines: Vec<&str> = formatted.split_inclusive('\n').collect();
    let (common_prefix, common_suffix) = common_ends(&old_lines, &new_lines);
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

/// How many items `old` and `new` share at their beginning, and then (of what is
/// left) at their end: what one replacement between the two keeps.
pub fn common_ends<T: PartialEq>(old: &[T], new: &[T]) -> (usize, usize) {
    let prefix = old
        .iter()
        .zip(new)
        .take_while(|(old, new)| old == new)
        .count();
    let suffix = old[prefix..]
        .iter()
        .rev()
        .zip(new[prefix..].iter().rev())
        .take_while(|(old, new)| old == new)
        .count();
    (prefix, suffix)
}

/// The formatters write LF; a CRLF text keeps CRLF.
fn with_line_ends_of(text: &str, formatted: String) -> String {
    if text.contains("\r\n") {
        formatted.replace("\r\n", "\n").replace('\n', "\r\n")
    } else {
        formatted
    }
}

/// The edits that format lines `first` to `last` (0-based, inclusive). The
/// formatters re-indent line by line, so when the line count stays the same each
/// changed line in the range is replaced (its content, not its line end); when
/// it does not (GLOC's canonical form can join or split lines), the one
/// whole-text edit is returned only if it lies within those lines.
pub fn range_formatting(
    language: Language,
    text: &str,
    first: usize,
    last: usize,
) -> Option<Vec<TextEdit>> {
    let formatted = with_line_ends_of(text, format(language, text)?);
    let old_lines: Vec<&str> = text.split_inclusive('\n').collect();
    let new_lines: Vec<&str> = formatted.split_inclusive('\n').collect();
    let line_starts: Vec<usize> = std::iter::once(0)
        .chain(old_lines.iter().scan(0, |end, line| {
            *end += line.len();
            Some(*end)
        }))
        .collect();
    if old_lines.len() != new_lines.len() {
        let edits = formatting(language, text)?;
        let range = line_starts.get(first).copied().unwrap_or(text.len())
            ..line_starts.get(last + 1).copied().unwrap_or(text.len());
        let inside = edits.iter().all(|edit| {
            range.start <= edit.span.start as usize && edit.span.end as usize <= range.end
        });
        return Some(if inside { edits } else { Vec::new() });
    }
    let content = |line: &str| line.trim_end_matches(['\n', '\r']).len();
    Some(
        old_lines
            .iter()
            .zip(&new_lines)
            .enumerate()
            .filter(|(index, (old, new))| *index >= first && *index <= last && old != new)
            .map(|(index, (old, new))| TextEdit {
                span: Span::new(line_starts[index], line_starts[index] + content(old)),
                new_text: new[..content(new)].to_string(),
            })
            .collect(),
    )
}

#[cfg(test)]
mod range_tests {
    use super::*;

    #[test]
    fn common_ends_never_count_an_item_twice() {
        // Worked by hand: "ab" begins both and "de" ends both; of "aa" → "aaa" the
        // beginning takes both of the old items, so none is left for the end.
        let chars = |text: &str| text.chars().collect::<Vec<_>>();
        assert_eq!(common_ends(&chars("abcxde"), &chars("abyyde")), (2, 2));
        assert_eq!(common_ends(&chars("aa"), &chars("aaa")), (2, 0));
        assert_eq!(common_ends(&chars("xyz"), &chars("xyz")), (3, 0));
        assert_eq!(common_ends::<char>(&[], &chars("q")), (0, 0));
    }

    #[test]
    fn only_the_lines_in_the_range_are_reindented() {
        // Worked by hand: GBASIC indents a block's body by two spaces.
        let text = "if 1 then
x = 1
y = 2
endif
";
        let edits = range_formatting(Language::Gbasic, text, 2, 2).expect("formats");
        assert_eq!(edits.len(), 1, "{edits:?}");
        assert_eq!(&text[edits[0].span.range()], "y = 2");
        assert_eq!(edits[0].new_text, "  y = 2");
        let all = range_formatting(Language::Gbasic, text, 0, 3).expect("formats");
        assert_eq!(all.len(), 2);
        // CRLF: the line end is never part of an edit.
        let crlf = text.replace('\n', "\r\n");
        let edits = range_formatting(Language::Gbasic, &crlf, 1, 1).expect("formats");
        assert_eq!(&crlf[edits[0].span.range()], "x = 1");
        assert_eq!(edits[0].new_text, "  x = 1");
    }
}
