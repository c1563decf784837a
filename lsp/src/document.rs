//! An open document: its text as a rope (for incremental edits), a flat copy
//! for the core (which takes `&str`), its language and version.

use std::path::PathBuf;

use ropey::Rope;
use tower_lsp_server::ls_types::{TextDocumentContentChangeEvent, Uri};

use crate::position;

pub use gloc_ide::Language;

/// The document's language: the file extension of its URI when it is one of
/// gloc's own, else the client's `languageId` ([`Language::detect`]).
pub fn detect_language(language_id: &str, uri: &Uri) -> Option<Language> {
    Language::detect(language_id, uri.path().as_str())
}

#[derive(Debug)]
pub struct Document {
    pub uri: Uri,
    pub language: Language,
    pub version: i32,
    rope: Rope,
    /// `rope` as one string, rebuilt after each batch of edits.
    text: String,
}

impl Document {
    pub fn new(uri: Uri, language: Language, version: i32, text: &str) -> Document {
        Document {
            uri,
            language,
            version,
            rope: Rope::from_str(text),
            text: text.to_string(),
        }
    }

    pub fn text(&self) -> &str {
        &self.text
    }

    pub fn rope(&self) -> &Rope {
        &self.rope
    }

    /// The file this document is, when its URI is a `file:` URI.
    pub fn path(&self) -> Option<PathBuf> {
        if self.uri.scheme().as_str().eq_ignore_ascii_case("file") {
            self.uri.to_file_path().map(|path| path.into_owned())
        } else {
            None
        }
    }

    /// Applies one `didChange` batch in order. A change with a range replaces
    /// that range (clamped to the document); one without replaces everything.
    pub fn apply_changes(&mut self, version: i32, changes: Vec<TextDocumentContentChangeEvent>) {
        for change in changes {
            match change.range {
                Some(range) => {
                    let start = position::char_index_of(&self.rope, range.start)
                        .unwrap_or(self.rope.len_chars());
                    let end = position::char_index_of(&self.rope, range.end)
                        .unwrap_or(self.rope.len_chars())
                        .max(start);
                    self.rope.remove(start..end);
                    self.rope.insert(start, &change.text);
                }
                None => self.rope = Rope::from_str(&change.text),
            }
        }
        self.text = self.rope.to_string();
        self.version = version;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tower_lsp_server::ls_types::{Position, Range};

    fn change(range: Option<(u32, u32, u32, u32)>, text: &str) -> TextDocumentContentChangeEvent {
        TextDocumentContentChangeEvent {
            range: range.map(|(l1, c1, l2, c2)| Range {
                start: Position {
                    line: l1,
                    character: c1,
                },
                end: Position {
                    line: l2,
                    character: c2,
                },
            }),
            range_length: None,
            text: text.to_string(),
        }
    }

    fn uri(text: &str) -> Uri {
        text.parse().expect("uri")
    }

    #[test]
    fn incremental_edits_with_non_ascii_text() {
        let mut document = Document::new(
            uri("file:///a.gbas"),
            Language::Gbasic,
            1,
            "x = 1 ' 𝄞é\ny = 2\n",
        );
        // Replace "é" (UTF-16 column 10..11 after the 2-unit '𝄞').
        document.apply_changes(2, vec![change(Some((0, 10, 0, 11)), "ü")]);
        assert_eq!(document.text(), "x = 1 ' 𝄞ü\ny = 2\n");
        // Insert across lines, then delete a line break.
        document.apply_changes(
            3,
            vec![
                change(Some((1, 0, 1, 0)), "z = 3\n"),
                change(Some((0, 11, 1, 0)), " "),
            ],
        );
        assert_eq!(document.text(), "x = 1 ' 𝄞ü z = 3\ny = 2\n");
        assert_eq!(document.version, 3);
    }

    #[test]
    fn out_of_range_edits_are_clamped_and_full_replacement_works() {
        let mut document = Document::new(uri("file:///a.gloc"), Language::Gloc, 1, "ab");
        document.apply_changes(2, vec![change(Some((5, 0, 9, 9)), "!")]);
        assert_eq!(document.text(), "ab!");
        document.apply_changes(3, vec![change(Some((0, 2, 0, 1)), "?")]);
        assert_eq!(document.text(), "ab?!");
        document.apply_changes(4, vec![change(None, "new")]);
        assert_eq!(document.text(), "new");
    }

    #[test]
    fn language_from_id_or_extension() {
        assert_eq!(
            detect_language("gloc", &uri("untitled:1")),
            Some(Language::Gloc)
        );
        assert_eq!(
            detect_language("plaintext", &uri("file:///x/y.GBAS")),
            Some(Language::Gbasic)
        );
        assert_eq!(
            detect_language("toml", &uri("file:///x/gloc.toml")),
            Some(Language::Config)
        );
        // The compiler's extensions: what `gloc check` reads as GBASIC, the editor does.
        assert_eq!(
            detect_language("plaintext", &uri("file:///x/old.bas")),
            Some(Language::Gbasic)
        );
        assert_eq!(
            detect_language("plaintext", &uri("file:///x/y.gbasic")),
            Some(Language::Gbasic)
        );
        assert_eq!(detect_language("rust", &uri("file:///x/y.rs")), None);
        // The extension wins over a language id that disagrees (Emacs with eglot
        // sends one id for every file of a server); a `.txt` keeps the client's.
        assert_eq!(
            detect_language("gbasic", &uri("file:///x/fig2.gloc")),
            Some(Language::Gloc)
        );
        assert_eq!(
            detect_language("gbasic", &uri("file:///g/missions/nsb3.mi")),
            Some(Language::Mission)
        );
        assert_eq!(
            detect_language("gloc", &uri("file:///x/fig3.gbas")),
            Some(Language::Gbasic)
        );
        assert_eq!(
            detect_language("gbasic", &uri("file:///g/mafiles/yo10.ma")),
            Some(Language::MissionArgs)
        );
        assert_eq!(
            detect_language("gloc", &uri("file:///x/notes.txt")),
            Some(Language::Gloc)
        );
        assert_eq!(
            detect_language("slocum_mission", &uri("untitled:2")),
            Some(Language::Mission)
        );
        assert_eq!(
            detect_language("plaintext", &uri("file:///g/missions/NSB3.MI")),
            Some(Language::Mission)
        );
        assert_eq!(
            detect_language("slocum_ma", &uri("untitled:3")),
            Some(Language::MissionArgs)
        );
        assert_eq!(
            detect_language("plaintext", &uri("file:///g/mafiles/yo10.ma")),
            Some(Language::MissionArgs)
        );
        assert_eq!(
            detect_language("plaintext", &uri("file:///g/cac/813B137D.CAC")),
            Some(Language::Masterdata)
        );
        assert_eq!(
            detect_language("plaintext", &uri("file:///g/config/masterdata")),
            Some(Language::Masterdata)
        );
        assert_eq!(
            detect_language("slocum_masterdata", &uri("untitled:4")),
            Some(Language::Masterdata)
        );
    }
}
