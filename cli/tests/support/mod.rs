//! What the CLI tests of real data share: the binary, and paths in the repository and
//! in the repository's real glider files (`data/`, through gloc_testsupport).
#![allow(dead_code)]

pub mod peer;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `gloc` binary with `args`.
pub fn gloc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gloc"))
        .args(args)
        .output()
        .expect("the gloc binary runs")
}

/// Runs the `gloc` binary with `args` in `folder` (relative outputs land there).
pub fn gloc_in(args: &[&str], folder: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gloc"))
        .args(args)
        .current_dir(folder)
        .output()
        .expect("the gloc binary runs")
}

/// An empty folder of this test process for `name` (emptied if a run left it).
pub fn temp_folder(name: &str) -> PathBuf {
    let folder = std::env::temp_dir().join(format!("gloc-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).expect("temp folder");
    folder
}

/// A path in the repository.
pub fn repo(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(path)
        .display()
        .to_string()
}

/// A real glider file in the repository's `data/` (a missing one fails the test).
pub fn real_file(path: &str) -> String {
    gloc_testsupport::data_arg(path)
}

pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}
