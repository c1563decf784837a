//! Workspace symbols: which scripts of the workspace folders are read (bounded
//! in count, size and depth), which of their symbols are listed, and how a
//! query picks and orders them (the completion matcher).

use std::path::PathBuf;

use crate::analysis::{Analysis, Symbol, SymbolKind};
use crate::completion::match_class;
use crate::Language;

/// At most this many scripts are read from disk.
pub const MAX_FILES: usize = 2_000;
/// A script larger than this is skipped (open documents are always searched).
pub const MAX_FILE_BYTES: u64 = 1 << 20;
/// At most this many bytes of scripts in all.
pub const MAX_TOTAL_BYTES: u64 = 64 << 20;
/// Folders deeper than this below a workspace folder are not entered.
pub const MAX_DEPTH: usize = 12;
/// At most this many symbols in one answer.
pub const MAX_RESULTS: usize = 500;

/// A script found on disk.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScriptFile {
    pub path: PathBuf,
    pub language: Language,
    pub bytes: u64,
    pub modified: Option<std::time::SystemTime>,
}

/// The `.gbas`/`.gloc` scripts under `roots`, in a stable order, within the bounds
/// above. Hidden folders, `target` and `node_modules` are skipped, and so are
/// symbolic links (no cycles).
pub fn script_files(roots: &[PathBuf]) -> Vec<ScriptFile> {
    let mut found = Vec::new();
    let mut total = 0u64;
    let mut pending: Vec<(PathBuf, usize)> = roots.iter().map(|root| (root.clone(), 0)).collect();
    pending.reverse();
    while let Some((folder, depth)) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(&folder) else {
            continue;
        };
        let mut entries: Vec<_> = entries.flatten().collect();
        entries.sort_by_key(|entry| entry.file_name());
        let mut subfolders = Vec::new();
        for entry in entries {
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            let name = entry.file_name();
            let name = name.to_string_lossy();
            if kind.is_dir() {
                let skipped = name.starts_with('.') || name == "target" || name == "node_modules";
                if !skipped && depth < MAX_DEPTH {
                    subfolders.push((entry.path(), depth + 1));
                }
                continue;
            }
            if !kind.is_file() {
                continue;
            }
            let path = entry.path();
            let Some(language) = Language::detect("", &path.to_string_lossy())
                .filter(|language| matches!(language, Language::Gloc | Language::Gbasic))
            else {
                continue;
            };
            let Ok(metadata) = entry.metadata() else {
                continue;
            };
            if metadata.len() > MAX_FILE_BYTES || total + metadata.len() > MAX_TOTAL_BYTES {
                continue;
            }
            total += metadata.len();
            found.push(ScriptFile {
                path,
                language,
                bytes: metadata.len(),
                modified: metadata.modified().ok(),
            });
            if found.len() >= MAX_FILES {
                return found;
            }
        }
        pending.extend(subfolders.into_iter().rev());
    }
    found
}

/// The symbols a workspace search lists: defined labels, variables, arrays and
/// constants (sensors are not the workspace's).
pub fn listed(analysis: &Analysis) -> impl Iterator<Item = &Symbol> {
    analysis.symbols.iter().filter(|symbol| {
        symbol.occurrences.definition.is_some() && symbol.kind != SymbolKind::Sensor
    })
}

/// Whether `name` answers `query`, and how well (lower is better; the completion
/// matcher's classes).
pub fn query_class(query: &str, name: &str) -> Option<u32> {
    match_class(query.trim(), name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_scripts_skipping_hidden_target_and_other_files() {
        let root = gloc_testsupport::scratch_dir("ide-ws");
        for folder in ["a/b", ".git", "target/debug", "node_modules/x"] {
            std::fs::create_dir_all(root.join(folder)).expect("folder");
        }
        for file in [
            "z.gbas",
            "a/b/c.gloc",
            "a/notes.txt",
            "a/m.mi",
            ".git/d.gbas",
            "target/debug/e.gbas",
            "node_modules/x/f.gloc",
        ] {
            std::fs::write(root.join(file), "yield\n").expect("file");
        }
        let found: Vec<String> = script_files(std::slice::from_ref(&root))
            .iter()
            .map(|file| {
                file.path
                    .strip_prefix(&root)
                    .expect("under root")
                    .display()
                    .to_string()
            })
            .collect();
        assert_eq!(found, ["z.gbas", "a/b/c.gloc"]);
        std::fs::remove_dir_all(&root).expect("clean up");
    }
}
