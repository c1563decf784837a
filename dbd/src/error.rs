//! Errors and warnings as values: every one names the file and the byte offset.

use std::fmt;

/// Where in a file something is. For a compressed file the offset counts the
/// decompressed bytes, and `block` is the file offset of the LZ4 block they came from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Location {
    pub offset: u64,
    pub block: Option<u64>,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.block {
            Some(block) => write!(
                f,
                "byte {} of the decompressed data (LZ4 block at file byte {block})",
                self.offset
            ),
            None => write!(f, "byte {}", self.offset),
        }
    }
}

/// Why a file cannot be read: the front ends give the two different exit codes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DbdErrorKind {
    /// The bytes are not a log gloc can read (a corrupt header, list or cycle).
    #[default]
    Content,
    /// The file (or the sensor list it needs) cannot be opened or read.
    Unreadable,
}

/// A file that cannot be read (further): what is wrong, where, and what to do.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{file}: {at}: {message}{}", help.as_ref().map(|help| format!("\n  help: {help}")).unwrap_or_default())]
pub struct DbdError {
    pub file: String,
    pub at: Location,
    pub message: String,
    pub help: Option<String>,
    pub kind: DbdErrorKind,
}

impl DbdError {
    /// Bad content.
    pub fn new(file: &str, at: Location, message: impl Into<String>) -> DbdError {
        DbdError {
            file: file.to_string(),
            at,
            message: message.into(),
            help: None,
            kind: DbdErrorKind::Content,
        }
    }

    /// A file that cannot be opened or read, or a sensor list not found.
    pub fn unreadable(file: &str, at: Location, message: impl Into<String>) -> DbdError {
        DbdError {
            kind: DbdErrorKind::Unreadable,
            ..DbdError::new(file, at, message)
        }
    }

    pub fn with_help(mut self, help: impl Into<String>) -> DbdError {
        self.help = Some(help.into());
        self
    }
}

/// Something read around, such as a truncated last cycle: the cycles before it are kept.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    pub file: String,
    pub at: Location,
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}: {}", self.file, self.at, self.message)
    }
}
