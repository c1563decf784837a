//! The IDE core: what the language server knows about a document, computed
//! from text and byte offsets with no protocol in sight. `analysis` is the
//! neutral shape both languages fill (`lang::analyze` dispatches to the
//! adapters `gloc_lang` and `gbasic_lang`); one module per feature reads it:
//! `hover`, `completion`, `signature`, `references` (definition, references,
//! highlights), `rename`, `symbols`, `folding`, `tokens` (semantic tokens),
//! `hints`, `format`, `actions` (quick fixes, compiled GLOC), `lens` (cycle
//! figures per label), `selection`, `links` (gloc.toml paths, `args_from_file`
//! targets), `workspace` (workspace symbols), `mission` (the `.mi`/`.ma`
//! languages). The `gloc-lsp`
//! crate keeps the protocol: position conversion, document state, transport.

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

pub mod actions;
pub mod analysis;
pub mod completion;
pub mod folding;
pub mod format;
pub mod gbasic_lang;
pub mod gloc_lang;
pub mod hints;
pub mod hover;
pub mod lang;
pub mod lens;
pub mod links;
pub mod masterdata;
pub mod mission;
pub mod references;
pub mod rename;
pub mod selection;
pub mod signature;
pub mod symbols;
pub mod tokens;
pub mod workspace;

/// The kinds of document the editor tooling answers for: a script in one of the
/// two languages (`Gloc`, `Gbasic`: the compiler's [`gloc_compiler::Language`],
/// whose file extensions `detect` uses) or an editor-only kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Language {
    Gloc,
    Gbasic,
    /// A `gloc.toml`: only its problems are reported.
    Config,
    /// A Slocum mission file (`.mi`).
    Mission,
    /// A Slocum mission argument file (`.ma`).
    MissionArgs,
    /// A sensor list: a masterdata file or a `.cac` list (hover and navigation).
    Masterdata,
}

impl Language {
    /// The mission language this is, if it is one.
    pub fn mission_file(self) -> Option<mission::MissionFile> {
        match self {
            Language::Mission => Some(mission::MissionFile::Mission),
            Language::MissionArgs => Some(mission::MissionFile::Args),
            _ => None,
        }
    }

    /// The document's language: by the file's path (or URI path) when its
    /// extension or name is one of gloc's own, whatever the editor's language id
    /// says (an editor such as Emacs with eglot sends one id for every file of a
    /// server); otherwise (`untitled:` buffers, a `.txt`) by the language id.
    pub fn detect(language_id: &str, path: &str) -> Option<Language> {
        Language::of_path(path).or_else(|| Language::of_language_id(language_id))
    }

    /// By the editor's language id alone.
    pub fn of_language_id(language_id: &str) -> Option<Language> {
        match language_id.to_ascii_lowercase().as_str() {
            "gloc" => Some(Language::Gloc),
            "gbasic" | "gbas" => Some(Language::Gbasic),
            "slocum_mission" => Some(Language::Mission),
            "slocum_ma" => Some(Language::MissionArgs),
            "slocum_masterdata" => Some(Language::Masterdata),
            _ => None,
        }
    }

    /// By the path's extension or name alone: the compiler's script extensions,
    /// `.mi`, `.ma`, `.cac`, a file named `masterdata` and `gloc.toml`.
    pub fn of_path(path: &str) -> Option<Language> {
        let script = std::path::Path::new(path)
            .extension()
            .and_then(|extension| extension.to_str())
            .and_then(gloc_compiler::Language::of_extension);
        let path = path.to_ascii_lowercase();
        if let Some(script) = script {
            Some(script.into())
        } else if path.ends_with(".mi") {
            Some(Language::Mission)
        } else if path.ends_with(".ma") {
            Some(Language::MissionArgs)
        } else if path.ends_with(".cac") || path.ends_with("/masterdata") || path == "masterdata" {
            Some(Language::Masterdata)
        } else if path.ends_with("/gloc.toml") || path == "gloc.toml" {
            Some(Language::Config)
        } else {
            None
        }
    }
}

impl From<gloc_compiler::Language> for Language {
    fn from(language: gloc_compiler::Language) -> Language {
        match language {
            gloc_compiler::Language::Gloc => Language::Gloc,
            gloc_compiler::Language::Gbasic => Language::Gbasic,
        }
    }
}
