//! `gloc.forecast`: the forecast crate's calls as `gloc forecast` makes them
//! (the logs' history, the mission, the true current, the ensemble's options),
//! and the tracks and regions as plain tuples. Three calls, so that Python can
//! spread an ensemble's members over a Dask cluster: `forecast` flies the track
//! (and, with `threads`, the members on this machine's threads), `forecast_members`
//! flies members `first..last` (a chunk, in a worker), and `forecast_summary`
//! reduces the members' tracks to the regions. Each call sets the forecast up
//! anew from the same arguments: a member depends on the seed and its number
//! only (`gloc_forecast::ensemble::fly_member`), so any split gives the same members.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gloc_dbd::Deployment;
use gloc_engine::sensors::SensorList;
use gloc_forecast::currents::CurrentField;
use gloc_forecast::ensemble::{self, EnsembleInput, EnsembleOptions};
use gloc_forecast::fly::Flight;
use gloc_forecast::fly::{Surfacing, Track, TrackPoint, Truth};
use gloc_forecast::{LogHistory, Request, Start};
use gloc_project::simulation::Unscripted;
use gloc_project::{Overrides, Surface};
use gloc_sim::navigation::Xy;
use gloc_sim::{Mission, SimConfig};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::{log_error, mission_error, project, project_error};

/// What a forecast is asked for, as Python passes it to each of the three calls.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct Asked {
    logs: Vec<PathBuf>,
    mission: PathBuf,
    hours: f64,
    currents: Option<PathBuf>,
    bathymetry: Option<PathBuf>,
    sensor_cache: Option<PathBuf>,
    simulator: Vec<(String, f64)>,
    members: usize,
    seed: u64,
    /// σ of the current (m/s east, north); `None`: the logs' own spread.
    spread: Option<(f64, f64)>,
}

/// A member's (or the forecast's) track: `(points, surfacings, ended,
/// amp_hours_used, left_grid)`, a point `(time, lat, lon, depth)`, a surfacing
/// `(time, lat, lon, waypoint_lat, waypoint_lon, distance_to_waypoint,
/// underwater, estimate_u, estimate_v)`, decimal degrees, Unix seconds.
type PyTrack = (
    Vec<(f64, f64, f64, f64)>,
    Vec<PySurfacing>,
    Option<String>,
    f64,
    Option<String>,
);
type PySurfacing = (
    f64,
    f64,
    f64,
    Option<f64>,
    Option<f64>,
    Option<f64>,
    f64,
    f64,
    f64,
);

/// Everything every track of the forecast shares, set up as `gloc forecast` does.
struct Setup {
    history: LogHistory,
    sensors: Arc<SensorList>,
    config: SimConfig,
    /// What setting the flight up warned of (as `gloc.run`'s summary gives them).
    warnings: Vec<String>,
    request: Request,
    mission: Mission,
    start: Start,
    /// The mission as the glider flies it from the start.
    prepared: Mission,
    truth: Truth,
    options: EnsembleOptions,
}

impl Setup {
    fn new(asked: &Asked, threads: usize) -> PyResult<Setup> {
        gloc_forecast::check_hours(asked.hours)
            .map_err(|why| PyValueError::new_err(format!("hours={}: {why}", asked.hours)))?;
        if asked.members > 0 {
            ensemble::check_members(asked.members).map_err(|why| {
                PyValueError::new_err(format!(
                    "members={}: {why} (or 0: no ensemble)",
                    asked.members
                ))
            })?;
        }
        let (settings, sensors) = project(
            Some(&asked.mission),
            Overrides {
                mission: Some(asked.mission.clone()),
                sensor_cache: asked.sensor_cache.clone(),
                simulator: asked.simulator.clone(),
                ..Overrides::new(Surface::Cli)
            },
        )?;
        let sensors = Arc::new(sensors);
        let (mission, prepared) =
            match gloc_project::simulation::prepare_unscripted(&settings, &sensors)
                .map_err(project_error)?
            {
                Unscripted::MissionErrors(mission) => {
                    return Err(mission_error(&mission, "forecast"));
                }
                Unscripted::Ready { mission, prepared } => (mission, prepared),
            };
        let warnings: Vec<String> = prepared
            .warnings
            .into_iter()
            .map(crate::warning_text)
            .collect();
        let config = prepared.config;
        let mut source =
            Deployment::open(&asked.logs, settings.sensor_cache.as_deref()).map_err(log_error)?;
        let history =
            gloc_forecast::logs::read_history(&mut source).map_err(|error| match error {
                gloc_forecast::logs::LogError::Read(error) => log_error(error),
                gloc_forecast::logs::LogError::Content(message) => {
                    PyValueError::new_err(format!("cannot forecast: {message}"))
                }
            })?;
        let currents = match &asked.currents {
            Some(path) => Some(load_currents(path, history.depth_range)?),
            None => None,
        };
        let bathymetry = match &asked.bathymetry {
            Some(path) => {
                let grid = gloc_forecast::netcdf::read_bathymetry(path).map_err(|message| {
                    PyValueError::new_err(format!("bathymetry `{}`: {message}", path.display()))
                })?;
                let shared: Arc<dyn gloc_forecast::netcdf::DepthField> = Arc::new(grid);
                Some(shared)
            }
            None => None,
        };
        let options = EnsembleOptions {
            members: asked.members,
            seed: asked.seed,
            spread: match asked.spread {
                Some((x, y)) if valid_spread(x) && valid_spread(y) => Xy::new(x, y),
                Some((x, y)) => {
                    return Err(PyValueError::new_err(format!(
                        "spread=({x}, {y}): give each σ 0 to 5 m/s"
                    )))
                }
                None => ensemble::spread_from_history(&history),
            },
            threads: threads.max(1),
        };
        let request = Request {
            hours: asked.hours,
            currents,
            bathymetry,
            ensemble: None,
        };
        let start = Start::from_history(&history).map_err(forecast_error)?;
        let prepared = gloc_forecast::fly::prepare_mission(&mission, &start);
        let (truth, _) = gloc_forecast::truth(&request, &start);
        Ok(Setup {
            history,
            sensors,
            config,
            warnings,
            start,
            prepared,
            mission,
            truth,
            options,
            request,
        })
    }

    fn input(&self) -> EnsembleInput<'_> {
        EnsembleInput {
            flight: Flight {
                mission: &self.prepared,
                sensors: &self.sensors,
                config: &self.config,
                start: &self.start,
                truth: &self.truth,
                bathymetry: self.request.bathymetry.as_ref(),
            },
            hours: self.request.hours,
        }
    }
}

fn valid_spread(value: f64) -> bool {
    value.is_finite() && (0.0..=5.0).contains(&value)
}

fn forecast_error(error: gloc_forecast::ForecastError) -> PyErr {
    PyValueError::new_err(format!("cannot forecast: {error}"))
}

/// A current file by its extension, as `gloc forecast --currents` takes it.
fn load_currents(
    path: &Path,
    depth_range: Option<(f64, f64)>,
) -> PyResult<(Arc<dyn CurrentField>, String)> {
    gloc_forecast::currents::load(path, depth_range)
        .map_err(|error| PyValueError::new_err(format!("currents: {error}")))
}

fn track_out(track: &Track) -> PyTrack {
    (
        track
            .points
            .iter()
            .map(|p| (p.time, p.lat, p.lon, p.depth))
            .collect(),
        track
            .surfacings
            .iter()
            .map(|s| {
                (
                    s.time,
                    s.lat,
                    s.lon,
                    s.waypoint.map(|w| w.0),
                    s.waypoint.map(|w| w.1),
                    s.distance_to_waypoint,
                    s.underwater,
                    s.estimate.x,
                    s.estimate.y,
                )
            })
            .collect(),
        track.ended.clone(),
        track.amp_hours_used,
        track.left_grid.clone(),
    )
}

fn track_in(track: PyTrack) -> Track {
    let (points, surfacings, ended, amp_hours_used, left_grid) = track;
    Track {
        points: points
            .into_iter()
            .map(|(time, lat, lon, depth)| TrackPoint {
                time,
                lat,
                lon,
                depth,
            })
            .collect(),
        surfacings: surfacings
            .into_iter()
            .map(
                |(time, lat, lon, wlat, wlon, distance, underwater, u, v)| Surfacing {
                    time,
                    lat,
                    lon,
                    waypoint: wlat.zip(wlon),
                    distance_to_waypoint: distance,
                    underwater,
                    estimate: Xy::new(u, v),
                },
            )
            .collect(),
        ended,
        amp_hours_used,
        left_grid,
    }
}

/// `gloc.forecast`'s first call: the forecast `gloc forecast` makes (the start,
/// the track in the forecast's current) and the ensemble's σ, as a dict; with
/// `threads` > 0 and members asked, the members flown here on that many threads
/// (`members`, their tracks) and their summary (`ensemble`).
#[pyfunction]
pub fn forecast(py: Python<'_>, asked: Asked, threads: usize) -> PyResult<Bound<'_, PyDict>> {
    let (setup, made, members) = py.allow_threads(|| {
        let setup = Setup::new(&asked, threads)?;
        let made = gloc_forecast::forecast(
            &setup.history,
            &setup.mission,
            &setup.sensors,
            &setup.config,
            &setup.request,
        )
        .map_err(forecast_error)?;
        let members = if threads > 0 && setup.options.members > 0 {
            let tracks =
                ensemble::fly_members(&setup.input(), &setup.options).map_err(forecast_error)?;
            let summary = ensemble::summarize(&setup.input(), &setup.options, &tracks);
            Some((tracks, summary))
        } else {
            None
        };
        Ok::<_, PyErr>((setup, made, members))
    })?;
    let out = PyDict::new(py);
    let start = &made.start;
    let (lat, lon) = gloc_forecast::fly::degrees(start.lat, start.lon);
    let begin = PyDict::new(py);
    begin.set_item("time", start.time)?;
    begin.set_item("lat", lat)?;
    begin.set_item("lon", lon)?;
    begin.set_item("believed", (start.believed.x, start.believed.y))?;
    begin.set_item("waypoint", start.waypoint)?;
    begin.set_item("avg_speed", start.avg_speed)?;
    begin.set_item("amp_hours", start.amp_hours)?;
    begin.set_item("battery", start.battery)?;
    out.set_item("start", begin)?;
    out.set_item("mission", &made.mission_name)?;
    out.set_item("current", &made.current)?;
    out.set_item("hours", made.hours)?;
    out.set_item("spread", (setup.options.spread.x, setup.options.spread.y))?;
    out.set_item("warnings", &setup.warnings)?;
    out.set_item("end_time", setup.history.end_time)?;
    out.set_item(
        "fixes",
        setup
            .history
            .fixes
            .iter()
            .map(|fix| {
                let (lat, lon) = gloc_forecast::fly::degrees(fix.lat, fix.lon);
                (fix.time, lat, lon)
            })
            .collect::<Vec<_>>(),
    )?;
    out.set_item("track", track_out(&made.track))?;
    if let Some((tracks, summary)) = members {
        out.set_item("members", tracks.iter().map(track_out).collect::<Vec<_>>())?;
        out.set_item("ensemble", summary_out(py, &summary)?)?;
    }
    Ok(out)
}

/// `gloc.forecast`'s chunk: members `first..last` flown one after the other
/// (a Dask task's work), their tracks by number.
#[pyfunction]
pub fn forecast_members(
    py: Python<'_>,
    asked: Asked,
    first: usize,
    last: usize,
) -> PyResult<Vec<PyTrack>> {
    if first > last || last > asked.members {
        return Err(PyValueError::new_err(format!(
            "members {first}..{last}: give a range within 0..{}",
            asked.members
        )));
    }
    py.allow_threads(|| {
        let setup = Setup::new(&asked, 1)?;
        let input = setup.input();
        (first..last)
            .map(|number| {
                ensemble::fly_member(&input, &setup.options, number)
                    .map(|track| track_out(&track))
                    .map_err(forecast_error)
            })
            .collect()
    })
}

/// `gloc.forecast`'s reduction: every member's track, by number, to the regions
/// per hour and the surfacing spreads.
#[pyfunction]
pub fn forecast_summary(
    py: Python<'_>,
    asked: Asked,
    tracks: Vec<PyTrack>,
) -> PyResult<Bound<'_, PyDict>> {
    if tracks.len() != asked.members {
        return Err(PyValueError::new_err(format!(
            "{} member tracks for an ensemble of {}",
            tracks.len(),
            asked.members
        )));
    }
    let summary = py.allow_threads(|| {
        let setup = Setup::new(&asked, 1)?;
        let tracks: Vec<Track> = tracks.into_iter().map(track_in).collect();
        Ok::<_, PyErr>(ensemble::summarize(&setup.input(), &setup.options, &tracks))
    })?;
    summary_out(py, &summary)
}

/// An ensemble's summary as a dict: `offsets` `[(u, v)]` by member; `regions`
/// `[(hour, time, members, [(lat, lon)])]`; `surfacings` `[(number, members,
/// earliest, latest, mean_time, mean_lat, mean_lon, radius_95, radius_max,
/// [(lat, lon)])]`; `left_grid` `[(member, message)]`.
fn summary_out<'py>(py: Python<'py>, summary: &ensemble::Ensemble) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item(
        "offsets",
        summary
            .offsets
            .iter()
            .map(|o| (o.x, o.y))
            .collect::<Vec<_>>(),
    )?;
    out.set_item(
        "regions",
        summary
            .regions
            .iter()
            .map(|r| (r.hour, r.time, r.members, r.hull.clone()))
            .collect::<Vec<_>>(),
    )?;
    out.set_item(
        "surfacings",
        summary
            .surfacings
            .iter()
            .map(|s| {
                (
                    s.number,
                    s.members,
                    s.earliest,
                    s.latest,
                    s.mean_time,
                    s.mean.0,
                    s.mean.1,
                    s.radius_95,
                    s.radius_max,
                    s.hull.clone(),
                )
            })
            .collect::<Vec<_>>(),
    )?;
    out.set_item("left_grid", summary.left_grid.clone())?;
    Ok(out)
}
