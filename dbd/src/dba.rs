//! ASCII logs (`.dba`): dbd2asc's output and gloc's own. A header like a binary
//! log's, three label lines (names, units, byte sizes), then one line per
//! cycle with `NaN` for a sensor the cycle did not update.

use std::io::{BufReader, Read};
use std::sync::Arc;

use crate::cycle::{time_column, Cycle, FileSensor, SensorColumns, State};
use crate::error::{DbdError, Location, Warning};
use crate::header::{read_header, read_line, Header};

/// The most label lines a `.dba` may announce: dbd2asc writes 3 (names, units, byte
/// sizes). `num_label_lines: 99999999999999` had every line of a 40 MB file held as a
/// label (2.1 GB).
const MAX_LABEL_LINES: u64 = 16;

/// Streams the cycles of one `.dba` file, one line at a time.
pub struct DbaReader {
    file: String,
    input: BufReader<Box<dyn Read + Send>>,
    offset: u64,
    header: Header,
    sensors: SensorColumns,
    time: Option<usize>,
    cycle: Cycle,
    started: bool,
    done: bool,
    warnings: Vec<Warning>,
}

fn at(offset: u64) -> Location {
    Location {
        offset,
        block: None,
    }
}

impl DbaReader {
    pub fn new(source: impl Read + Send + 'static, file: &str) -> Result<DbaReader, DbdError> {
        let mut input: BufReader<Box<dyn Read + Send>> =
            BufReader::with_capacity(64 * 1024, Box::new(source));
        let mut offset = 0u64;
        let header = read_header(&mut input, &mut offset, file, at)?;
        if !header.get("dbd_label").unwrap_or("").starts_with("DBD_ASC") {
            return Err(DbdError::new(
                file,
                at(0),
                "this is not an ASCII log: its `dbd_label` is not `DBD_ASC(…)`",
            )
            .with_help("a binary log needs its glider extension (.dbd, .ebd, …)"));
        }
        let labels = header.get_number("num_label_lines").unwrap_or(3);
        if !(3..=MAX_LABEL_LINES).contains(&labels) {
            return Err(DbdError::new(
                file,
                at(0),
                format!(
                    "`num_label_lines: {labels}`: expected 3 (names, units, bytes), at most {MAX_LABEL_LINES}"
                ),
            ));
        }
        // The first three are kept; further label lines are read past, not held.
        let mut lines = Vec::with_capacity(3);
        for _ in 0..labels {
            let start = offset;
            match read_line(&mut input, &mut offset, file, at)? {
                Some(line) if lines.len() < 3 => lines.push(line),
                Some(_) => {}
                None => {
                    return Err(DbdError::new(
                        file,
                        at(start),
                        "the file ends inside its label lines",
                    ))
                }
            }
        }
        let names: Vec<&str> = lines[0].split_whitespace().collect();
        let units: Vec<&str> = lines[1].split_whitespace().collect();
        let bytes: Vec<&str> = lines[2].split_whitespace().collect();
        if units.len() != names.len() || bytes.len() != names.len() {
            return Err(DbdError::new(
                file,
                at(0),
                format!(
                    "the label lines disagree: {} names, {} units, {} byte sizes",
                    names.len(),
                    units.len(),
                    bytes.len()
                ),
            ));
        }
        if let Some(count) = header.get_number("sensors_per_cycle") {
            if count as usize != names.len() {
                return Err(DbdError::new(
                    file,
                    at(0),
                    format!(
                        "`sensors_per_cycle: {count}` but the label line names {} sensors",
                        names.len()
                    ),
                ));
            }
        }
        let sensors: Vec<FileSensor> = names
            .iter()
            .zip(&units)
            .zip(&bytes)
            .map(|((name, units), bytes)| FileSensor {
                name: name.to_string(),
                units: units.to_string(),
                bytes: bytes.parse().unwrap_or(8),
            })
            .collect();
        let mut cycle = Cycle::default();
        cycle.reset(sensors.len());
        Ok(DbaReader {
            file: file.to_string(),
            input,
            offset,
            header,
            time: time_column(&sensors),
            sensors: Arc::from(sensors),
            cycle,
            started: false,
            done: false,
            warnings: Vec::new(),
        })
    }

    fn read_row(&mut self) -> Result<bool, DbdError> {
        loop {
            if self.done {
                return Ok(false);
            }
            let start = self.offset;
            let Some(line) = read_line(&mut self.input, &mut self.offset, &self.file, at)? else {
                self.done = true;
                return Ok(false);
            };
            if line.trim().is_empty() {
                continue;
            }
            let complete = self.offset > start + line.len() as u64;
            // Every line sets every column's state; `updated` lists the numbers.
            self.cycle.updated.clear();
            let mut column = 0usize;
            let mut position = 0usize;
            for token in line.split(' ') {
                let token_at = position;
                position += token.len() + 1;
                if token.is_empty() {
                    continue;
                }
                if column >= self.sensors.len() {
                    self.done = true;
                    return Err(DbdError::new(
                        &self.file,
                        at(start + token_at as u64),
                        format!("more values than the {} sensors", self.sensors.len()),
                    ));
                }
                if token == "NaN" || token == "nan" {
                    self.cycle.states[column] = State::NotUpdated;
                } else {
                    // A 4-byte column holds a float32: reading it as one gives
                    // back exactly the value the binary log had.
                    let parsed = if self.sensors[column].bytes == 4 {
                        token.parse::<f32>().map(f64::from)
                    } else {
                        token.parse::<f64>()
                    };
                    match parsed {
                        Ok(value) => {
                            self.cycle.states[column] = State::New;
                            self.cycle.values[column] = value;
                            self.cycle.updated.push(column);
                        }
                        Err(_) => {
                            self.done = true;
                            return Err(DbdError::new(
                                &self.file,
                                at(start + token_at as u64),
                                format!(
                                    "`{token}` is not a number (sensor `{}`)",
                                    self.sensors[column].name
                                ),
                            ));
                        }
                    }
                }
                column += 1;
            }
            if column < self.sensors.len() {
                self.done = true;
                if !complete {
                    self.warnings.push(Warning {
                        file: self.file.clone(),
                        at: at(start),
                        message: format!(
                            "the file ends inside a line ({column} of {} values): the lines before it are kept",
                            self.sensors.len()
                        ),
                    });
                    return Ok(false);
                }
                return Err(DbdError::new(
                    &self.file,
                    at(start),
                    format!("{column} values for {} sensors", self.sensors.len()),
                ));
            }
            if self.started {
                self.cycle.number += 1;
            }
            self.started = true;
            self.cycle.offset = start;
            self.cycle.time = match self.time {
                Some(column) => self.cycle.value(column).unwrap_or(f64::NAN),
                None => f64::NAN,
            };
            return Ok(true);
        }
    }
}

crate::one_file_source!(DbaReader, read_row);
