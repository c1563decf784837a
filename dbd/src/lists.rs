//! Sensor lists of binary logs: the `s:` lines (a `.cac` file, a `.ccc`, or the
//! list inside a log whose list is not factored out) turned into file columns.

use std::collections::HashMap;

use gloc_engine::sensors::{parse_cac_entries, CacEntry};

use crate::cycle::FileSensor;
use crate::error::{DbdError, Location};

/// The text of a sensor list found for a CRC, and where it came from (for messages).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SensorListText {
    pub text: String,
    pub origin: String,
}

/// Where a reader gets a factored-out sensor list (`sensor_list_factored: 1`).
pub trait SensorLists {
    /// The list named by `crc` (lower-case hex, as in `1f35be3b.cac`), or a
    /// message saying what was searched.
    fn find(&self, crc: &str) -> Result<SensorListText, String>;
}

/// No cache: only logs that carry their own list can be read.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoSensorLists;

impl SensorLists for NoSensorLists {
    fn find(&self, crc: &str) -> Result<SensorListText, String> {
        Err(format!(
            "the sensor list {crc} is not in the file and no cache folder was given"
        ))
    }
}

/// Lists held in memory, by lower-case CRC (tests, or a caller with its own store).
impl SensorLists for HashMap<String, String> {
    fn find(&self, crc: &str) -> Result<SensorListText, String> {
        self.get(crc)
            .map(|text| SensorListText {
                text: text.clone(),
                origin: format!("{crc} (in memory)"),
            })
            .ok_or_else(|| format!("no sensor list {crc} among the {} given", self.len()))
    }
}

/// The columns of a log from its list: the entries with a column (≥ 0), in
/// column order. Checks that they are exactly `0..sensors_per_cycle`.
pub fn file_columns(
    entries: &[CacEntry],
    sensors_per_cycle: usize,
    file: &str,
    at: Location,
    origin: &str,
) -> Result<Vec<FileSensor>, DbdError> {
    let mut slots: Vec<Option<&CacEntry>> = vec![None; sensors_per_cycle];
    for entry in entries.iter().filter(|entry| entry.column >= 0) {
        let column = entry.column as usize;
        let Some(slot) = slots.get_mut(column) else {
            return Err(mismatch(
                file,
                at,
                origin,
                format!(
                    "it puts `{}` in column {column}, but the file has {sensors_per_cycle} sensors per cycle",
                    entry.name
                ),
            ));
        };
        if slot.is_some() {
            return Err(mismatch(
                file,
                at,
                origin,
                format!("column {column} appears twice (line {})", entry.line),
            ));
        }
        *slot = Some(entry);
    }
    if let Some(missing) = slots.iter().position(Option::is_none) {
        return Err(mismatch(
            file,
            at,
            origin,
            format!(
                "the file has {sensors_per_cycle} sensors per cycle but the list has no sensor in column {missing}"
            ),
        ));
    }
    Ok(slots
        .into_iter()
        .flatten()
        .map(|entry| FileSensor {
            name: entry.name.clone(),
            units: entry.units.clone(),
            bytes: entry.bytes,
        })
        .collect())
}

fn mismatch(file: &str, at: Location, origin: &str, detail: String) -> DbdError {
    DbdError::new(
        file,
        at,
        format!("the sensor list {origin} does not fit this file: {detail}"),
    )
    .with_help("the header's `sensor_list_crc` names the wrong list, or the list file is damaged")
}

/// Parses the `s:` lines of a list (from `origin`) for the log `file`; the
/// first malformed line is an error.
pub fn parse_list(
    text: &str,
    origin: &str,
    file: &str,
    at: Location,
) -> Result<Vec<CacEntry>, DbdError> {
    let (entries, diagnostics) = parse_cac_entries(text);
    if let Some(first) = diagnostics.first() {
        let line = text[..(first.span.start as usize).min(text.len())]
            .matches('\n')
            .count()
            + 1;
        return Err(DbdError::new(
            file,
            at,
            format!("sensor list {origin}, line {line}: {}", first.message),
        ));
    }
    Ok(entries)
}

/// The `sensor_list_crc` of a list: the CRC-32 (IEEE, reflected, initial value
/// 0xFFFFFFFF) of the `.cac` file's bytes *without* the final inversion, that
/// is `!crc32(bytes)`. Established on all six real lists in data/
/// (`1f35be3b.cac` … and the decompressed `06a36d4e.ccc`, `daad1b20.ccc`):
/// each file's name is this value of its contents.
pub fn sensor_list_crc(bytes: &[u8]) -> u32 {
    const TABLE: [u32; 256] = {
        let mut table = [0u32; 256];
        let mut i = 0;
        while i < 256 {
            let mut c = i as u32;
            let mut bit = 0;
            while bit < 8 {
                c = if c & 1 != 0 {
                    (c >> 1) ^ 0xEDB8_8320
                } else {
                    c >> 1
                };
                bit += 1;
            }
            table[i] = c;
            i += 1;
        }
        table
    };
    let mut crc = 0xFFFF_FFFFu32;
    for &byte in bytes {
        crc = (crc >> 8) ^ TABLE[((crc ^ byte as u32) & 0xFF) as usize];
    }
    crc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_is_the_inverted_ieee_crc32() {
        // The standard check value: CRC-32("123456789") = 0xCBF43926, so the
        // uninverted register is !0xCBF43926 = 0x340BC6D9.
        assert_eq!(sensor_list_crc(b"123456789"), 0x340B_C6D9);
        assert_eq!(sensor_list_crc(b""), 0xFFFF_FFFF);
    }
}
