//! The exit codes of every subcommand, by cause (README, "Exit codes"):
//!
//! | code | cause |
//! |---|---|
//! | 0 | success |
//! | 1 | the script or the data it reads (sensor list, mission, profile) has errors; the run trapped; a batch mission failed; a forecast's logs, currents or bathymetry cannot serve (no fix, a malformed NetCDF, a track off the grid) |
//! | 2 | usage: bad arguments or settings (flags, `gloc.toml`), an output that would overwrite an input, a file of another kind given as the script; a recording gloc cannot use (a log whose `<crc>.cac` is not found, or that cannot be opened or parsed; a malformed replay CSV) |
//! | 3 | an input cannot be read (script, `gloc.toml`, sensor list, mission, profile, a replay file that does not exist) |
//! | 4 | an output cannot be written |
//! | 5 | the simulated mission aborted (abend: `MS_ABORT_OVERDEPTH`, …); in `batch`, a mission aborted and none failed |
//! | 128 + N | stopped by signal N (130 for Ctrl-C) |

use std::process::ExitCode;

use gloc_project::ErrorKind;

pub const ERRORS: u8 = 1;
pub const USAGE: u8 = 2;
pub const UNREADABLE: u8 = 3;
pub const UNWRITABLE: u8 = 4;
/// The mission flew and abend aborted it: the run itself worked, the mission did not.
pub const ABORTED: u8 = 5;

pub fn code(code: u8) -> ExitCode {
    ExitCode::from(code)
}

/// An input that cannot be read, outside the project layer (a log, a CSV).
#[derive(Debug)]
pub struct Unreadable(pub String);

/// An output that cannot be written.
#[derive(Debug)]
pub struct Unwritable(pub String);

/// An input that was read but cannot serve (a forecast's logs without a fix, currents
/// that do not cover the track): exit code 1.
#[derive(Debug)]
pub struct Invalid(pub String);

impl std::fmt::Display for Invalid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Invalid {}

impl std::fmt::Display for Unreadable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::fmt::Display for Unwritable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Unreadable {}
impl std::error::Error for Unwritable {}

/// The exit code of a project error, by its kind.
pub fn of_project(error: &gloc_project::ProjectError) -> u8 {
    match error.kind {
        ErrorKind::Setting => USAGE,
        ErrorKind::Unreadable => UNREADABLE,
        ErrorKind::Invalid => ERRORS,
    }
}

/// The exit code of an error a subcommand returned: by the first cause in its chain
/// that has one; anything else is a usage error.
pub fn of_error(error: &anyhow::Error) -> u8 {
    for cause in error.chain() {
        if let Some(project) = cause.downcast_ref::<gloc_project::ProjectError>() {
            return of_project(project);
        }
        if let Some(log) = cause.downcast_ref::<gloc_dbd::DbdError>() {
            return match log.kind {
                gloc_dbd::DbdErrorKind::Unreadable => UNREADABLE,
                gloc_dbd::DbdErrorKind::Content => ERRORS,
            };
        }
        if let Some(replay) = cause.downcast_ref::<gloc_replay::ReplayError>() {
            return match replay.kind {
                gloc_replay::ReplayErrorKind::Usage => USAGE,
                gloc_replay::ReplayErrorKind::Unreadable => UNREADABLE,
                gloc_replay::ReplayErrorKind::Content => ERRORS,
            };
        }
        if cause.is::<Unreadable>() {
            return UNREADABLE;
        }
        if cause.is::<Unwritable>() {
            return UNWRITABLE;
        }
        if cause.is::<Invalid>() {
            return ERRORS;
        }
    }
    USAGE
}
