//! The IDE core: what the language server knows about a document, computed
//! from text and byte offsets with no protocol in sight. `analysis` is the
//! neutral shape both languages fill; `lang` dispatches on the language to its
//! adapter (`gloc_lang`, `gbasic_lang`). The `gloc-lsp` crate keeps the
//! protocol: position conversion, document state and transport.

pub mod analysis;
pub mod completion;
pub mod gbasic_lang;
pub mod gloc_lang;
pub mod lang;
pub mod lens;
pub mod links;
pub mod selection;
pub mod workspace;

/// The languages the editor tooling answers for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Language {
    Gloc,
    Gbasic,
    /// A `gloc.toml`: only its problems are reported.
    Config,
}

impl Language {
    /// From an editor's language id, falling back to the file's path (or URI
    /// path) extension.
    pub fn detect(language_id: &str, path: &str) -> Option<Language> {
        match language_id.to_ascii_lowercase().as_str() {
            "gloc" => return Some(Language::Gloc),
            "gbasic" | "gbas" => return Some(Language::Gbasic),
            _ => {}
        }
        let path = path.to_ascii_lowercase();
        if path.ends_with(".gloc") {
            Some(Language::Gloc)
        } else if path.ends_with(".gbas") || path.ends_with(".gbasic") {
            Some(Language::Gbasic)
        } else if path.ends_with("/gloc.toml") || path == "gloc.toml" {
            Some(Language::Config)
        } else {
            None
        }
    }
}
