//! The forecast on a map (PNG or SVG, with plotters and the simulator's
//! embedded font): longitude and latitude at equal metric scales, the logged
//! fixes, the forecast track, the predicted surfacings with their times, the
//! waypoint, and with an ensemble the region of each hour and the spread of
//! each surfacing.

use std::path::Path;

use gloc_sim::plot::{bounds, map_chart, MapBox, MapChart, PlotFormat};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::export::iso_time;
use crate::logs::Fix;
use crate::Forecast;

const WIDTH: u32 = 1100;
const HEIGHT: u32 = 930;

/// Draws with `$draw` (given the drawing area) on `$backend` and presents the area
/// (writes the file); a failure as text.
macro_rules! present {
    ($backend:expr, |$root:ident| $draw:expr) => {{
        let area = $backend.into_drawing_area();
        let $root = &area;
        $draw
            .and_then(|()| area.present())
            .map_err(|error| error.to_string())
    }};
}

/// Draws with `$draw` (given the drawing area) on the backend `$path`'s extension names
/// (PNG or SVG, as [`PlotFormat::from_path`] tells the simulator's plots), and words a
/// failure with the path: one body for every map. Macros, because the drawing
/// functions are generic over the backend.
macro_rules! render {
    ($path:expr, |$root:ident| $draw:expr) => {{
        let path: &Path = $path;
        let result = match PlotFormat::from_path(path) {
            Ok(PlotFormat::Png) => {
                present!(BitMapBackend::new(path, (WIDTH, HEIGHT)), |$root| $draw)
            }
            Ok(PlotFormat::Svg) => present!(SVGBackend::new(path, (WIDTH, HEIGHT)), |$root| $draw),
            Err(_) => Err("a map is .png or .svg".to_string()),
        };
        result.map_err(|error| format!("cannot draw the map `{}`: {error}", path.display()))
    }};
}

/// Draws the map to `path` (PNG or SVG by the extension). `fixes` are the
/// logged GPS fixes to show where the glider has been.
pub fn write_map(forecast: &Forecast, fixes: &[Fix], path: &Path) -> Result<(), String> {
    gloc_sim::plot::register_font();
    render!(path, |root| draw(root, forecast, fixes))
}

/// Every (lat, lon) the map shows.
fn extent(forecast: &Forecast, fixes: &[Fix]) -> Vec<(f64, f64)> {
    let mut points: Vec<(f64, f64)> = forecast
        .track
        .points
        .iter()
        .map(|p| (p.lat, p.lon))
        .collect();
    points.extend(fixes.iter().map(|f| crate::fly::degrees(f.lat, f.lon)));
    points.push(crate::fly::degrees(forecast.start.lat, forecast.start.lon));
    if let Some(ensemble) = &forecast.ensemble {
        for region in &ensemble.regions {
            points.extend(region.hull.iter().copied());
        }
    }
    points
}

/// The logged GPS fixes as grey dots: where the glider has been.
fn draw_fixes<DB: DrawingBackend>(
    chart: &mut MapChart<'_, DB>,
    fixes: &[Fix],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let grey = RGBColor(120, 120, 120);
    chart.draw_series(fixes.iter().map(|fix| {
        let (lat, lon) = crate::fly::degrees(fix.lat, fix.lon);
        Circle::new((lon, lat), 2, grey.filled())
    }))?;
    Ok(())
}

/// Room below the chart for the legend (px).
const LEGEND: u32 = 28;

/// The map's chart around `points` (lat, lon): longitude and latitude in
/// degrees at equal metric scales ([`map_chart`]'s rule), a grid every few
/// hundredths of a degree.
fn frame<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    points: &[(f64, f64)],
    title: String,
) -> Result<MapChart<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let (low, high) = bounds(points.iter().map(|&(lat, lon)| (lon, lat)));
    // A degree of longitude is cos(latitude) of one of latitude.
    let middle = (low.1 + high.1) / 2.0;
    let map = MapBox {
        low,
        high,
        x_unit: middle.to_radians().cos().max(0.05),
        min_span: 0.01,
    };
    let mut chart = map_chart(root, (&title, 20), LEGEND, map)?;
    chart
        .configure_mesh()
        .x_desc("longitude (°E)")
        .y_desc("latitude (°N)")
        .x_label_formatter(&|v| format!("{v:.2}"))
        .y_label_formatter(&|v| format!("{v:.2}"))
        .light_line_style(RGBColor(238, 238, 238))
        .draw()?;
    Ok(chart)
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    forecast: &Forecast,
    fixes: &[Fix],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let title = format!(
        "gloc forecast: {} from {}, {} h",
        forecast.mission_name,
        iso_time(forecast.start.time),
        forecast.hours
    );
    let mut chart = frame(root, &extent(forecast, fixes), title)?;
    let blue = RGBColor(40, 110, 220);
    if let Some(ensemble) = &forecast.ensemble {
        for region in &ensemble.regions {
            if region.hull.len() >= 3 {
                let ring: Vec<(f64, f64)> =
                    region.hull.iter().map(|&(lat, lon)| (lon, lat)).collect();
                chart.draw_series(std::iter::once(Polygon::new(
                    ring.clone(),
                    blue.mix(0.08).filled(),
                )))?;
                let mut closed = ring.clone();
                closed.push(ring[0]);
                chart.draw_series(std::iter::once(PathElement::new(
                    closed,
                    ShapeStyle::from(&blue.mix(0.6)).stroke_width(1),
                )))?;
                // The hour at the region's easternmost corner.
                if let Some(&(lon, lat)) = ring.iter().max_by(|a, b| a.0.total_cmp(&b.0)) {
                    chart.draw_series(std::iter::once(Text::new(
                        format!("{} h", region.hour),
                        (lon, lat),
                        ("sans-serif", 13).into_font().color(&blue),
                    )))?;
                }
            }
        }
    }
    draw_fixes(&mut chart, fixes)?;
    let red = RGBColor(200, 30, 30);
    chart.draw_series(LineSeries::new(
        forecast.track.points.iter().map(|p| (p.lon, p.lat)),
        ShapeStyle::from(&red).stroke_width(2),
    ))?;
    for (index, surfacing) in forecast.track.surfacings.iter().enumerate() {
        let at = (surfacing.lon, surfacing.lat);
        chart.draw_series(std::iter::once(Circle::new(
            at,
            6,
            ShapeStyle::from(&BLACK).stroke_width(2),
        )))?;
        let clock = iso_time(surfacing.time);
        chart.draw_series(std::iter::once(Text::new(
            format!("  {} {}", index + 1, &clock[11..16]),
            at,
            ("sans-serif", 14).into_font().color(&BLACK),
        )))?;
    }
    let (slat, slon) = crate::fly::degrees(forecast.start.lat, forecast.start.lon);
    let green = RGBColor(20, 130, 60);
    chart.draw_series(std::iter::once(Circle::new(
        (slon, slat),
        6,
        green.filled(),
    )))?;
    chart.draw_series(std::iter::once(Text::new(
        "  start (last fix)",
        (slon, slat),
        ("sans-serif", 14).into_font().color(&green),
    )))?;
    if let Some((wlat, wlon)) = forecast
        .start
        .waypoint
        .map(|(lat, lon)| crate::fly::degrees(lat, lon))
    {
        if chart.x_range().contains(&wlon) && chart.y_range().contains(&wlat) {
            chart.draw_series(std::iter::once(Cross::new(
                (wlon, wlat),
                9,
                ShapeStyle::from(&red).stroke_width(3),
            )))?;
        }
    }
    let legend = match &forecast.ensemble {
        Some(ensemble) => format!(
            "red: forecast track, circles: predicted first fixes (UTC); grey: logged fixes; blue: where {} members can be, per hour (current sd {:.2} east, {:.2} north m/s)",
            ensemble.members, ensemble.spread.x, ensemble.spread.y
        ),
        None => "red: forecast track, circles: predicted first fixes (UTC); grey: logged fixes".to_string(),
    };
    root.draw(&Text::new(
        legend,
        (20, (HEIGHT - 22) as i32),
        ("sans-serif", 13).into_font().color(&BLACK),
    ))?;
    Ok(())
}

/// Draws a hindcast to `path` (PNG or SVG): per segment the track flown with
/// the current found after it (red), with the prior current (orange, the
/// null model), the start (green) and the real first fix (black cross).
pub fn write_hindcast_map(
    segments: &[crate::hindcast::SegmentHindcast],
    fixes: &[Fix],
    path: &Path,
) -> Result<(), String> {
    gloc_sim::plot::register_font();
    render!(path, |root| draw_hindcast(root, segments, fixes))
}

fn draw_hindcast<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    segments: &[crate::hindcast::SegmentHindcast],
    fixes: &[Fix],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let mut points: Vec<(f64, f64)> = fixes
        .iter()
        .map(|f| crate::fly::degrees(f.lat, f.lon))
        .collect();
    for result in segments {
        points.extend(result.track.iter().copied());
        points.extend(result.null_track.iter().copied());
    }
    let title = format!("gloc hindcast: {} segment(s) flown again", segments.len());
    let mut chart = frame(root, &points, title)?;
    draw_fixes(&mut chart, fixes)?;
    let red = RGBColor(200, 30, 30);
    let orange = RGBColor(235, 140, 20);
    let green = RGBColor(20, 130, 60);
    for result in segments {
        let swap = |&(lat, lon): &(f64, f64)| (lon, lat);
        chart.draw_series(LineSeries::new(
            result.null_track.iter().map(swap),
            ShapeStyle::from(&orange).stroke_width(2),
        ))?;
        chart.draw_series(LineSeries::new(
            result.track.iter().map(swap),
            ShapeStyle::from(&red).stroke_width(2),
        ))?;
        let (slat, slon) = crate::fly::degrees(result.segment.start.lat, result.segment.start.lon);
        chart.draw_series(std::iter::once(Circle::new(
            (slon, slat),
            6,
            green.filled(),
        )))?;
        let (elat, elon) = crate::fly::degrees(result.segment.end.lat, result.segment.end.lon);
        chart.draw_series(std::iter::once(Cross::new(
            (elon, elat),
            9,
            ShapeStyle::from(&BLACK).stroke_width(3),
        )))?;
        let label = match (result.miss, result.null_miss) {
            (Some(miss), Some(null)) => {
                format!("{miss:.0} m (null model {:.1} km)", null / 1000.0)
            }
            _ => "no surfacing".to_string(),
        };
        // Beside the cross, above it: the next segment starts where this one ended.
        chart.draw_series(std::iter::once(
            EmptyElement::at((elon, elat))
                + Text::new(
                    label,
                    (12, -24),
                    ("sans-serif", 15).into_font().color(&BLACK),
                ),
        ))?;
    }
    root.draw(&Text::new(
        "green: start (last fix before the dive); red: flown with the current found after the segment; orange: with the prior current; black cross: the real first fix; grey: logged fixes",
        (20, (HEIGHT - 22) as i32),
        ("sans-serif", 13).into_font().color(&BLACK),
    ))?;
    Ok(())
}
