//! Chooses the interpreter's dispatch for this build: threaded dispatch
//! (`src/vm/threaded.rs`) only when the optimiser runs, because it relies on
//! LLVM turning each handler's tail call into a jump, which it does not do at
//! `opt-level` 0 (there every op would add a stack frame).
//! `tests/tail_calls.rs` checks the release build's handlers.

fn main() {
    println!("cargo::rustc-check-cfg=cfg(gloc_threaded)");
    println!("cargo::rerun-if-changed=build.rs");
    let opt_level = std::env::var("OPT_LEVEL").unwrap_or_default();
    if matches!(opt_level.as_str(), "2" | "3" | "s" | "z") {
        println!("cargo::rustc-cfg=gloc_threaded");
    }
}
