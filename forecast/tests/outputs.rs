//! The outputs' structure checked by readers that did not write them: the
//! GeoJSON against RFC 7946's rules read with serde_json (a FeatureCollection
//! of Features, positions longitude first and in range, polygon rings closed,
//! at least four positions, counter-clockwise), the KML with quick-xml's
//! reader against the KML 2.2 schema's required structure; and the ensemble
//! giving the same members on one thread and on two.

use std::path::PathBuf;
use std::sync::Arc;

use gloc_engine::sensors::SensorList;
use gloc_forecast::ensemble::{run_ensemble, EnsembleInput, EnsembleOptions};
use gloc_forecast::fly::{prepare_mission, Flight, Start, Truth};
use gloc_forecast::logs::{read_history, LogHistory};
use gloc_forecast::{export, forecast, Request};
use gloc_sim::navigation::Xy;
use gloc_sim::{Mission, SimConfig};
use serde_json::Value;

fn history() -> LogHistory {
    let files: Vec<PathBuf> = [
        "comet/from-glider/comet-2019-222-02-152.sbd",
        "comet/from-glider/comet-2019-222-02-153.sbd",
        "comet/from-glider/comet-2019-222-02-154.dbd",
    ]
    .iter()
    .map(|file| gloc_testsupport::data(file))
    .collect();
    let cache = gloc_testsupport::data("cac");
    let mut source =
        gloc_dbd::Deployment::open(&files, Some(&cache)).unwrap_or_else(|e| panic!("{e}"));
    read_history(&mut source).unwrap_or_else(|e| panic!("{e}"))
}

fn mission() -> Mission {
    Mission::load(&gloc_testsupport::data("comet/missions/nsb3.mi"))
}

fn comet_forecast(members: usize, hours: f64) -> gloc_forecast::Forecast {
    let request = Request {
        hours,
        currents: None,
        bathymetry: None,
        ensemble: Some(EnsembleOptions {
            members,
            seed: 3,
            spread: Xy::new(0.05, 0.05),
            threads: 2,
        }),
    };
    forecast(
        &history(),
        &mission(),
        &Arc::new(SensorList::embedded()),
        &SimConfig::default(),
        &request,
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

fn check_position(position: &Value) {
    let pair = position.as_array().expect("a position is an array");
    assert!(pair.len() >= 2, "{position}");
    let (lon, lat) = (
        pair[0].as_f64().expect("lon"),
        pair[1].as_f64().expect("lat"),
    );
    assert!((-180.0..=180.0).contains(&lon) && (-90.0..=90.0).contains(&lat));
    // comet's waters: 54° N, 7° E (longitude first).
    assert!(
        (53.0..56.0).contains(&lat) && (6.0..9.0).contains(&lon),
        "{position}"
    );
}

fn check_geometry(geometry: &Value) -> String {
    let kind = geometry["type"]
        .as_str()
        .expect("a geometry type")
        .to_string();
    let coordinates = &geometry["coordinates"];
    match kind.as_str() {
        "Point" => check_position(coordinates),
        "LineString" => {
            let line = coordinates.as_array().expect("positions");
            assert!(line.len() >= 2);
            line.iter().for_each(check_position);
        }
        "Polygon" => {
            for ring in coordinates.as_array().expect("rings") {
                let ring = ring.as_array().expect("a ring");
                assert!(ring.len() >= 4, "a linear ring has at least four positions");
                assert_eq!(ring.first(), ring.last(), "a ring is closed");
                ring.iter().for_each(check_position);
                let area: f64 = ring
                    .windows(2)
                    .map(|pair| {
                        let (a, b) = (&pair[0], &pair[1]);
                        a[0].as_f64().unwrap_or(0.0) * b[1].as_f64().unwrap_or(0.0)
                            - b[0].as_f64().unwrap_or(0.0) * a[1].as_f64().unwrap_or(0.0)
                    })
                    .sum();
                assert!(
                    area > 0.0,
                    "exterior rings are counter-clockwise (RFC 7946 §3.1.6)"
                );
            }
        }
        other => panic!("unexpected geometry {other}"),
    }
    kind
}

#[test]
fn the_geojson_follows_rfc_7946() {
    let forecast = comet_forecast(30, 6.0);
    let text = export::to_geojson(&forecast);
    let root: Value = serde_json::from_str(&text).expect("JSON");
    assert_eq!(root["type"], "FeatureCollection");
    let mut kinds = Vec::new();
    for feature in root["features"].as_array().expect("features") {
        assert_eq!(feature["type"], "Feature");
        assert!(feature["properties"].is_object());
        let geometry = check_geometry(&feature["geometry"]);
        kinds.push((
            feature["properties"]["kind"]
                .as_str()
                .unwrap_or("")
                .to_string(),
            geometry,
        ));
    }
    let count = |kind: &str, geometry: &str| {
        kinds
            .iter()
            .filter(|(k, g)| k == kind && g == geometry)
            .count()
    };
    assert_eq!(count("track", "LineString"), 1);
    assert_eq!(count("start", "Point"), 1);
    assert_eq!(count("surfacing", "Point"), 2, "{kinds:?}");
    // Six hours: a region per hour, each a polygon of 30 members.
    assert_eq!(count("region", "Polygon"), 6, "{kinds:?}");
    assert_eq!(count("surfacing_region", "Polygon"), 2, "{kinds:?}");
}

#[test]
fn the_kml_has_the_required_structure() {
    use quick_xml::events::Event;
    let forecast = comet_forecast(12, 4.0);
    let bytes = export::to_kml(&forecast).expect("KML");
    let mut reader = quick_xml::Reader::from_reader(bytes.as_slice());
    let mut stack: Vec<String> = Vec::new();
    let mut seen: Vec<String> = Vec::new();
    let mut buffer = Vec::new();
    let mut coordinates = 0;
    loop {
        match reader
            .read_event_into(&mut buffer)
            .expect("well-formed XML")
        {
            Event::Start(start) => {
                let name = start.name().as_ref().to_string();
                if stack.is_empty() {
                    assert_eq!(name, "kml", "the root is kml");
                    let namespace = start
                        .attributes()
                        .filter_map(Result::ok)
                        .find(|a| a.key.as_ref() == "xmlns")
                        .map(|a| a.value.to_string());
                    assert_eq!(namespace.as_deref(), Some("http://www.opengis.net/kml/2.2"));
                }
                stack.push(name.clone());
                seen.push(stack.join("/"));
            }
            Event::End(_) => {
                stack.pop();
            }
            Event::Text(text) if stack.last().map(String::as_str) == Some("coordinates") => {
                let content = AsRef::<str>::as_ref(&text).to_string();
                for tuple in content.split_whitespace() {
                    let values: Vec<f64> = tuple
                        .split(',')
                        .map(|v| v.parse().expect("a number"))
                        .collect();
                    assert_eq!(values.len(), 3, "lon,lat,alt: {tuple}");
                    assert!((6.0..9.0).contains(&values[0]) && (53.0..56.0).contains(&values[1]));
                }
                coordinates += 1;
            }
            Event::Eof => break,
            _ => {}
        }
        buffer.clear();
    }
    assert!(stack.is_empty(), "every element closed");
    let has = |path: &str| seen.iter().any(|s| s == path);
    assert!(has("kml/Document/name"));
    assert!(has("kml/Document/Placemark/LineString/coordinates"));
    assert!(has("kml/Document/Folder/Placemark/Point/coordinates"));
    assert!(has("kml/Document/Folder/Placemark/TimeStamp/when"));
    assert!(has(
        "kml/Document/Folder/Placemark/Polygon/outerBoundaryIs/LinearRing/coordinates"
    ));
    assert!(coordinates > 6);
}

#[test]
fn the_same_seed_gives_the_same_members_on_any_number_of_threads() {
    let history = history();
    let start = Start::from_history(&history).expect("a fix");
    let prepared = prepare_mission(&mission(), &start);
    let sensors = Arc::new(SensorList::embedded());
    let config = SimConfig::default();
    let truth = Truth::Uniform(start.believed);
    let input = EnsembleInput {
        flight: Flight {
            mission: &prepared,
            sensors: &sensors,
            config: &config,
            start: &start,
            truth: &truth,
            bathymetry: None,
        },
        hours: 2.0,
    };
    let options = |threads| EnsembleOptions {
        members: 9,
        seed: 11,
        spread: Xy::new(0.1, 0.1),
        threads,
    };
    let one = run_ensemble(&input, &options(1)).expect("flies");
    let three = run_ensemble(&input, &options(3)).expect("flies");
    assert_eq!(one, three);
    assert_eq!(one.regions.len(), 2);
    // Another seed: other members.
    let other = run_ensemble(
        &input,
        &EnsembleOptions {
            seed: 12,
            ..options(2)
        },
    )
    .expect("flies");
    assert_ne!(one.offsets, other.offsets);
    // The hull after two hours spans about σ × 2 h × a few: 0.1 m/s × 7,200 s
    // = 720 m per σ; nine members spread over a kilometre or more.
    let lmc = start.lmc();
    let hull: Vec<Xy> = one.regions[1]
        .hull
        .iter()
        .map(|&(lat, lon)| lmc.to_xy(lat, lon))
        .collect();
    let width = hull
        .iter()
        .flat_map(|a| hull.iter().map(move |b| a.distance(*b)))
        .fold(0.0, f64::max);
    assert!((700.0..5000.0).contains(&width), "{width}");
}
