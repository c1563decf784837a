//! One forecast track: the mission set up to start from a glider's logged
//! state (position, belief, waypoint, surface timers), flown in the simulator
//! with a true current (uniform or a field in time and space), with the
//! predicted surfacings and a thinned track recorded.

use std::sync::Arc;

use gloc_engine::diagnostic::Span;
use gloc_engine::sensors::SensorList;
use gloc_mission::mission::{Arg, Location, SensorSetting};
use gloc_mission::BehaviorKind;
use gloc_sim::navigation::{nmea_to_degrees, DrState, Lmc, Xy};
use gloc_sim::{EndReason, Mission, SimConfig, Simulation};

use crate::currents::CurrentField;
use crate::logs::{LogHistory, Segment};
use crate::netcdf::DepthField;
use crate::ForecastError;

/// Where and in what state a forecast starts: the glider at its last fix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Start {
    /// Unix seconds of the fix.
    pub time: f64,
    /// The fix, NMEA.
    pub lat: f64,
    pub lon: f64,
    /// The current the glider believes in (`m_water_vx/vy`, m/s).
    pub believed: Xy,
    /// `m_avg_speed`, when logged.
    pub avg_speed: Option<f64>,
    /// The waypoint it steers to (`c_wpt_lat/lon`, NMEA), when logged.
    pub waypoint: Option<(f64, f64)>,
    /// How far the mission's surface timers had run (s).
    pub timers_elapsed: f64,
    /// `m_coulomb_amphr_total` and `m_battery` at the end of the logs, and
    /// the capacity the count runs down from (`f_coulomb_battery_capacity`,
    /// Ah): the simulator's energy model starts from them ([`crate::battery`]).
    pub amp_hours: Option<f64>,
    pub battery: Option<f64>,
    pub battery_capacity: Option<f64>,
    pub heading: Option<f64>,
}

impl Start {
    /// The state at the end of the logs: the last fix, the latest belief,
    /// waypoint, mean speed and battery.
    pub fn from_history(history: &LogHistory) -> Result<Start, ForecastError> {
        let fix = history.fixes.last().ok_or_else(|| {
            ForecastError::Logs(
                "the logs hold no GPS fix (m_gps_lat/m_gps_lon): a forecast starts at the last one"
                    .to_string(),
            )
        })?;
        Ok(Start {
            time: fix.time,
            lat: fix.lat,
            lon: fix.lon,
            believed: history.last_water.unwrap_or(Xy::ZERO),
            avg_speed: history.last_avg_speed,
            waypoint: history.last_waypoint,
            timers_elapsed: history.last_timers_elapsed,
            amp_hours: history.last_amp_hours,
            battery: history.last_battery,
            battery_capacity: history.battery_capacity,
            heading: history.last_heading,
        })
    }

    /// The start of a logged segment (its last fix before the dive).
    pub fn of_segment(segment: &Segment, history: &LogHistory) -> Start {
        Start {
            time: segment.start.time,
            lat: segment.start.lat,
            lon: segment.start.lon,
            believed: segment.prior,
            avg_speed: segment.avg_speed.or(history.last_avg_speed),
            waypoint: segment.waypoint,
            timers_elapsed: segment.timers_elapsed,
            amp_hours: None,
            battery: None,
            battery_capacity: None,
            heading: None,
        }
    }

    /// The local mission coordinates centred on the start fix.
    pub fn lmc(&self) -> Lmc {
        Lmc::from_nmea(self.lat, self.lon)
    }
}

/// The true current a track is flown in.
#[derive(Clone)]
pub enum Truth {
    /// One depth-averaged current everywhere and always (m/s, x east, y north).
    Uniform(Xy),
    /// A field in time and space, plus a constant offset (an ensemble
    /// member's perturbation).
    Field(Arc<dyn CurrentField>, Xy),
}

/// A predicted surfacing: the first GPS fix after a dive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surfacing {
    /// Unix seconds.
    pub time: f64,
    /// Decimal degrees.
    pub lat: f64,
    pub lon: f64,
    /// The waypoint steered to then (decimal degrees) and the fix's distance to it (m).
    pub waypoint: Option<(f64, f64)>,
    pub distance_to_waypoint: Option<f64>,
    /// Seconds underwater before it (`m_dr_time`).
    pub underwater: f64,
    /// The glider's own current estimate at the fix (`m_initial_water_vx/vy`).
    pub estimate: Xy,
}

/// A point of the track.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackPoint {
    /// Unix seconds.
    pub time: f64,
    /// Decimal degrees.
    pub lat: f64,
    pub lon: f64,
    /// m.
    pub depth: f64,
}

/// One flown forecast.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Track {
    pub points: Vec<TrackPoint>,
    pub surfacings: Vec<Surfacing>,
    /// Why the flight ended before the horizon, if it did (mission completed,
    /// aborted, battery).
    pub ended: Option<String>,
    /// Charge the flight used (Ah).
    pub amp_hours_used: f64,
    /// Where and when the track left its current or bathymetry grid, if it did
    /// (with [`Outside::Stop`]).
    pub left_grid: Option<String>,
}

/// How a track is flown.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlightPlan {
    /// The horizon (s after the start).
    pub seconds: f64,
    /// A track point at least this often (s); also one at the horizon.
    pub record_every: f64,
    /// Stop at the first surfacing (a hindcast's segment).
    pub stop_at_first_fix: StopAt,
    /// What leaving the current or bathymetry grid does.
    pub outside: Outside,
}

/// What a track that leaves its current or bathymetry grid does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outside {
    /// The flight fails with the error (the forecast's own track).
    Fail,
    /// The track ends there, the error kept in [`Track::left_grid`] (an
    /// ensemble member: the others fly on, and the regions say how many
    /// members each holds).
    Stop,
}

/// Where a flight stops.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopAt {
    Horizon,
    FirstSurfacing,
}

/// The mission as the glider flies it from `start`: the start fix, its belief
/// and mean speed as `sensor:` settings (`s_ini_lat/lon`, `m_water_vx/vy`,
/// `m_avg_speed`, `m_heading`), the goto list starting at the logged waypoint,
/// and `prepare_to_dive` diving at once (the glider is at its last fix, done
/// at the surface).
pub fn prepare_mission(mission: &Mission, start: &Start) -> Mission {
    let mut mission = mission.clone();
    let mut set = |name: &str, units: &str, value: f64| {
        mission.sensor_settings.push(SensorSetting {
            name: name.to_string(),
            units: units.to_string(),
            value,
            at: Location {
                file: 0,
                span: Span::default(),
            },
            name_span: Span::default(),
        });
    };
    set("s_ini_lat", "lat", start.lat);
    set("s_ini_lon", "lon", start.lon);
    set("m_water_vx", "m/s", start.believed.x);
    set("m_water_vy", "m/s", start.believed.y);
    if let Some(speed) = start.avg_speed {
        set("m_avg_speed", "m/s", speed);
    }
    if let Some(heading) = start.heading {
        set("m_heading", "rad", heading);
    }
    for spec in &mut mission.behaviors {
        match spec.kind {
            BehaviorKind::GotoList => {
                if let Some(index) = start
                    .waypoint
                    .and_then(|(lat, lon)| waypoint_index(spec, lat, lon))
                {
                    set_arg(spec, "initial_wpt", "enum", index as f64);
                }
            }
            BehaviorKind::PrepareToDive => set_arg(spec, "wait_time", "s", 0.0),
            _ => {}
        }
    }
    mission
}

/// The index of the goto list's waypoint at (lat, lon) NMEA, within 0.001′.
fn waypoint_index(spec: &gloc_mission::mission::BehaviorSpec, lat: f64, lon: f64) -> Option<usize> {
    (0..MAX_WAYPOINTS).find(|number| {
        let x = spec.arg(&format!("wpt_x_{number}"));
        let y = spec.arg(&format!("wpt_y_{number}"));
        matches!((x, y), (Some(x), Some(y)) if (x - lon).abs() < 1e-3 && (y - lat).abs() < 1e-3)
    })
}

/// The waypoints a goto list is searched for the logged one.
const MAX_WAYPOINTS: usize = 64;

/// Sets every copy of a behavior's argument (the `.mi`'s and the `.ma`'s), or adds it.
fn set_arg(spec: &mut gloc_mission::mission::BehaviorSpec, name: &str, units: &str, value: f64) {
    let mut found = false;
    for arg in &mut spec.args {
        if arg.name.eq_ignore_ascii_case(name) {
            arg.value = value;
            found = true;
        }
    }
    if !found {
        spec.args.push(Arg {
            name: name.to_string(),
            units: units.to_string(),
            value,
            at: spec.at,
        });
    }
}

/// Flies `mission` (already [`prepare_mission`]ed) from `start` in `truth`,
/// over `bathymetry`'s water depth when given (else the mission's or the
/// configuration's).
pub fn fly(
    mission: &Mission,
    sensors: &Arc<SensorList>,
    config: &SimConfig,
    start: &Start,
    truth: &Truth,
    bathymetry: Option<&Arc<dyn DepthField>>,
    plan: &FlightPlan,
) -> Result<Track, ForecastError> {
    let flight = Flight {
        mission,
        sensors,
        config,
        start,
        truth,
        bathymetry,
    };
    fly_with(&flight, plan, &Extras::default()).map(|flown| flown.track)
}

/// One flight's inputs, as [`fly`] takes them.
#[derive(Clone, Copy)]
pub struct Flight<'a> {
    /// The mission, already [`prepare_mission`]ed for `start`.
    pub mission: &'a Mission,
    pub sensors: &'a Arc<SensorList>,
    pub config: &'a SimConfig,
    pub start: &'a Start,
    /// The current the glider flies in.
    pub truth: &'a Truth,
    /// The water depth; `None`: the mission's or the configuration's.
    pub bathymetry: Option<&'a Arc<dyn DepthField>>,
}

/// What a flight can do beyond a forecast member's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Extras {
    /// The drift at the surface, from a surfacing to the next dive (m/s east,
    /// north); `None`: the truth's current there too. A hindcast flies the
    /// current the glider found underwater and the drift it measured at the
    /// surface apart, as the firmware separates them.
    pub surface_drift: Option<Xy>,
    /// The charge (Ah, as `m_coulomb_amphr_total` counts it) at which the
    /// flight notes when the battery reaches the mission's limit.
    pub battery_limit: Option<BatteryLimit>,
}

/// The charge at which the battery reaches a limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BatteryLimit {
    /// `m_coulomb_amphr_total` at the start (Ah).
    pub used_at_start: f64,
    /// `m_coulomb_amphr_total` at the limit (Ah).
    pub used_at_limit: f64,
}

/// A flight's track and what [`Extras`] asked to watch.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Flown {
    pub track: Track,
    /// Unix seconds when the charge used reached [`BatteryLimit::used_at_limit`].
    pub battery_limit_at: Option<f64>,
}

pub(crate) fn fly_with(
    flight: &Flight<'_>,
    plan: &FlightPlan,
    extras: &Extras,
) -> Result<Flown, ForecastError> {
    let (start, truth, bathymetry) = (flight.start, flight.truth, flight.bathymetry);
    let mut config = flight.config.clone();
    config.start_time = start.time;
    let mut sim = Simulation::new(flight.mission, flight.sensors.clone(), None, &config)
        .map_err(|error| ForecastError::Mission(error.to_string()))?;
    sim.start_timers_before(start.timers_elapsed);
    if let Some(fraction) = crate::battery::used_fraction(start, &config) {
        sim.start_battery(fraction, start.amp_hours.unwrap_or(0.0));
    }
    let lmc = sim.navigation().lmc;
    let mut flown = Flown::default();
    let mut track = Track::default();
    let mut dove = false;
    let mut state = sim.navigation().dr_state;
    let mut next_record = 0.0;
    let amp_hours_before = sim.amp_hours();
    loop {
        let now = sim.time();
        if let Truth::Uniform(water) = truth {
            sim.set_true_water(*water);
        }
        if let Err(message) = set_surroundings(&mut sim, &lmc, start.time + now, truth, bathymetry)
        {
            match plan.outside {
                Outside::Fail => return Err(ForecastError::Currents(message)),
                Outside::Stop => {
                    track.left_grid = Some(message);
                    break;
                }
            }
        }
        let at_surface = matches!(
            sim.navigation().dr_state,
            DrState::Surfaced | DrState::FirstFix
        );
        if let (Some(drift), true) = (extras.surface_drift, at_surface) {
            sim.set_true_water(drift);
        }
        if let Some(limit) = extras.battery_limit {
            let used = limit.used_at_start + sim.amp_hours() - amp_hours_before;
            if flown.battery_limit_at.is_none() && used >= limit.used_at_limit {
                flown.battery_limit_at = Some(start.time + now);
            }
        }
        if now >= next_record || now >= plan.seconds {
            let (lat, lon) = lmc.to_lat_lon(sim.navigation().true_position);
            track.points.push(TrackPoint {
                time: start.time + now,
                lat,
                lon,
                depth: sim.depth(),
            });
            // Aligned to multiples of `record_every` after the start (an
            // ensemble's hourly regions look the points up by the hour).
            while next_record <= now {
                next_record += plan.record_every.max(1.0);
            }
        }
        if now >= plan.seconds {
            break;
        }
        if !sim.step_cycle() {
            track.ended = sim.end().map(|end| match end.reason {
                EndReason::Completed => "the mission completed".to_string(),
                reason => format!("the mission ended: {reason}"),
            });
            break;
        }
        let nav = sim.navigation();
        dove |= nav.dr_state == DrState::Underwater;
        if nav.dr_state != state {
            state = nav.dr_state;
            if state == DrState::FirstFix && dove {
                let fix = nav.gps_fix.unwrap_or(nav.true_position);
                let (lat, lon) = lmc.to_lat_lon(fix);
                let waypoint = sim.waypoint();
                track.surfacings.push(Surfacing {
                    time: start.time + sim.time(),
                    lat,
                    lon,
                    waypoint: waypoint.map(|at| lmc.to_lat_lon(at)),
                    distance_to_waypoint: waypoint.map(|at| at.distance(fix)),
                    underwater: nav.dr_time,
                    estimate: nav.initial_water,
                });
                if plan.stop_at_first_fix == StopAt::FirstSurfacing {
                    let (lat, lon) = lmc.to_lat_lon(fix);
                    track.points.push(TrackPoint {
                        time: start.time + sim.time(),
                        lat,
                        lon,
                        depth: sim.depth(),
                    });
                    break;
                }
            }
        }
    }
    track.amp_hours_used = sim.amp_hours() - amp_hours_before;
    flown.track = track;
    Ok(flown)
}

/// The true current and the water depth at the glider's true position now.
fn set_surroundings(
    sim: &mut Simulation,
    lmc: &Lmc,
    time: f64,
    truth: &Truth,
    bathymetry: Option<&Arc<dyn DepthField>>,
) -> Result<(), String> {
    let (lat, lon) = lmc.to_lat_lon(sim.navigation().true_position);
    if let Truth::Field(field, offset) = truth {
        let water = field.at(time, lat, lon)?;
        sim.set_true_water(water + *offset);
    }
    if let Some(bathymetry) = bathymetry {
        sim.set_water_depth(bathymetry.depth_at(time, lat, lon)?);
    }
    Ok(())
}

/// Decimal degrees of an NMEA pair.
pub fn degrees(lat: f64, lon: f64) -> (f64, f64) {
    (nmea_to_degrees(lat), nmea_to_degrees(lon))
}
