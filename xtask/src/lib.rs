//! The workspace's own tasks: `tidy`, the checks of the house's habits that the compiler
//! does not make. `cargo xtask tidy` runs them from the command line; `cargo test -p
//! xtask` (part of the README's test command) fails on any problem.

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

pub mod tidy;
