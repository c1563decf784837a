//! Tidy checks over the whole workspace, as rust-analyzer's `tidy.rs` does: every Rust
//! module opens with a `//!` line saying what it is for, and every crate takes the
//! workspace's lints (`[lints] workspace = true`), so `cargo clippy` holds each crate to
//! the same rules (no `unwrap`, no `dbg!`, no `todo!`).

use std::path::{Path, PathBuf};

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the cli crate sits inside the workspace")
        .to_path_buf()
}

/// Every `.rs` file under `dir`, skipping build output and nested workspaces.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if path.is_dir() {
            if name == "target" || name.starts_with('.') || name == "node_modules" {
                continue;
            }
            rust_files(&path, out);
        } else if name.ends_with(".rs") {
            out.push(path);
        }
    }
}

/// The workspace's member crates, read from the root Cargo.toml.
fn members(root: &Path) -> Vec<String> {
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).expect("root Cargo.toml");
    let start = manifest.find("members = [").expect("a members list");
    let end = start + manifest[start..].find(']').expect("the list closes");
    manifest[start..end]
        .split('"')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

#[test]
fn every_module_opens_with_a_doc_line() {
    let root = workspace_root();
    let mut files = Vec::new();
    for member in members(&root) {
        rust_files(&root.join(member), &mut files);
    }
    assert!(files.len() > 50, "found only {} files", files.len());
    let missing: Vec<String> = files
        .iter()
        .filter(|path| {
            let text = std::fs::read_to_string(path).unwrap_or_default();
            !text.trim_start().starts_with("//!")
        })
        .map(|path| {
            path.strip_prefix(&root)
                .unwrap_or(path)
                .display()
                .to_string()
        })
        .collect();
    assert!(
        missing.is_empty(),
        "these files do not open with a `//!` line saying what they are for:\n  {}",
        missing.join("\n  ")
    );
}

#[test]
fn every_crate_takes_the_workspace_lints() {
    let root = workspace_root();
    let root_manifest = std::fs::read_to_string(root.join("Cargo.toml")).expect("root manifest");
    for lint in ["unwrap_used", "dbg_macro", "todo"] {
        assert!(
            root_manifest.contains(&format!("{lint} = \"deny\"")),
            "the root Cargo.toml's [workspace.lints] must deny {lint}"
        );
    }
    let members = members(&root);
    assert!(members.len() >= 9, "members: {members:?}");
    for member in members {
        let manifest = std::fs::read_to_string(root.join(&member).join("Cargo.toml"))
            .expect("member manifest");
        assert!(
            manifest.contains("[lints]\nworkspace = true"),
            "{member}/Cargo.toml does not take the workspace lints (`[lints] workspace = true`)"
        );
    }
    for protocol_crate in ["lsp", "dap"] {
        let lib = std::fs::read_to_string(root.join(protocol_crate).join("src/lib.rs"))
            .expect("protocol crate lib.rs");
        assert!(
            lib.contains("#![deny(clippy::print_stdout)]"),
            "{protocol_crate}'s stdout is its protocol: its lib.rs must deny print_stdout"
        );
    }
}

/// The code literals (`"E0101"`, `"W2302"`, `"S0107"`) in the non-test part of a file
/// (before its first `#[cfg(test)]`), with their line numbers.
fn code_literals(text: &str) -> Vec<(usize, String)> {
    let code_part = text.split("#[cfg(test)]").next().unwrap_or("");
    let mut found = Vec::new();
    for (number, line) in code_part.lines().enumerate() {
        let bytes = line.as_bytes();
        for start in 0..bytes.len().saturating_sub(6) {
            let candidate = &bytes[start..start + 7];
            if candidate[0] == b'"'
                && candidate[6] == b'"'
                && matches!(candidate[1], b'E' | b'W' | b'S')
                && candidate[2..6].iter().all(u8::is_ascii_digit)
            {
                found.push((number + 1, line[start + 1..start + 6].to_string()));
            }
        }
    }
    found
}

#[test]
fn every_diagnostic_code_in_the_sources_is_registered() {
    let root = workspace_root();
    let mut files = Vec::new();
    for member in members(&root) {
        rust_files(&root.join(member).join("src"), &mut files);
    }
    let mut unregistered = Vec::new();
    let mut seen = 0;
    for path in &files {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        for (line, code) in code_literals(&text) {
            seen += 1;
            if gloc_engine::codes::lookup(&code).is_none() {
                let shown = path
                    .strip_prefix(&root)
                    .unwrap_or(path)
                    .display()
                    .to_string();
                unregistered.push(format!("{shown}:{line}: {code}"));
            }
        }
    }
    assert!(
        unregistered.is_empty(),
        "codes used but not in gloc_engine::codes (register them there, with a one-line doc, \
         and in docs/diagnostics.md):\n  {}",
        unregistered.join("\n  ")
    );
    // The registry's own table is the one place codes are written as literals.
    assert!(
        seen >= 90,
        "only {seen} code literals found: is the registry still scanned?"
    );
}
