//! The GBASIC compiler (filled by the compiler work).
