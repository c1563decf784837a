//! `gloc forecast`: where will the glider be? Parses the flags, resolves the
//! project (mission, sensor list, `[simulator]`), reads the logs and hands
//! everything to `gloc_forecast`; prints the predicted surfacings (or the
//! hindcast table) and writes the outputs, each by its extension.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use anyhow::{bail, Context as _};
use clap::Args;
use gloc_forecast::currents::{CurrentField, LoadError};
use gloc_forecast::export::{iso_time, nmea_text, Format};
use gloc_forecast::map::write_map;
use gloc_forecast::{ensemble, hindcast, EnsembleOptions, Forecast, Request};
use gloc_project::simulation::Unscripted;
use gloc_project::{Overrides, Settings, Surface};
use gloc_sim::navigation::Xy;
use gloc_sim::plot::PlotFormat;

use crate::data::SourceArgs;
use crate::render::Tally;

#[derive(Args, Debug)]
pub struct ForecastArgs {
    #[command(flatten)]
    pub source: SourceArgs,
    /// The mission the glider flies (`.mi`); default: gloc.toml's `mission`.
    #[arg(long, value_name = "M.mi")]
    pub mission: Option<PathBuf>,
    /// Hours to forecast, up to 720; default 12.
    #[arg(long, value_name = "H", default_value_t = 12.0)]
    pub hours: f64,
    /// The true current: an ocean model's CF NetCDF (`.nc`: u/v on time × [depth ×] lat ×
    /// lon, averaged over the glider's depth range) or a CSV time series `time,u,v` (Unix
    /// seconds or UTC, m/s east and north); default: the glider's own latest estimate
    /// (`m_water_vx/vy`).
    #[arg(long, value_name = "FILE")]
    pub currents: Option<PathBuf>,
    /// The water depth under the track: a NetCDF elevation or depth grid (GEBCO-style,
    /// `.nc`); default: the mission's `s_water_depth_avg`, else 40 m.
    #[arg(long, value_name = "FILE")]
    pub bathymetry: Option<PathBuf>,
    /// Write the forecast (repeatable): `.geojson`, `.kml` or `.csv` by the extension, or
    /// a map `.png` / `.svg`; default: print only.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub outputs: Vec<PathBuf>,
    /// Fly each segment of the logs again with the current found after it and print
    /// the miss at the real first fix, beside the null model's (the prior current); `-o`
    /// then takes a map (.png, .svg); default: forecast from the logs' end.
    #[arg(long, conflicts_with_all = ["members", "currents", "bathymetry"])]
    pub hindcast: bool,
    /// Fly an ensemble of N members over the current's uncertainty (up to 100,000);
    /// default: none, the single track.
    #[arg(long, value_name = "N")]
    pub members: Option<usize>,
    /// The σ of the ensemble's current, m/s east,north (or one value for both);
    /// default: the spread of the glider's own current estimates in the logs, at least 0.02.
    #[arg(long, value_name = "SX[,SY]")]
    pub current_spread: Option<String>,
    /// The ensemble's seed; default 1. The same seed gives the same members on any
    /// number of threads.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u64,
    /// Threads for the ensemble; default: the number of cores.
    #[arg(long, short = 'j', value_name = "N")]
    pub jobs: Option<usize>,
    #[command(flatten)]
    pub sensors: crate::flags::SensorListArgs,
    /// A folder searched first for the mission's `.ma` files; default: gloc.toml's `mafiles`.
    #[arg(long, value_name = "DIR")]
    pub mafiles: Option<PathBuf>,
    /// Set a simulator constant (repeatable), e.g. `dive_rate=0.2`; wins over gloc.toml's
    /// `[simulator]` (calibrate with `gloc calibrate`).
    #[arg(long = "sim", value_name = "NAME=VALUE", value_parser = gloc_project::settings::parse_simulator_setting)]
    pub simulator: Vec<(String, f64)>,
}

pub fn main(args: ForecastArgs) -> anyhow::Result<ExitCode> {
    gloc_forecast::check_hours(args.hours)
        .map_err(|why| anyhow::anyhow!("--hours {}: {why}", args.hours))?;
    let formats = args
        .outputs
        .iter()
        .map(|path| match PlotFormat::from_path(path) {
            Ok(_) => Ok(None),
            Err(_) => Format::from_path(path)
                .map(Some)
                .map_err(|message| anyhow::anyhow!("{message}, or a map .png or .svg")),
        })
        .collect::<anyhow::Result<Vec<Option<Format>>>>()?;
    let mut inputs: Vec<&Path> = args.source.files.iter().map(PathBuf::as_path).collect();
    inputs.extend(args.mission.as_deref());
    inputs.extend(args.currents.as_deref());
    inputs.extend(args.bathymetry.as_deref());
    let outputs: Vec<crate::output::Output<'_>> = args
        .outputs
        .iter()
        .map(|path| crate::output::Output { flag: "-o", path })
        .collect();
    crate::output::check_outputs(&inputs, &outputs)?;
    if let Some(count) = args.members {
        ensemble::check_members(count)
            .map_err(|why| anyhow::anyhow!("--members {count}: {why}"))?;
    }

    let Some((sensors, mission, config)) = set_up(&args)? else {
        return Ok(crate::exit::code(crate::exit::ERRORS));
    };

    let mut source = crate::data::open(&args.source)?;
    let history = gloc_forecast::logs::read_history(&mut source).map_err(|error| match error {
        gloc_forecast::logs::LogError::Read(error) => anyhow::Error::new(error),
        gloc_forecast::logs::LogError::Content(message) => {
            anyhow::Error::new(crate::exit::Invalid(message))
        }
    })?;
    for warning in gloc_dbd::CycleSource::take_warnings(&mut source) {
        eprintln!("warning: {warning}");
    }

    if args.hindcast {
        if let Some(path) = args
            .outputs
            .iter()
            .find(|path| PlotFormat::from_path(path).is_err())
        {
            bail!(
                "-o `{}`: a hindcast writes a map (.png or .svg)",
                path.display()
            );
        }
        return print_hindcast(&history, &mission, &sensors, &config, &args.outputs);
    }
    let currents = match &args.currents {
        Some(path) => Some(load_currents(path, history.depth_range)?),
        None => None,
    };
    let bathymetry = match &args.bathymetry {
        Some(path) => {
            readable(path, "the bathymetry")?;
            let grid = gloc_forecast::netcdf::read_bathymetry(path)
                .map_err(|message| anyhow::Error::new(crate::exit::Invalid(message)))
                .context("--bathymetry")?;
            let shared: Arc<dyn gloc_forecast::netcdf::DepthField> = Arc::new(grid);
            Some(shared)
        }
        None => None,
    };
    let ensemble = match args.members {
        Some(members) => Some(EnsembleOptions {
            members,
            seed: args.seed,
            spread: match &args.current_spread {
                Some(text) => parse_spread(text)?,
                None => ensemble::spread_from_history(&history),
            },
            threads: args.jobs.unwrap_or_else(|| {
                std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
            }),
        }),
        None => None,
    };
    let request = Request {
        hours: args.hours,
        currents,
        bathymetry,
        ensemble,
    };
    let forecast = gloc_forecast::forecast(&history, &mission, &sensors, &config, &request)
        .map_err(|error| crate::exit::Invalid(format!("cannot forecast: {error}")))?;
    print_forecast(&forecast, &history);
    for (path, format) in args.outputs.iter().zip(formats) {
        match format {
            Some(format) => {
                let bytes = format.write(&forecast).map_err(anyhow::Error::msg)?;
                crate::output::write_atomically(path, &bytes)
                    .map_err(|error| crate::output::write_error(error, "the forecast", path))?;
            }
            None => crate::output::write_through_temporary(path, |temporary| {
                write_map(&forecast, &history.fixes, temporary)
            })?,
        }
        eprintln!("wrote {}", path.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// The project the forecast flies in: the settings resolved, the sensor list, the
/// mission, and the simulator set up where `gloc run` sets its flights up (the
/// mission built and checked against the list, its warnings printed). `None` after
/// errors that were printed.
fn set_up(
    args: &ForecastArgs,
) -> anyhow::Result<
    Option<(
        Arc<gloc_engine::sensors::SensorList>,
        gloc_sim::Mission,
        gloc_sim::SimConfig,
    )>,
> {
    let settings = Settings::resolve(
        args.mission
            .as_deref()
            .or(args.source.files.first().map(PathBuf::as_path)),
        args.sensors.overrides(Overrides {
            mission: args.mission.clone(),
            mafiles: args.mafiles.clone(),
            sensor_cache: args.source.sensor_cache.clone(),
            simulator: args.simulator.clone(),
            ..Overrides::new(Surface::Cli)
        }),
    )?;
    if settings.mission.is_none() {
        bail!("--mission: name the mission the glider flies (or `mission` in gloc.toml)");
    }
    let mut tally = Tally::default();
    let Some(sensor_list) = crate::loading::active_sensors(&settings, &mut tally)? else {
        return Ok(None);
    };
    let sensors = Arc::new(sensor_list);
    let (mission, prepared) =
        match gloc_project::simulation::prepare_unscripted(&settings, &sensors)? {
            Unscripted::MissionErrors(mission) => {
                eprint!("{}", mission.render_plain());
                eprintln!("error: the mission has errors; nothing was forecast");
                return Ok(None);
            }
            Unscripted::Ready { mission, prepared } => (mission, prepared),
        };
    crate::simulate::print_warnings(&prepared.warnings, &mission, "", "");
    Ok(Some((sensors, mission, prepared.config)))
}

fn load_currents(
    path: &Path,
    depth_range: Option<(f64, f64)>,
) -> anyhow::Result<(Arc<dyn CurrentField>, String)> {
    gloc_forecast::currents::load(path, depth_range).map_err(|error| match error {
        LoadError::Unreadable(message) => anyhow::Error::new(crate::exit::Unreadable(message)),
        LoadError::Invalid(message) => {
            anyhow::Error::new(crate::exit::Invalid(message)).context("--currents")
        }
    })
}

fn readable(path: &Path, what: &str) -> anyhow::Result<()> {
    gloc_engine::files::open_regular(path)
        .map(drop)
        .map_err(|error| {
            anyhow::Error::new(crate::exit::Unreadable(format!(
                "cannot read {what} `{}`: {error}",
                path.display()
            )))
        })
}

fn parse_spread(text: &str) -> anyhow::Result<Xy> {
    let values: Vec<f64> = text
        .split(',')
        .map(|part| part.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| anyhow::anyhow!("--current-spread `{text}`: give SX or SX,SY in m/s"))?;
    let valid = |value: f64| value.is_finite() && (0.0..=5.0).contains(&value);
    match values[..] {
        [both] if valid(both) => Ok(Xy::new(both, both)),
        [x, y] if valid(x) && valid(y) => Ok(Xy::new(x, y)),
        _ => bail!("--current-spread `{text}`: give SX or SX,SY, each 0 to 5 m/s"),
    }
}

fn print_forecast(forecast: &Forecast, history: &gloc_forecast::LogHistory) {
    let start = &forecast.start;
    let (lat, lon) = gloc_forecast::fly::degrees(start.lat, start.lon);
    outln!(
        "start    {}  {} {}  ({lat:.5}, {lon:.5})  the last fix of the logs",
        iso_time(start.time),
        nmea_text(lat),
        nmea_text(lon)
    );
    outln!("current  {}", forecast.current);
    if let Some((wlat, wlon)) = start.waypoint {
        outln!("waypoint {wlat:.3} {wlon:.3} (c_wpt_lat/lon)");
    }
    let battery = match (start.amp_hours, start.battery) {
        (Some(ah), Some(volts)) => format!("{ah:.2} Ah used, {volts:.2} V"),
        (Some(ah), None) => format!("{ah:.2} Ah used"),
        (None, Some(volts)) => format!("{volts:.2} V"),
        (None, None) => "not in the logs".to_string(),
    };
    outln!(
        "battery  {battery}; the forecast uses {:.2} Ah more",
        forecast.track.amp_hours_used
    );
    if let Some(outlook) = &forecast.battery {
        print_battery(outlook, forecast.hours);
    }
    if history.end_time > start.time + 600.0 {
        eprintln!(
            "warning: the logs go on {:.0} s after the last fix: the forecast starts at the fix",
            history.end_time - start.time
        );
    }
    outln!("predicted surfacings (first GPS fix after each dive):");
    if forecast.track.surfacings.is_empty() {
        outln!("  none within {} h", forecast.hours);
    }
    for (index, s) in forecast.track.surfacings.iter().enumerate() {
        let distance = match (s.distance_to_waypoint, s.waypoint) {
            (Some(d), Some((wlat, wlon))) => format!(
                "  {d:.0} m to the waypoint {} {}",
                nmea_text(wlat),
                nmea_text(wlon)
            ),
            _ => String::new(),
        };
        outln!(
            "  {:>2}  {}  {} {}  ({:.5}, {:.5}){distance}",
            index + 1,
            iso_time(s.time),
            nmea_text(s.lat),
            nmea_text(s.lon),
            s.lat,
            s.lon
        );
    }
    if let Some(ended) = &forecast.track.ended {
        outln!("the flight stopped early: {ended}");
    }
    if let Some(ensemble) = &forecast.ensemble {
        outln!(
            "ensemble {} members, seed {}, current σ ({:.3}, {:.3}) m/s east, north",
            ensemble.members,
            ensemble.seed,
            ensemble.spread.x,
            ensemble.spread.y
        );
        if let Some((number, message)) = ensemble.left_grid.first() {
            eprintln!(
                "warning: {} of {} members left the grid and stopped there (they count in the hours before); member {number}: {message}",
                ensemble.left_grid.len(),
                ensemble.members
            );
        }
        for spread in &ensemble.surfacings {
            outln!(
                "  surfacing {}: {} members, {} to {}, 95% within {:.0} m of ({:.5}, {:.5}), all within {:.0} m",
                spread.number,
                spread.members,
                iso_time(spread.earliest),
                iso_time(spread.latest),
                spread.radius_95,
                spread.mean.0,
                spread.mean.1,
                spread.radius_max
            );
        }
    }
}

/// The charge left against the mission's low-battery abort, and when the
/// forecast reaches it.
fn print_battery(outlook: &gloc_forecast::battery::BatteryOutlook, hours: f64) {
    let capacity = if outlook.capacity_from_logs {
        format!("{:.0} Ah (f_coulomb_battery_capacity)", outlook.capacity)
    } else {
        format!(
            "{:.0} Ah (the simulator's battery_wh / volts_full: the logs hold no f_coulomb_battery_capacity)",
            outlook.capacity
        )
    };
    let limit = match outlook.remaining_charge_min {
        Some(percent) => format!(
            "abend's remaining_charge_min {percent}% aborts at {:.1} Ah used",
            outlook.limit
        ),
        None => format!(
            "no abend: the battery runs out at {:.1} Ah used",
            outlook.limit
        ),
    };
    let when = match outlook.reached_at {
        Some(time) => format!("reached at {}", iso_time(time)),
        None if outlook.margin() <= 0.0 => "already past it".to_string(),
        None => format!("not within {hours} h ({:.1} Ah to go)", outlook.margin()),
    };
    outln!(
        "         {:.1}% left of {capacity}; {limit}: {when}",
        outlook.remaining_percent()
    );
    if outlook.reached_at.is_some() || outlook.margin() <= 0.0 {
        eprintln!(
            "warning: the battery reaches the mission's low-battery abort within the forecast"
        );
    }
}

fn print_hindcast(
    history: &gloc_forecast::LogHistory,
    mission: &gloc_sim::Mission,
    sensors: &Arc<gloc_engine::sensors::SensorList>,
    config: &gloc_sim::SimConfig,
    maps: &[PathBuf],
) -> anyhow::Result<ExitCode> {
    let results = hindcast::hindcast(history, mission, sensors, config)
        .map_err(|error| crate::exit::Invalid(format!("cannot hindcast: {error}")))?;
    if results.is_empty() {
        bail!(
            "no segment to hindcast: the logs need a fix before a dive, the first fix after \
             it, and the current estimate the glider made there"
        );
    }
    let metres =
        |value: Option<f64>| value.map_or("no surfacing".to_string(), |m| format!("{m:.0} m"));
    outln!("segment start         underwater  real first fix         miss    bound   null model (prior current)");
    let mut within = 0;
    for result in &results {
        let segment = &result.segment;
        let (lat, lon) = gloc_forecast::fly::degrees(segment.end.lat, segment.end.lon);
        outln!(
            "{}  {:>7.0} s  {} {}  {:>7}  {:>5.0} m  {}",
            iso_time(segment.start.time),
            segment.underwater,
            nmea_text(lat),
            nmea_text(lon),
            metres(result.miss),
            result.bound,
            metres(result.null_miss)
        );
        if result.miss.is_some_and(|miss| miss <= result.bound) {
            within += 1;
        }
    }
    outln!(
        "{within} of {} segments within the bound max(150 m, 0.015 m/s × time underwater)",
        results.len()
    );
    let skipped = history.segments.len() - results.len();
    if skipped > 0 {
        outln!(
            "{skipped} segment(s) skipped: the logs end before the glider's estimate after them"
        );
    }
    for path in maps {
        crate::output::write_through_temporary(path, |temporary| {
            gloc_forecast::map::write_hindcast_map(&results, &history.fixes, temporary)
        })?;
        eprintln!("wrote {}", path.display());
    }
    Ok(ExitCode::SUCCESS)
}
