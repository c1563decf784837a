//! gloc-forecast: where will the glider be? Trajectory forecasts from a
//! glider's own logs (`docs/forecast.md`).
//!
//! - [`logs`]: the last state, the current estimates and the segments, read
//!   from the logs by sensor name.
//! - [`fly`]: the mission set up from that state and flown in the simulator,
//!   with a uniform current or a field; the predicted surfacings and track.
//! - [`hindcast`]: each logged segment flown again, the miss at the first fix.
//! - [`ensemble`]: members over the current's uncertainty on every core, the
//!   region per hour and the surfacing spread.
//! - [`battery`]: the logs' coulomb count, the simulator's energy model
//!   started from it, and when the mission's low-battery abort comes.
//! - [`currents`]: current fields in time and space (CSV time series);
//!   [`netcdf`]: ocean-model currents and bathymetry from NetCDF;
//!   [`export`]: GeoJSON, KML and CSV; [`map`]: the map (PNG, SVG).
//!
//! Decision: a crate of its own above `gloc-project` (ARCHITECTURE.md): it
//! reads logs and flies the simulator, starts threads (the simulator never
//! does) and carries the output formats' crates, which the language server
//! and the debugger, linking `gloc-project`, do not need.

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

use std::sync::Arc;

use gloc_engine::sensors::SensorList;
use gloc_sim::navigation::Xy;
use gloc_sim::{Mission, SimConfig};

pub mod battery;
pub mod currents;
pub mod ensemble;
pub mod export;
pub mod fly;
pub mod hindcast;
pub mod logs;
pub mod map;
pub mod netcdf;

pub use ensemble::{Ensemble, EnsembleOptions};
pub use fly::{Start, Surfacing, Track, Truth};
pub use logs::LogHistory;

/// Why a forecast cannot be made.
#[derive(Debug, thiserror::Error)]
pub enum ForecastError {
    /// The logs lack what a forecast starts from.
    #[error("{0}")]
    Logs(String),
    /// The simulator refused the mission.
    #[error("{0}")]
    Mission(String),
    /// The current field does not cover the track (where and when).
    #[error("{0}")]
    Currents(String),
}

/// A forecast: the start, the track flown in the forecast's current, and
/// optionally the ensemble around it.
#[derive(Clone, Debug)]
pub struct Forecast {
    pub mission_name: String,
    pub start: Start,
    pub hours: f64,
    /// What the current is, in words (for the outputs).
    pub current: String,
    pub track: Track,
    pub ensemble: Option<Ensemble>,
    /// The battery against the mission's low-battery abort, when the logs
    /// hold a coulomb count.
    pub battery: Option<battery::BatteryOutlook>,
}

impl Forecast {
    /// One line: the mission, the start, the current, the surfacings.
    pub fn summary_line(&self) -> String {
        format!(
            "{} from {} for {} h in {}; {} predicted surfacing(s)",
            self.mission_name,
            export::iso_time(self.start.time),
            self.hours,
            self.current,
            self.track.surfacings.len()
        )
    }
}

/// What a forecast is asked for.
#[derive(Clone)]
pub struct Request {
    pub hours: f64,
    /// The true current; `None`: the glider's own latest estimate.
    pub currents: Option<(Arc<dyn currents::CurrentField>, String)>,
    /// The water depth under the track; `None`: the mission's or the configuration's.
    pub bathymetry: Option<Arc<dyn netcdf::DepthField>>,
    pub ensemble: Option<EnsembleOptions>,
}

/// The largest horizon (h).
pub const MAX_HOURS: f64 = 24.0 * 30.0;

/// What is wrong with a horizon of `hours`, if anything: a forecast flies above 0
/// and up to [`MAX_HOURS`] hours. Every surface (the CLI's `--hours`, the Python
/// package's `hours=`) asks here and names its own input in the error.
pub fn check_hours(hours: f64) -> Result<(), String> {
    if hours > 0.0 && hours <= MAX_HOURS {
        Ok(())
    } else {
        Err(format!(
            "give a horizon above 0 and up to {MAX_HOURS} hours"
        ))
    }
}

/// The true current every track of the forecast flies in, and what it is in
/// words: the request's field, else the glider's own estimate at `start`.
pub fn truth(request: &Request, start: &Start) -> (Truth, String) {
    match &request.currents {
        Some((field, name)) => (Truth::Field(field.clone(), Xy::ZERO), name.clone()),
        None => (
            Truth::Uniform(start.believed),
            format!(
                "the glider's own estimate ({:+.3}, {:+.3}) m/s east, north",
                start.believed.x, start.believed.y
            ),
        ),
    }
}

/// Flies the forecast from the end of `history`.
pub fn forecast(
    history: &LogHistory,
    mission: &Mission,
    sensors: &Arc<SensorList>,
    config: &SimConfig,
    request: &Request,
) -> Result<Forecast, ForecastError> {
    let start = Start::from_history(history)?;
    let prepared = fly::prepare_mission(mission, &start);
    let (truth, current) = truth(request, &start);
    let plan = fly::FlightPlan {
        seconds: request.hours * 3600.0,
        record_every: 60.0,
        stop_at_first_fix: fly::StopAt::Horizon,
        outside: fly::Outside::Fail,
    };
    let mut battery = battery::outlook(&start, mission, config);
    let flight = fly::Flight {
        mission: &prepared,
        sensors,
        config,
        start: &start,
        truth: &truth,
        bathymetry: request.bathymetry.as_ref(),
    };
    let flown = fly::fly_with(
        &flight,
        &plan,
        &fly::Extras {
            surface_drift: None,
            battery_limit: battery.map(|outlook| fly::BatteryLimit {
                used_at_start: outlook.used_at_start,
                used_at_limit: outlook.limit,
            }),
        },
    )?;
    if let Some(outlook) = &mut battery {
        outlook.reached_at = flown.battery_limit_at;
    }
    let track = flown.track;
    let ensemble = match &request.ensemble {
        Some(options) => Some(ensemble::run_ensemble(
            &ensemble::EnsembleInput {
                flight,
                hours: request.hours,
            },
            options,
        )?),
        None => None,
    };
    Ok(Forecast {
        mission_name: mission.name.clone(),
        start,
        hours: request.hours,
        current,
        track,
        ensemble,
        battery,
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_horizon_is_above_0_and_up_to_720_hours() {
        for (hours, allowed) in [(0.0, false), (0.1, true), (720.0, true), (720.5, false)] {
            assert_eq!(super::check_hours(hours).is_ok(), allowed, "{hours} h");
        }
        assert!(super::check_hours(f64::NAN).is_err());
    }
}
