//! The debugger follows the journey (issue 25, item 5): the Navigation scope, stops at a
//! waypoint reached and at a surfacing (the `waypoint` and `surfacing` exception
//! filters), data breakpoints on the navigation sensors. The mission is
//! `examples/goto.mi` (a goto_list through four waypoints, a surface behavior every
//! three hours, a current the glider does not know of at the start).
//!
//! Expected values come from other routes than the debugger: a reference run of the
//! simulator alone (`gloc_sim::Simulation`, phase by phase, the sensors read at each
//! cycle boundary, which is what the CSV log of the same seed holds), the mission file's
//! own numbers (the waypoints in NMEA, `list_when_wpt_dist`, the current), and distances
//! worked with the haversine formula from the NMEA positions, by hand.

mod support;

use std::sync::Arc;

use gloc_compiler::{load_script, Language, LoadOptions};
use gloc_engine::sensors::SensorList;
use gloc_sim::{Mission, SimConfig, Simulation};
use serde_json::{json, Value};
use support::{cycle, stopped, value, Client};

/// The Navigation scope's `variablesReference`.
const NAVIGATION: i64 = 6;

fn fixture(name: &str) -> String {
    format!("{}/tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn goto_mission() -> String {
    format!("{}/../examples/goto.mi", env!("CARGO_MANIFEST_DIR"))
}

/// The mission's first waypoint (`wpt_y_0`, `wpt_x_0`: NMEA latitude, longitude) and
/// `list_when_wpt_dist`, as examples/goto.mi writes them.
const WAYPOINT_0: (f64, f64) = (5419.5, 726.0);
const WHEN_WPT_DIST: f64 = 200.0;

/// The navigation sensors at one cycle boundary of the reference run.
#[derive(Clone, Copy, Debug)]
struct Boundary {
    cycle: u64,
    lat: f64,
    lon: f64,
    heading: f64,
    dist_to_wpt: f64,
    dr_state: f64,
    hit_waypoint: f64,
    present_time: f64,
}

/// The simulator alone, no debugger: the sensors after each `begin_cycle`.
fn reference(cycles: usize) -> Vec<Boundary> {
    let sensors = SensorList::embedded();
    let text = std::fs::read_to_string(fixture("journey.gbas")).expect("fixture");
    let loaded = load_script(&text, Language::Gbasic, &sensors, &LoadOptions::default());
    let mission = Mission::load(std::path::Path::new(&goto_mission()));
    let index = |name: &str| sensors.lookup(name).expect(name).index();
    let slots = [
        "m_lat",
        "m_lon",
        "m_heading",
        "m_dist_to_wpt",
        "x_dr_state",
        "x_hit_a_waypoint",
    ]
    .map(index);
    let mut sim = Simulation::new(
        &mission,
        Arc::new(sensors.clone()),
        loaded.program,
        &SimConfig::default(),
    )
    .expect("reference simulation");
    let mut boundaries = Vec::new();
    while boundaries.len() < cycles && sim.begin_cycle() {
        let read = |slot: usize| sim.sensors()[slots[slot]];
        boundaries.push(Boundary {
            cycle: sim.cycle(),
            lat: read(0),
            lon: read(1),
            heading: read(2),
            dist_to_wpt: read(3),
            dr_state: read(4),
            hit_waypoint: read(5),
            present_time: sim.present_time(),
        });
        sim.run_script();
        sim.finish_cycle();
    }
    boundaries
}

/// NMEA `ddmm.mmm` to degrees, by hand: the degrees are the hundreds, the rest minutes.
fn degrees(nmea: f64) -> f64 {
    let whole = (nmea.abs() / 100.0).floor();
    (whole + (nmea.abs() - whole * 100.0) / 60.0).copysign(nmea)
}

/// The great-circle distance (m) between two NMEA positions on a sphere of the mean
/// earth radius: the haversine formula.
fn haversine(from: (f64, f64), to: (f64, f64)) -> f64 {
    const RADIUS: f64 = 6_371_008.8;
    let (lat1, lon1) = (degrees(from.0).to_radians(), degrees(from.1).to_radians());
    let (lat2, lon2) = (degrees(to.0).to_radians(), degrees(to.1).to_radians());
    let a = ((lat2 - lat1) / 2.0).sin().powi(2)
        + lat1.cos() * lat2.cos() * ((lon2 - lon1) / 2.0).sin().powi(2);
    2.0 * RADIUS * a.sqrt().asin()
}

fn start(extra: Value) -> Client {
    let mut client = Client::start();
    client.ok(
        "initialize",
        json!({ "adapterID": "gloc", "linesStartAt1": true }),
    );
    let mut arguments = json!({
        "program": fixture("journey.gbas"),
        "mission": goto_mission(),
        "history": false,
    });
    if let (Some(arguments), Some(extra)) = (arguments.as_object_mut(), extra.as_object()) {
        arguments.extend(extra.clone());
    }
    client.ok("launch", arguments);
    client.event("initialized");
    client
}

fn number(client: &mut Client, name: &str) -> f64 {
    let shown = value(client, NAVIGATION, name);
    shown
        .parse()
        .unwrap_or_else(|_| panic!("{name} = {shown} is not a number"))
}

#[test]
fn the_navigation_scope_shows_the_belief_in_the_gliders_sensors_and_the_truth() {
    let boundaries = reference(101);
    let at = boundaries[100];
    let before = boundaries[99];
    let mut client = start(json!({}));
    client.ok(
        "setFunctionBreakpoints",
        json!({ "breakpoints": [{ "name": "cycle 100" }] }),
    );
    client.ok("configurationDone", json!({}));
    assert_eq!(stopped(&mut client)["reason"], "function breakpoint");
    assert_eq!(cycle(&mut client), 100);
    assert_eq!(at.cycle, 100);
    let scopes = client.ok("scopes", json!({ "frameId": 1 }));
    let navigation = scopes["scopes"]
        .as_array()
        .expect("scopes")
        .iter()
        .find(|scope| scope["name"] == "Navigation")
        .expect("a Navigation scope")
        .clone();
    assert_eq!(navigation["variablesReference"], NAVIGATION);
    // The glider's own sensors, exactly as the reference run published them.
    assert_eq!(number(&mut client, "m_lat"), at.lat);
    assert_eq!(number(&mut client, "m_lon"), at.lon);
    assert_eq!(number(&mut client, "m_heading"), at.heading);
    assert_eq!(number(&mut client, "m_dist_to_wpt"), at.dist_to_wpt);
    assert_eq!(number(&mut client, "x_dr_state"), at.dr_state);
    // Decimal degrees worked by hand from the NMEA value; the heading in degrees.
    let lat_degrees = number(&mut client, "m_lat (°)");
    assert!(
        (lat_degrees - degrees(at.lat)).abs() < 1e-12,
        "{lat_degrees}"
    );
    assert!(
        (lat_degrees - 54.3).abs() < 0.05,
        "near 54°18' N: {lat_degrees}"
    );
    let heading_degrees = number(&mut client, "m_heading (°)");
    assert!((heading_degrees - at.heading * 180.0 / std::f64::consts::PI).abs() < 1e-9);
    // m_dist_to_wpt at a boundary is what the goto behavior measured in the cycle
    // before, from the dead-reckoned position published at that cycle's boundary:
    // the haversine distance from there to the mission's first waypoint.
    let by_hand = haversine((before.lat, before.lon), WAYPOINT_0);
    assert!(
        (at.dist_to_wpt - by_hand).abs() < 0.005 * by_hand,
        "m_dist_to_wpt {} against {by_hand} by hand",
        at.dist_to_wpt
    );
    assert_eq!(value(&mut client, NAVIGATION, "waypoint index"), "0 of 4");
    assert_eq!(number(&mut client, "c_wpt_lat"), WAYPOINT_0.0);
    assert_eq!(number(&mut client, "c_wpt_lon"), WAYPOINT_0.1);
    // The mission's current: s_water_speed 0.15 m/s toward s_water_direction 1.2 rad
    // = 68.75°; the glider starts believing in none (m_water_vx/vy 0).
    assert_eq!(
        value(&mut client, NAVIGATION, "true current"),
        "0.150 m/s toward 68.8°"
    );
    assert_eq!(
        value(&mut client, NAVIGATION, "current estimate"),
        "0.000 m/s toward 0.0°"
    );
    // Believing in no current, the glider's dead reckoning misses the drift since it
    // dived (at the surface before, its GPS knew where it was): 0.15 m/s for the time
    // from the first boundary underwater (x_dr_state 1) to this one.
    let dived = boundaries
        .iter()
        .find(|boundary| boundary.dr_state == 1.0)
        .expect("a dive");
    // Plus what the firmware's dead reckoning (|depth rate| / tan(|pitch| + the
    // steady α)) misses of the glider's way through the water while it is not in
    // a steady glide, at the dive's start and its turn, where the pumped volume acts
    // 4.75 s late (`ballast_delay`): about half a metre here; held to 2%.
    let elapsed = at.present_time - dived.present_time;
    let error = number(&mut client, "dead-reckoning error (m)");
    assert!(
        (error - 0.15 * elapsed).abs() < 0.02 * 0.15 * elapsed,
        "error {error} m after {elapsed} s"
    );
    // Every row named by a sensor evaluates to the value shown.
    let body = client.ok("variables", json!({ "variablesReference": NAVIGATION }));
    for variable in body["variables"].as_array().expect("variables") {
        let Some(name) = variable["evaluateName"].as_str() else {
            continue;
        };
        let evaluated = client.ok("evaluate", json!({ "expression": name, "frameId": 1 }));
        assert_eq!(evaluated["result"], variable["value"], "{name}");
    }
    // The truth is read-only; a sensor row sets its sensor.
    let refused = client.request(
        "setVariable",
        Some(json!({ "variablesReference": NAVIGATION, "name": "true lat", "value": "1" })),
    );
    assert_eq!(refused["success"], false);
}

#[test]
fn a_run_stops_at_a_surfacing_and_at_a_waypoint_reached_when_the_filters_are_on() {
    // The first waypoint comes at cycle 4,495 of the reference run (its own count,
    // found below); the window only needs to hold it.
    let boundaries = reference(5000);
    // From the reference run: the first boundary where x_dr_state reads 2 (surfaced),
    // and the first where x_hit_a_waypoint reads 1 (it shows the cycle before's hit).
    let surfaced = boundaries
        .iter()
        .find(|boundary| boundary.dr_state == 2.0)
        .expect("a surfacing")
        .cycle;
    let hit = boundaries
        .iter()
        .find(|boundary| boundary.hit_waypoint == 1.0)
        .expect("a waypoint reached")
        .cycle;
    let mut client = start(json!({}));
    let body = client.ok(
        "setExceptionBreakpoints",
        json!({ "filters": ["waypoint", "surfacing"] }),
    );
    assert_eq!(body["breakpoints"].as_array().map(Vec::len), Some(2));
    client.ok("configurationDone", json!({}));

    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "surfacing", "{stop}");
    assert_eq!(cycle(&mut client), surfaced);
    let description = stop["description"].as_str().expect("description");
    assert!(
        description.contains(&format!("surfaced in cycle {}", surfaced - 1)),
        "{description}"
    );
    assert_eq!(number(&mut client, "x_dr_state"), 2.0);

    client.ok("continue", json!({ "threadId": 1 }));
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "waypoint", "{stop}");
    assert_eq!(cycle(&mut client), hit);
    let text = stop["text"].as_str().expect("text");
    assert!(
        text.starts_with(&format!(
            "waypoint 0 (of 4) reached in cycle {} at 5419.5 726.0: ",
            hit - 1
        )),
        "{text}"
    );
    // The hit was judged on the dead-reckoned position of the cycle it happened in
    // (published at that cycle's boundary): within list_when_wpt_dist, the haversine
    // distance from there to the mission's waypoint.
    let reached_in = &boundaries[(hit - 1) as usize];
    let by_hand = haversine((reached_in.lat, reached_in.lon), WAYPOINT_0);
    let shown: f64 = text
        .split(": ")
        .nth(1)
        .and_then(|rest| rest.split(" m from it").next())
        .and_then(|number| number.parse().ok())
        .expect("the distance by dead reckoning");
    assert!(by_hand < WHEN_WPT_DIST, "{by_hand}");
    assert!(
        (shown - by_hand).abs() < 0.005 * WHEN_WPT_DIST,
        "{shown} against {by_hand}"
    );
    // The cycle before, the goto behavior measured no less (it is published at the
    // boundary of the cycle the hit came in).
    assert!(reached_in.dist_to_wpt >= WHEN_WPT_DIST, "{reached_in:?}");
    // Now steering to the next waypoint.
    assert_eq!(value(&mut client, NAVIGATION, "waypoint index"), "1 of 4");
}

#[test]
fn the_journey_filters_are_off_by_default() {
    let mut client = Client::start();
    let capabilities = client.ok("initialize", json!({ "adapterID": "gloc" }));
    let filters = capabilities["exceptionBreakpointFilters"]
        .as_array()
        .expect("filters");
    let defaults: Vec<(&str, bool)> = filters
        .iter()
        .map(|filter| {
            (
                filter["filter"].as_str().unwrap_or_default(),
                filter["default"].as_bool().unwrap_or(false),
            )
        })
        .collect();
    assert_eq!(
        defaults,
        [
            ("trap", true),
            ("overrun", true),
            ("abend", true),
            ("waypoint", false),
            ("surfacing", false)
        ]
    );
}

#[test]
fn data_breakpoints_watch_the_navigation_sensors() {
    let boundaries = reference(3000);
    let surfaced = boundaries
        .iter()
        .find(|boundary| boundary.dr_state == 2.0)
        .expect("a surfacing")
        .cycle;
    // The first boundary where m_dist_to_wpt changed to under 3,000 m.
    let closer = boundaries
        .windows(2)
        .find(|pair| pair[1].dist_to_wpt != pair[0].dist_to_wpt && pair[1].dist_to_wpt < 3000.0)
        .expect("closer than 3 km")[1];
    let mut client = start(json!({}));
    let mut data_id = |name: &str| {
        let info = client.ok(
            "dataBreakpointInfo",
            json!({ "variablesReference": NAVIGATION, "name": name }),
        );
        info["dataId"].as_str().expect("watchable").to_string()
    };
    let distance = data_id("m_dist_to_wpt");
    let state = data_id("x_dr_state");
    assert_eq!(state, "sensor:x_dr_state");
    let not_a_sensor = client.ok(
        "dataBreakpointInfo",
        json!({ "variablesReference": NAVIGATION, "name": "true lat" }),
    );
    assert_eq!(not_a_sensor["dataId"], Value::Null);
    // A condition that is no GBASIC expression (`==` is not GBASIC's equality) is
    // refused with the reason, not left to stop at every change.
    let refused = client.ok(
        "setDataBreakpoints",
        json!({ "breakpoints": [{ "dataId": state, "condition": "x_dr_state == 2" }] }),
    );
    assert_eq!(refused["breakpoints"][0]["verified"], false);
    let message = refused["breakpoints"][0]["message"]
        .as_str()
        .unwrap_or_default();
    assert!(
        message.starts_with("the condition `x_dr_state == 2` is not valid"),
        "{message}"
    );
    let body = client.ok(
        "setDataBreakpoints",
        json!({ "breakpoints": [
            { "dataId": distance, "condition": "m_dist_to_wpt < 3000" },
            { "dataId": state, "condition": "x_dr_state = 2" },
        ] }),
    );
    assert_eq!(body["breakpoints"][0]["verified"], true);
    assert_eq!(body["breakpoints"][1]["verified"], true);
    client.ok("configurationDone", json!({}));
    let mut stops = Vec::new();
    for _ in 0..2 {
        let stop = stopped(&mut client);
        assert_eq!(stop["reason"], "data breakpoint", "{stop}");
        stops.push((
            cycle(&mut client),
            stop["text"].as_str().unwrap_or_default().to_string(),
        ));
        client.ok(
            "setDataBreakpoints",
            json!({ "breakpoints": [{ "dataId": state, "condition": "x_dr_state = 2" }] }),
        );
        client.ok("continue", json!({ "threadId": 1 }));
    }
    // The distance stop comes first (then only the state is watched: the distance
    // changes in nearly every cycle).
    assert!(closer.cycle < surfaced, "{closer:?}, {surfaced}");
    assert_eq!(stops[0].0, closer.cycle, "{stops:?}");
    assert!(stops[0].1.starts_with("m_dist_to_wpt: "), "{stops:?}");
    assert_eq!(stops[1].0, surfaced, "{stops:?}");
    assert_eq!(stops[1].1, "x_dr_state: 1.0 → 2.0");
}
