//! gloc-engine: the pure core of gloc. Sensor lists ("Masterdata"), the GLOC
//! language (parser, printer, safety checker) and the interpreter.
//!
//! Nothing here does network IO, starts threads or knows about LSP or DAP.

pub mod codes;
pub mod diagnostic;
pub mod files;
pub mod gloc;
pub mod lz4;
pub mod program;
pub mod render;
pub mod rng;
pub mod sensors;
pub mod suggest;
pub mod vm;

pub use diagnostic::{Diagnostic, Label, LineIndex, Occurrences, Severity, Span};
