//! Writing binary logs as the glider does: a header with the sensor list
//! factored out into `<crc>.cac`, the known cycle, then per cycle the state
//! bits and only the values that changed, and the end tag `X`.

use std::io::{self, Write};

use crate::cycle::FileSensor;
use crate::lists::sensor_list_crc;

/// One sensor of the glider's whole list, for the `.cac` file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ListSensor {
    pub name: String,
    pub units: String,
    /// 1, 2, 4 or 8.
    pub bytes: u8,
    /// Logged in this file (it gets a column).
    pub logged: bool,
}

/// A sensor list as written: the `.cac` text, its CRC and the logged columns.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WrittenList {
    /// The `.cac` file's contents.
    pub text: String,
    /// `sensor_list_crc`, 8 lower-case hex digits: the `.cac` file's name.
    pub crc: String,
    /// The logged sensors, in column order.
    pub columns: Vec<FileSensor>,
    pub total: usize,
}

impl WrittenList {
    /// Lines as the glider writes them: `s: T|F INDEX COLUMN BYTES NAME UNITS`,
    /// index and column right-aligned in 4 characters, column −1 when not logged.
    pub fn new(sensors: &[ListSensor]) -> WrittenList {
        let mut text = String::new();
        let mut columns = Vec::new();
        for (index, sensor) in sensors.iter().enumerate() {
            let column = if sensor.logged {
                columns.push(FileSensor {
                    name: sensor.name.clone(),
                    units: sensor.units.clone(),
                    bytes: sensor.bytes,
                });
                columns.len() as i64 - 1
            } else {
                -1
            };
            let units = if sensor.units.is_empty() {
                "nodim"
            } else {
                sensor.units.as_str()
            };
            text.push_str(&format!(
                "s: {} {index:>4} {column:>4} {} {} {units}\n",
                if sensor.logged { 'T' } else { 'F' },
                sensor.bytes,
                sensor.name,
            ));
        }
        WrittenList {
            crc: format!("{:08x}", sensor_list_crc(text.as_bytes())),
            text,
            columns,
            total: sensors.len(),
        }
    }
}

/// The header facts of a written log.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LogIdentity {
    /// E.g. `gloc-2019-222-0-0`.
    pub full_filename: String,
    /// E.g. `00000000`.
    pub the8x3_filename: String,
    /// `dbd` or `ebd`.
    pub filename_extension: String,
    pub mission_name: String,
    /// `Wed_Aug_21_13:54:25_2019`.
    pub fileopen_time: String,
}

/// Streams a binary log, little-endian. Memory: one cycle.
pub struct DbdWriter<W: Write> {
    out: W,
    sizes: Vec<u8>,
    /// The bytes last written per column (None before the first value).
    last: Vec<Option<[u8; 8]>>,
    record: Vec<u8>,
    cycles: u64,
}

impl<W: Write> DbdWriter<W> {
    /// Writes the header (`sensor_list_factored: 1`) and the known cycle.
    pub fn new(mut out: W, identity: &LogIdentity, list: &WrittenList) -> io::Result<DbdWriter<W>> {
        let count = list.columns.len();
        let fields = [
            ("dbd_label", "DBD(dinkum_binary_data)file".to_string()),
            ("encoding_ver", "5".to_string()),
            ("num_ascii_tags", "14".to_string()),
            (
                "all_sensors",
                if count == list.total { "T" } else { "F" }.to_string(),
            ),
            ("the8x3_filename", identity.the8x3_filename.clone()),
            ("full_filename", identity.full_filename.clone()),
            ("filename_extension", identity.filename_extension.clone()),
            ("mission_name", identity.mission_name.clone()),
            ("fileopen_time", identity.fileopen_time.clone()),
            ("total_num_sensors", list.total.to_string()),
            ("sensors_per_cycle", count.to_string()),
            ("state_bytes_per_cycle", count.div_ceil(4).to_string()),
            ("sensor_list_crc", list.crc.clone()),
            ("sensor_list_factored", "1".to_string()),
        ];
        for (key, value) in fields {
            writeln!(out, "{key}:    {value}")?;
        }
        let mut known = Vec::with_capacity(16);
        known.extend_from_slice(b"sa");
        known.extend_from_slice(&0x1234i16.to_le_bytes());
        known.extend_from_slice(&123.456f32.to_le_bytes());
        known.extend_from_slice(&123_456_789.123_45f64.to_le_bytes());
        out.write_all(&known)?;
        Ok(DbdWriter {
            out,
            sizes: list.columns.iter().map(|sensor| sensor.bytes).collect(),
            last: vec![None; count],
            record: Vec::new(),
            cycles: 0,
        })
    }

    /// Writes one cycle: a column whose encoded value differs from the last one
    /// written is a new value (state 2); an unchanged one is not updated (0),
    /// as the glider logs a sensor nobody changed. NaN is a value like any other.
    pub fn write_cycle(&mut self, values: &[f64]) -> io::Result<()> {
        let count = self.sizes.len();
        let state_bytes = count.div_ceil(4);
        self.record.clear();
        self.record.push(b'd');
        self.record.resize(1 + state_bytes, 0);
        for column in 0..count {
            let value = values.get(column).copied().unwrap_or(f64::NAN);
            let size = self.sizes[column] as usize;
            let mut encoded = [0u8; 8];
            encode(value, size, &mut encoded);
            if self.last[column] == Some(encoded) {
                continue;
            }
            self.last[column] = Some(encoded);
            self.record[1 + column / 4] |= 2 << (6 - 2 * (column % 4));
            self.record.extend_from_slice(&encoded[..size]);
        }
        self.cycles += 1;
        self.out.write_all(&self.record)
    }

    pub fn cycles(&self) -> u64 {
        self.cycles
    }

    /// Writes the end tag `X` and flushes.
    pub fn finish(mut self) -> io::Result<W> {
        self.out.write_all(b"X")?;
        self.out.flush()?;
        Ok(self.out)
    }
}

/// `value` as the glider stores a sensor of `size` bytes, little-endian: i8 and
/// i16 rounded and saturated, f32, f64.
fn encode(value: f64, size: usize, out: &mut [u8; 8]) {
    match size {
        1 => out[0] = (value.round() as i8) as u8,
        2 => out[..2].copy_from_slice(&(value.round() as i16).to_le_bytes()),
        4 => out[..4].copy_from_slice(&(value as f32).to_le_bytes()),
        _ => out.copy_from_slice(&value.to_le_bytes()),
    }
}
