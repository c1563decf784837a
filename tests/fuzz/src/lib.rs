//! The checks behind the fuzz targets, as plain functions so that the seed
//! corpus can also be replayed by `cargo test` here without libFuzzer.
//!
//! Each function panics (and so makes libFuzzer report a crash) when an
//! invariant breaks: a panic inside the core, a span out of bounds, or a
//! differential oracle that disagrees.

pub mod dbd_target;
pub mod files_target;
pub mod gbasic_target;
pub mod gloc_target;
pub mod lsp_target;
