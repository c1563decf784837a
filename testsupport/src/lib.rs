//! What the tests of every crate share: the real glider files kept in the repository's
//! `data/` folder (found by one locator that fails loudly), paths in the repository,
//! scratch folders, the one seeded random-number generator (re-exported from the
//! engine), the one format for expected diagnostics ([`annotate`]), and the reader of a
//! language server's framed messages ([`read_frame`]).
//!
//! A test that needs a real file calls [`data`]; a missing file is a failure that names
//! the path, never a silent skip.

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

use std::path::{Path, PathBuf};

/// The repository's root folder (the workspace, one level above this crate).
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")))
}

/// A real glider file or folder in the repository's `data/` (see `data/README.md` for
/// where each came from). Panics, naming the path, when it is missing: the files are part
/// of the repository, so a missing one is a broken checkout, not a reason to skip.
pub fn data(relative: &str) -> PathBuf {
    let path = repo_root().join("data").join(relative);
    if !path.exists() {
        panic!(
            "the real glider file {} is missing: it belongs to the repository (data/README.md); \
             restore it with `git checkout -- data`",
            path.display()
        );
    }
    path
}

/// A text file of the repository's `data/` ([`data`]) and its path. Panics, naming the
/// path, when it cannot be read.
pub fn data_text(relative: &str) -> (PathBuf, String) {
    let path = data(relative);
    match std::fs::read_to_string(&path) {
        Ok(text) => (path, text),
        Err(error) => panic!(
            "cannot read {} ({error}): a file of the repository's data/",
            path.display()
        ),
    }
}

/// The names of the entries of `dir`, sorted: what a test that checks which files a
/// command left behind compares.
pub fn file_names(dir: &Path) -> Vec<String> {
    let entries = std::fs::read_dir(dir)
        .unwrap_or_else(|error| panic!("cannot list {} ({error})", dir.display()));
    let mut names: Vec<String> = entries
        .map(|entry| match entry {
            Ok(entry) => entry.file_name().to_string_lossy().into_owned(),
            Err(error) => panic!("cannot list {} ({error})", dir.display()),
        })
        .collect();
    names.sort();
    names
}

/// [`data`] as a display string, for command lines.
pub fn data_arg(relative: &str) -> String {
    data(relative).display().to_string()
}

/// A scratch folder for a test's files: `$TMPDIR/gloc-NAME-PID`, emptied the first time
/// this process asks for it, then shared by the process's tests (each names its own
/// files). A folder left by an earlier run whose process had the same id must not leak
/// its files into this one: a `.cac` list left beside a script changed what `gloc check`
/// found, and failed a clean-clone CI run.
pub fn scratch_dir(name: &str) -> PathBuf {
    static FRESH: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());
    let dir = std::env::temp_dir().join(format!("gloc-{name}-{}", std::process::id()));
    let mut fresh = FRESH
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if !fresh.iter().any(|seen| seen == name) {
        fresh.push(name.to_string());
        let _ = std::fs::remove_dir_all(&dir);
    }
    if let Err(error) = std::fs::create_dir_all(&dir) {
        panic!("cannot make the scratch folder {}: {error}", dir.display());
    }
    dir
}

/// The body of one message framed as the language server protocol frames it
/// (`Content-Length: N`, other headers, a blank line, N bytes); `None` at the end of
/// the stream. Panics on a read error or a message without its length: what a test
/// client of a server reads.
pub async fn read_frame<R: tokio::io::AsyncBufRead + Unpin>(reader: &mut R) -> Option<Vec<u8>> {
    use tokio::io::{AsyncBufReadExt, AsyncReadExt};
    let mut length = None;
    loop {
        let mut line = String::new();
        let read = reader.read_line(&mut line).await.expect("read a header");
        if read == 0 {
            return None;
        }
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some(value) = line.strip_prefix("Content-Length: ") {
            length = Some(value.parse::<usize>().expect("a length"));
        }
    }
    let mut body = vec![0; length.expect("a Content-Length header")];
    reader.read_exact(&mut body).await.expect("read the body");
    Some(body)
}

/// The one seeded generator (SplitMix64, `gloc_engine::rng`), for property tests.
pub use gloc_engine::rng::Rng;

mod annotate;
pub use annotate::{annotate, diagnostic_notes, expect_diagnostics};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scratch_folder_starts_empty_once_per_process() {
        let dir = scratch_dir("testsupport-self");
        std::fs::write(dir.join("left.txt"), "x").expect("write");
        // Asked again by the same process: shared, not emptied.
        assert!(scratch_dir("testsupport-self").join("left.txt").exists());
        // What an earlier process left: emptied on first use.
        let stale =
            std::env::temp_dir().join(format!("gloc-testsupport-stale-{}", std::process::id()));
        std::fs::create_dir_all(&stale).expect("dir");
        std::fs::write(stale.join("old.cac"), "x").expect("write");
        assert!(!scratch_dir("testsupport-stale").join("old.cac").exists());
    }

    #[test]
    fn the_data_folder_is_found_and_a_missing_file_fails_loudly() {
        assert!(data("comet/missions/nsb3.mi").is_file());
        let missing = std::panic::catch_unwind(|| data("no/such/file.dbd"));
        assert!(missing.is_err());
    }
}
