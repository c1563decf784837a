//! gloc-sim: a glider simulator that flies whole missions much faster than
//! real time, with the GLOC engine as one behavior of the layered control.
//!
//! - [`mission`]: `.mi` and `.ma` files (the `gloc-mission` crate, re-exported).
//! - [`calibrate`]: a yo's figures from a log (real or simulated) and the
//!   constants fitted from a glider's own log.
//! - [`behaviors`]: the behavior stack (abend, surface, yo, dive_to, climb_to,
//!   hook, the script behavior, …) and per-actuator arbitration.
//! - [`flight`]: the kinematic vertical-plane model and the power model.
//! - [`navigation`]: position (true and dead-reckoned), heading, GPS, the
//!   current estimate and the firmware's steering to waypoints.
//! - [`environment`]: water depth, temperature profile, seeded noise.
//! - [`simulation`]: the sensor array and the control cycle, in phases.
//! - [`log`] and [`plot`]: CSV / Slocum ASCII logs and the SVG flight profile.
//! - [`faults`]: fault injection (sensor dropouts, stuck values, NaN, spikes).
//!
//! Pure and deterministic: no IO except what a caller asks for (loading a
//! mission, writing a log), no threads, and the same seed gives the same run.

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

pub mod behaviors;
pub mod calibrate;
pub mod environment;
pub mod faults;
pub mod flight;
pub mod log;
pub mod navigation;
pub mod plot;
pub mod settings;
pub mod simulation;

pub use environment::TemperatureProfile;
pub use gloc_mission::{mission, Mission};
pub use simulation::{EndReason, MissionEnd, Phase, SimConfig, SimError, SimHost, Simulation};

/// The embedded default mission: the paper's Fig. 2 scenario (also
/// `examples/fig2.mi`).
pub const DEFAULT_MISSION: &str = include_str!("../data/fig2.mi");

/// The default mission, parsed.
pub fn default_mission() -> Mission {
    Mission::parse("fig2.mi", DEFAULT_MISSION)
}
