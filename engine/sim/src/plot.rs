//! The flight profile: depth (downward) against time, like the paper's Fig. 2
//! and 4b, with the script's stores as an event track below it and optional
//! panels (temperature as colour along the track, battery voltage, chosen
//! sensors). SVG or PNG.
//!
//! The time axis is in minutes, hours or days by the run's length. A long run
//! is drawn as a min/max envelope, one column per pixel. Every store is marked
//! (no cap); a label is drawn only where it does not overlap another.

use std::path::Path;

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
        if self.points.is_empty() {
            self.points.push((0.0, 0.0));
            self.volts.push(sim.battery_volts() as f32);
            self.temps.push(sim.water_temperature() as f32);
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
        let extension = path
            .extension()
            .and_then(|extension| extension.to_str())
            .map(str::to_ascii_lowercase);
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
    MAIN_HEIGHT + EVENT_HEIGHT + BATTERY_HEIGHT * panels(trace, options).len() as u32
}

static FONT: &[u8] = include_bytes!("../data/fonts/DejaVuSans-subset.ttf");

fn register_font() {
    // A subset of DejaVu Sans (ASCII, °, ±, ×, –, −, µ; data/fonts, its
    // licence beside it): plotters measures and draws text with it.
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Renders the trace to an SVG document.
pub fn render_svg_with(trace: &Trace, options: &PlotOptions) -> Result<String, String> {
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

/// One pixel column of a long run: time span and depth range, mean temperature.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Column {
    start: f64,
    end: f64,
    shallowest: f64,
    deepest: f64,
    /// Temperature at the shallowest and the deepest point (NaN: not recorded).
    shallow_temperature: f64,
    deep_temperature: f64,
}

/// Per-column min and max: every turn's extreme is kept.
fn envelope(points: &[(f32, f32)], temps: &[f32], columns: usize) -> Vec<Column> {
    let per = points.len().div_ceil(columns.max(1)).max(1);
    points
        .chunks(per)
        .enumerate()
        .map(|(index, chunk)| {
            let (mut shallowest, mut deepest) = (f64::INFINITY, f64::NEG_INFINITY);
            let (mut shallow_at, mut deep_at) = (0, 0);
            for (at, &(_, depth)) in chunk.iter().enumerate() {
                if (depth as f64) < shallowest {
                    shallowest = depth as f64;
                    shallow_at = at;
                }
                if depth as f64 > deepest {
                    deepest = depth as f64;
                    deep_at = at;
                }
            }
            let from = index * per;
            let temperature = |at: usize| temps.get(from + at).map_or(f64::NAN, |&t| t as f64);
            Column {
                start: chunk[0].0 as f64,
                end: chunk[chunk.len() - 1].0 as f64,
                shallowest,
                deepest,
                shallow_temperature: temperature(shallow_at),
                deep_temperature: temperature(deep_at),
            }
        })
        .collect()
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
    root: &DrawingArea<DB, plotters::coord::Shift>,
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
    let long = trace.points.len() > 2 * columns;
    if long {
        // A long run: one bar per pixel column from its shallowest to its
        // deepest depth, coloured by its mean temperature when asked.
        let bars = envelope(&trace.points, &trace.temps, columns);
        // Each bar reaches the next one's start: no hairline gaps.
        let ends: Vec<f64> = bars
            .iter()
            .skip(1)
            .map(|bar| bar.start)
            .chain(bars.last().map(|bar| bar.end))
            .collect();
        let pieces = if temperature { BAR_PIECES } else { 1 };
        chart.draw_series(bars.iter().zip(&ends).flat_map(|(bar, &end)| {
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
                let span = bar.deepest - bar.shallowest;
                Rectangle::new(
                    [
                        (bar.start / scale, bar.shallowest + span * a),
                        (end / scale, bar.shallowest + span * b),
                    ],
                    ShapeStyle::from(&colour).filled(),
                )
            })
        }))?;
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
    let mut track = ChartBuilder::on(&events)
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
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_envelope_keeps_extremes() {
        let points: Vec<(f32, f32)> = (0..100_000)
            .map(|i| (i as f32, ((i % 1000) as f32 - 500.0).abs()))
            .collect();
        let columns = envelope(&points, &[], 100);
        assert_eq!(columns.len(), 100);
        assert!(columns
            .iter()
            .all(|c| c.shallowest == 0.0 && c.deepest == 500.0));
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
}
