//! Fuzz target: random `didChange` sequences against the language server.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| gloc_fuzz::lsp_target::check_lsp_edits_bytes(data));
