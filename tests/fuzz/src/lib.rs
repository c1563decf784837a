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

/// One fuzz input of a text format: any bytes, checked as text when they are UTF-8.
pub fn when_text(data: &[u8], check: fn(&str)) {
    if let Ok(text) = std::str::from_utf8(data) {
        check(text);
    }
}

/// The embedded sensor list, read once for all inputs.
pub fn embedded_sensors() -> &'static gloc_engine::sensors::SensorList {
    static SENSORS: std::sync::OnceLock<gloc_engine::sensors::SensorList> =
        std::sync::OnceLock::new();
    SENSORS.get_or_init(gloc_engine::sensors::SensorList::embedded)
}
