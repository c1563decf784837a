//! `cargo xtask tidy`: prints every problem the tidy checks find; exit 1 if any.

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

use std::process::ExitCode;

fn main() -> ExitCode {
    let task = std::env::args().nth(1).unwrap_or_default();
    if task != "tidy" {
        eprintln!("usage: cargo xtask tidy   (the workspace's tidy checks; xtask/src/tidy.rs)");
        return ExitCode::from(2);
    }
    let problems = xtask::tidy::all(&xtask::tidy::workspace_root());
    for problem in &problems {
        println!("{problem}");
    }
    if problems.is_empty() {
        println!("tidy: no problems");
        ExitCode::SUCCESS
    } else {
        println!("tidy: {} problems", problems.len());
        ExitCode::from(1)
    }
}
