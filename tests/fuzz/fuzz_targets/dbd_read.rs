//! Fuzz target: the glider-log readers (binary, LZ4, .dba).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| gloc_fuzz::dbd_target::check_dbd_bytes(data));
