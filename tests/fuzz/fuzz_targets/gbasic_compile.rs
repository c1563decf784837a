//! Fuzz target: GBASIC compile (plain and -O), the checker on its output, and the -O differential run.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| gloc_fuzz::when_text(
    data,
    gloc_fuzz::gbasic_target::check_gbasic
));
