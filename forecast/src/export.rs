//! A forecast written out: GeoJSON (RFC 7946, through the `geojson` crate),
//! KML 2.2 (what pilots open in Google Earth, through `quick-xml`'s writer)
//! and CSV (the track, one row per point). [`Format::from_path`] picks one by
//! the output's extension. Positions are WGS 84 decimal degrees, longitude
//! first as both formats want; times ISO 8601 UTC.

use std::path::Path;

use geojson::{Feature, FeatureCollection, Geometry, GeometryValue, JsonObject, JsonValue};
use quick_xml::events::{BytesDecl, BytesText, Event};
use quick_xml::Writer;

use crate::ensemble::Ensemble;
use crate::Forecast;
use gloc_sim::navigation::degrees_to_nmea;

/// An output format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    GeoJson,
    Kml,
    Csv,
}

impl Format {
    /// By the extension: `.geojson` or `.json`, `.kml`, `.csv`.
    pub fn from_path(path: &Path) -> Result<Format, String> {
        let extension = gloc_engine::files::extension(path);
        match extension.as_deref() {
            Some("geojson" | "json") => Ok(Format::GeoJson),
            Some("kml") => Ok(Format::Kml),
            Some("csv") => Ok(Format::Csv),
            _ => Err(format!(
                "`{}`: the output's extension picks its format: .geojson (or .json), .kml or .csv",
                path.display()
            )),
        }
    }

    /// The forecast in this format.
    pub fn write(self, forecast: &Forecast) -> Result<Vec<u8>, String> {
        match self {
            Format::GeoJson => Ok(to_geojson(forecast).into_bytes()),
            Format::Kml => to_kml(forecast),
            Format::Csv => Ok(to_csv(forecast).into_bytes()),
        }
    }
}

/// Unix seconds as ISO 8601 UTC (`2019-08-21T13:54:06Z`, whole seconds); the
/// number itself outside the years 0 to 9999.
pub fn iso_time(unix: f64) -> String {
    gloc_dbd::header::iso_time(unix.round()).unwrap_or_else(|| format!("{unix}"))
}

/// NMEA `ddmm.mmm` of decimal degrees, as the glider writes it.
pub fn nmea_text(degrees: f64) -> String {
    format!("{:.4}", degrees_to_nmea(degrees))
}

fn round6(value: f64) -> f64 {
    (value * 1e6).round() / 1e6
}

fn position(lat: f64, lon: f64) -> [f64; 2] {
    [round6(lon), round6(lat)]
}

fn feature(geometry: GeometryValue, properties: JsonObject) -> Feature {
    Feature {
        geometry: Some(Geometry::new(geometry)),
        properties: Some(properties),
        ..Feature::default()
    }
}

fn properties(pairs: Vec<(&str, JsonValue)>) -> JsonObject {
    pairs
        .into_iter()
        .map(|(key, value)| (key.to_string(), value))
        .collect()
}

fn number(value: f64) -> JsonValue {
    serde_json::Number::from_f64(value).map_or(JsonValue::Null, JsonValue::Number)
}

/// The forecast as a GeoJSON FeatureCollection: the track (LineString), the
/// start, each predicted surfacing and the waypoint (Points), and with an
/// ensemble the region of each hour and of each surfacing (Polygons; a
/// region of fewer than three distinct positions is a Point or LineString).
/// Every feature's `kind` property says which.
pub fn to_geojson(forecast: &Forecast) -> String {
    let mut features = Vec::new();
    let track = &forecast.track;
    let line: Vec<[f64; 2]> = track
        .points
        .iter()
        .map(|point| position(point.lat, point.lon))
        .collect();
    if line.len() >= 2 {
        features.push(feature(
            GeometryValue::new_line_string(line),
            properties(vec![
                ("kind", "track".into()),
                ("mission", forecast.mission_name.clone().into()),
                ("start", iso_time(forecast.start.time).into()),
                (
                    "end",
                    iso_time(track.points.last().map_or(0.0, |p| p.time)).into(),
                ),
                ("current", forecast.current.clone().into()),
            ]),
        ));
    }
    let (lat, lon) = crate::fly::degrees(forecast.start.lat, forecast.start.lon);
    let mut start = vec![
        ("kind", "start".into()),
        ("time", iso_time(forecast.start.time).into()),
        ("lat_nmea", nmea_text(lat).into()),
        ("lon_nmea", nmea_text(lon).into()),
    ];
    if let Some(battery) = &forecast.battery {
        // The charge left and the mission's low-battery abort (crate::battery).
        start.push(("battery_used_ah", number(battery.used_at_start)));
        start.push(("battery_capacity_ah", number(battery.capacity)));
        start.push(("battery_limit_ah", number(battery.limit)));
        if let Some(time) = battery.reached_at {
            start.push(("battery_limit_reached", iso_time(time).into()));
        }
    }
    features.push(feature(
        GeometryValue::new_point(position(lat, lon)),
        properties(start),
    ));
    for (number_of, surfacing) in track.surfacings.iter().enumerate() {
        let mut pairs = vec![
            ("kind", "surfacing".into()),
            ("number", (number_of + 1).into()),
            ("time", iso_time(surfacing.time).into()),
            ("lat_nmea", nmea_text(surfacing.lat).into()),
            ("lon_nmea", nmea_text(surfacing.lon).into()),
            ("underwater_s", number(surfacing.underwater.round())),
        ];
        if let Some(distance) = surfacing.distance_to_waypoint {
            pairs.push(("distance_to_waypoint_m", number(distance.round())));
        }
        features.push(feature(
            GeometryValue::new_point(position(surfacing.lat, surfacing.lon)),
            properties(pairs),
        ));
    }
    if let Some((lat, lon)) = track.surfacings.iter().find_map(|s| s.waypoint).or(forecast
        .start
        .waypoint
        .map(|(lat, lon)| crate::fly::degrees(lat, lon)))
    {
        features.push(feature(
            GeometryValue::new_point(position(lat, lon)),
            properties(vec![
                ("kind", "waypoint".into()),
                ("lat_nmea", nmea_text(lat).into()),
                ("lon_nmea", nmea_text(lon).into()),
            ]),
        ));
    }
    if let Some(ensemble) = &forecast.ensemble {
        ensemble_features(ensemble, &mut features);
    }
    let collection = FeatureCollection::new(features);
    let mut text = collection.to_string();
    text.push('\n');
    text
}

fn region_geometry(hull: &[(f64, f64)]) -> GeometryValue {
    match hull.len() {
        0 | 1 => {
            let (lat, lon) = hull.first().copied().unwrap_or((0.0, 0.0));
            GeometryValue::new_point(position(lat, lon))
        }
        2 => GeometryValue::new_line_string(hull.iter().map(|&(lat, lon)| position(lat, lon))),
        _ => {
            // Counter-clockwise (RFC 7946's right-hand rule), closed.
            let mut ring: Vec<[f64; 2]> =
                hull.iter().map(|&(lat, lon)| position(lat, lon)).collect();
            ring.push(ring[0]);
            GeometryValue::new_polygon([ring])
        }
    }
}

fn ensemble_features(ensemble: &Ensemble, features: &mut Vec<Feature>) {
    for region in &ensemble.regions {
        features.push(feature(
            region_geometry(&region.hull),
            properties(vec![
                ("kind", "region".into()),
                ("hour", region.hour.into()),
                ("time", iso_time(region.time).into()),
                ("members", region.members.into()),
            ]),
        ));
    }
    for spread in &ensemble.surfacings {
        features.push(feature(
            region_geometry(&spread.hull),
            properties(vec![
                ("kind", "surfacing_region".into()),
                ("number", spread.number.into()),
                ("members", spread.members.into()),
                ("earliest", iso_time(spread.earliest).into()),
                ("latest", iso_time(spread.latest).into()),
                ("mean_time", iso_time(spread.mean_time).into()),
                ("radius_95_m", number(spread.radius_95.round())),
                ("radius_max_m", number(spread.radius_max.round())),
            ]),
        ));
    }
}

/// KML colours are `aabbggrr`.
const TRACK_COLOUR: &str = "ff0000ff";
const REGION_LINE: &str = "ffff8800";
const REGION_FILL: &str = "40ff8800";

type XmlWriter = Writer<Vec<u8>>;

fn text_element(writer: &mut XmlWriter, name: &str, text: &str) -> std::io::Result<()> {
    writer
        .create_element(name)
        .write_text_content(BytesText::new(text))?;
    Ok(())
}

fn kml_coordinates(points: impl Iterator<Item = (f64, f64)>) -> String {
    let mut text = String::new();
    for (lat, lon) in points {
        if !text.is_empty() {
            text.push(' ');
        }
        text.push_str(&format!("{:.6},{:.6},0", lon, lat));
    }
    text
}

fn placemark(
    writer: &mut XmlWriter,
    name: &str,
    description: &str,
    when: Option<(f64, Option<f64>)>,
    style: &str,
    geometry: impl FnOnce(&mut XmlWriter) -> std::io::Result<()>,
) -> std::io::Result<()> {
    writer
        .create_element("Placemark")
        .write_inner_content(|w| {
            text_element(w, "name", name)?;
            if !description.is_empty() {
                text_element(w, "description", description)?;
            }
            match when {
                Some((at, None)) => {
                    w.create_element("TimeStamp")
                        .write_inner_content(|w| text_element(w, "when", &iso_time(at)))?;
                }
                Some((begin, Some(end))) => {
                    w.create_element("TimeSpan").write_inner_content(|w| {
                        text_element(w, "begin", &iso_time(begin))?;
                        text_element(w, "end", &iso_time(end))
                    })?;
                }
                None => {}
            }
            text_element(w, "styleUrl", style)?;
            geometry(w)
        })?;
    Ok(())
}

fn kml_point(writer: &mut XmlWriter, lat: f64, lon: f64) -> std::io::Result<()> {
    writer.create_element("Point").write_inner_content(|w| {
        text_element(
            w,
            "coordinates",
            &kml_coordinates(std::iter::once((lat, lon))),
        )
    })?;
    Ok(())
}

fn kml_region(writer: &mut XmlWriter, hull: &[(f64, f64)]) -> std::io::Result<()> {
    match hull.len() {
        0 | 1 => {
            let (lat, lon) = hull.first().copied().unwrap_or((0.0, 0.0));
            kml_point(writer, lat, lon)
        }
        2 => {
            writer
                .create_element("LineString")
                .write_inner_content(|w| {
                    text_element(w, "coordinates", &kml_coordinates(hull.iter().copied()))
                })?;
            Ok(())
        }
        _ => {
            let ring = hull.iter().chain(hull.first()).copied();
            writer.create_element("Polygon").write_inner_content(|w| {
                w.create_element("outerBoundaryIs")
                    .write_inner_content(|w| {
                        w.create_element("LinearRing").write_inner_content(|w| {
                            text_element(w, "coordinates", &kml_coordinates(ring))
                        })?;
                        Ok(())
                    })?;
                Ok(())
            })?;
            Ok(())
        }
    }
}

/// A KML sub-style's (tag, value) children.
type KmlValues = &'static [(&'static str, &'static str)];

/// The document's styles: each `Style` id and its sub-styles (`LineStyle`, …).
const KML_STYLES: &[(&str, &[(&str, KmlValues)])] = &[
    (
        "track",
        &[("LineStyle", &[("color", TRACK_COLOUR), ("width", "2")])],
    ),
    (
        "surfacing",
        &[("IconStyle", &[("color", TRACK_COLOUR), ("scale", "0.8")])],
    ),
    (
        "region",
        &[
            ("LineStyle", &[("color", REGION_LINE), ("width", "1")]),
            ("PolyStyle", &[("color", REGION_FILL)]),
        ],
    ),
];

fn kml_styles(w: &mut XmlWriter) -> std::io::Result<()> {
    for &(id, styles) in KML_STYLES {
        w.create_element("Style")
            .with_attribute(("id", id))
            .write_inner_content(|w| {
                for &(style, children) in styles {
                    w.create_element(style).write_inner_content(|w| {
                        for &(tag, value) in children {
                            text_element(w, tag, value)?;
                        }
                        Ok(())
                    })?;
                }
                Ok(())
            })?;
    }
    Ok(())
}

/// The forecast as KML 2.2: a Document with the styles, the track, a folder
/// of surfacings (each with its time) and, with an ensemble, a folder of the
/// hourly regions (each with its time span) and one of the surfacing regions.
pub fn to_kml(forecast: &Forecast) -> Result<Vec<u8>, String> {
    write_kml(forecast).map_err(|error| format!("cannot write the KML: {error}"))
}

fn write_kml(forecast: &Forecast) -> std::io::Result<Vec<u8>> {
    let mut writer = Writer::new_with_indent(Vec::new(), b' ', 1);
    writer.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let track = &forecast.track;
    writer
        .create_element("kml")
        .with_attribute(("xmlns", "http://www.opengis.net/kml/2.2"))
        .write_inner_content(|w| {
            w.create_element("Document").write_inner_content(|w| {
                text_element(
                    w,
                    "name",
                    &format!(
                        "gloc forecast: {} from {}",
                        forecast.mission_name,
                        iso_time(forecast.start.time)
                    ),
                )?;
                text_element(w, "description", &forecast.summary_line())?;
                kml_styles(w)?;
                let end = track.points.last().map_or(forecast.start.time, |p| p.time);
                if track.points.len() >= 2 {
                    placemark(
                        w,
                        "forecast track",
                        &format!("current: {}", forecast.current),
                        Some((forecast.start.time, Some(end))),
                        "#track",
                        |w| {
                            w.create_element("LineString").write_inner_content(|w| {
                                text_element(w, "tessellate", "1")?;
                                text_element(
                                    w,
                                    "coordinates",
                                    &kml_coordinates(track.points.iter().map(|p| (p.lat, p.lon))),
                                )
                            })?;
                            Ok(())
                        },
                    )?;
                }
                let (lat, lon) = crate::fly::degrees(forecast.start.lat, forecast.start.lon);
                placemark(
                    w,
                    "start (last fix)",
                    &format!("{} {}", nmea_text(lat), nmea_text(lon)),
                    Some((forecast.start.time, None)),
                    "#surfacing",
                    |w| kml_point(w, lat, lon),
                )?;
                w.create_element("Folder").write_inner_content(|w| {
                    text_element(w, "name", "predicted surfacings")?;
                    for (index, s) in track.surfacings.iter().enumerate() {
                        let distance = s
                            .distance_to_waypoint
                            .map_or(String::new(), |d| format!(", {d:.0} m to the waypoint"));
                        placemark(
                            w,
                            &format!("surfacing {}", index + 1),
                            &format!(
                                "{} {} at {}{distance}",
                                nmea_text(s.lat),
                                nmea_text(s.lon),
                                iso_time(s.time)
                            ),
                            Some((s.time, None)),
                            "#surfacing",
                            |w| kml_point(w, s.lat, s.lon),
                        )?;
                    }
                    Ok(())
                })?;
                if let Some(ensemble) = &forecast.ensemble {
                    kml_ensemble(w, ensemble)?;
                }
                Ok(())
            })?;
            Ok(())
        })?;
    let mut bytes = writer.into_inner();
    bytes.push(b'\n');
    Ok(bytes)
}

fn kml_ensemble(w: &mut XmlWriter, ensemble: &Ensemble) -> std::io::Result<()> {
    w.create_element("Folder").write_inner_content(|w| {
        text_element(
            w,
            "name",
            &format!(
                "where the glider can be, per hour ({} members)",
                ensemble.members
            ),
        )?;
        for region in &ensemble.regions {
            placemark(
                w,
                &format!("hour {}", region.hour),
                &format!("{} members at {}", region.members, iso_time(region.time)),
                Some((region.time, Some(region.time + 3600.0))),
                "#region",
                |w| kml_region(w, &region.hull),
            )?;
        }
        Ok(())
    })?;
    w.create_element("Folder").write_inner_content(|w| {
        text_element(w, "name", "surfacing spread")?;
        for spread in &ensemble.surfacings {
            placemark(
                w,
                &format!("surfacing {}", spread.number),
                &format!(
                    "{} members, {} to {}, 95% within {:.0} m of the mean",
                    spread.members,
                    iso_time(spread.earliest),
                    iso_time(spread.latest),
                    spread.radius_95
                ),
                Some((spread.earliest, Some(spread.latest))),
                "#region",
                |w| kml_region(w, &spread.hull),
            )?;
        }
        Ok(())
    })?;
    Ok(())
}

/// The track as CSV: `time,unix_time,lat,lon,lat_nmea,lon_nmea,depth_m`, one
/// row per point; then `# surfacing` comment rows are not used, so any CSV
/// reader takes it (surfacings are printed by the command and are in the
/// GeoJSON and KML).
pub fn to_csv(forecast: &Forecast) -> String {
    let mut text = String::from("time,unix_time,lat,lon,lat_nmea,lon_nmea,depth_m\n");
    for point in &forecast.track.points {
        text.push_str(&format!(
            "{},{:.1},{:.6},{:.6},{},{},{:.2}\n",
            iso_time(point.time),
            point.time,
            point.lat,
            point.lon,
            nmea_text(point.lat),
            nmea_text(point.lon),
            point.depth
        ));
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iso_times_are_whole_seconds() {
        // `date -u -d @1566395646`: Wed Aug 21 13:54:06 UTC 2019.
        assert_eq!(iso_time(1_566_395_646.4), "2019-08-21T13:54:06Z");
        assert_eq!(iso_time(1_566_395_645.5), "2019-08-21T13:54:06Z");
        // Past the year 9999: the number.
        assert_eq!(iso_time(3e11), "300000000000");
    }

    #[test]
    fn formats_by_extension() {
        assert_eq!(
            Format::from_path(Path::new("a.GeoJSON")),
            Ok(Format::GeoJson)
        );
        assert_eq!(Format::from_path(Path::new("a.kml")), Ok(Format::Kml));
        assert_eq!(Format::from_path(Path::new("a.csv")), Ok(Format::Csv));
        assert!(Format::from_path(Path::new("a.txt")).is_err());
    }
}
