//! Merging logs: a flight log with its science log onto the flight computer's
//! cycles ([`Merged`]), and a deployment's files in time order across
//! sensor-list changes ([`Deployment`]).
//!
//! The merge rule: each flight cycle carries, for every science sensor, the
//! latest science value whose science time (`sci_m_present_time`) is at or
//! before the flight cycle's time (`m_present_time`); the sensor counts as
//! updated in that flight cycle when a science cycle in between updated it.
//! A name in both logs takes the science log's value (as dbdreader's
//! `MultiDBD` does). dbdreader's `get_sync` instead interpolates linearly
//! between science samples; a script on the glider only ever sees past
//! values, so the replay rule never looks ahead. Science cycles after the last
//! flight cycle are dropped.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::cycle::{time_column, Cycle, FileSensor, SensorColumns, State};
use crate::error::{DbdError, Location, Warning};
use crate::fs::{open_path, LogKind};
use crate::header::Header;
use crate::CycleSource;

/// A science cycle's update: its column, state and value.
type Update = (usize, State, f64);

/// A flight log and its science log, on the flight log's cycles.
pub struct Merged {
    flight: Box<dyn CycleSource>,
    science: Box<dyn CycleSource>,
    sensors: SensorColumns,
    /// Per science column: its merged column.
    science_columns: Vec<usize>,
    /// Per flight column: `false` when the science log owns the name.
    flight_owns: Vec<bool>,
    science_time: Option<usize>,
    /// The next science cycle not yet applied: its updates (science column,
    /// state, value) and time.
    pending: Option<(Vec<Update>, f64)>,
    last_science_time: f64,
    science_done: bool,
    last_flight_time: f64,
    cycle: Cycle,
}

impl Merged {
    pub fn new(flight: Box<dyn CycleSource>, science: Box<dyn CycleSource>) -> Merged {
        let science_names: std::collections::HashSet<&str> = science
            .sensors()
            .iter()
            .map(|sensor| sensor.name.as_str())
            .collect();
        let mut sensors: Vec<FileSensor> = flight.sensors().to_vec();
        let flight_owns = sensors
            .iter()
            .map(|sensor| !science_names.contains(sensor.name.as_str()))
            .collect();
        // Names are looked up in a map: a list of 100,000 sensors is refused only
        // above that, and a linear search per science name took minutes there.
        let mut columns: std::collections::HashMap<String, usize> =
            std::collections::HashMap::new();
        for (column, sensor) in sensors.iter().enumerate() {
            columns.entry(sensor.name.clone()).or_insert(column);
        }
        let mut science_columns = Vec::with_capacity(science.sensors().len());
        for sensor in science.sensors().iter() {
            match columns.get(&sensor.name) {
                Some(&column) => science_columns.push(column),
                None => {
                    columns.insert(sensor.name.clone(), sensors.len());
                    science_columns.push(sensors.len());
                    sensors.push(sensor.clone());
                }
            }
        }
        let mut cycle = Cycle::default();
        cycle.reset(sensors.len());
        Merged {
            science_time: science.time_column(),
            flight,
            science,
            sensors: Arc::from(sensors),
            science_columns,
            flight_owns,
            pending: None,
            last_science_time: f64::NEG_INFINITY,
            science_done: false,
            last_flight_time: f64::NAN,
            cycle,
        }
    }

    /// Reads the next science cycle into `pending` (none at the end).
    fn fetch_science(&mut self) -> Result<(), DbdError> {
        if self.science_done || self.pending.is_some() {
            return Ok(());
        }
        match self.science.next_cycle()? {
            Some(cycle) => {
                let time = match self.science_time {
                    Some(column) if cycle.states[column].is_updated() => cycle.values[column],
                    _ => self.last_science_time,
                };
                self.last_science_time = time;
                let updates = cycle
                    .updated
                    .iter()
                    .map(|&column| (column, cycle.states[column], cycle.values[column]))
                    .collect();
                self.pending = Some((updates, time));
            }
            None => self.science_done = true,
        }
        Ok(())
    }

    fn merge_next(&mut self) -> Result<bool, DbdError> {
        let Some(flight) = self.flight.next_cycle()? else {
            return Ok(false);
        };
        // Only what changed: the last cycle's updates cleared, this one's set (a
        // flight-owned value changes only when the flight log updates it).
        self.cycle.clear_updates();
        for &column in &flight.updated {
            if self.flight_owns[column] {
                self.cycle
                    .update(column, flight.states[column], flight.values[column]);
            }
        }
        self.cycle.offset = flight.offset;
        self.cycle.number = flight.number;
        if !flight.time.is_nan() {
            self.last_flight_time = flight.time;
        }
        self.cycle.time = flight.time;
        let until = self.last_flight_time;
        loop {
            self.fetch_science()?;
            let Some((updates, time)) = &self.pending else {
                break;
            };
            // Before any flight time is known nothing can be placed; NaN science
            // times (no time sensor yet) go with the next timed cycle.
            if until.is_nan() || *time > until {
                break;
            }
            for &(science_column, state, value) in updates {
                self.cycle
                    .update(self.science_columns[science_column], state, value);
            }
            self.pending = None;
        }
        Ok(true)
    }
}

impl CycleSource for Merged {
    fn file(&self) -> &str {
        self.flight.file()
    }

    fn header(&self) -> &Header {
        self.flight.header()
    }

    fn sensors(&self) -> &SensorColumns {
        &self.sensors
    }

    fn time_column(&self) -> Option<usize> {
        self.flight.time_column()
    }

    fn next_cycle(&mut self) -> Result<Option<&Cycle>, DbdError> {
        Ok(self.merge_next()?.then_some(&self.cycle))
    }

    fn take_warnings(&mut self) -> Vec<Warning> {
        let mut warnings = self.flight.take_warnings();
        warnings.extend(self.science.take_warnings());
        warnings
    }
}

/// One step of a deployment: its files, and when the first was opened.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Segment {
    pub files: SegmentFiles,
    /// Unix seconds of the header's `fileopen_time` (files without one sort last).
    pub opened: Option<i64>,
}

/// A flight file, a science file, or a flight file with its science file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SegmentFiles {
    Flight(PathBuf),
    Science(PathBuf),
    Both { flight: PathBuf, science: PathBuf },
}

impl SegmentFiles {
    pub fn flight(&self) -> Option<&PathBuf> {
        match self {
            SegmentFiles::Flight(flight) | SegmentFiles::Both { flight, .. } => Some(flight),
            SegmentFiles::Science(_) => None,
        }
    }

    pub fn science(&self) -> Option<&PathBuf> {
        match self {
            SegmentFiles::Science(science) | SegmentFiles::Both { science, .. } => Some(science),
            SegmentFiles::Flight(_) => None,
        }
    }

    /// The flight file, else the science file: the one whose header dates the
    /// segment and names it.
    pub fn first(&self) -> &PathBuf {
        match self {
            SegmentFiles::Flight(first)
            | SegmentFiles::Science(first)
            | SegmentFiles::Both { flight: first, .. } => first,
        }
    }

    fn open(&self, sensor_cache: Option<&Path>) -> Result<Box<dyn CycleSource>, DbdError> {
        match self {
            SegmentFiles::Both { flight, science } => Ok(Box::new(Merged::new(
                open_path(flight, sensor_cache)?,
                open_path(science, sensor_cache)?,
            ))),
            SegmentFiles::Flight(only) | SegmentFiles::Science(only) => {
                open_path(only, sensor_cache)
            }
        }
    }
}

/// Pairs flight and science files by name (`x.dbd` with `x.ebd`, `x.sbd` with
/// `x.tbd`, `x.mbd` with `x.nbd`, compressed forms alike) and orders the pairs
/// by their header's `fileopen_time`, then by name.
pub fn plan(paths: &[PathBuf]) -> Result<Vec<Segment>, DbdError> {
    let mut segments: Vec<(String, Segment)> = Vec::new();
    for path in paths {
        let kind = LogKind::from_path(path);
        let pair = match kind {
            Some(LogKind::Binary { letter, .. }) => match letter {
                b'd' | b'e' => 'd',
                b's' | b't' => 's',
                _ => 'm',
            },
            _ => 'a',
        };
        let stem = path.with_extension("").display().to_string();
        let key = format!("{stem}\u{0}{pair}");
        let science = kind.is_some_and(LogKind::is_science);
        // The first segment of the same name that lacks this kind of file takes it.
        let joined = segments
            .iter()
            .enumerate()
            .find_map(|(index, (known, segment))| {
                let files = match (&segment.files, science) {
                    (SegmentFiles::Flight(flight), true) => SegmentFiles::Both {
                        flight: flight.clone(),
                        science: path.clone(),
                    },
                    (SegmentFiles::Science(science), false) => SegmentFiles::Both {
                        flight: path.clone(),
                        science: science.clone(),
                    },
                    _ => return None,
                };
                (*known == key).then_some((index, files))
            });
        match joined {
            Some((index, files)) => segments[index].1.files = files,
            None => {
                let files = if science {
                    SegmentFiles::Science(path.clone())
                } else {
                    SegmentFiles::Flight(path.clone())
                };
                segments.push((
                    key,
                    Segment {
                        files,
                        opened: None,
                    },
                ));
            }
        }
    }
    let mut segments: Vec<Segment> = segments.into_iter().map(|(_, segment)| segment).collect();
    for segment in &mut segments {
        segment.opened = crate::fs::read_file_header(segment.files.first())?.fileopen_seconds();
    }
    segments.sort_by(|a, b| {
        let key = |segment: &Segment| (segment.opened.is_none(), segment.opened);
        (key(a), a.files.first()).cmp(&(key(b), b.files.first()))
    });
    Ok(segments)
}

/// The most segments a [`Deployment`] keeps open from the start.
pub const KEEP_OPEN: usize = 16;

/// A deployment: its files in time order as one stream of cycles. The columns
/// are every file's sensors by name, in order of first appearance; a sensor's
/// latest value carries over from one file to the next.
pub struct Deployment {
    segments: Vec<Segment>,
    sensor_cache: Option<PathBuf>,
    sensors: SensorColumns,
    /// Column of each name in `sensors`.
    columns: std::collections::HashMap<String, usize>,
    time: Option<usize>,
    next: usize,
    current: Option<(Box<dyn CycleSource>, Vec<usize>)>,
    /// The sources opened to learn the sensors, kept for the stream when the
    /// deployment has at most [`KEEP_OPEN`] segments (each file then opened and
    /// its sensor list parsed once); a longer one opens each file again in its
    /// turn, so it never holds more than that many open.
    opened: Vec<Option<Box<dyn CycleSource>>>,
    empty_header: Header,
    cycle: Cycle,
    started: bool,
    warnings: Vec<Warning>,
}

impl Deployment {
    /// Opens every file once to learn its sensors (header and list only), then
    /// streams them one at a time.
    pub fn open(paths: &[PathBuf], sensor_cache: Option<&Path>) -> Result<Deployment, DbdError> {
        let segments = plan(paths)?;
        let mut sensors: Vec<FileSensor> = Vec::new();
        let mut names = std::collections::HashMap::new();
        let mut opened = Vec::new();
        for segment in &segments {
            let source = segment.files.open(sensor_cache)?;
            for sensor in source.sensors().iter() {
                if !names.contains_key(&sensor.name) {
                    names.insert(sensor.name.clone(), sensors.len());
                    sensors.push(sensor.clone());
                }
            }
            if segments.len() <= KEEP_OPEN {
                opened.push(Some(source));
            }
        }
        let mut cycle = Cycle::default();
        cycle.reset(sensors.len());
        Ok(Deployment {
            segments,
            sensor_cache: sensor_cache.map(Path::to_path_buf),
            time: time_column(&sensors),
            sensors: Arc::from(sensors),
            columns: names,
            next: 0,
            current: None,
            opened,
            empty_header: Header::default(),
            cycle,
            started: false,
            warnings: Vec::new(),
        })
    }

    /// The files in the order they are read.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    fn advance(&mut self) -> Result<bool, DbdError> {
        loop {
            if self.current.is_none() {
                let Some(segment) = self.segments.get(self.next) else {
                    return Ok(false);
                };
                let kept = self.opened.get_mut(self.next).and_then(Option::take);
                self.next += 1;
                let source = match kept {
                    Some(source) => source,
                    None => segment.files.open(self.sensor_cache.as_deref())?,
                };
                let mut map = Vec::with_capacity(source.sensors().len());
                for sensor in source.sensors().iter() {
                    match self.columns.get(&sensor.name) {
                        Some(&column) => map.push(column),
                        None => {
                            return Err(DbdError::new(
                                source.file(),
                                Location::default(),
                                format!(
                                    "sensor `{}` was not in this file's list when the deployment was opened: was the file replaced?",
                                    sensor.name
                                ),
                            ))
                        }
                    }
                }
                self.current = Some((source, map));
            }
            let Some((source, map)) = self.current.as_mut() else {
                continue;
            };
            match source.next_cycle()? {
                Some(cycle) => {
                    self.cycle.clear_updates();
                    for &column in &cycle.updated {
                        self.cycle
                            .update(map[column], cycle.states[column], cycle.values[column]);
                    }
                    self.cycle.offset = cycle.offset;
                    self.cycle.time = cycle.time;
                    if self.started {
                        self.cycle.number += 1;
                    }
                    self.started = true;
                    return Ok(true);
                }
                None => {
                    self.warnings.extend(source.take_warnings());
                    self.current = None;
                }
            }
        }
    }
}

impl CycleSource for Deployment {
    fn file(&self) -> &str {
        match &self.current {
            Some((source, _)) => source.file(),
            None => "",
        }
    }

    fn header(&self) -> &Header {
        match &self.current {
            Some((source, _)) => source.header(),
            None => &self.empty_header,
        }
    }

    fn sensors(&self) -> &SensorColumns {
        &self.sensors
    }

    fn time_column(&self) -> Option<usize> {
        self.time
    }

    fn next_cycle(&mut self) -> Result<Option<&Cycle>, DbdError> {
        Ok(self.advance()?.then_some(&self.cycle))
    }

    fn take_warnings(&mut self) -> Vec<Warning> {
        if let Some((source, _)) = self.current.as_mut() {
            self.warnings.extend(source.take_warnings());
        }
        std::mem::take(&mut self.warnings)
    }
}
