//! Fuzz target: the mission (.mi) parser and a short simulation of what parses.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| gloc_fuzz::files_target::check_mission_bytes(data));
