//! The numbers the adapter hands the client for what it shows: the one thread and
//! frame, the scopes' and arrays' variable references, and instruction addresses
//! (`0x1f`), and the source. Shared by the session, the request handlers and the features, which
//! import this module rather than each other.

use crate::debugger::Debugger;
use crate::types::Source;
use crate::world::World;

pub const THREAD_ID: i64 = 1;
pub(crate) const FRAME_ID: i64 = 1;
pub(crate) const SCOPE_VARIABLES: i64 = 1;
pub(crate) const SCOPE_REGISTERS: i64 = 2;
pub(crate) const SCOPE_SENSORS: i64 = 3;
pub(crate) const SCOPE_VEHICLE: i64 = 4;
pub(crate) const ALL_SENSORS: i64 = 5;
pub(crate) const SCOPE_NAVIGATION: i64 = 6;
/// `ARRAYS + i`: the elements of the i-th GBASIC variable (an array).
pub(crate) const ARRAYS: i64 = 1000;

/// A pc as the client sees an instruction's address.
pub(crate) fn address(pc: usize) -> String {
    format!("0x{pc:x}")
}

/// An address the client sends back (`0x1f` or decimal).
pub(crate) fn parse_address(text: &str) -> Option<i64> {
    let text = text.trim();
    match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => i64::from_str_radix(hex, 16).ok(),
        None => text.parse().ok(),
    }
}

/// The program's source as the client is shown it.
pub(crate) fn source_of(debugger: &Debugger<World>) -> Source {
    Source {
        name: Some(debugger.info.source_name()),
        path: Some(debugger.info.path.display().to_string()),
    }
}
