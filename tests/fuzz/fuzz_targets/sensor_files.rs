//! Fuzz target: the masterdata and .cac parsers.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| gloc_fuzz::files_target::check_sensor_file_bytes(data));
