//! Replay inputs: recorded control cycles of (sensor name → value), from a CSV file
//! or from real glider logs (`gloc-dbd`: `.dbd .ebd .sbd .tbd …`, compressed, `.dba`;
//! several files are a deployment in time order, a flight log merged with its science
//! log), mapped by name onto the active sensor list. `gloc run --replay` streams an
//! [`Input`]; the debugger holds a whole [`Recording`] so it can step back.
//!
//! Decision: the script is checked against the active list (`--masterdata`,
//! `gloc.toml`, the embedded list), never against the data's own list, and the data's
//! sensors are matched to it by name; a sensor of the data that the active list lacks
//! is ignored, and all of them are named in one warning ([`ColumnMap::warning`]).

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

use std::path::{Path, PathBuf};

use gloc_dbd::{CycleSource, Deployment};
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::{suggest, LineIndex};

/// A replay input that cannot be read: the message names the file and the place
/// (`path:line:col` in a CSV file, the byte offset in a glider log).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct ReplayError {
    pub message: String,
    pub kind: ReplayErrorKind,
}

/// What a [`ReplayError`] is about, for the front ends' exit codes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReplayErrorKind {
    /// The files asked for do not make a replay (none, or a CSV among logs).
    Usage,
    /// A file (or a log's sensor list) cannot be opened or read.
    Unreadable,
    /// A file's contents are wrong (a CSV cell, a corrupt log).
    Content,
}

impl ReplayError {
    fn usage(message: impl Into<String>) -> ReplayError {
        ReplayError {
            message: message.into(),
            kind: ReplayErrorKind::Usage,
        }
    }

    fn content(message: impl Into<String>) -> ReplayError {
        ReplayError {
            message: message.into(),
            kind: ReplayErrorKind::Content,
        }
    }
}

impl From<gloc_dbd::DbdError> for ReplayError {
    fn from(error: gloc_dbd::DbdError) -> ReplayError {
        ReplayError {
            message: error.to_string(),
            kind: match error.kind {
                gloc_dbd::DbdErrorKind::Unreadable => ReplayErrorKind::Unreadable,
                gloc_dbd::DbdErrorKind::Content => ReplayErrorKind::Content,
            },
        }
    }
}

/// How many unknown sensor names the warning lists before "and N more".
const NAMED_IN_WARNING: usize = 20;

/// Recorded cycles, read one at a time (memory does not grow with the input).
pub struct Input {
    kind: InputKind,
    names: Vec<String>,
    description: String,
}

enum InputKind {
    Csv(CsvInput),
    Logs(Box<Deployment>),
}

impl Input {
    /// Opens `paths`: one `.csv` file (a header of sensor names, any case, a `cycle`
    /// column ignored; one row per cycle; an empty cell keeps the value), or glider
    /// logs, each file's sensor list found in `sensor_cache`, beside the file, then
    /// the per-user folder (`gloc_dbd::CacheFolders::standard`).
    pub fn open(paths: &[PathBuf], sensor_cache: Option<&Path>) -> Result<Input, ReplayError> {
        let is_csv = |path: &PathBuf| {
            path.extension()
                .is_some_and(|extension| extension.eq_ignore_ascii_case("csv"))
        };
        match paths {
            [] => Err(ReplayError::usage("--replay needs at least one file")),
            [path] if is_csv(path) => {
                let csv = CsvInput::open(path)?;
                Ok(Input {
                    names: csv.names.clone(),
                    description: path.display().to_string(),
                    kind: InputKind::Csv(csv),
                })
            }
            _ if paths.iter().any(is_csv) => Err(ReplayError::usage(
                "a CSV replay is one file: give one `.csv`, or glider logs (.dbd, .ebd, …) only",
            )),
            _ => {
                let deployment = Deployment::open(paths, sensor_cache)?;
                let names = deployment
                    .sensors()
                    .iter()
                    .map(|sensor| sensor.name.clone())
                    .collect();
                let description = match paths {
                    [path] => path.display().to_string(),
                    _ => format!("{} files", paths.len()),
                };
                Ok(Input {
                    kind: InputKind::Logs(Box::new(deployment)),
                    names,
                    description,
                })
            }
        }
    }

    /// The recorded sensors, in column order ([`Input::next_cycle`] refers to them).
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The file, or `N files` for a deployment.
    pub fn description(&self) -> &str {
        &self.description
    }

    /// The next cycle's updated values as (column, value), replacing `updates`;
    /// `Ok(false)` at the end.
    pub fn next_cycle(&mut self, updates: &mut Vec<(usize, f64)>) -> Result<bool, ReplayError> {
        updates.clear();
        match &mut self.kind {
            InputKind::Csv(csv) => csv.next_row(updates),
            InputKind::Logs(logs) => {
                let Some(cycle) = logs.next_cycle()? else {
                    return Ok(false);
                };
                updates.extend(
                    cycle
                        .states
                        .iter()
                        .enumerate()
                        .filter(|(_, state)| state.is_updated())
                        .filter_map(|(column, _)| {
                            cycle.values.get(column).map(|value| (column, *value))
                        }),
                );
                Ok(true)
            }
        }
    }

    /// What the reader read around so far (a truncated last cycle, …); drains them.
    pub fn take_warnings(&mut self) -> Vec<String> {
        match &mut self.kind {
            InputKind::Csv(_) => Vec::new(),
            InputKind::Logs(logs) => logs
                .take_warnings()
                .iter()
                .map(|warning| warning.to_string())
                .collect(),
        }
    }
}

/// The data's columns matched to the active list by name.
#[derive(Clone, Debug, PartialEq)]
pub struct ColumnMap {
    /// Per column: the sensor in the active list, `None` when it lacks it.
    pub ids: Vec<Option<SensorId>>,
    /// The names the active list lacks, in column order.
    pub unknown: Vec<String>,
}

impl ColumnMap {
    pub fn new(names: &[String], list: &SensorList) -> ColumnMap {
        let ids: Vec<Option<SensorId>> = names.iter().map(|name| list.lookup(name)).collect();
        let unknown = names
            .iter()
            .zip(&ids)
            .filter(|(_, id)| id.is_none())
            .map(|(name, _)| name.clone())
            .collect();
        ColumnMap { ids, unknown }
    }

    /// One line naming the recorded sensors the active list lacks (the first
    /// twenty, then how many more), or `None` when it has them all. With three or
    /// fewer, each gets a "did you mean" when a name is close (a typo in a CSV header).
    pub fn warning(&self, list: &SensorList) -> Option<String> {
        if self.unknown.is_empty() {
            return None;
        }
        let count = self.unknown.len();
        let suggest_names = count <= 3;
        let mut named: Vec<String> = self
            .unknown
            .iter()
            .take(NAMED_IN_WARNING)
            .map(|name| {
                let hint = if suggest_names {
                    suggest::closest(name, list.iter().map(|(_, sensor)| sensor.name.as_str()))
                        .map(|close| format!(" (did you mean `{close}`?)"))
                        .unwrap_or_default()
                } else {
                    String::new()
                };
                format!("`{name}`{hint}")
            })
            .collect();
        if count > NAMED_IN_WARNING {
            named.push(format!("and {} more", count - NAMED_IN_WARNING));
        }
        Some(format!(
            "warning: {count} recorded sensor{} not in the active sensor list ({}) and {} ignored: {}",
            if count == 1 { " is" } else { "s are" },
            list.label(),
            if count == 1 { "is" } else { "are" },
            named.join(", ")
        ))
    }
}

/// The most cycles a [`Recording`] holds (three months of 4 s cycles; a month is 650,000), and the
/// most values (16 bytes each: 256 MB). A 264 KB compressed log of identical cycles
/// decompresses to tens of millions of them (1.26 GB held).
pub const MAX_RECORDED_CYCLES: usize = 2_000_000;
pub const MAX_RECORDED_VALUES: usize = 16_000_000;

/// A whole recording in memory, as sensor updates per cycle in the active list's
/// indices (for the debugger, which steps back and forth).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Recording {
    /// The input's description (a file, or `N files`).
    pub source: String,
    /// Every cycle's updates, one after another; `starts[i]..starts[i + 1]` is cycle i.
    updates: Vec<(SensorId, f64)>,
    starts: Vec<usize>,
    /// The unknown-sensors line and the reader's warnings.
    pub warnings: Vec<String>,
    /// The recorded sensors the active list has, in column order (for the Sensors scope).
    pub recorded: Vec<SensorId>,
}

impl Recording {
    /// Reads all of `input`, keeping only the sensors `list` has.
    pub fn read(mut input: Input, list: &SensorList) -> Result<Recording, ReplayError> {
        let map = ColumnMap::new(input.names(), list);
        let mut recording = Recording {
            source: input.description().to_string(),
            recorded: map.ids.iter().flatten().copied().collect(),
            ..Recording::default()
        };
        recording.warnings.extend(map.warning(list));
        let mut updates = Vec::new();
        while input.next_cycle(&mut updates)? {
            recording.starts.push(recording.updates.len());
            recording
                .updates
                .extend(updates.iter().filter_map(|&(column, value)| {
                    map.ids.get(column).copied().flatten().map(|id| (id, value))
                }));
            if recording.starts.len() > MAX_RECORDED_CYCLES
                || recording.updates.len() > MAX_RECORDED_VALUES
            {
                return Err(ReplayError::content(format!(
                    "{}: the recording is longer than the debugger holds ({MAX_RECORDED_CYCLES} cycles or {MAX_RECORDED_VALUES} values; cycle {} is past it): the debugger keeps a whole recording to step back; replay it with `gloc run --replay`, or give fewer files",
                    recording.source,
                    recording.starts.len()
                )));
            }
        }
        recording.warnings.extend(input.take_warnings());
        Ok(recording)
    }

    /// The number of recorded cycles.
    pub fn len(&self) -> usize {
        self.starts.len()
    }

    pub fn is_empty(&self) -> bool {
        self.starts.is_empty()
    }

    /// The updates of cycle `index` (0-based), in the active list's indices.
    pub fn cycle(&self, index: usize) -> Option<&[(SensorId, f64)]> {
        let start = *self.starts.get(index)?;
        let end = self
            .starts
            .get(index + 1)
            .copied()
            .unwrap_or(self.updates.len());
        self.updates.get(start..end)
    }
}

/// A CSV replay file, read from memory row by row.
struct CsvInput {
    display: String,
    text: String,
    index: LineIndex,
    /// Byte offset of the next line.
    offset: usize,
    /// Per cell of a row: the name column it fills (`None`: the `cycle` column).
    cells: Vec<Option<usize>>,
    names: Vec<String>,
}

impl CsvInput {
    fn open(path: &Path) -> Result<CsvInput, ReplayError> {
        let display = path.display().to_string();
        let bytes =
            gloc_engine::files::read(path, gloc_engine::files::REPLAY).map_err(|error| {
                ReplayError {
                    message: format!("cannot read the replay file `{display}`: {error}"),
                    kind: ReplayErrorKind::Unreadable,
                }
            })?;
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let mut csv = CsvInput {
            index: LineIndex::new(&text),
            display,
            text,
            offset: 0,
            cells: Vec::new(),
            names: Vec::new(),
        };
        let Some((_, header)) = csv.next_line() else {
            return Err(ReplayError::content(format!(
                "{}: the replay file is empty; it needs a header of sensor names",
                csv.display
            )));
        };
        // Spreadsheets often start a CSV with a byte-order mark.
        let header = header
            .strip_prefix('\u{feff}')
            .unwrap_or(&header)
            .to_string();
        for (_, name) in cells(&header) {
            let name = name.trim_matches('"');
            if name.eq_ignore_ascii_case("cycle") {
                csv.cells.push(None);
            } else {
                csv.cells.push(Some(csv.names.len()));
                csv.names.push(name.to_string());
            }
        }
        Ok(csv)
    }

    /// The next non-blank line (without its line end) and its byte offset.
    fn next_line(&mut self) -> Option<(usize, String)> {
        while self.offset < self.text.len() {
            let start = self.offset;
            let rest = &self.text[start..];
            let length = rest.find('\n').map_or(rest.len(), |end| end + 1);
            self.offset += length;
            let line = rest[..length].trim_end_matches(['\n', '\r']);
            if !line.trim().is_empty() {
                return Some((start, line.to_string()));
            }
        }
        None
    }

    fn location(&self, offset: usize) -> String {
        let (line, column) = self.index.line_col(&self.text, offset);
        format!("{}:{line}:{column}", self.display)
    }

    fn next_row(&mut self, updates: &mut Vec<(usize, f64)>) -> Result<bool, ReplayError> {
        let Some((line_offset, line)) = self.next_line() else {
            return Ok(false);
        };
        let mut count = 0;
        for (cell_index, (at, cell)) in cells(&line).enumerate() {
            count += 1;
            let Some(column) = self.cells.get(cell_index) else {
                return Err(ReplayError::content(format!(
                    "{}: this row has more cells than the header has names ({})",
                    self.location(line_offset + at),
                    self.cells.len()
                )));
            };
            if cell.is_empty() {
                continue;
            }
            let Some(column) = column else { continue };
            let value: f64 = cell.parse().map_err(|_| {
                ReplayError::content(format!(
                    "{}: `{cell}` is not a number (sensor values are decimal numbers such as `12.5`)",
                    self.location(line_offset + at)
                ))
            })?;
            updates.push((*column, value));
        }
        if count < self.cells.len() {
            return Err(ReplayError::content(format!(
                "{}: this row has {count} cells but the header has {} names",
                self.location(line_offset),
                self.cells.len()
            )));
        }
        Ok(true)
    }
}

/// The comma-separated cells of a CSV line with their byte offsets.
fn cells(line: &str) -> impl Iterator<Item = (usize, &str)> {
    line.split(',').scan(0usize, |offset, cell| {
        let start = *offset;
        *offset += cell.len() + 1;
        let leading = cell.len() - cell.trim_start().len();
        Some((start + leading, cell.trim()))
    })
}
