//! The GBASIC compiler's diagnostic codes (E2xxx: E20xx syntax, E21xx names, E22xx
//! types, E23xx control flow and structure; W2xxx warnings). They are registered,
//! with their one-line docs, in the one registry `gloc_engine::codes`; this module
//! only brings them into the compiler's scope under their names.

pub use gloc_engine::codes::gbasic::*;
