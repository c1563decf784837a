//! The binary reader: header, sensor list, known cycle, then cycle by cycle.

use std::io::{BufReader, Read};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use crate::cycle::{time_column, Cycle, FileSensor, SensorColumns, State};
use crate::error::{DbdError, Location, Warning};
use crate::header::{read_header, read_line, Header};
use crate::lists::{file_columns, parse_list, sensor_list_crc, SensorLists};
use crate::lz4::{read_full, Lz4Blocks, Lz4Problem};

/// Byte order of a log's values, fixed by its known cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ByteOrder {
    Little,
    Big,
}

type Input = BufReader<Box<dyn Read + Send>>;

/// Longest sensor list read from inside a log (a real one is about 100 kB).
const MAX_LIST_TEXT: usize = 16 << 20;

/// Streams the cycles of one binary log. Memory: one cycle and a read buffer.
pub struct DbdReader {
    file: String,
    input: Input,
    /// Decompressed-stream offset of the next byte.
    offset: u64,
    block: Option<Arc<AtomicU64>>,
    header: Header,
    sensors: SensorColumns,
    crc: String,
    order: ByteOrder,
    time: Option<usize>,
    state_bytes: usize,
    states: Vec<u8>,
    data: Vec<u8>,
    cycle: Cycle,
    started: bool,
    done: bool,
    warnings: Vec<Warning>,
}

impl DbdReader {
    /// Reads the header, the sensor list (from the file or `lists`) and the
    /// known cycle. `compressed`: the source is LZ4 blocks (.dcd …).
    pub fn new(
        source: impl Read + Send + 'static,
        file: &str,
        compressed: bool,
        lists: &dyn SensorLists,
    ) -> Result<DbdReader, DbdError> {
        let (input, block): (Box<dyn Read + Send>, _) = if compressed {
            let blocks = Lz4Blocks::new(source);
            let tracker = blocks.block_tracker();
            (Box::new(blocks), Some(tracker))
        } else {
            (Box::new(source), None)
        };
        let mut reader = DbdReader {
            file: file.to_string(),
            input: BufReader::with_capacity(64 * 1024, input),
            offset: 0,
            block,
            header: Header::default(),
            sensors: Arc::from(Vec::new()),
            crc: String::new(),
            order: ByteOrder::Little,
            time: None,
            state_bytes: 0,
            states: Vec::new(),
            data: Vec::new(),
            cycle: Cycle::default(),
            started: false,
            done: false,
            warnings: Vec::new(),
        };
        reader.open(lists)?;
        Ok(reader)
    }

    fn at(&self, offset: u64) -> Location {
        Location {
            offset,
            block: self
                .block
                .as_ref()
                .map(|block| block.load(Ordering::Relaxed)),
        }
    }

    fn error(&self, offset: u64, message: impl Into<String>) -> DbdError {
        DbdError::new(&self.file, self.at(offset), message)
    }

    /// Turns a read failure into an error, or `None` for a truncation (already warned).
    fn read_failure(&mut self, error: std::io::Error, start: u64, what: &str) -> Option<DbdError> {
        if let Some(problem) = error
            .get_ref()
            .and_then(|inner| inner.downcast_ref::<Lz4Problem>())
        {
            let at = Location {
                offset: self.offset,
                block: Some(problem.block),
            };
            if problem.truncated {
                self.warnings.push(Warning {
                    file: self.file.clone(),
                    at,
                    message: format!(
                        "{}; {what} is incomplete and dropped, the cycles before it are kept",
                        problem.message
                    ),
                });
                return None;
            }
            return Some(DbdError::new(&self.file, at, problem.message.clone()));
        }
        Some(crate::io_error(&self.file, self.at(start), &error))
    }

    fn open(&mut self, lists: &dyn SensorLists) -> Result<(), DbdError> {
        let file = self.file.clone();
        let block = self.block.clone();
        let at = move |offset| Location {
            offset,
            block: block.as_ref().map(|block| block.load(Ordering::Relaxed)),
        };
        let header = read_header(&mut self.input, &mut self.offset, &file, &at)?;
        let label = header.get("dbd_label").unwrap_or("");
        if label.starts_with("DBD_ASC") {
            return Err(self
                .error(0, "this is an ASCII log (`.dba`), not a binary one")
                .with_help("name it `.dba` so gloc reads it as text"));
        }
        let number = |key: &str| {
            header
                .get_number(key)
                .ok_or_else(|| self.error(0, format!("the header has no number `{key}:`")))
        };
        let sensors_per_cycle = number("sensors_per_cycle")? as usize;
        let total = number("total_num_sensors")? as usize;
        let state_bytes = number("state_bytes_per_cycle")? as usize;
        let factored = header.get_number("sensor_list_factored").unwrap_or(0) == 1;
        if sensors_per_cycle > 100_000 || total > 100_000 || sensors_per_cycle > total {
            return Err(self.error(
                0,
                format!("implausible sensor counts: {sensors_per_cycle} per cycle of {total}"),
            ));
        }
        if state_bytes != sensors_per_cycle.div_ceil(4) {
            return Err(self.error(
                0,
                format!(
                    "`state_bytes_per_cycle: {state_bytes}` does not fit `sensors_per_cycle: {sensors_per_cycle}` (4 sensors to a byte)"
                ),
            ));
        }
        let crc = header.sensor_list_crc().unwrap_or_default();
        let list_at = self.offset;
        let (text, origin) = if factored {
            if crc.is_empty() || !crc.bytes().all(|byte| byte.is_ascii_hexdigit()) {
                return Err(self.error(0, format!("`sensor_list_crc: {crc}` is not a CRC")));
            }
            match lists.find(&crc) {
                Ok(found) => (found.text, found.origin),
                Err(message) => {
                    return Err(DbdError::unreadable(
                        &self.file,
                        self.at(0),
                        format!("sensor list {crc} not found: {message}"),
                    )
                        .with_help(format!(
                            "put {crc}.cac (or .ccc) from the glider's cache folder in one of these folders, or name a folder with --sensor-cache"
                        )))
                }
            }
        } else {
            let mut text = String::new();
            for _ in 0..total {
                let start = self.offset;
                match read_line(&mut self.input, &mut self.offset, &file, &at)? {
                    Some(line) => {
                        text.push_str(&line);
                        text.push('\n');
                        if text.len() > MAX_LIST_TEXT {
                            return Err(self.error(
                                start,
                                format!(
                                    "the sensor list in the file is longer than {} MB",
                                    MAX_LIST_TEXT >> 20
                                ),
                            ));
                        }
                    }
                    None => return Err(self.error(start, "the file ends inside its sensor list")),
                }
            }
            (text, format!("in {file}"))
        };
        let entries = parse_list(&text, &origin, &file, self.at(list_at))?;
        let fits = file_columns(
            &entries,
            sensors_per_cycle,
            &file,
            self.at(list_at),
            &origin,
        );
        let actual = format!("{:08x}", sensor_list_crc(text.as_bytes()));
        if !crc.is_empty() && actual != crc {
            let message = format!(
                "the header's `sensor_list_crc: {crc}` is not the CRC of the sensor list {origin}, which is {actual}"
            );
            match &fits {
                Ok(_) => self.warnings.push(Warning {
                    file: file.clone(),
                    at: self.at(0),
                    message: format!("{message}; the list fits the file, so it is read with it"),
                }),
                Err(error) => {
                    return Err(self.error(0, format!("{message}: {}", error.message)).with_help(
                        "the list is not the one this file was written with: find the right `.cac` in the glider's cache folder",
                    ))
                }
            }
        }
        let columns: Vec<FileSensor> = fits?;
        self.time = time_column(&columns);
        self.sensors = Arc::from(columns);
        self.crc = crc;
        self.header = header;
        self.state_bytes = state_bytes;
        self.states = vec![0; state_bytes];
        self.read_known_cycle()?;
        self.cycle.reset(self.sensors.len());
        Ok(())
    }

    fn read_known_cycle(&mut self) -> Result<(), DbdError> {
        let start = self.offset;
        let mut known = [0u8; 16];
        let got = match read_full(&mut self.input, &mut known) {
            Ok(got) => got,
            Err(error) => {
                return Err(self
                    .read_failure(error, start, "the known cycle")
                    .unwrap_or_else(|| self.error(start, "the file ends inside its known cycle")))
            }
        };
        self.offset += got as u64;
        if got < 16 {
            return Err(self.error(start, "the file ends inside its known cycle"));
        }
        if known[0] != b's' {
            return Err(self.error(
                start,
                format!(
                    "expected the known cycle's tag `s`, found byte 0x{:02x}",
                    known[0]
                ),
            ));
        }
        self.order = match [known[2], known[3]] {
            [0x12, 0x34] => ByteOrder::Big,
            [0x34, 0x12] => ByteOrder::Little,
            other => {
                return Err(self.error(
                    start + 2,
                    format!(
                    "the known cycle's 0x1234 reads {:02x} {:02x}: the byte order cannot be told",
                    other[0], other[1]
                ),
                ))
            }
        };
        let float = decode(&known[4..8], self.order);
        let double = decode(&known[8..16], self.order);
        if float != 123.456f32 as f64 || double != 123_456_789.123_45 {
            return Err(self.error(
                start + 4,
                format!("the known cycle's 123.456 and 123456789.12345 read {float} and {double}"),
            ));
        }
        Ok(())
    }

    /// The sensor list's CRC (lower case) as the header gives it.
    pub fn sensor_list_crc(&self) -> &str {
        &self.crc
    }

    pub fn byte_order(&self) -> ByteOrder {
        self.order
    }

    fn read_cycle(&mut self) -> Result<bool, DbdError> {
        if self.done {
            return Ok(false);
        }
        let start = self.offset;
        let mut tag = [0u8; 1];
        let got = match read_full(&mut self.input, &mut tag) {
            Ok(got) => got,
            Err(error) => return self.stop(error, start, "the next cycle"),
        };
        if got == 0 {
            self.done = true;
            if self.block.is_some() {
                // The compressed files gliders write end after their last
                // cycle, without the tag (01600000.dcd and .ecd do).
                return Ok(false);
            }
            self.warnings.push(Warning {
                file: self.file.clone(),
                at: self.at(start),
                message: "the file ends without its end tag `X`: it may be truncated".into(),
            });
            return Ok(false);
        }
        self.offset += 1;
        match tag[0] {
            b'd' => {}
            b'X' => {
                self.done = true;
                return Ok(false);
            }
            other => {
                self.done = true;
                return Err(self.error(
                    start,
                    format!(
                        "expected a cycle tag `d` or the end tag `X`, found byte 0x{other:02x}"
                    ),
                ));
            }
        }
        let got = match read_full(&mut self.input, &mut self.states) {
            Ok(got) => got,
            Err(error) => return self.stop(error, start, "the last cycle"),
        };
        self.offset += got as u64;
        if got < self.state_bytes {
            return Ok(self.truncated(start));
        }
        let sensors = Arc::clone(&self.sensors);
        self.cycle.clear_updates();
        // Four sensors a state byte; a zero byte (four not updated, most of a wide
        // log's) is skipped whole, so a cycle costs its updates, not its columns.
        let mut length = 0usize;
        for (index, &byte) in self.states.iter().enumerate() {
            if byte == 0 {
                continue;
            }
            for slot in 0..4 {
                let column = 4 * index + slot;
                let Some(sensor) = sensors.get(column) else {
                    break;
                };
                let state = match (byte >> (6 - 2 * slot)) & 3 {
                    0 => continue,
                    1 => State::Same,
                    2 => {
                        length += sensor.bytes as usize;
                        State::New
                    }
                    _ => {
                        self.done = true;
                        return Err(self.error(
                            start + 1 + index as u64,
                            format!("state bits 11 (not a state) for `{}`", sensor.name),
                        ));
                    }
                };
                self.cycle.states[column] = state;
                self.cycle.updated.push(column);
            }
        }
        self.data.resize(length, 0);
        let got = match read_full(&mut self.input, &mut self.data) {
            Ok(got) => got,
            Err(error) => return self.stop(error, start, "the last cycle"),
        };
        self.offset += got as u64;
        if got < length {
            return Ok(self.truncated(start));
        }
        // The new values follow in column order, as `updated` lists the columns.
        let mut at = 0usize;
        for &column in &self.cycle.updated {
            if self.cycle.states[column] == State::New {
                let size = sensors[column].bytes as usize;
                self.cycle.values[column] = decode(&self.data[at..at + size], self.order);
                at += size;
            }
        }
        if self.started {
            self.cycle.number += 1;
        }
        self.started = true;
        self.cycle.offset = start;
        self.cycle.time = match self.time {
            Some(column) if self.cycle.states[column].is_updated() => self.cycle.values[column],
            _ => f64::NAN,
        };
        Ok(true)
    }

    fn truncated(&mut self, start: u64) -> bool {
        self.done = true;
        self.warnings.push(Warning {
            file: self.file.clone(),
            at: self.at(start),
            message: format!(
                "the file ends inside a cycle (it has {} bytes after the cycle's start): the {} complete cycles before it are kept",
                self.offset - start,
                if self.started { self.cycle.number + 1 } else { 0 }
            ),
        });
        false
    }

    fn stop(&mut self, error: std::io::Error, start: u64, what: &str) -> Result<bool, DbdError> {
        self.done = true;
        match self.read_failure(error, start, what) {
            Some(error) => Err(error),
            None => Ok(false),
        }
    }
}

/// One value of 1, 2, 4 or 8 bytes: i8, i16, f32, f64.
pub(crate) fn decode(bytes: &[u8], order: ByteOrder) -> f64 {
    macro_rules! read {
        ($type:ty, $n:literal) => {{
            let mut raw = [0u8; $n];
            raw.copy_from_slice(bytes);
            match order {
                ByteOrder::Little => <$type>::from_le_bytes(raw) as f64,
                ByteOrder::Big => <$type>::from_be_bytes(raw) as f64,
            }
        }};
    }
    match bytes.len() {
        1 => bytes[0] as i8 as f64,
        2 => read!(i16, 2),
        4 => read!(f32, 4),
        8 => read!(f64, 8),
        _ => f64::NAN,
    }
}

crate::one_file_source!(DbdReader, read_cycle);
