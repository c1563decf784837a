//! The flight profile: depth (downward) against time, like the paper's Fig. 2
//! and 4b, with the script's stores as an event track below it and optional
//! panels (temperature as colour along the track, battery voltage, chosen
//! sensors). SVG or PNG.
//!
//! The time axis is in minutes, hours or days by the run's length. A long run
//! is drawn as joined min/max bars, one per pixel while a yo spans several
//! pixels, two yos wide when it does not (see [`TrackStyle`]). Every store is
//! marked (no cap); a label is drawn only where it does not overlap another.
//! When the glider moved horizontally, a map panel closes the plot: the true
//! track, the dead-reckoned one, the waypoints, the surfacings and the current.

use std::ops::Range;
use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::simulation::Simulation;

/// A mark on the event track: the script stored a new value in a sensor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Action {
    /// Mission seconds.
    pub time: f32,
    pub depth: f32,
    /// Index into [`Trace::names`].
    pub name: u32,
    pub value: f64,
}

/// Depth over time, the script's stores, and the optional panels' values,
/// recorded cycle by cycle for the plot. Compact: a 30-day run of 648,000
/// cycles takes about 10 MB.
#[derive(Clone, Debug, Default)]
pub struct Trace {
    /// (mission seconds, depth), one per cycle.
    pub points: Vec<(f32, f32)>,
    /// Battery voltage per point (empty: not recorded).
    pub volts: Vec<f32>,
    /// Water temperature per point (empty: not recorded).
    pub temps: Vec<f32>,
    pub actions: Vec<Action>,
    /// Names of the sensors the script stored.
    pub names: Vec<String>,
    /// Chosen sensors recorded per point for their own panels: (name, sensor
    /// index, values). Set with [`Trace::with_sensors`].
    pub series: Vec<(String, u32, Vec<f32>)>,
    /// Last value the script stored in each sensor it stored (for "changed" marks).
    last_stored: Vec<(u32, f64)>,
    /// The map: true and dead-reckoned positions per point (m east, north of
    /// the mission origin), the waypoints steered to, the first fix of each
    /// surfacing, and the true current (m/s).
    pub track: Vec<(f32, f32)>,
    pub dead_reckoned: Vec<(f32, f32)>,
    pub waypoints: Vec<(f32, f32)>,
    pub surfacings: Vec<(f32, f32)>,
    pub current: (f32, f32),
    /// What the map's lines are, when not a simulation's (a real log's).
    pub map_caption: Option<String>,
    surfacings_seen: u64,
}

impl Trace {
    /// A trace that also records these sensors (name and id) for panels.
    pub fn with_sensors(sensors: &[(String, gloc_engine::sensors::SensorId)]) -> Trace {
        Trace {
            series: sensors
                .iter()
                .map(|(name, id)| (name.clone(), id.0, Vec::new()))
                .collect(),
            ..Trace::default()
        }
    }

    /// Records the finished cycle: call after `finish_cycle`/`step_cycle`.
    pub fn record(&mut self, sim: &Simulation) {
        // The finished cycle ends where the next one starts.
        let time = sim.time() as f32;
        let depth = sim.depth() as f32;
        let navigation = sim.navigation();
        let truth = navigation.true_position;
        let believed = navigation.dead_reckoned;
        if self.points.is_empty() {
            self.points.push((0.0, 0.0));
            self.volts.push(sim.battery_volts() as f32);
            self.temps.push(sim.water_temperature() as f32);
            self.track.push((0.0, 0.0));
            self.dead_reckoned.push((0.0, 0.0));
            self.current = (
                navigation.true_water.x as f32,
                navigation.true_water.y as f32,
            );
        }
        self.track.push((truth.x as f32, truth.y as f32));
        self.dead_reckoned
            .push((believed.x as f32, believed.y as f32));
        if let Some(waypoint) = sim.waypoint() {
            let point = (waypoint.x as f32, waypoint.y as f32);
            if self.waypoints.last() != Some(&point) && !self.waypoints.contains(&point) {
                self.waypoints.push(point);
            }
        }
        if navigation.surfacings != self.surfacings_seen {
            self.surfacings_seen = navigation.surfacings;
            if let Some(fix) = navigation.gps_fix {
                self.surfacings.push((fix.x as f32, fix.y as f32));
            }
        }
        self.points.push((time, depth));
        self.volts.push(sim.battery_volts() as f32);
        self.temps.push(sim.water_temperature() as f32);
        let sensors = sim.sensors();
        for (_, index, values) in &mut self.series {
            let value = sensors.get(*index as usize).copied().unwrap_or(f64::NAN);
            if values.is_empty() {
                values.push(value as f32);
            }
            values.push(value as f32);
        }
        for &id in sim.stored() {
            let value = sim.sensor(id).unwrap_or(f64::NAN);
            let previous = self
                .last_stored
                .iter_mut()
                .find(|(sensor, _)| *sensor == id.0);
            let changed = match previous {
                Some((_, last)) if *last == value || (last.is_nan() && value.is_nan()) => false,
                Some((_, last)) => {
                    *last = value;
                    true
                }
                None => {
                    self.last_stored.push((id.0, value));
                    true
                }
            };
            if changed {
                let name = sim.sensor_list().name(id).unwrap_or("sensor");
                let index = match self.names.iter().position(|known| known == name) {
                    Some(index) => index,
                    None => {
                        self.names.push(name.to_string());
                        self.names.len() - 1
                    }
                };
                self.actions.push(Action {
                    time,
                    depth,
                    name: index as u32,
                    value,
                });
            }
        }
    }

    fn label(&self, action: &Action) -> String {
        let name = self
            .names
            .get(action.name as usize)
            .map_or("sensor", String::as_str);
        format!("{name}={}", action.value)
    }
}

/// Most points a [`Thinned`] keeps (2 MB): far more than the plot has pixel columns,
/// so the track drawn from them is the track drawn from every sample.
pub const MAX_PLOT_POINTS: usize = 1 << 18;

/// Depth points gathered for a plot in bounded memory, however long the log
/// (`gloc data plot` of a 1 MB compressed log of 120 million cycles kept them all:
/// 950 MB). Samples are taken in runs of `stride`, and each run keeps its first,
/// shallowest, deepest and last sample, in time order: every extreme and every
/// transition between runs survive, which is what [`envelope`] draws. When
/// [`MAX_PLOT_POINTS`] are kept, the kept points are thinned by the same rule in
/// runs of 8 and the stride grows to match.
#[derive(Clone, Debug, Default)]
pub struct Thinned {
    points: Vec<(f32, f32)>,
    stride: u64,
    /// The run being gathered: first, shallowest, deepest, last (with their positions
    /// in the run, for the order), and how many samples it holds.
    run: Option<[(u64, (f32, f32)); 4]>,
    in_run: u64,
}

impl Thinned {
    pub fn push(&mut self, point: (f32, f32)) {
        let at = self.in_run;
        let run = self.run.get_or_insert([(at, point); 4]);
        if point.1 < run[1].1 .1 {
            run[1] = (at, point);
        }
        if point.1 > run[2].1 .1 {
            run[2] = (at, point);
        }
        run[3] = (at, point);
        self.in_run += 1;
        if self.in_run >= self.stride.max(1) {
            self.close_run();
            if self.points.len() >= MAX_PLOT_POINTS {
                self.points = thin(&self.points, 8);
                self.stride = if self.stride < 8 { 8 } else { self.stride * 2 };
            }
        }
    }

    /// The points kept, in time order.
    pub fn finish(mut self) -> Vec<(f32, f32)> {
        self.close_run();
        self.points
    }

    fn close_run(&mut self) {
        if let Some(mut run) = self.run.take() {
            run.sort_by_key(|(at, _)| *at);
            let mut last = None;
            for (at, point) in run {
                if last != Some(at) {
                    self.points.push(point);
                    last = Some(at);
                }
            }
        }
        self.in_run = 0;
    }
}

/// `points` in runs of `size`, each reduced to its first, shallowest, deepest and
/// last point in time order.
fn thin(points: &[(f32, f32)], size: usize) -> Vec<(f32, f32)> {
    let mut thinned = Thinned {
        stride: size as u64,
        ..Thinned::default()
    };
    for &point in points {
        thinned.push(point);
    }
    thinned.finish()
}

/// What to draw besides the depth profile.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotOptions {
    /// The title: file names, never paths.
    pub title: String,
    pub water_depth: f64,
    /// Colour the track by the water temperature (needs `Trace::temps`).
    pub temperature: bool,
    /// A battery-voltage panel (needs `Trace::volts`).
    pub battery: bool,
}

/// The image formats, by the output's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlotFormat {
    Svg,
    Png,
}

impl PlotFormat {
    /// `.svg` or `.png` (any case); anything else is refused with what is allowed.
    pub fn from_path(path: &Path) -> Result<PlotFormat, String> {
        let extension = gloc_engine::files::extension(path);
        match extension.as_deref() {
            Some("svg") => Ok(PlotFormat::Svg),
            Some("png") => Ok(PlotFormat::Png),
            _ => Err(format!(
                "cannot plot to `{}`: give a file ending in .svg or .png",
                path.display()
            )),
        }
    }
}

/// Plot width and the main panel's height (px); the panels add theirs.
const WIDTH: u32 = 1200;
const MAIN_HEIGHT: u32 = 460;
const EVENT_HEIGHT: u32 = 120;
const BATTERY_HEIGHT: u32 = 150;
/// Colour steps along an envelope bar's depth.
const BAR_PIECES: usize = 8;
/// Label lanes of the event track.
const LANES: usize = 4;

/// The panels below the event track: the battery, then each chosen sensor.
fn panels(trace: &Trace, options: &PlotOptions) -> Vec<(String, Vec<f32>)> {
    let mut panels = Vec::new();
    if options.battery && trace.volts.len() == trace.points.len() && !trace.volts.is_empty() {
        panels.push(("battery (V)".to_string(), trace.volts.clone()));
    }
    for (name, _, values) in &trace.series {
        if values.len() == trace.points.len() && !values.is_empty() {
            panels.push((name.clone(), values.clone()));
        }
    }
    panels
}

fn height(trace: &Trace, options: &PlotOptions) -> u32 {
    let map = if has_map(trace) { MAP_HEIGHT } else { 0 };
    MAIN_HEIGHT + EVENT_HEIGHT + BATTERY_HEIGHT * panels(trace, options).len() as u32 + map
}

/// The map panel's height (px).
const MAP_HEIGHT: u32 = 620;

/// Whether the glider moved far enough (10 m) for a map, with every point recorded.
fn has_map(trace: &Trace) -> bool {
    if trace.track.len() != trace.points.len() || trace.track.is_empty() {
        return false;
    }
    let (low, high) = map_bounds(trace);
    (high.0 - low.0).max(high.1 - low.1) > 10.0
}

/// The map's extent: tracks, waypoints and surfacings (m).
fn map_bounds(trace: &Trace) -> ((f64, f64), (f64, f64)) {
    let all = trace
        .track
        .iter()
        .chain(&trace.dead_reckoned)
        .chain(&trace.waypoints)
        .chain(&trace.surfacings);
    bounds(all.map(|&(x, y)| (f64::from(x), f64::from(y))))
}

/// The least box around the finite points, as its (low, high) corners; (0, 0)
/// twice when none is finite.
pub fn bounds(points: impl IntoIterator<Item = (f64, f64)>) -> ((f64, f64), (f64, f64)) {
    let mut low = (f64::INFINITY, f64::INFINITY);
    let mut high = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for (x, y) in points {
        if x.is_finite() && y.is_finite() {
            low = (low.0.min(x), low.1.min(y));
            high = (high.0.max(x), high.1.max(y));
        }
    }
    if !low.0.is_finite() {
        return ((0.0, 0.0), (0.0, 0.0));
    }
    (low, high)
}

/// The chart of a map: x across, y up, both `f64`.
pub type MapChart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// What a map shows: a box of data and how its two units compare.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapBox {
    /// The box's corners (x, y), as [`bounds`] gives them.
    pub low: (f64, f64),
    pub high: (f64, f64),
    /// How long one x unit is in y units: 1 for km east and north; cos(latitude)
    /// for degrees of longitude against degrees of latitude.
    pub x_unit: f64,
    /// The least span shown on either axis, in its own units (a single point is
    /// still a map).
    pub min_span: f64,
}

/// Each span shown, as a share of the data's: 7.5% of room on each side.
const MAP_ROOM: f64 = 1.15;
/// A map chart's margin on every side, and the room for its axes' labels (px).
const MAP_MARGIN: u32 = 16;
const MAP_X_LABELS: u32 = 45;
const MAP_Y_LABELS: u32 = 75;

/// A map chart on `area`, by one rule for every map gloc draws (the simulator's
/// map panel, the forecast's and the hindcast's maps): `caption` on top in
/// `caption_size` px, `footer` px left free below (for a legend), and `map`'s box
/// at equal scales (one length per pixel across and up), centred.
pub fn map_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    (caption, caption_size): (&str, u32),
    footer: u32,
    map: MapBox,
) -> Result<MapChart<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    let style = ("sans-serif", caption_size).into_text_style(area);
    // As plotters lays a chart out: the margins, the caption (its height and up to
    // 5 px above and below it), the label areas; the rest is the plot.
    let (_, text_height) = area.estimate_text_size(caption, &style)?;
    let caption_height = text_height + 2 * (text_height / 2).min(5);
    let (width, height) = area.dim_in_pixel();
    let plot = (
        f64::from(width.saturating_sub(2 * MAP_MARGIN + MAP_Y_LABELS).max(1)),
        f64::from(
            height
                .saturating_sub(2 * MAP_MARGIN + footer + caption_height + MAP_X_LABELS)
                .max(1),
        ),
    );
    let (x_range, y_range) = equal_scales(map, plot);
    ChartBuilder::on(area)
        .caption(caption, style)
        .margin(MAP_MARGIN)
        .margin_bottom(MAP_MARGIN + footer)
        .x_label_area_size(MAP_X_LABELS)
        .y_label_area_size(MAP_Y_LABELS)
        .build_cartesian_2d(x_range, y_range)
}

/// The x and y ranges that show `map`'s box with room around it on a plot of
/// `plot` (width, height) px at equal scales: one y unit per so many pixels up,
/// and `x_unit` of it per as many pixels across.
fn equal_scales(map: MapBox, plot: (f64, f64)) -> (Range<f64>, Range<f64>) {
    let ((x0, y0), (x1, y1)) = (map.low, map.high);
    let x_unit = map.x_unit.max(f64::MIN_POSITIVE);
    let span_x = ((x1 - x0) * MAP_ROOM).max(map.min_span);
    let span_y = ((y1 - y0) * MAP_ROOM).max(map.min_span);
    // y units a pixel holds, the same across (in x's length) and up.
    let per_pixel = (span_y / plot.1).max(span_x * x_unit / plot.0);
    let half_x = per_pixel * plot.0 / 2.0 / x_unit;
    let half_y = per_pixel * plot.1 / 2.0;
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    ((cx - half_x)..(cx + half_x), (cy - half_y)..(cy + half_y))
}

static FONT: &[u8] = include_bytes!("../data/fonts/DejaVuSans-subset.ttf");

/// Registers the embedded font as plotters' `sans-serif` (once per process):
/// every plot gloc draws, the forecast's map too, measures and draws text with it.
pub fn register_font() {
    // A subset of DejaVu Sans (ASCII, °, ±, ×, –, −, µ; data/fonts, its
    // licence beside it): plotters measures and draws text with it.
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Refuses a trace whose axes cannot be drawn: an infinite time or depth (a value
/// beyond f32::MAX) made the axis' tick search loop for ever.
fn check_axes(trace: &Trace) -> Result<(), String> {
    match trace
        .points
        .iter()
        .find(|(time, depth)| !time.is_finite() || !depth.is_finite())
    {
        Some((time, depth)) => Err(format!(
            "cannot plot a point at {time} s and {depth} m: times and depths must be finite and at most {:e}",
            f32::MAX
        )),
        None => Ok(()),
    }
}

/// Renders the trace to an SVG document.
pub fn render_svg_with(trace: &Trace, options: &PlotOptions) -> Result<String, String> {
    check_axes(trace)?;
    // Text is measured with the embedded font in SVG too.
    register_font();
    let mut svg = String::new();
    {
        let root =
            SVGBackend::with_string(&mut svg, (WIDTH, height(trace, options))).into_drawing_area();
        draw(&root, trace, options).map_err(|error| error.to_string())?;
        root.present().map_err(|error| error.to_string())?;
    }
    Ok(svg)
}

/// Renders the trace to an SVG document (the depth profile and the stores).
pub fn render_svg(trace: &Trace, title: &str, water_depth: f64) -> Result<String, String> {
    render_svg_with(
        trace,
        &PlotOptions {
            title: title.to_string(),
            water_depth,
            temperature: false,
            battery: false,
        },
    )
}

/// Writes the plot to `path` in the format its extension names.
pub fn write_plot(trace: &Trace, options: &PlotOptions, path: &Path) -> Result<(), String> {
    match PlotFormat::from_path(path)? {
        PlotFormat::Svg => {
            let svg = render_svg_with(trace, options)?;
            std::fs::write(path, svg)
                .map_err(|error| format!("cannot write `{}`: {error}", path.display()))
        }
        PlotFormat::Png => {
            check_axes(trace)?;
            register_font();
            let root =
                BitMapBackend::new(path, (WIDTH, height(trace, options))).into_drawing_area();
            draw(&root, trace, options).map_err(|error| error.to_string())?;
            // The PNG is encoded and written here.
            root.present()
                .map_err(|error| format!("cannot write `{}`: {error}", path.display()))
        }
    }
}

/// The time axis: its unit's seconds and name, by the run's length.
fn time_unit(duration: f64) -> (f64, &'static str) {
    if duration <= 3.0 * 3600.0 {
        (60.0, "minutes")
    } else if duration <= 3.0 * 86400.0 {
        (3600.0, "hours")
    } else {
        (86400.0, "days")
    }
}

/// How the depth track is drawn (chosen by [`track_style`]).
///
/// With no more samples than pixels the track is a line through every
/// sample. Otherwise: a yo is a sawtooth, and drawn on a pixel grid it is
/// only honest in two regimes. When a yo spans many pixels ([`MIN_YO_PX`] or more) the sawtooth
/// itself is drawn: as a line through every sample when there are few samples
/// per pixel ([`LINE_SAMPLES_PER_PX`] or fewer), otherwise as one bar per pixel
/// column that is exactly what that line would light (see [`envelope`]). When
/// a yo spans only a few pixels, any per-pixel drawing beats against the yo
/// period: a column catches a turn or misses it by the phase of the yo at its
/// edge, and the tops and bottoms wander with the beat period (about an hour
/// for a 4-minute yo over 24 hours, drawn as 1100 columns) as if the glider
/// had flown a wave. There the columns are made at least two median yo periods
/// wide, so every column holds a whole yo and spans its turns: a band from the
/// shallowest to the deepest turn that changes only where the turns do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TrackStyle {
    /// Every sample joined by a line.
    Line,
    /// Bars `width` pixels wide over their samples (see [`envelope`]).
    Columns { width: u32 },
}

/// A yo resolved on the plot spans at least this many pixels.
const MIN_YO_PX: f64 = 8.0;
/// Up to this many samples per pixel the track is drawn as a line.
const LINE_SAMPLES_PER_PX: f64 = 8.0;

/// The median time from one turn to the next, doubled: the yo period in
/// seconds (None: fewer than two turns). A turn is a depth extreme the glider
/// leaves by more than a tenth of the trace's depth range (at least 0.2 m),
/// so sensor noise and small wiggles are not turns.
fn yo_period(points: &[(f32, f32)]) -> Option<f64> {
    let (low, high) = points
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.1), hi.max(p.1))
        });
    let hysteresis = ((high - low) * 0.1).max(0.2);
    let &(first_time, first_depth) = points.first()?;
    // Direction: 1 down, -1 up, 0 not yet known; the extreme since the last turn.
    let (mut direction, mut extreme, mut extreme_at) = (0i8, first_depth, first_time);
    let mut turns = Vec::new();
    for &(time, depth) in points {
        match direction {
            0 if (depth - extreme).abs() > hysteresis => {
                direction = if depth > extreme { 1 } else { -1 };
                (extreme, extreme_at) = (depth, time);
            }
            1 if depth > extreme => (extreme, extreme_at) = (depth, time),
            -1 if depth < extreme => (extreme, extreme_at) = (depth, time),
            1 | -1 if (depth - extreme).abs() > hysteresis => {
                turns.push(extreme_at);
                direction = -direction;
                (extreme, extreme_at) = (depth, time);
            }
            _ => {}
        }
    }
    let mut halves: Vec<f64> = turns
        .windows(2)
        .map(|pair| (pair[1] - pair[0]) as f64)
        .collect();
    if halves.is_empty() {
        return None;
    }
    halves.sort_by(f64::total_cmp);
    Some(2.0 * halves[halves.len() / 2])
}

/// How to draw `points` on a plot `plot_px` pixels wide (see [`TrackStyle`]).
fn track_style(points: &[(f32, f32)], plot_px: u32) -> TrackStyle {
    let plot_px = plot_px.max(1) as f64;
    let duration = points.last().map_or(0.0, |p| p.0 as f64).max(60.0);
    let px_per_second = plot_px / duration;
    if points.len() as f64 <= plot_px {
        // A pixel or more per sample: the line is the data, nothing to alias.
        return TrackStyle::Line;
    }
    match yo_period(points) {
        Some(period) if period * px_per_second < MIN_YO_PX => TrackStyle::Columns {
            width: ((2.0 * period * px_per_second).ceil() as u32).max(1),
        },
        _ if points.len() as f64 <= LINE_SAMPLES_PER_PX * plot_px => TrackStyle::Line,
        _ => TrackStyle::Columns { width: 1 },
    }
}

/// One column of the track: pixels `x..x_end` from the plot's left edge, the
/// depth range it covers, and the temperature at its two ends.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Column {
    x: u32,
    x_end: u32,
    shallowest: f64,
    deepest: f64,
    /// Temperature at the shallowest and the deepest point (NaN: not recorded).
    shallow_temperature: f64,
    deep_temperature: f64,
}

/// The track as columns `width` pixels wide on a plot `plot_px` pixels wide
/// spanning `duration` seconds. A column spans the depths of its samples AND
/// the last sample of the column before it (the continuity rule): the track
/// goes from there into this column, so the bars meet and read as one line,
/// exactly the pixels a line through every sample would light. Every extreme
/// is kept. A column reaches the next one's left edge, so a column with no
/// sample (a gap in time) is bridged at the last depth.
fn envelope(
    points: &[(f32, f32)],
    temps: &[f32],
    duration: f64,
    plot_px: u32,
    width: u32,
) -> Vec<Column> {
    let width = width.max(1);
    let count = plot_px.max(1).div_ceil(width);
    let per_second = count as f64 / duration.max(1e-9);
    let temperature = |at: usize| temps.get(at).map_or(f64::NAN, |&t| t as f64);
    let mut columns: Vec<Column> = Vec::new();
    let mut current: Option<u32> = None;
    for (at, &(time, depth)) in points.iter().enumerate() {
        let index = ((time as f64 * per_second).max(0.0) as u32).min(count - 1);
        let depth = depth as f64;
        if current != Some(index) {
            // A new column starts at the previous column's last sample.
            let (from, from_temperature) = match at.checked_sub(1) {
                Some(last) => (points[last].1 as f64, temperature(last)),
                None => (depth, temperature(at)),
            };
            columns.push(Column {
                x: index * width,
                x_end: index * width + width,
                shallowest: from,
                deepest: from,
                shallow_temperature: from_temperature,
                deep_temperature: from_temperature,
            });
            current = Some(index);
        }
        if let Some(column) = columns.last_mut() {
            if depth < column.shallowest {
                column.shallowest = depth;
                column.shallow_temperature = temperature(at);
            }
            if depth > column.deepest {
                column.deepest = depth;
                column.deep_temperature = temperature(at);
            }
        }
    }
    let edges: Vec<u32> = columns.iter().skip(1).map(|column| column.x).collect();
    for (column, edge) in columns.iter_mut().zip(edges) {
        column.x_end = edge;
    }
    if let Some(last) = columns.last_mut() {
        last.x_end = last.x_end.min(plot_px.max(1));
    }
    columns
}

/// Blue (cold) to red (warm).
fn heat(temperature: f64, low: f64, high: f64) -> RGBColor {
    let span = (high - low).max(1e-6);
    let x = ((temperature - low) / span).clamp(0.0, 1.0);
    RGBColor(
        (40.0 + 215.0 * x) as u8,
        (60.0 + 60.0 * (1.0 - (2.0 * x - 1.0).abs())) as u8,
        (255.0 - 215.0 * x) as u8,
    )
}

/// Where each store's label goes: the first of [`LANES`] lanes whose last
/// label ends left of it, or none (the mark is still drawn); none either when
/// it would run past `right`. `x` in pixels, `width` the label's estimated width.
fn place_labels(marks: &[(f64, f64)], right: f64) -> Vec<Option<usize>> {
    let mut lane_end = [f64::NEG_INFINITY; LANES];
    marks
        .iter()
        .map(|&(x, width)| {
            if x + width > right {
                return None;
            }
            let lane = lane_end.iter().position(|&end| end + 6.0 <= x)?;
            lane_end[lane] = x + width;
            Some(lane)
        })
        .collect()
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    trace: &Trace,
    options: &PlotOptions,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let duration = trace
        .points
        .last()
        .map(|p| p.0 as f64)
        .unwrap_or(0.0)
        .max(60.0);
    let (scale, unit) = time_unit(duration);
    let x_range = 0.0..duration / scale;
    let deepest = trace
        .points
        .iter()
        .map(|p| p.1 as f64)
        .fold(0.0, f64::max)
        .max(5.0);
    let water_depth = options.water_depth;
    let bottom = (deepest * 1.1)
        .min(water_depth.max(deepest))
        .max(deepest + 1.0);
    let (main, rest) = root.split_vertically(MAIN_HEIGHT);
    let (events, battery) = rest.split_vertically(EVENT_HEIGHT);
    let temperature = options.temperature && trace.temps.len() == trace.points.len();
    let (low, high) = trace
        .temps
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &t| {
            (lo.min(t as f64), hi.max(t as f64))
        });
    let caption = if temperature {
        format!(
            "{}   (colour: water temperature, blue {:.1} °C to red {:.1} °C)",
            options.title, low, high
        )
    } else {
        options.title.clone()
    };
    let mut chart = ChartBuilder::on(&main)
        .caption(caption, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(36)
        .y_label_area_size(60)
        .build_cartesian_2d(x_range.clone(), bottom..0.0)?;
    chart
        .configure_mesh()
        .x_desc(format!("time ({unit})"))
        .y_desc("depth (m)")
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    if water_depth <= bottom {
        chart.draw_series(LineSeries::new(
            [(0.0, water_depth), (duration / scale, water_depth)],
            ShapeStyle::from(&RGBColor(140, 100, 60)).stroke_width(2),
        ))?;
    }
    let blue = RGBColor(30, 70, 200);
    let columns = (WIDTH as usize).saturating_sub(100);
    let (plot_px, _) = chart.plotting_area().dim_in_pixel();
    let style = track_style(&trace.points, plot_px);
    let long = style != TrackStyle::Line;
    if let TrackStyle::Columns { width } = style {
        // Drawn in the plot's pixels, so that every bar is at least one
        // pixel wide and tall and the bars tile the width without gaps.
        let bars = envelope(&trace.points, &trace.temps, duration, plot_px, width);
        let area = chart.plotting_area();
        let top = area.get_base_pixel().1;
        let y = |depth: f64| area.map_coordinate(&(0.0, depth)).1 - top;
        let pixels = area.strip_coord_spec();
        let pieces = if temperature { BAR_PIECES } else { 1 };
        for rectangle in bars.iter().flat_map(|bar| {
            let (y0, y1) = (y(bar.shallowest), y(bar.deepest) + 1);
            // Coloured from the shallow end's temperature to the deep end's.
            (0..pieces).map(move |piece| {
                let (a, b) = (
                    piece as f64 / pieces as f64,
                    (piece + 1) as f64 / pieces as f64,
                );
                let colour = if temperature {
                    let t = bar.shallow_temperature
                        + (bar.deep_temperature - bar.shallow_temperature) * (a + b) / 2.0;
                    heat(t, low, high)
                } else {
                    blue
                };
                let at = |f: f64| y0 + (f64::from(y1 - y0) * f).round() as i32;
                Rectangle::new(
                    [(bar.x as i32, at(a)), (bar.x_end as i32, at(b))],
                    ShapeStyle::from(&colour).filled(),
                )
            })
        }) {
            pixels.draw(&rectangle)?;
        }
    } else if temperature {
        chart.draw_series(trace.points.windows(2).zip(&trace.temps).map(|(pair, &t)| {
            PathElement::new(
                vec![
                    (pair[0].0 as f64 / scale, pair[0].1 as f64),
                    (pair[1].0 as f64 / scale, pair[1].1 as f64),
                ],
                ShapeStyle::from(&heat(t as f64, low, high)).stroke_width(3),
            )
        }))?;
    } else {
        chart.draw_series(LineSeries::new(
            trace
                .points
                .iter()
                .map(|&(t, d)| (t as f64 / scale, d as f64)),
            ShapeStyle::from(&blue).stroke_width(2),
        ))?;
    }
    let red = RGBColor(200, 30, 30);
    // The stores on the track: small marks (the labels are on the event
    // track); a long run has them on the event track only.
    let on_track: &[Action] = if long { &[] } else { &trace.actions };
    chart.draw_series(on_track.iter().map(|action| {
        Circle::new(
            (action.time as f64 / scale, action.depth as f64),
            2,
            ShapeStyle::from(&red).filled(),
        )
    }))?;

    draw_events(&events, trace, &x_range, scale)?;
    let below = draw_panels(battery, trace, options, (&x_range, scale, unit), columns)?;
    if has_map(trace) {
        let (area, _) = below.split_vertically(MAP_HEIGHT);
        draw_map(&area, trace)?;
    }
    Ok(())
}

/// The event track: every store a tick, labels where they fit.
fn draw_events<DB: DrawingBackend>(
    events: &DrawingArea<DB, Shift>,
    trace: &Trace,
    x_range: &std::ops::Range<f64>,
    scale: f64,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let red = RGBColor(200, 30, 30);
    // The event track: every store a tick, labels where they fit.
    let labelled_caption = |labelled: usize| {
        format!(
            "script stores: {} (labels shown where they do not overlap: {labelled})",
            trace.actions.len()
        )
    };
    let pixel = |time: f64| {
        let span = (x_range.end - x_range.start).max(1e-9);
        (time / scale - x_range.start) / span * (WIDTH as f64 - 100.0)
    };
    let labels: Vec<String> = trace.actions.iter().map(|a| trace.label(a)).collect();
    let lanes = place_labels(
        &trace
            .actions
            .iter()
            .zip(&labels)
            .map(|(action, label)| (pixel(action.time as f64), 7.0 * label.len() as f64))
            .collect::<Vec<_>>(),
        WIDTH as f64 - 100.0,
    );
    let labelled = lanes.iter().filter(|lane| lane.is_some()).count();
    let mut track = ChartBuilder::on(events)
        .caption(labelled_caption(labelled), ("sans-serif", 14))
        .margin_left(16)
        .margin_right(16)
        .x_label_area_size(0)
        .y_label_area_size(60)
        .build_cartesian_2d(x_range.clone(), 0.0..(LANES as f64 + 1.0))?;
    track
        .configure_mesh()
        .disable_y_mesh()
        .disable_y_axis()
        .light_line_style(RGBColor(245, 245, 245))
        .draw()?;
    track.draw_series(trace.actions.iter().map(|action| {
        PathElement::new(
            vec![
                (action.time as f64 / scale, 0.0),
                (action.time as f64 / scale, 0.8),
            ],
            ShapeStyle::from(&red).stroke_width(1),
        )
    }))?;
    track.draw_series(trace.actions.iter().zip(&labels).zip(&lanes).filter_map(
        |((action, label), lane)| {
            let lane = (*lane)?;
            Some(Text::new(
                label.clone(),
                (action.time as f64 / scale, LANES as f64 + 0.9 - lane as f64),
                ("sans-serif", 12).into_font().color(&red),
            ))
        },
    ))?;
    Ok(())
}

/// The panels below the event track (battery, chosen sensors), one per series, on the
/// depth plot's time axis; returns the area left below them.
fn draw_panels<DB: DrawingBackend>(
    battery: DrawingArea<DB, Shift>,
    trace: &Trace,
    options: &PlotOptions,
    (x_range, scale, unit): (&std::ops::Range<f64>, f64, &str),
    columns: usize,
) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    let mut below = battery;
    for (name, values) in panels(trace, options) {
        let (area, rest) = below.split_vertically(BATTERY_HEIGHT);
        below = rest;
        let (vlow, vhigh) = values
            .iter()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v as f64), hi.max(v as f64))
            });
        let (vlow, vhigh) = if vlow.is_finite() {
            (vlow, vhigh)
        } else {
            (0.0, 1.0)
        };
        let pad = ((vhigh - vlow) * 0.1).max(0.05);
        let mut panel = ChartBuilder::on(&area)
            .caption(name, ("sans-serif", 14))
            .margin_left(16)
            .margin_right(16)
            .margin_bottom(8)
            .x_label_area_size(28)
            .y_label_area_size(60)
            .build_cartesian_2d(x_range.clone(), (vlow - pad)..(vhigh + pad))?;
        panel
            .configure_mesh()
            .x_desc(format!("time ({unit})"))
            .light_line_style(RGBColor(240, 240, 240))
            .draw()?;
        // A long run: every k-th point, k keeping about 4 per pixel column.
        let step = trace.points.len().div_ceil(4 * columns).max(1);
        panel.draw_series(LineSeries::new(
            trace
                .points
                .iter()
                .zip(&values)
                .step_by(step)
                .filter(|(_, v)| v.is_finite())
                .map(|(&(t, _), &v)| (t as f64 / scale, v as f64)),
            ShapeStyle::from(&RGBColor(20, 130, 60)).stroke_width(2),
        ))?;
    }
    Ok(below)
}

/// The map panel: east and north in km on equal scales, the true track
/// (blue), the dead-reckoned one (grey, dashed by points), waypoints (red
/// crosses), surfacings (first fixes, black circles), the current (an arrow
/// from the start, 1 h of drift long).
fn draw_map<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    trace: &Trace,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (low, high) = map_bounds(trace);
    let drift = (
        trace.current.0 as f64 * 3600.0,
        trace.current.1 as f64 * 3600.0,
    );
    let in_km = |(x, y): (f64, f64)| (x / 1000.0, y / 1000.0);
    let (low, high) = bounds([low, high, drift].map(in_km));
    let speed = (trace.current.0 as f64).hypot(trace.current.1 as f64);
    let caption = trace.map_caption.clone().unwrap_or_else(|| {
        format!(
            "map (km east and north of the start): true track blue, dead reckoning grey, waypoints red, first fixes black; current {speed:.2} m/s (arrow: 1 h of drift)"
        )
    });
    let map_box = MapBox {
        low,
        high,
        x_unit: 1.0,
        min_span: 0.001,
    };
    let mut map = map_chart(area, (&caption, 14), 0, map_box)?;
    map.configure_mesh()
        .x_desc("east (km)")
        .y_desc("north (km)")
        .light_line_style(RGBColor(240, 240, 240))
        .draw()?;
    let km = |&(x, y): &(f32, f32)| (x as f64 / 1000.0, y as f64 / 1000.0);
    let known = |point: &&(f32, f32)| point.0.is_finite() && point.1.is_finite();
    // A long run: every k-th point, about 8,000 in all.
    let step = trace.track.len().div_ceil(8000).max(1);
    map.draw_series(LineSeries::new(
        trace
            .dead_reckoned
            .iter()
            .step_by(step)
            .filter(known)
            .map(km),
        ShapeStyle::from(&RGBColor(150, 150, 150)).stroke_width(1),
    ))?;
    map.draw_series(LineSeries::new(
        trace.track.iter().step_by(step).filter(known).map(km),
        ShapeStyle::from(&RGBColor(30, 70, 200)).stroke_width(2),
    ))?;
    let red = RGBColor(200, 30, 30);
    map.draw_series(
        trace
            .waypoints
            .iter()
            .map(|point| Cross::new(km(point), 8, ShapeStyle::from(&red).stroke_width(3))),
    )?;
    map.draw_series(
        trace
            .surfacings
            .iter()
            .map(|point| Circle::new(km(point), 5, ShapeStyle::from(&BLACK).stroke_width(2))),
    )?;
    map.draw_series(std::iter::once(Circle::new(
        (0.0, 0.0),
        4,
        ShapeStyle::from(&RGBColor(20, 130, 60)).filled(),
    )))?;
    if speed > 0.0 {
        let tip = (drift.0 / 1000.0, drift.1 / 1000.0);
        let green = RGBColor(20, 130, 60);
        map.draw_series(LineSeries::new(
            [(0.0, 0.0), tip],
            ShapeStyle::from(&green).stroke_width(3),
        ))?;
        // The head: two strokes back from the tip, ±25° about the shaft.
        let length = (drift.0.hypot(drift.1) / 1000.0).max(1e-9);
        let back = (-tip.0 / length, -tip.1 / length);
        let head = 0.15 * length;
        for angle in [0.44f64, -0.44] {
            let (sin, cos) = angle.sin_cos();
            let side = (back.0 * cos - back.1 * sin, back.0 * sin + back.1 * cos);
            map.draw_series(LineSeries::new(
                [tip, (tip.0 + side.0 * head, tip.1 + side.1 * head)],
                ShapeStyle::from(&green).stroke_width(3),
            ))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Worked by hand: a 10 × 5 km box on a 200 × 100 px plot fills it both ways
    /// (11.5 × 5.75 km with the room, 0.0575 km a pixel), centred on (5, 2.5).
    #[test]
    fn a_box_of_the_plots_aspect_fills_it() {
        let map = MapBox {
            low: (0.0, 0.0),
            high: (10.0, 5.0),
            x_unit: 1.0,
            min_span: 0.001,
        };
        let (x, y) = equal_scales(map, (200.0, 100.0));
        for (got, want) in [
            (x.start, -0.75),
            (x.end, 10.75),
            (y.start, -0.375),
            (y.end, 5.375),
        ] {
            assert!((got - want).abs() < 1e-12, "{got} against {want}");
        }
    }

    /// At 60° N a degree of longitude is half one of latitude: a box one degree
    /// square on a square plot shows twice as many degrees across as up (2.3 and
    /// 1.15), so a kilometre is as long either way.
    #[test]
    fn degrees_of_longitude_are_shortened_by_the_latitude() {
        let map = MapBox {
            low: (10.0, 59.5),
            high: (11.0, 60.5),
            x_unit: 60f64.to_radians().cos(),
            min_span: 0.01,
        };
        let (x, y) = equal_scales(map, (100.0, 100.0));
        assert!((x.end - x.start - 2.3).abs() < 1e-9, "{x:?}");
        assert!((y.end - y.start - 1.15).abs() < 1e-9, "{y:?}");
        assert!((x.start + x.end - 21.0).abs() < 1e-9 && (y.start + y.end - 120.0).abs() < 1e-9);
    }

    /// One point is still a map: the least span about it, on either axis.
    #[test]
    fn a_single_point_gets_the_least_span() {
        let (low, high) = bounds([(3.0, 4.0), (f64::NAN, 1.0)]);
        assert_eq!((low, high), ((3.0, 4.0), (3.0, 4.0)));
        let map = MapBox {
            low,
            high,
            x_unit: 1.0,
            min_span: 0.5,
        };
        let (x, y) = equal_scales(map, (100.0, 50.0));
        assert!((y.end - y.start - 0.5).abs() < 1e-12 && (x.end - x.start - 1.0).abs() < 1e-12);
        assert_eq!(bounds([(f64::NAN, 0.0)]), ((0.0, 0.0), (0.0, 0.0)));
    }

    /// A yo between 10 m and 23 m with a 240 s period, sampled every 4.4 s
    /// for `hours`: comet's cycle, the thermocline example's yo.
    fn yo_trace(hours: f64) -> Vec<(f32, f32)> {
        let count = (hours * 3600.0 / 4.4) as usize + 1;
        (0..count)
            .map(|i| {
                let t = i as f64 * 4.4;
                let phase = (t / 240.0).fract();
                (
                    t as f32,
                    (10.0 + 13.0 * (1.0 - (2.0 * phase - 1.0).abs())) as f32,
                )
            })
            .collect()
    }

    #[test]
    fn thinned_points_are_bounded_in_order_and_keep_the_extremes() {
        let count = 3 * MAX_PLOT_POINTS;
        let depth = |i: usize| match i {
            123_457 => 5000.0,
            654_321 => -50.0,
            _ => ((i * 7919) % 1000) as f32,
        };
        let mut thinned = Thinned::default();
        for i in 0..count {
            thinned.push((i as f32, depth(i)));
        }
        let points = thinned.finish();
        assert!(points.len() <= MAX_PLOT_POINTS, "{}", points.len());
        assert_eq!(points.first(), Some(&(0.0, 0.0)));
        assert_eq!(points.last(), Some(&((count - 1) as f32, depth(count - 1))));
        assert!(points.contains(&(123_457.0, 5000.0)));
        assert!(points.contains(&(654_321.0, -50.0)));
        assert!(points.windows(2).all(|pair| pair[0].0 < pair[1].0));
    }

    fn overlaps(a: &Column, b: &Column) -> bool {
        a.shallowest <= b.deepest && b.shallowest <= a.deepest
    }

    #[test]
    fn the_envelope_keeps_extremes() {
        let points: Vec<(f32, f32)> = (0..100_000)
            .map(|i| (i as f32, ((i % 1000) as f32 - 500.0).abs()))
            .collect();
        let columns = envelope(&points, &[], 100_000.0, 100, 1);
        assert_eq!(columns.len(), 100);
        assert!(columns
            .iter()
            .all(|c| c.shallowest == 0.0 && c.deepest == 500.0));
    }

    #[test]
    fn the_yo_period_is_measured_from_the_turns() {
        // 240 s by construction; turns are found to the nearest 4.4 s sample.
        let period = yo_period(&yo_trace(6.0)).expect("a yo");
        assert!((period - 240.0).abs() <= 2.0 * 4.4, "{period}");
        // A dive that never turns has no period.
        let dive: Vec<(f32, f32)> = (0..100).map(|i| (i as f32 * 4.0, i as f32)).collect();
        assert_eq!(yo_period(&dive), None);
    }

    #[test]
    fn bars_connect_from_column_to_column() {
        // 6 h drawn as one bar per pixel: about 4.5 samples per column, each
        // a metre apart, so bars over their own samples only would leave
        // gaps between them (the dashes the first renderer drew).
        let points = yo_trace(6.0);
        let duration = points.last().expect("points").0 as f64;
        let columns = envelope(&points, &[], duration, 1100, 1);
        assert!(columns.len() > 1000, "{}", columns.len());
        let mut next = 0;
        for pair in columns.windows(2) {
            assert!(overlaps(&pair[0], &pair[1]), "{pair:?}");
            // Tiled: each bar reaches the next one's left edge.
            assert_eq!(pair[0].x_end, pair[1].x, "{pair:?}");
            // The bar holds the previous column's last sample.
            while next < points.len()
                && (points[next].0 as f64) * 1100.0 / duration < pair[1].x as f64
            {
                next += 1;
            }
            let last = points[next - 1].1 as f64;
            assert!(
                pair[1].shallowest <= last && last <= pair[1].deepest,
                "{pair:?} {last}"
            );
        }
    }

    #[test]
    fn one_sample_per_column_draws_the_samples() {
        // One sample in the middle of each pixel: each bar runs from the
        // previous sample's depth to its own, the pixels of the line between.
        let depths: Vec<f32> = (0..100).map(|i| ((i * 37) % 11) as f32).collect();
        let points: Vec<(f32, f32)> = depths
            .iter()
            .enumerate()
            .map(|(i, &d)| (i as f32 + 0.5, d))
            .collect();
        let columns = envelope(&points, &[], 100.0, 100, 1);
        assert_eq!(columns.len(), 100);
        assert_eq!((columns[0].shallowest, columns[0].deepest), (0.0, 0.0));
        for (i, column) in columns.iter().enumerate().skip(1) {
            let (a, b) = (depths[i - 1] as f64, depths[i] as f64);
            assert_eq!((column.shallowest, column.deepest), (a.min(b), a.max(b)));
            assert_eq!((column.x, column.x_end), (i as u32, i as u32 + 1));
        }
        // So few samples are drawn as the line itself.
        assert_eq!(track_style(&points, 100), TrackStyle::Line);
    }

    #[test]
    fn an_unresolved_yo_is_drawn_as_a_band() {
        // 24 h of 4-minute yos over 1100 pixels: 3.1 pixels per yo.
        let points = yo_trace(24.0);
        let duration = points.last().expect("points").0 as f64;
        // One bar per pixel aliases: some columns miss the top turn by more
        // than 3 m (the wave the first renderer drew).
        let aliased = envelope(&points, &[], duration, 1100, 1);
        assert!(aliased.iter().any(|c| c.shallowest > 13.0));
        // The chosen columns hold two yos each: 2 × 240 s × 1100 / 86400 s
        // = 6.1 pixels, so 7; every full column spans both turns (samples
        // land within 4.4 s × 13 m / 120 s = 0.48 m of a turn).
        let style = track_style(&points, 1100);
        assert_eq!(style, TrackStyle::Columns { width: 7 });
        let band = envelope(&points, &[], duration, 1100, 7);
        let full = &band[..band.len() - 1];
        assert!(full.len() > 150, "{}", full.len());
        for column in full {
            assert!(
                column.shallowest < 10.5 && column.deepest > 22.5,
                "{column:?}"
            );
        }
        // A yo of 12 pixels (6 h) is drawn as the sawtooth, 4.5 samples a pixel.
        assert_eq!(track_style(&yo_trace(6.0), 1100), TrackStyle::Line);
        // 30 days: a fifth of a pixel per yo, bars of one pixel.
        let month: Vec<(f32, f32)> = yo_trace(30.0 * 24.0);
        assert_eq!(track_style(&month, 1100), TrackStyle::Columns { width: 1 });
    }

    #[test]
    fn the_time_axis_adapts() {
        assert_eq!(time_unit(6.0 * 3600.0).1, "hours");
        assert_eq!(time_unit(40.0 * 60.0).1, "minutes");
        assert_eq!(time_unit(30.0 * 86400.0).1, "days");
    }

    #[test]
    fn labels_never_overlap_and_every_mark_stays() {
        // Two stores in one cycle (same x), then a crowd: no two labels in a
        // lane overlap; what does not fit is unlabelled.
        let marks: Vec<(f64, f64)> = (0..50).map(|i| ((i / 2) as f64 * 10.0, 120.0)).collect();
        let lanes = place_labels(&marks, f64::INFINITY);
        assert_eq!(lanes.len(), marks.len());
        assert_ne!(lanes[0], lanes[1]);
        for lane in 0..LANES {
            let mut spans: Vec<(f64, f64)> = marks
                .iter()
                .zip(&lanes)
                .filter(|(_, l)| **l == Some(lane))
                .map(|(&(x, w), _)| (x, x + w))
                .collect();
            spans.sort_by(|a, b| a.0.total_cmp(&b.0));
            assert!(spans.windows(2).all(|w| w[0].1 <= w[1].0), "{spans:?}");
        }
    }

    #[test]
    fn formats_by_extension() {
        assert_eq!(
            PlotFormat::from_path(Path::new("a.SVG")),
            Ok(PlotFormat::Svg)
        );
        assert_eq!(
            PlotFormat::from_path(Path::new("a.png")),
            Ok(PlotFormat::Png)
        );
        let refused = PlotFormat::from_path(Path::new("a.jpg")).expect_err("jpg");
        assert!(refused.contains(".svg or .png"), "{refused}");
    }

    #[test]
    fn renders_an_svg_with_marks_and_a_png() {
        let mut trace = Trace::default();
        for i in 0..100 {
            trace
                .points
                .push((i as f32 * 4.0, (i as f32 * 0.5).min(20.0)));
        }
        trace.names.push("sci_ruhp_behs".to_string());
        for value in [128.0, 0.0] {
            trace.actions.push(Action {
                time: 120.0,
                depth: 15.2,
                name: 0,
                value,
            });
        }
        let svg = render_svg(&trace, "test", 40.0).expect("svg");
        assert!(svg.starts_with("<svg"), "{}", &svg[..40.min(svg.len())]);
        // Two stores in one cycle: both labelled, in different lanes.
        assert!(svg.contains("sci_ruhp_behs=128") && svg.contains("sci_ruhp_behs=0"));
        assert!(svg.contains("depth (m)") && svg.contains("time (minutes)"));
        let path = std::env::temp_dir().join(format!("gloc-plot-{}.png", std::process::id()));
        let options = PlotOptions {
            title: "test".into(),
            water_depth: 40.0,
            temperature: false,
            battery: false,
        };
        write_plot(&trace, &options, &path).expect("png");
        let bytes = std::fs::read(&path).expect("written");
        let _ = std::fs::remove_file(&path);
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    }

    #[test]
    fn a_map_is_drawn_only_when_the_glider_moved() {
        let mut trace = Trace::default();
        for i in 0..100 {
            trace.points.push((i as f32 * 4.0, 10.0));
            trace.track.push((i as f32 * 0.05, 0.0));
            trace.dead_reckoned.push((i as f32 * 0.05, 0.0));
        }
        // 5 m east: no map.
        assert!(!has_map(&trace));
        let plain = render_svg(&trace, "test", 40.0).expect("svg");
        assert!(!plain.contains("east (km)"));
        for (i, point) in trace.track.iter_mut().enumerate() {
            *point = (i as f32 * 30.0, i as f32 * 10.0);
        }
        trace.waypoints.push((3000.0, 1000.0));
        trace.surfacings.push((2970.0, 990.0));
        trace.current = (0.1, 0.0);
        assert!(has_map(&trace));
        let options = PlotOptions {
            title: "test".into(),
            water_depth: 40.0,
            temperature: false,
            battery: false,
        };
        assert_eq!(
            height(&trace, &options),
            MAIN_HEIGHT + EVENT_HEIGHT + MAP_HEIGHT
        );
        let svg = render_svg(&trace, "test", 40.0).expect("svg");
        assert!(svg.contains("east (km)") && svg.contains("north (km)"));
        assert!(svg.contains("current 0.10 m/s"));
        // A track shorter than the points (not recorded every cycle) draws no map.
        trace.track.pop();
        assert!(!has_map(&trace));
    }
}
