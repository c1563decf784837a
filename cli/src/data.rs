//! `gloc data`: a glider log's header, sensors, cycles and time span (`info`),
//! conversion to CSV or `.dba` (`convert`, a dbd2asc replacement), and the
//! flight-profile plot a simulated run gets (`plot`).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context as _};
use clap::{Args, Subcommand};
use gloc_dbd::{CycleSource, Deployment, FileSensor};
use gloc_sim::log::{LogFormat, NumberText};

#[derive(Subcommand, Debug)]
pub enum DataCommand {
    /// Header, sensor list CRC, sensor count, cycles and time span of each file.
    Info(InfoArgs),
    /// Convert logs to CSV or `.dba` (several files: merged and in time order).
    Convert(ConvertArgs),
    /// Plot depth over time as SVG or PNG, with the plotter of `gloc run --plot`.
    Plot(PlotArgs),
}

#[derive(Args, Debug)]
pub struct SourceArgs {
    /// Glider logs: .dbd .ebd .sbd .tbd .mbd .nbd, compressed .dcd …, or .dba.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// A folder of sensor lists (`<crc>.cac`/`.ccc`), searched before the file's
    /// own folder and the per-user folder; default: `sensor_cache` in gloc.toml.
    #[arg(long, value_name = "DIR")]
    pub sensor_cache: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct InfoArgs {
    #[command(flatten)]
    pub source: SourceArgs,
    /// Also list every sensor (name, units, bytes).
    #[arg(long)]
    pub sensors: bool,
}

#[derive(Args, Debug)]
pub struct ConvertArgs {
    #[command(flatten)]
    pub source: SourceArgs,
    /// The output: `.csv` or `.dba`. Never one of the inputs.
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    pub output: PathBuf,
    /// Only these sensors, comma-separated, in this order (default: every sensor).
    #[arg(long, value_name = "NAMES")]
    pub sensors: Option<String>,
}

#[derive(Args, Debug)]
pub struct PlotArgs {
    #[command(flatten)]
    pub source: SourceArgs,
    /// The SVG to write.
    #[arg(short = 'o', long = "output", value_name = "OUT.svg")]
    pub output: PathBuf,
}

pub fn main(command: DataCommand) -> anyhow::Result<ExitCode> {
    match command {
        DataCommand::Info(args) => info(args),
        DataCommand::Convert(args) => convert(args),
        DataCommand::Plot(args) => plot(args),
    }
}

/// `--sensor-cache`, else `sensor_cache` from the gloc.toml above the first file.
fn sensor_cache(source: &SourceArgs) -> anyhow::Result<Option<PathBuf>> {
    let settings = gloc_project::Settings::resolve(
        source.files.first().map(PathBuf::as_path),
        gloc_project::Overrides {
            sensor_cache: source.sensor_cache.clone(),
            ..gloc_project::Overrides::new(gloc_project::Surface::Cli)
        },
    )?;
    Ok(settings.sensor_cache)
}

pub(crate) fn open(source: &SourceArgs) -> anyhow::Result<Deployment> {
    let cache = sensor_cache(source)?;
    Ok(Deployment::open(&source.files, cache.as_deref())?)
}

fn print_warnings(source: &mut dyn CycleSource) {
    for warning in source.take_warnings() {
        eprintln!("warning: {warning}");
    }
}

/// A number as a person reads it: `20`, `4.5`, and `1e300` rather than 301 digits.
fn number(value: f64) -> String {
    if value.abs() < 1e15 {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

/// Unix seconds as `2019-08-21T13:54:25.500Z` (`1e300 s` outside the years 0 to
/// 9999, `-` for NaN).
fn utc(seconds: f64) -> String {
    if !seconds.is_finite() {
        return "-".to_string();
    }
    gloc_dbd::header::iso_time(seconds).unwrap_or_else(|| format!("{} s", number(seconds)))
}

fn info(args: InfoArgs) -> anyhow::Result<ExitCode> {
    let cache = sensor_cache(&args.source)?;
    for (position, path) in args.source.files.iter().enumerate() {
        if position > 0 {
            outln!();
        }
        let mut source = gloc_dbd::open_path(path, cache.as_deref())?;
        outln!("{}", path.display());
        for (key, value) in &source.header().fields {
            outln!("  {key}: {value}");
        }
        let sensors = source.sensors().clone();
        let time = source.time_column();
        let (mut cycles, mut first, mut last) = (0u64, f64::NAN, f64::NAN);
        while let Some(cycle) = source.next_cycle()? {
            cycles += 1;
            if !cycle.time.is_nan() {
                if first.is_nan() {
                    first = cycle.time;
                }
                last = cycle.time;
            }
        }
        outln!("  sensors: {}", sensors.len());
        outln!(
            "  time sensor: {}",
            time.map_or("none", |column| sensors[column].name.as_str())
        );
        outln!("  cycles: {cycles}");
        if first.is_finite() && last.is_finite() {
            outln!(
                "  time span: {} .. {} ({} s)",
                utc(first),
                utc(last),
                number((last - first).round())
            );
        } else {
            outln!("  time span: none (no cycle with a time)");
        }
        if args.sensors {
            for sensor in sensors.iter() {
                outln!(
                    "    {} ({}) {} bytes",
                    sensor.name,
                    sensor.units,
                    sensor.bytes
                );
            }
        }
        print_warnings(source.as_mut());
    }
    Ok(ExitCode::SUCCESS)
}

/// Refuses an output that is one of the inputs (the CLI's one check, by device and
/// inode).
pub(crate) fn check_output(output: &Path, inputs: &[PathBuf]) -> anyhow::Result<()> {
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    crate::output::check_output(&inputs, "-o", output)
}

/// The columns to write: every sensor, or the `--sensors` names in that order.
fn select(sensors: &[FileSensor], names: Option<&str>) -> anyhow::Result<Vec<usize>> {
    let Some(names) = names else {
        return Ok((0..sensors.len()).collect());
    };
    names
        .split(',')
        .map(str::trim)
        .filter(|name| !name.is_empty())
        .map(|name| {
            sensors
                .iter()
                .position(|sensor| sensor.name.eq_ignore_ascii_case(name))
                .with_context(|| format!("`{name}` is not a sensor of these files ({} sensors; `gloc data info --sensors` lists them)", sensors.len()))
        })
        .collect()
}

fn convert(args: ConvertArgs) -> anyhow::Result<ExitCode> {
    let format = LogFormat::from_path(&args.output).with_context(|| {
        format!(
            "{}: the output must end in .csv or .dba",
            args.output.display()
        )
    })?;
    check_output(&args.output, &args.source.files)?;
    let mut source = open(&args.source)?;
    let sensors = source.sensors().clone();
    let columns = select(&sensors, args.sensors.as_deref())?;
    // Written beside the output and renamed over it when complete: a failure leaves
    // the previous output as it was.
    let unwritable = |error| crate::output::write_error(error, "the output", &args.output);
    let mut out = crate::output::AtomicFile::create(&args.output).map_err(unwritable)?;
    let mut line = Vec::with_capacity(columns.len() * 12);
    match format {
        LogFormat::Csv => {
            let names: Vec<&str> = columns.iter().map(|&c| sensors[c].name.as_str()).collect();
            writeln!(out, "{}", names.join(",")).map_err(unwritable)?;
        }
        LogFormat::Dba => {
            let mut header = Vec::new();
            write_dba_header(&mut header, &source, &sensors, &columns)?;
            out.write_all(&header).map_err(unwritable)?;
        }
    }
    let (separator, missing): (u8, &[u8]) = match format {
        LogFormat::Csv => (b',', b""),
        LogFormat::Dba => (b' ', b"NaN"),
    };
    let mut numbers = NumberText::default();
    let mut rows = 0u64;
    while let Some(cycle) = source.next_cycle()? {
        line.clear();
        for (position, &column) in columns.iter().enumerate() {
            if position > 0 {
                line.push(separator);
            }
            match cycle.value(column) {
                Some(value) => numbers.push(&mut line, value, sensors[column].bytes == 8),
                None => line.extend_from_slice(missing),
            }
        }
        if format == LogFormat::Dba {
            line.push(b' ');
        }
        line.push(b'\n');
        out.write_all(&line).map_err(unwritable)?;
        rows += 1;
    }
    out.commit().map_err(unwritable)?;
    print_warnings(&mut source);
    eprintln!(
        "wrote {} ({rows} cycles, {} sensors)",
        args.output.display(),
        columns.len()
    );
    Ok(ExitCode::SUCCESS)
}

/// dbd2asc's header: the first file's facts, then the three label lines.
fn write_dba_header(
    out: &mut impl Write,
    source: &Deployment,
    sensors: &[FileSensor],
    columns: &[usize],
) -> anyhow::Result<()> {
    let first = source.segments().first();
    let path = first.map(|segment| segment.files.first().clone());
    let header = match &path {
        Some(path) => gloc_dbd::fs::read_file_header(path)?,
        None => gloc_dbd::Header::default(),
    };
    let get = |key: &str| header.get(key).unwrap_or("unknown").to_string();
    let filename = header.full_filename().unwrap_or("unknown").to_string();
    let extension = get("filename_extension");
    writeln!(out, "dbd_label: DBD_ASC(dinkum_binary_data_ascii)file")?;
    writeln!(out, "encoding_ver: 2")?;
    writeln!(out, "num_ascii_tags: 14")?;
    writeln!(
        out,
        "all_sensors: {}",
        i32::from(columns.len() == sensors.len())
    )?;
    writeln!(out, "filename: {filename}")?;
    writeln!(out, "the8x3_filename: {}", get("the8x3_filename"))?;
    writeln!(out, "filename_extension: {extension}")?;
    writeln!(
        out,
        "filename_label: {filename}-{extension}({})",
        get("the8x3_filename")
    )?;
    writeln!(out, "mission_name: {}", get("mission_name"))?;
    writeln!(out, "fileopen_time: {}", get("fileopen_time"))?;
    writeln!(out, "sensors_per_cycle: {}", columns.len())?;
    writeln!(out, "num_label_lines: 3")?;
    writeln!(out, "num_segments: {}", source.segments().len())?;
    writeln!(out, "segment_filename_0: {filename}")?;
    let label = |field: &dyn Fn(&FileSensor) -> String| {
        let mut text = String::new();
        for &column in columns {
            text.push_str(&field(&sensors[column]));
            text.push(' ');
        }
        text
    };
    writeln!(out, "{}", label(&|sensor| sensor.name.clone()))?;
    writeln!(out, "{}", label(&|sensor| sensor.units.clone()))?;
    writeln!(out, "{}", label(&|sensor| sensor.bytes.to_string()))?;
    Ok(())
}

/// The map of a log: the glider's logged position (`m_lat`/`m_lon`), its GPS
/// fixes and the waypoints it steered to, in km from its first position (the
/// simulator's one projection, `gloc_sim::navigation::Lmc`).
struct LogMap {
    columns: [Option<usize>; 6],
    /// The latest (lat, lon), fix (lat, lon) of this cycle, waypoint (lat, lon).
    position: Option<(f64, f64)>,
    fix: Option<(f64, f64)>,
    waypoint: Option<(f64, f64)>,
    lmc: Option<gloc_sim::navigation::Lmc>,
}

impl LogMap {
    fn new(column: &dyn Fn(&str) -> Option<usize>) -> LogMap {
        LogMap {
            columns: [
                column("m_lat"),
                column("m_lon"),
                column("m_gps_lat"),
                column("m_gps_lon"),
                column("c_wpt_lat"),
                column("c_wpt_lon"),
            ],
            position: None,
            fix: None,
            waypoint: None,
            lmc: None,
        }
    }

    /// Takes this cycle's positions (only updated values that hold one).
    fn read(&mut self, cycle: &gloc_dbd::cycle::Cycle) {
        use gloc_sim::navigation::nmea_is_set;
        let pair = |lat: Option<usize>, lon: Option<usize>| {
            let (lat, lon) = (cycle.value(lat?)?, cycle.value(lon?)?);
            (nmea_is_set(lat) && nmea_is_set(lon) && lat.abs() <= 9000.0).then_some((lat, lon))
        };
        let [lat, lon, gps_lat, gps_lon, wpt_lat, wpt_lon] = self.columns;
        if let Some(position) = pair(lat, lon) {
            self.position = Some(position);
        }
        self.fix = pair(gps_lat, gps_lon);
        if let Some(waypoint) = pair(wpt_lat, wpt_lon) {
            self.waypoint = Some(waypoint);
        }
    }

    /// Adds one point to the trace's map (the trace's points gained one).
    fn record(&mut self, trace: &mut gloc_sim::plot::Trace) {
        let Some((lat, lon)) = self.position.or(self.fix) else {
            // No position yet: the map starts at the first one (has_map needs one per point).
            trace.track.push((f32::NAN, f32::NAN));
            trace.dead_reckoned.push((f32::NAN, f32::NAN));
            return;
        };
        let lmc = *self
            .lmc
            .get_or_insert_with(|| gloc_sim::navigation::Lmc::from_nmea(lat, lon));
        let at = lmc.nmea_to_xy(lat, lon);
        trace.track.push((at.x as f32, at.y as f32));
        trace.dead_reckoned.push((at.x as f32, at.y as f32));
        if let Some((lat, lon)) = self.fix.take() {
            let fix = lmc.nmea_to_xy(lat, lon);
            trace.surfacings.push((fix.x as f32, fix.y as f32));
        }
        if let Some((lat, lon)) = self.waypoint {
            let at = lmc.nmea_to_xy(lat, lon);
            let point = (at.x as f32, at.y as f32);
            if !trace.waypoints.contains(&point) {
                trace.waypoints.push(point);
            }
        }
        trace.map_caption = Some(
            "map (km east and north of the first position): logged position (m_lat, m_lon) blue, GPS fixes black, waypoints red"
                .to_string(),
        );
    }
}

fn plot(args: PlotArgs) -> anyhow::Result<ExitCode> {
    check_output(&args.output, &args.source.files)?;
    gloc_sim::plot::PlotFormat::from_path(&args.output).map_err(anyhow::Error::msg)?;
    let mut source = open(&args.source)?;
    let sensors = source.sensors().clone();
    let column = |name: &str| sensors.iter().position(|sensor| sensor.name == name);
    let depth = column("m_depth")
        .or_else(|| column("sci_water_pressure"))
        .context("these files have neither `m_depth` nor `sci_water_pressure` to plot")?;
    // sci_water_pressure is in bar: 10 m of sea water per bar.
    let scale = if sensors[depth].name == "m_depth" {
        1.0
    } else {
        10.0
    };
    let water = column("m_water_depth");
    let mut points = gloc_sim::plot::Thinned::default();
    let (mut start, mut water_depth, mut count) = (f64::NAN, 0.0f64, 0u64);
    // Points whose time from the start or depth does not fit the plot's numbers
    // (beyond f32::MAX): skipped, the first one named.
    let mut unplottable: (u64, Option<String>) = (0, None);
    // The map's positions (a log with m_lat/m_lon or GPS fixes), kept as they stream:
    // every `map_stride`-th point, halved whenever they reach the plot's cap.
    let mut map = LogMap::new(&column);
    let mut nav = gloc_sim::plot::Trace::default();
    let (mut map_stride, mut map_seen) = (1u64, 0u64);
    while let Some(cycle) = source.next_cycle()? {
        map.read(cycle);
        if let Some(value) = water.and_then(|water| cycle.value(water)) {
            if value.is_finite() && value > 0.0 {
                water_depth = water_depth.max(value);
            }
        }
        let (Some(value), time) = (cycle.value(depth), cycle.time) else {
            continue;
        };
        if !value.is_finite() || !time.is_finite() {
            continue;
        }
        if start.is_nan() {
            start = time;
        }
        let point = ((time - start) as f32, (value * scale) as f32);
        if !point.0.is_finite() || !point.1.is_finite() {
            unplottable.0 += 1;
            if unplottable.1.is_none() {
                let (cycle_number, offset) = (cycle.number, cycle.offset);
                unplottable.1 = Some(format!(
                    "{} cycle {cycle_number} (byte {offset}): {} s after the first, {} m",
                    source.file(),
                    number(time - start),
                    number(value * scale)
                ));
            }
            continue;
        }
        points.push(point);
        count += 1;
        if map_seen % map_stride == 0 {
            map.record(&mut nav);
            if nav.track.len() >= gloc_sim::plot::MAX_PLOT_POINTS {
                nav.track = nav.track.iter().copied().step_by(2).collect();
                nav.dead_reckoned = nav.dead_reckoned.iter().copied().step_by(2).collect();
                map_stride *= 2;
            }
        }
        map_seen += 1;
    }
    print_warnings(&mut source);
    if let (skipped @ 1.., Some(first)) = unplottable {
        eprintln!(
            "warning: {skipped} cycles skipped: their time or depth is beyond what a plot can draw ({:e}); the first: {first}",
            f32::MAX
        );
    }
    if count == 0 {
        bail!("no depth values to plot");
    }
    let mut trace = gloc_sim::plot::Trace::default();
    trace.points = points.finish();
    // The map needs a position per plotted point: the kept positions spread over them.
    let plotted = trace.points.len();
    if !nav.track.is_empty() && plotted > 0 {
        let spread = |positions: &[(f32, f32)]| -> Vec<(f32, f32)> {
            (0..plotted)
                .map(|index| positions[index * positions.len() / plotted])
                .collect()
        };
        trace.track = spread(&nav.track);
        trace.dead_reckoned = spread(&nav.dead_reckoned);
    }
    trace.surfacings = nav.surfacings;
    trace.waypoints = nav.waypoints;
    trace.map_caption = nav.map_caption;
    let title = args
        .source
        .files
        .first()
        .and_then(|path| path.file_name())
        .map(|name| name.to_string_lossy().into_owned())
        .unwrap_or_default();
    let options = gloc_sim::plot::PlotOptions {
        title,
        water_depth,
        temperature: false,
        battery: false,
    };
    crate::output::write_through_temporary(&args.output, |temporary| {
        gloc_sim::plot::write_plot(&trace, &options, temporary)
    })?;
    eprintln!(
        "wrote {} ({count} depth points from {})",
        args.output.display(),
        utc(start)
    );
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::utc;

    #[test]
    fn utc_prints_civil_time() {
        // date -u -d @1566395665 → 2019-08-21 13:54:25
        assert_eq!(utc(1_566_395_665.25), "2019-08-21T13:54:25.250Z");
        assert_eq!(utc(f64::NAN), "-");
        // Outside the years 0 to 9999: seconds, not a 974-character date.
        assert_eq!(utc(1e300), "1e300 s");
        assert_eq!(utc(-1e20), "-1e20 s");
    }
}
