//! gloc-mission: the Slocum glider's mission language, as the glider reads it, without
//! the flight model.
//!
//! - [`mission`]: `.mi` and `.ma` files, parsed and loaded (parsing never fails: what was
//!   understood plus diagnostics).
//! - [`behaviors`]: the behavior table (names, arguments, units, defaults, docs) that the
//!   checks, the editor and the simulator read.
//!
//! Below the simulator (`gloc-sim` flies a [`Mission`]) and beside the compiler, so the
//! IDE completes a `b_arg` without linking the flight model.

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

pub mod behaviors;
pub mod checks;
pub mod files;
pub mod mission;

pub use behaviors::{ArgDef, BehaviorKind, KnownArgs};
pub use files::{Disk, MissionFiles};
pub use mission::{LoadOptions, Mission};
