//! The one error type of the project layer: where the value at fault came from,
//! what kind of failure it is, and what is wrong.

use std::fmt;

use crate::settings::Origin;

/// Why a project could not be set up; the CLI's exit code follows it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// A setting is not allowed (a zero cycle budget, a bad `gloc.toml`).
    Setting,
    /// An input file cannot be read (missing, unreadable, too large).
    Unreadable,
    /// An input file was read but has errors (a sensor list, a mission, a profile).
    Invalid,
}

/// A project error: `ORIGIN: MESSAGE`, e.g. `gloc.toml:2:14: cannot read the sensor
/// list `nosuch.mi`: …` or `--cycle-budget: the cycle budget must be …`.
#[derive(Clone, Debug, PartialEq)]
pub struct ProjectError {
    pub kind: ErrorKind,
    /// Where the value at fault came from; `None` for a default (nothing to name).
    pub origin: Option<Origin>,
    pub message: String,
}

impl ProjectError {
    pub fn new(kind: ErrorKind, origin: Option<Origin>, message: impl Into<String>) -> Self {
        ProjectError {
            kind,
            origin,
            message: message.into(),
        }
    }
}

/// Test support: asserts that `error` is a file that cannot be read, its message
/// starting with `start`.
#[cfg(test)]
pub(crate) fn assert_unreadable(error: &ProjectError, start: &str) {
    assert_eq!(error.kind, ErrorKind::Unreadable, "{error}");
    assert!(error.to_string().starts_with(start), "{error}");
}

impl fmt::Display for ProjectError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.origin {
            Some(origin) if !matches!(origin, Origin::Default) => {
                write!(f, "{origin}: {}", self.message)
            }
            _ => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for ProjectError {}
