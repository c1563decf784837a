//! Slocum glider logs: the binary `.dbd .ebd .sbd .tbd .mbd .nbd`, their LZ4
//! forms `.dcd .ecd .scd .tcd .mcd .ncd`, and ASCII `.dba`, read as a stream of
//! cycles (memory does not grow with the file); merging a flight log with its
//! science log and a deployment's files in time order; writing binary logs.
//!
//! The readers take any `Read`; [`fs`] is the one module that touches the file
//! system (opening a path by its extension, the sensor-list cache search).
//! Format and rules: `docs/data.md`.

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

pub mod binary;
pub mod cycle;
pub mod dba;
pub mod error;
pub mod fs;
pub mod header;
pub mod lists;
/// LZ4 blocks live in the engine, which also reads `.ccc` sensor lists with them.
pub use gloc_engine::lz4;
pub mod merge;
pub mod writer;

pub use binary::{ByteOrder, DbdReader};
pub use cycle::{columns_of, time_column, Cycle, FileSensor, SensorColumns, State};
pub use dba::DbaReader;
pub use error::{DbdError, DbdErrorKind, Location, Warning};
pub use fs::{open_path, CacheFolders, LogKind};
pub use header::Header;
pub use lists::{sensor_list_crc, NoSensorLists, SensorListText, SensorLists};
pub use merge::{plan, Deployment, Merged, Segment, SegmentFiles};
pub use writer::{DbdWriter, ListSensor, LogIdentity, WrittenList};

/// A stream of cycles: one log file, a flight log merged with its science log,
/// or a whole deployment. Every source reuses one [`Cycle`].
pub trait CycleSource: Send {
    /// The file name used in messages (for a merge or deployment, the current file).
    fn file(&self) -> &str;
    fn header(&self) -> &Header;
    /// The sensors, in column order: `Cycle::states` and `Cycle::values` follow it.
    fn sensors(&self) -> &SensorColumns;
    /// The column of the time sensor (`m_present_time`, else `sci_m_present_time`).
    fn time_column(&self) -> Option<usize>;
    /// The next cycle, `Ok(None)` at the end (see [`CycleSource::take_warnings`]).
    fn next_cycle(&mut self) -> Result<Option<&Cycle>, DbdError>;
    /// Warnings so far (a truncated last cycle, a missing end tag); drains them.
    fn take_warnings(&mut self) -> Vec<Warning>;
}

/// The `CycleSource` of a one-file reader: its fields `file`, `header`,
/// `sensors`, `time`, `cycle`, `warnings`, and `$read`, which fills `cycle`
/// and says whether there was one.
macro_rules! one_file_source {
    ($type:ty, $read:ident) => {
        impl $crate::CycleSource for $type {
            fn file(&self) -> &str {
                &self.file
            }

            fn header(&self) -> &$crate::Header {
                &self.header
            }

            fn sensors(&self) -> &$crate::SensorColumns {
                &self.sensors
            }

            fn time_column(&self) -> Option<usize> {
                self.time
            }

            fn next_cycle(&mut self) -> Result<Option<&$crate::Cycle>, $crate::DbdError> {
                Ok(self.$read()?.then_some(&self.cycle))
            }

            fn take_warnings(&mut self) -> Vec<$crate::Warning> {
                std::mem::take(&mut self.warnings)
            }
        }
    };
}
pub(crate) use one_file_source;

/// A read failure as an error value; an LZ4 problem keeps its block's offset.
pub(crate) fn io_error(file: &str, at: Location, error: &std::io::Error) -> DbdError {
    if let Some(problem) = error
        .get_ref()
        .and_then(|inner| inner.downcast_ref::<lz4::Lz4Problem>())
    {
        return DbdError::new(
            file,
            Location {
                offset: at.offset,
                block: Some(problem.block),
            },
            problem.message.clone(),
        );
    }
    DbdError::unreadable(file, at, format!("cannot read: {error}"))
}
