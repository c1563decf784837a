//! The project layer: what the CLI, the language server and the debugger all need
//! to know about a script's project, decided in one place.
//!
//! - [`settings`]: one precedence rule (a flag, an editor setting or a launch attribute
//!   wins over `gloc.toml`, which wins over the default) and one validation, into
//!   types that cannot hold a meaningless value ([`settings::CycleBudget`]).
//! - [`sensors`]: the active sensor list (masterdata, `.cac`, `.ccc`, or the embedded
//!   list), with one error format.
//! - [`script`]: a `.gloc` or `.gbas` script loaded into program and source map, and
//!   the hint when a file is in the other language.
//! - [`logs`]: a glider's own logs read into the calibration's track.
//! - [`simulation`]: the mission, the temperature profile and the simulator built from
//!   the settings.
//!
//! Every error is a [`ProjectError`] that names where the value at fault came from
//! (`gloc.toml:3:16`, `--cycle-budget`, `launch attribute cycleBudget`, `editor
//! setting gloc.masterdata`) and says whether it is a bad setting, an input that
//! cannot be read, or an input with errors; the CLI's exit codes follow that cause.

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

pub mod config;
pub mod error;
pub mod logs;
pub mod script;
pub mod sensors;
pub mod settings;
pub mod simulation;

pub use error::{ErrorKind, ProjectError};
pub use settings::{CycleBudget, Origin, Overrides, Settings, Surface};
