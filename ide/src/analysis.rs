//! What the server knows about one version of a document, in a shape shared by
//! both languages. The language adapters (`gloc_lang`, `gbasic_lang`) fill it
//! from the core crates; the feature modules (`hover`, `completion`, …) only read it.
//! Everything here is in byte offsets; `position` converts at the edge.

use std::sync::Arc;

use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::{Diagnostic, Occurrences, Span};

/// The project settings an analysis depends on.
#[derive(Clone, Debug)]
pub struct Context {
    pub sensors: Arc<SensorList>,
    /// Instructions per control cycle a script may use, when configured.
    pub cycle_budget: Option<u64>,
    /// Where `cycle_budget` came from, as the project layer words it (`the default`,
    /// `gloc.toml:3:16`, `editor setting gloc.cycleBudget`), for the editor's text.
    pub cycle_budget_from: Option<String>,
    /// Where a GLOC file's `# sensors: CRC` list is looked for as `<crc>.cac`
    /// when it is neither the active list nor the embedded one: the document's
    /// folder, the active list's, then `sensor_cache` of gloc.toml.
    pub list_folders: Vec<std::path::PathBuf>,
    /// The folder searched first for a mission's `.ma` files (`mafiles` in gloc.toml),
    /// as `gloc check` and `gloc run` search it.
    pub mafiles: Option<std::path::PathBuf>,
}

impl Context {
    /// The context of a document outside any project: `sensors`, no cycle budget, no
    /// folders to find a `# sensors:` list or `.ma` files in.
    pub fn new(sensors: Arc<SensorList>) -> Context {
        Context {
            sensors,
            cycle_budget: None,
            cycle_budget_from: None,
            list_folders: Vec::new(),
            mafiles: None,
        }
    }
}

#[derive(Clone, Debug, Default)]
pub struct Analysis {
    pub diagnostics: Vec<Diagnostic>,
    /// Labels, variables and constants with every place they are used.
    pub symbols: Vec<Symbol>,
    /// Classified pieces of the text, sorted by start, not overlapping.
    pub tokens: Vec<Token>,
    /// Foldable regions (label sections, blocks), as byte spans.
    pub folds: Vec<Span>,
    pub hints: Vec<Hint>,
    /// Where each control cycle starts (the first statement, each `yield`) with
    /// its worst-case instruction count, from the checker's cycle analysis.
    pub cycles: Vec<CycleStart>,
    /// The compiled GLOC of a GBASIC document without errors.
    pub compiled: Option<String>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SymbolKind {
    Label,
    Variable,
    Array,
    Constant,
    /// A sensor named in GBASIC (never defined in the document, not renamable).
    Sensor,
    /// A mission's `behavior:` (or a `.ma` file's `behavior_name=`).
    Behavior,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Symbol {
    pub name: String,
    pub kind: SymbolKind,
    /// Where the name is defined (not for a label only jumped to) and used.
    pub occurrences: Occurrences,
    /// The whole defining line or section (for document symbols).
    pub extent: Span,
    /// A type or a short description (`integer`, `float array(10)`, …).
    pub detail: String,
    /// Whether a rename may change it: GLOC labels are numbers and renaming
    /// one renumbers it; GBASIC names are identifiers.
    pub renamable: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TokenKind {
    Keyword,
    /// A GLOC header directive (`nregs`, `nblbs`, `ninstr`, `nmem`).
    Directive,
    Function,
    Variable,
    Constant,
    Register,
    Label,
    Number,
    String,
    Comment,
    Operator,
    SensorRead,
    SensorWrite,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Token {
    pub span: Span,
    pub kind: TokenKind,
    /// The sensor a `SensorRead`/`SensorWrite` token names (by name or by index).
    pub sensor: Option<SensorId>,
}

/// A control cycle's start: the end of the line it starts after (the first
/// instruction's, or a `yield`'s) and the most instructions it can execute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CycleStart {
    pub offset: usize,
    pub worst: gloc_engine::gloc::Bound,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Hint {
    /// Where the hint is shown (after this byte).
    pub offset: usize,
    pub label: String,
    pub tooltip: Option<String>,
    pub padding_left: bool,
}

/// Replace `span` with `new_text`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextEdit {
    pub span: Span,
    pub new_text: String,
}

/// A completion candidate, before it becomes an LSP item.
#[derive(Clone, Debug, PartialEq)]
pub struct Completion {
    pub label: String,
    pub kind: CompletionKind,
    pub detail: Option<String>,
    pub documentation: Option<String>,
    /// What goes into the text instead of the label, when not the label.
    pub insert: Option<Insert>,
    /// What the client matches typed text against, when not the label.
    pub filter_text: Option<String>,
    /// Sort key, when not the label (to rank in-scope names first).
    pub sort_text: Option<String>,
}

/// What a completion puts into the text instead of its label.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Insert {
    /// A snippet, with `$1` placeholders.
    Snippet(String),
    /// Plain text (a mission keyword with the space after its colon).
    Text(String),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompletionKind {
    Sensor,
    Keyword,
    Instruction,
    Variable,
    Constant,
    Label,
    Function,
    Register,
}

/// A built-in function's or instruction's signature, for signature help.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Signature {
    pub label: String,
    pub documentation: String,
    /// Byte ranges of each parameter within `label`.
    pub parameters: Vec<(usize, usize)>,
    pub active_parameter: usize,
}

impl Analysis {
    /// The token covering `offset` (a cursor right after a token counts).
    pub fn token_at(&self, offset: usize) -> Option<&Token> {
        let index = self
            .tokens
            .partition_point(|token| (token.span.end as usize) < offset);
        let token = self.tokens.get(index)?;
        token.span.contains(offset).then_some(token)
    }

    /// The symbol with an occurrence covering `offset`.
    pub fn symbol_at(&self, offset: usize) -> Option<(&Symbol, Span)> {
        self.symbols
            .iter()
            .find_map(|symbol| symbol.occurrences.at(offset).map(|span| (symbol, span)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn token_at_finds_the_token_under_or_just_before_the_cursor() {
        let token = |start, end| Token {
            span: Span::new(start, end),
            kind: TokenKind::Number,
            sensor: None,
        };
        let analysis = Analysis {
            tokens: vec![token(0, 3), token(5, 7)],
            ..Analysis::default()
        };
        assert_eq!(analysis.token_at(0).map(|t| t.span), Some(Span::new(0, 3)));
        assert_eq!(analysis.token_at(3).map(|t| t.span), Some(Span::new(0, 3)));
        assert_eq!(analysis.token_at(4), None);
        assert_eq!(analysis.token_at(7).map(|t| t.span), Some(Span::new(5, 7)));
        assert_eq!(analysis.token_at(8), None);
    }
}
