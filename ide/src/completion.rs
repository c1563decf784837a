//! Completion: the candidates at a cursor, from the language's adapter; then,
//! at scale, the word being typed, fuzzy matching and ranking of the
//! candidates, and the cut to a limit. The server sends only what survives, in
//! this order, and says when the list was cut.

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
        Language::Config | Language::Masterdata => Vec::new(),
        Language::Mission | Language::MissionArgs => match language.mission_file() {
            Some(kind) => crate::mission::completions(kind, text, offset, &context.sensors),
            None => Vec::new(),
        },
    }))
    .unwrap_or_default()
}

/// How many items a completion answer carries unless the client's settings say
/// otherwise (LuaLS's default).
pub const DEFAULT_LIMIT: usize = 100;

/// Where a detail marks a sensor that a script may read but not store.
pub const READ_ONLY_MARK: &str = "read-only: cannot be stored";

/// The word the cursor is in or right after (letters, digits, `_`), as byte offsets.
pub fn typed_word(text: &str, offset: usize) -> (usize, &str) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let start = before
        .trim_end_matches(|c: char| c.is_ascii_alphanumeric() || c == '_')
        .len();
    (start, &text[start..offset])
}

/// How well `typed` matches `candidate`, lower is better; `None` when it does not.
/// 0: the candidate starts with it (case ignored); 1: a part after `_` or a space
/// starts with it (the index in a GLOC sensor's filter text `m_depth 444`); 2 and up: its characters appear in order (the more spread, the higher).
pub fn match_class(typed: &str, candidate: &str) -> Option<u32> {
    if typed.is_empty() {
        return Some(0);
    }
    let typed = typed.to_ascii_lowercase();
    let candidate = candidate.to_ascii_lowercase();
    if candidate.starts_with(&typed) {
        return Some(0);
    }
    if candidate
        .split(['_', ' '])
        .skip(1)
        .any(|part| part.starts_with(&typed))
    {
        return Some(1);
    }
    // A subsequence: count the gaps between matched characters.
    let mut gaps = 0u32;
    let mut chars = candidate.chars();
    for wanted in typed.chars() {
        let mut skipped = 0u32;
        loop {
            match chars.next() {
                Some(c) if c == wanted => break,
                Some(_) => skipped += 1,
                None => return None,
            }
        }
        if skipped > 0 {
            gaps += 1;
        }
    }
    Some(2 + gaps)
}

/// The candidates that match `typed`, best first: by match class, then by the
/// language's own grouping (`sort_text`: declared names, built-ins, keywords,
/// sensors; demoted items last), then by label. At most `limit` of them; the
/// flag says whether some were cut.
pub fn rank(candidates: Vec<Completion>, typed: &str, limit: usize) -> (Vec<Completion>, bool) {
    let mut scored: Vec<(u32, Completion)> = candidates
        .into_iter()
        .filter_map(|completion| {
            let key = completion
                .filter_text
                .as_deref()
                .unwrap_or(&completion.label);
            // The filter text (a GLOC sensor's `name index`) or the label, the better.
            let class = [
                match_class(typed, key),
                match_class(typed, &completion.label),
            ]
            .into_iter()
            .flatten()
            .min()?;
            Some((class, completion))
        })
        .collect();
    scored.sort_by(|(class_a, a), (class_b, b)| {
        class_a
            .cmp(class_b)
            .then_with(|| group(a).cmp(group(b)))
            .then_with(|| a.label.len().cmp(&b.label.len()))
            .then_with(|| a.label.cmp(&b.label))
    });
    let cut = scored.len() > limit;
    scored.truncate(limit);
    (
        scored
            .into_iter()
            .map(|(_, completion)| completion)
            .collect(),
        cut,
    )
}

/// The language's grouping key: `sort_text` without its name part is enough, as
/// every language writes a one-character group before the name.
fn group(completion: &Completion) -> &str {
    completion
        .sort_text
        .as_deref()
        .and_then(|text| text.get(..1))
        .unwrap_or("5")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::CompletionKind;

    fn item(label: &str, sort: Option<&str>) -> Completion {
        Completion {
            label: label.to_string(),
            kind: CompletionKind::Sensor,
            detail: None,
            documentation: None,
            insert: None,
            filter_text: None,
            sort_text: sort.map(str::to_string),
        }
    }

    #[test]
    fn the_typed_word_stops_at_the_first_non_identifier_character() {
        assert_eq!(typed_word("x = m_dep", 9), (4, "m_dep"));
        assert_eq!(typed_word("x = ", 4), (4, ""));
        assert_eq!(typed_word("é_a", 4), (2, "_a"));
        assert_eq!(typed_word("é_a", 1), (0, ""));
        assert_eq!(typed_word("ab", 99), (0, "ab"));
    }

    #[test]
    fn classes_prefix_then_word_part_then_spread_subsequence() {
        assert_eq!(match_class("M_DEP", "m_depth"), Some(0));
        assert_eq!(match_class("dep", "m_depth"), Some(1));
        // m_depth: "mdp" = m, (skip _) d, (skip e) p: two gaps.
        assert_eq!(match_class("mdp", "m_depth"), Some(4));
        assert_eq!(match_class("mdpth", "m_depth"), Some(4));
        assert_eq!(match_class("xyz", "m_depth"), None);
        // A GLOC sensor's filter text: typing its index finds it as a word part.
        assert_eq!(match_class("44", "m_depth 444"), Some(1));
        assert_eq!(match_class("", "anything"), Some(0));
    }

    #[test]
    fn exact_prefix_first_demoted_after_and_cut_to_the_limit() {
        let candidates = vec![
            item("c_depth_dummy", Some("9")),
            item("m_depth_rate", Some("5")),
            item("m_depth", Some("9")),
            item("u_min_depth", Some("5")),
            item("m_dip", Some("5")),
            item("x", Some("0")),
        ];
        let (ranked, cut) = rank(candidates.clone(), "m_dep", 10);
        let labels: Vec<&str> = ranked.iter().map(|c| c.label.as_str()).collect();
        // Prefix matches first (the writable group before the demoted one), then
        // the subsequence ones; `x` and `m_dip` do not match.
        assert_eq!(labels, ["m_depth_rate", "m_depth", "u_min_depth"]);
        assert!(!cut);
        let (ranked, cut) = rank(candidates, "", 2);
        assert_eq!(ranked.len(), 2);
        assert_eq!(ranked[0].label, "x");
        assert!(cut);
    }
}
