//! Fixture tests of every IDE feature in both languages, in the manner of
//! rust-analyzer's: a short document with a cursor marker `$0` (two markers for
//! a range), one `check_<feature>` helper per feature that runs gloc-ide on it
//! and renders the answer as text, and the expected answer inline
//! (`expect![[...]]`), worked out by hand from docs/gbasic.md, docs/gloc.md and
//! the embedded sensor list. Renderings: spans are drawn under their line
//! (`^^^` with a note; `|` marks an empty span), positions are `line:column`
//! from 0, edits are shown applied. Never regenerate them with `UPDATE_EXPECT=1`
//! without checking each change by hand: an expectation copied from the output
//! tests nothing.

mod actions;
mod completion;
mod diagnostics;
mod folding;
mod format;
mod hints;
mod hover;
mod navigation;
mod rename;
mod signature;
mod symbols;
mod tokens;

use std::sync::Arc;

use gloc_engine::sensors::SensorList;
use gloc_engine::Span;
use gloc_ide::analysis::{Analysis, Context, TextEdit};
use gloc_ide::Language;

pub use expect_test::{expect, Expect};
pub use gloc_ide::Language::{Gbasic, Gloc};

/// The marker for the cursor (one) or a range (two).
const CURSOR: &str = "$0";

/// The fixture's text without its markers, and the markers' byte offsets.
pub fn parse_fixture(fixture: &str) -> (String, Vec<usize>) {
    let mut text = String::with_capacity(fixture.len());
    let mut offsets = Vec::new();
    let mut rest = fixture;
    while let Some(at) = rest.find(CURSOR) {
        text.push_str(&rest[..at]);
        offsets.push(text.len());
        rest = &rest[at + CURSOR.len()..];
    }
    text.push_str(rest);
    (text, offsets)
}

/// The embedded sensor list, no cycle budget.
pub fn context() -> Context {
    Context::new(Arc::new(SensorList::embedded()))
}

pub struct Fixture {
    pub language: Language,
    pub text: String,
    pub offsets: Vec<usize>,
    pub context: Context,
    pub analysis: Analysis,
}

impl Fixture {
    pub fn new(language: Language, fixture: &str) -> Fixture {
        Fixture::with_context(language, fixture, context())
    }

    pub fn with_context(language: Language, fixture: &str, context: Context) -> Fixture {
        let (text, offsets) = parse_fixture(fixture);
        let analysis = gloc_ide::lang::analyze(language, &text, &context);
        Fixture {
            language,
            text,
            offsets,
            context,
            analysis,
        }
    }

    /// The one cursor.
    pub fn cursor(&self) -> usize {
        assert_eq!(self.offsets.len(), 1, "the fixture needs one `$0`");
        self.offsets[0]
    }

    /// The range between two markers, or the cursor as an empty range.
    pub fn range(&self) -> Span {
        match self.offsets[..] {
            [at] => Span::new(at, at),
            [start, end] => Span::new(start, end),
            _ => panic!("the fixture needs one or two `$0`"),
        }
    }

    /// `line:column` (from 0, columns in characters) of a byte offset.
    pub fn position(&self, offset: usize) -> String {
        let before = &self.text[..offset];
        let line = before.matches('\n').count();
        let line_start = before.rfind('\n').map_or(0, |at| at + 1);
        format!("{line}:{}", before[line_start..].chars().count())
    }

    pub fn line_of(&self, offset: usize) -> usize {
        self.text[..offset].matches('\n').count()
    }
}

pub use gloc_testsupport::annotate;

/// `text` with the edits applied (they must not overlap).
pub fn apply(text: &str, edits: &[TextEdit]) -> String {
    let mut edits = edits.to_vec();
    edits.sort_by_key(|edit| std::cmp::Reverse((edit.span.start, edit.span.end)));
    let mut out = text.to_string();
    for edit in edits {
        out.replace_range(edit.span.range(), &edit.new_text);
    }
    out
}
