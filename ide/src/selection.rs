//! Selection ranges ("expand selection"): from the word under the cursor out
//! through brackets, the statement's line, the blocks and label section around
//! it, to the whole document.

use gloc_engine::Span;

use crate::analysis::Analysis;

/// The spans around `offset`, innermost first, each strictly larger than the one
/// before and containing it.
pub fn selection_ranges(text: &str, analysis: &Analysis, offset: usize) -> Vec<Span> {
    let offset = offset.min(text.len());
    let mut candidates: Vec<Span> = Vec::new();
    if let Some(token) = analysis.token_at(offset) {
        candidates.push(token.span);
    }
    let line = line_content(text, offset);
    candidates.extend(brackets_around(text, line, offset));
    candidates.push(line);
    let mut folds: Vec<Span> = analysis
        .folds
        .iter()
        .copied()
        .filter(|fold| fold.start as usize <= offset && offset <= fold.end as usize)
        .collect();
    folds.sort_by_key(|fold| fold.len());
    candidates.extend(folds);
    candidates.push(Span::new(0, text.len()));
    let mut chain: Vec<Span> = Vec::new();
    for span in candidates {
        match chain.last() {
            Some(last) if !(span.start <= last.start && last.end <= span.end && span != *last) => {}
            _ => chain.push(span),
        }
    }
    chain
}

/// The line holding `offset`, without its indentation, trailing blanks and line end.
fn line_content(text: &str, offset: usize) -> Span {
    let start = text[..offset].rfind('\n').map_or(0, |at| at + 1);
    let end = text[offset..]
        .find('\n')
        .map_or(text.len(), |at| offset + at);
    let line = &text[start..end];
    let indent = line.len() - line.trim_start().len();
    let content_end = start + line.trim_end().len();
    let content_start = (start + indent).min(offset);
    Span::new(content_start, content_end.max(offset))
}

/// The bracketed groups `( … )` on the line that hold `offset`, innermost first;
/// brackets inside strings and comments are not counted.
fn brackets_around(text: &str, line: Span, offset: usize) -> Vec<Span> {
    let mut open: Vec<usize> = Vec::new();
    let mut groups = Vec::new();
    let mut in_string = false;
    for (index, character) in text[line.range()].char_indices() {
        let at = line.start as usize + index;
        match character {
            '"' => in_string = !in_string,
            '\'' | '#' if !in_string => break,
            '(' if !in_string => open.push(at),
            ')' if !in_string => {
                if let Some(start) = open.pop() {
                    if start < offset && offset <= at {
                        groups.push(Span::new(start, at + 1));
                    }
                }
            }
            _ => {}
        }
    }
    groups.sort_by_key(|group| group.len());
    groups
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Token, TokenKind};

    #[test]
    fn word_then_brackets_then_line_then_block_then_document() {
        let text = "if x then\n  c_pitch = max(-0.4, min(0.4, m_pitch))\nendif\n";
        let word = text.find("m_pitch").expect("m_pitch");
        let analysis = Analysis {
            tokens: vec![Token {
                span: Span::new(word, word + 7),
                kind: TokenKind::SensorRead,
                sensor: None,
            }],
            folds: vec![Span::new(0, text.len() - 1)],
            ..Analysis::default()
        };
        let chain = selection_ranges(text, &analysis, word + 2);
        let pieces: Vec<&str> = chain.iter().map(|span| &text[span.range()]).collect();
        assert_eq!(
            pieces,
            [
                "m_pitch",
                "(0.4, m_pitch)",
                "(-0.4, min(0.4, m_pitch))",
                "c_pitch = max(-0.4, min(0.4, m_pitch))",
                "if x then\n  c_pitch = max(-0.4, min(0.4, m_pitch))\nendif",
                text,
            ]
        );
    }

    #[test]
    fn brackets_in_comments_and_strings_do_not_count_and_empty_text_works() {
        let text = "print \"(a\" ' (b)";
        let chain = selection_ranges(text, &Analysis::default(), 14);
        assert_eq!(chain, [Span::new(0, text.len())]);
        assert_eq!(
            selection_ranges("", &Analysis::default(), 5),
            [Span::new(0, 0)]
        );
    }
}
