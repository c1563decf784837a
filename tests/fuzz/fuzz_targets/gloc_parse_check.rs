//! Fuzz target: GLOC parse, print round trip, check and a bounded run.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| gloc_fuzz::when_text(
    data,
    gloc_fuzz::gloc_target::check_gloc
));
