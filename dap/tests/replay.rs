//! Debugging a script over recorded data (`replay` launch attribute), every message
//! schema-checked. Real data: comet's `comet-2019-222-02-154.dbd` with its `.ebd`
//! (data/), sensor lists in data/cac. Expected values come from
//! dbdreader 0.6.3 (`skip_initial_line=False`, cycle = position of the value's time
//! among the 2,244 `m_present_time` values), run by hand:
//! - `m_depth` first exceeds 15 m in cycle 38 (15.43901252746582; 14.824023246765137
//!   in cycle 37), and first falls below 5 m after that in cycle 137 (4.7046637535095215).
//!
//! The paper's Fig. 3 stores `sci_ruhp_behs = 128` in the first cycle deeper than 15 m
//! and 0 in the next one shallower than 5 m; a data breakpoint stops at the boundary
//! after the change (cycles 39 and 138).

mod support;

use serde_json::{json, Value};
use support::{cycle, sensor, stopped, value, values, Client, SENSORS, VEHICLE};

/// The Navigation scope's `variablesReference`.
const NAVIGATION: i64 = 6;

fn fixture(name: &str) -> String {
    format!("{}/tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn shared(path: &str) -> String {
    gloc_testsupport::data_arg(path)
}

fn comet(extension: &str) -> String {
    shared(&format!(
        "comet/from-glider/comet-2019-222-02-154.{extension}"
    ))
}

fn start(arguments: Value) -> Client {
    let mut client = Client::start();
    client.ok(
        "initialize",
        json!({ "adapterID": "gloc", "linesStartAt1": true }),
    );
    client.ok("launch", arguments);
    client.event("capabilities");
    client.event("initialized");
    client
}

fn watch_behs(client: &mut Client) {
    let info = client.ok(
        "dataBreakpointInfo",
        json!({ "variablesReference": SENSORS, "name": "sci_ruhp_behs" }),
    );
    let data_id = info["dataId"].as_str().expect("watchable").to_string();
    let body = client.ok(
        "setDataBreakpoints",
        json!({ "breakpoints": [{ "dataId": data_id, "accessType": "write" }] }),
    );
    assert_eq!(body["breakpoints"][0]["verified"], true);
}

#[test]
fn a_real_deployment_stops_on_a_data_breakpoint_and_steps_back() {
    let mut client = start(json!({
        "program": fixture("fig3.gbas"),
        "replay": [comet("dbd"), comet("ebd")],
        "sensorCache": shared("cac"),
    }));
    watch_behs(&mut client);
    client.ok("configurationDone", json!({}));
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "data breakpoint");
    assert_eq!(cycle(&mut client), 39);
    assert_eq!(sensor(&mut client, "sci_ruhp_behs"), 128.0);
    // The recorded sensors are in the Sensors scope, flight and science alike.
    let scope: Vec<String> = values(&mut client, SENSORS)
        .into_iter()
        .map(|(name, _)| name)
        .collect();
    for name in ["m_depth", "m_present_time", "sci_water_temp", "m_pitch"] {
        assert!(
            scope.iter().any(|known| known == name),
            "{name} in {scope:?}"
        );
    }
    assert!(value(&mut client, VEHICLE, "replay of").contains("2244 cycles"));
    // The Navigation scope shows the recorded position: NMEA as comet logged it (off
    // Helgoland, 54° N 7° E), and in decimal degrees, converted here by hand.
    let navigation = values(&mut client, NAVIGATION);
    let shown = |name: &str| -> f64 {
        navigation
            .iter()
            .find(|(known, _)| known == name)
            .and_then(|(_, value)| value.parse().ok())
            .unwrap_or_else(|| panic!("{name} in {navigation:?}"))
    };
    let (lat, lon) = (shown("m_lat"), shown("m_lon"));
    assert!(
        (5400.0..5500.0).contains(&lat) && (700.0..800.0).contains(&lon),
        "{lat} {lon}"
    );
    let by_hand = 54.0 + (lat - 5400.0) / 60.0;
    assert!((shown("m_lat (°)") - by_hand).abs() < 1e-12);
    assert!(navigation
        .iter()
        .all(|(name, _)| !name.starts_with("true ")));
    // Back to the boundary of cycle 38: the recorded depth, and the store undone.
    client.ok("stepBack", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "step");
    assert_eq!(cycle(&mut client), 38);
    assert_eq!(sensor(&mut client, "m_depth"), 15.43901252746582);
    assert_eq!(sensor(&mut client, "sci_ruhp_behs"), 0.0);
    client.ok("stepBack", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(cycle(&mut client), 37);
    assert_eq!(sensor(&mut client, "m_depth"), 14.824023246765137);
    // Forward again: the same stop, then the next change (back to 0 below 5 m).
    client.ok("continue", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "data breakpoint");
    assert_eq!(cycle(&mut client), 39);
    client.ok("continue", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "data breakpoint");
    assert_eq!(cycle(&mut client), 138);
    assert_eq!(sensor(&mut client, "sci_ruhp_behs"), 0.0);
    client.ok("stepBack", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(sensor(&mut client, "m_depth"), 4.7046637535095215);
}

/// A depth ramp 0 → 20 → 0 m in 1 m steps, one row per cycle (as the CLI tests use).
fn ramp_csv(name: &str) -> String {
    let mut text = String::from("cycle,m_depth\n");
    for (cycle, depth) in (0..=20).chain((0..20).rev()).enumerate() {
        text.push_str(&format!("{cycle},{depth}\n"));
    }
    let path = std::env::temp_dir().join(format!("gloc-dap-replay-{}-{name}", std::process::id()));
    std::fs::write(&path, text).expect("write");
    path.display().to_string()
}

#[test]
fn a_csv_replay_honours_line_function_and_data_breakpoints() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "replay": ramp_csv("bp.csv") }));
    // Line 3 (`SCI_RUHP_BEHS = 128`) runs only in the first cycle deeper than 15 m:
    // row 16 (16 m), worked by hand from the ramp.
    let body = client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [{ "line": 3 }] }),
    );
    assert_eq!(body["breakpoints"][0]["verified"], true);
    client.ok(
        "setFunctionBreakpoints",
        json!({ "breakpoints": [{ "name": "cycle 30" }] }),
    );
    client.ok("configurationDone", json!({}));
    assert_eq!(stopped(&mut client)["reason"], "breakpoint");
    assert_eq!(cycle(&mut client), 16);
    assert_eq!(sensor(&mut client, "m_depth"), 16.0);
    client.ok("continue", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "function breakpoint");
    assert_eq!(cycle(&mut client), 30);
    // Row 30 is 40 - 30 = 10 m.
    assert_eq!(sensor(&mut client, "m_depth"), 10.0);
    // Reverse continue runs back to the line breakpoint's hit.
    client.ok("reverseContinue", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "breakpoint");
    assert_eq!(cycle(&mut client), 16);
}

#[test]
fn the_end_of_the_recording_ends_the_session_with_a_summary() {
    let mut client =
        start(json!({ "program": fixture("fig3.gbas"), "replay": ramp_csv("end.csv") }));
    client.ok("configurationDone", json!({}));
    client.event("terminated");
    let outputs: Vec<String> = client
        .received
        .iter()
        .filter(|message| message["event"] == "output")
        .map(|message| {
            message["body"]["output"]
                .as_str()
                .unwrap_or_default()
                .to_string()
        })
        .collect();
    assert!(
        outputs
            .iter()
            .any(|text| text.contains("end of the recording after 41 of 41 cycles")),
        "{outputs:?}"
    );
}

#[test]
fn replay_errors_say_what_is_wrong() {
    let mut client = Client::start();
    client.ok("initialize", json!({ "adapterID": "gloc" }));
    // No sensor list for the log beside it, and no cache given.
    let response = client.request(
        "launch",
        Some(json!({ "program": fixture("fig3.gbas"), "replay": comet("dbd") })),
    );
    assert_eq!(response["success"], false);
    let message = response["message"].as_str().unwrap_or_default();
    assert!(
        message.contains("sensor list 1f35be3b not found"),
        "{message}"
    );
    let response = client.request(
        "launch",
        Some(json!({ "program": fixture("fig3.gbas"), "replay": 7 })),
    );
    assert_eq!(response["success"], false);
    assert!(
        response["message"]
            .as_str()
            .unwrap_or_default()
            .contains("`replay` must be a path or a list of paths"),
        "{response}"
    );
}

#[test]
fn a_gloc_script_for_another_glider_is_refused_at_launch_with_each_index() {
    // Fig. 2 stated for comet's list (found through sensorCache), debugged with the
    // embedded list: 444 is `m_certainly_at_surface` there, `m_depth` here.
    let folder = gloc_testsupport::scratch_dir("dap-identity");
    std::fs::create_dir_all(&folder).expect("dir");
    let script = folder.join("fig2.gloc");
    let fig2 = std::fs::read_to_string(format!(
        "{}/../examples/fig2.gloc",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("fig2");
    std::fs::write(&script, format!("# sensors: 1f35be3b\n{fig2}")).expect("write");
    let mut client = Client::start();
    client.ok("initialize", json!({ "adapterID": "gloc" }));
    let response = client.request(
        "launch",
        Some(json!({ "program": script.display().to_string(), "sensorCache": shared("cac") })),
    );
    assert_eq!(response["success"], false);
    let message = response["message"].as_str().unwrap_or_default();
    assert!(
        message.contains(":6:7: error[E0113]: index 444 is `m_certainly_at_surface` in 1f35be3b but `m_depth` in 813b137d"),
        "{message}"
    );
}
