//! Completions for the debug console and the Watch panel: the names an expression can
//! use (variables, constants, built-in functions, sensors, the operator words),
//! filtered by the word before the cursor, ranked, and capped. Byte offsets in, plain
//! items out; the session converts them to DAP's columns.

/// What a name is, which also orders the list: the script's own names first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Kind {
    Variable,
    Array,
    Constant,
    Builtin,
    /// A sensor the script loads or stores.
    UsedSensor,
    Sensor,
    Keyword,
}

/// One name the console can complete.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    pub label: String,
    pub kind: Kind,
    /// A short description (`float array(4)`, `sensor 444`, a built-in's signature).
    pub detail: String,
}

/// The answer: at most `limit` items replacing the bytes `start..start + length` of the
/// line (the word typed so far).
#[derive(Clone, Debug, PartialEq)]
pub struct Completions {
    pub items: Vec<Candidate>,
    pub start: usize,
    pub length: usize,
    /// How many names matched in all (more than `items.len()` when capped).
    pub matched: usize,
}

/// As many items as LuaLS sends: enough to browse, small enough to send per keystroke.
pub const LIMIT: usize = 100;

/// GBASIC's keywords that are operators of expressions.
fn is_operator(word: &str) -> bool {
    matches!(word, "and" | "or" | "not" | "mod")
}

/// Every name an expression may use in this session, in no particular order.
#[derive(Clone, Debug, Default)]
pub struct Vocabulary {
    pub candidates: Vec<Candidate>,
}

impl Vocabulary {
    pub fn push(&mut self, label: impl Into<String>, kind: Kind, detail: impl Into<String>) {
        self.candidates.push(Candidate {
            label: label.into(),
            kind,
            detail: detail.into(),
        });
    }

    /// Adds GBASIC's built-in functions (the compiler's table) and operator words.
    pub fn with_language_words(mut self) -> Vocabulary {
        for builtin in gloc_compiler::builtins::BUILTINS {
            self.push(builtin.name, Kind::Builtin, builtin.signature());
        }
        // From the compiler's keyword table, so no word is offered that GBASIC lacks.
        for word in gloc_compiler::analysis::keywords() {
            if is_operator(word) {
                self.push(*word, Kind::Keyword, "operator");
            }
        }
        self
    }
}

/// The names that complete the word ending at byte `cursor` of `line` (clamped to the
/// line and to a character boundary): the names that start with it, ignoring case as
/// GBASIC does; exact case first, then by kind (the script's names, then the sensors it
/// uses, then the others), shorter names, alphabetically.
pub fn complete(line: &str, cursor: usize, vocabulary: &Vocabulary, limit: usize) -> Completions {
    let mut cursor = cursor.min(line.len());
    while !line.is_char_boundary(cursor) {
        cursor -= 1;
    }
    let start = line[..cursor]
        .char_indices()
        .rev()
        .take_while(|(_, character)| character.is_ascii_alphanumeric() || *character == '_')
        .last()
        .map_or(cursor, |(index, _)| index);
    let word = &line[start..cursor];
    let none = Completions {
        items: Vec::new(),
        start,
        length: word.len(),
        matched: 0,
    };
    // A number being typed (`12`, `1e3`) is not a name.
    if word.starts_with(|character: char| character.is_ascii_digit()) {
        return none;
    }
    let lower = word.to_ascii_lowercase();
    let mut ranked: Vec<(u8, &Candidate)> = vocabulary
        .candidates
        .iter()
        .filter_map(|candidate| {
            let label = candidate.label.to_ascii_lowercase();
            let rank = if candidate.label.starts_with(word) {
                0
            } else if label.starts_with(&lower) {
                1
            } else {
                return None;
            };
            Some((rank, candidate))
        })
        .collect();
    ranked.sort_by(|(rank_a, a), (rank_b, b)| {
        rank_a
            .cmp(rank_b)
            .then(a.kind.cmp(&b.kind))
            .then(a.label.len().cmp(&b.label.len()))
            .then_with(|| a.label.cmp(&b.label))
    });
    ranked.dedup_by(|(_, a), (_, b)| a.label.eq_ignore_ascii_case(&b.label));
    let matched = ranked.len();
    Completions {
        items: ranked
            .into_iter()
            .take(limit)
            .map(|(_, candidate)| candidate.clone())
            .collect(),
        matched,
        ..none
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vocabulary() -> Vocabulary {
        let mut vocabulary = Vocabulary::default();
        vocabulary.push("depth", Kind::Variable, "float");
        vocabulary.push("tsum", Kind::Array, "float array(4)");
        vocabulary.push("MAXD", Kind::Constant, "const MAXD = 15.0");
        vocabulary.push("m_depth", Kind::UsedSensor, "sensor 444");
        vocabulary.push("m_depth_rate", Kind::Sensor, "sensor 445");
        vocabulary.push("m_dep_x", Kind::Sensor, "sensor 1");
        vocabulary.push("c_dive_target_depth", Kind::Sensor, "sensor 2");
        vocabulary.with_language_words()
    }

    /// The labels offered for `text` with the cursor at `$0`.
    fn check(text: &str, expected: &[&str]) -> Completions {
        let cursor = text.find("$0").expect("a $0 marker");
        let line = text.replace("$0", "");
        let completions = complete(&line, cursor, &vocabulary(), LIMIT);
        let labels: Vec<&str> = completions
            .items
            .iter()
            .map(|item| item.label.as_str())
            .collect();
        assert_eq!(labels, expected, "{text}");
        completions
    }

    #[test]
    fn the_word_before_the_cursor_filters_and_ranks() {
        // The script's sensor before the others, then shorter first.
        let completions = check("m_dep$0", &["m_depth", "m_dep_x", "m_depth_rate"]);
        assert_eq!((completions.start, completions.length), (0, 5));
        // Only names that start with the word.
        let completions = check("x > dep$0", &["depth"]);
        assert_eq!((completions.start, completions.length), (4, 3));
        // Case is ignored, exact case first.
        check("max$0", &["max", "MAXD"]);
        check("ab$0", &["abs"]);
        check("NO$0", &["not"]);
        check("mo$0", &["mod"]);
        // The cursor inside a word completes what stands before it.
        check("ts$0um", &["tsum"]);
    }

    #[test]
    fn nothing_to_complete_gives_nothing() {
        check("12$0", &[]);
        check("1e$0", &[]);
        check("zzz$0", &[]);
        let everything = complete("", 0, &vocabulary(), LIMIT);
        assert_eq!(everything.items.len(), everything.matched);
        assert_eq!(everything.items[0].label, "depth");
    }

    #[test]
    fn the_list_is_capped_and_says_how_many_matched() {
        let mut many = Vocabulary::default();
        for index in 0..1_389 {
            many.push(format!("m_s{index}"), Kind::Sensor, "sensor");
        }
        let completions = complete("m_", 2, &many, LIMIT);
        assert_eq!(completions.items.len(), LIMIT);
        assert_eq!(completions.matched, 1_389);
        // The shortest names come first.
        assert_eq!(completions.items[0].label, "m_s0");
    }

    #[test]
    fn a_cursor_past_the_line_or_inside_a_character_is_clamped() {
        let completions = complete("dé", 2, &vocabulary(), LIMIT);
        assert_eq!(completions.start, 0);
        let completions = complete("dep", 99, &vocabulary(), LIMIT);
        assert_eq!((completions.start, completions.length), (0, 3));
    }
}
