//! Debugging sessions over the protocol, every message schema-checked. Expected cycles
//! come from an independent reference run of the simulator (`reference`), which drives
//! `gloc_sim::Simulation` directly, one whole phase at a time, with no debugger code.

mod support;

use std::sync::Arc;

use gloc_compiler::{load_script, Language, LoadOptions};
use gloc_engine::sensors::SensorList;
use gloc_sim::{Mission, SimConfig, Simulation};
use serde_json::{json, Value};
use support::{cycle, sensor, stopped, value, values, Client, SENSORS, VEHICLE};

fn fixture(name: &str) -> String {
    format!("{}/tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// What the script sees at one cycle boundary in the reference run.
#[derive(Debug, Clone, Copy)]
struct Boundary {
    cycle: u64,
    depth: f64,
    behs: f64,
    present_time: f64,
}

/// Runs `program` under `mission` with the simulator alone and records the sensors at
/// every cycle boundary (after `begin_cycle`, before the script runs).
fn reference(program: &str, mission: Option<&str>, cycles: usize) -> Vec<Boundary> {
    let sensors = SensorList::embedded();
    let text = std::fs::read_to_string(program).expect("fixture");
    let language = if program.ends_with(".gbas") {
        Language::Gbasic
    } else {
        Language::Gloc
    };
    let loaded = load_script(&text, language, &sensors, &LoadOptions::default());
    let mission = match mission {
        Some(path) => Mission::load(std::path::Path::new(path)),
        None => gloc_sim::default_mission(),
    };
    let depth = sensors.lookup("m_depth").expect("m_depth").index();
    let behs = sensors
        .lookup("sci_ruhp_behs")
        .expect("sci_ruhp_behs")
        .index();
    let mut sim = Simulation::new(
        &mission,
        Arc::new(sensors),
        loaded.program,
        &SimConfig::default(),
    )
    .expect("reference simulation");
    let mut boundaries = Vec::new();
    while boundaries.len() < cycles && sim.begin_cycle() {
        boundaries.push(Boundary {
            cycle: sim.cycle(),
            depth: sim.sensors()[depth],
            behs: sim.sensors()[behs],
            present_time: sim.present_time(),
        });
        sim.run_script();
        sim.finish_cycle();
    }
    boundaries
}

fn launch(client: &mut Client, arguments: Value) {
    let body = client.ok(
        "initialize",
        json!({ "adapterID": "gloc", "linesStartAt1": true }),
    );
    assert!(
        body.get("supportsStepBack").is_none(),
        "stepBack is announced only after launch"
    );
    client.ok("launch", arguments.clone());
    if arguments.get("history") != Some(&json!(false)) {
        let capabilities = client.event("capabilities");
        assert_eq!(
            capabilities["body"]["capabilities"]["supportsStepBack"],
            true
        );
    }
    client.event("initialized");
}

fn start(arguments: Value) -> Client {
    let mut client = Client::start();
    launch(&mut client, arguments);
    client
}

fn top_line(client: &mut Client) -> i64 {
    let body = client.ok("stackTrace", json!({ "threadId": 1 }));
    body["stackFrames"][0]["line"].as_i64().expect("line")
}

#[test]
fn stop_on_entry_shows_cycle_zero_at_the_first_statement() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    client.ok("configurationDone", json!({}));
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "entry");
    // Line 1 is `label: state1`, which has no code; the first statement is line 2.
    assert_eq!(top_line(&mut client), 2);
    assert_eq!(cycle(&mut client), 0);
    let threads = client.ok("threads", json!({}));
    assert_eq!(threads["threads"].as_array().map(Vec::len), Some(1));
    let scopes = client.ok("scopes", json!({ "frameId": 1 }));
    let names: Vec<&str> = scopes["scopes"]
        .as_array()
        .expect("scopes")
        .iter()
        .filter_map(|scope| scope["name"].as_str())
        .collect();
    assert_eq!(names, ["Variables", "Registers", "Sensors", "Vehicle"]);
    // The sensors the script touches come first, then the paged container of all.
    let sensors = values(&mut client, SENSORS);
    assert_eq!(sensors[0].0, "m_depth");
    assert_eq!(sensors[1].0, "sci_ruhp_behs");
    assert_eq!(sensors[2].0, "All sensors");
    let page = client.ok(
        "variables",
        json!({ "variablesReference": 5, "start": 444, "count": 2 }),
    );
    assert_eq!(page["variables"][0]["name"], "m_depth");
    assert_eq!(page["variables"].as_array().map(Vec::len), Some(2));
}

#[test]
fn line_breakpoint_in_fig3_hits_in_the_cycle_depth_first_exceeds_15() {
    let program = fixture("fig3.gbas");
    let expected = reference(&program, None, 400)
        .into_iter()
        .find(|boundary| boundary.depth > 15.0)
        .expect("the reference run goes below 15 m");
    let mut client = start(json!({ "program": program }));
    let body = client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [{ "line": 3 }] }),
    );
    assert_eq!(body["breakpoints"][0]["verified"], true);
    assert_eq!(body["breakpoints"][0]["line"], 3);
    client.ok("configurationDone", json!({}));
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "breakpoint");
    assert_eq!(top_line(&mut client), 3);
    assert_eq!(cycle(&mut client), expected.cycle);
    assert_eq!(sensor(&mut client, "m_depth"), expected.depth);
}

#[test]
fn breakpoints_move_to_the_next_line_with_code() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    let body = client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [{ "line": 1 }, { "line": 5 }, { "line": 8 }, { "line": 18 }] }),
    );
    let lines: Vec<i64> = body["breakpoints"]
        .as_array()
        .expect("breakpoints")
        .iter()
        .map(|breakpoint| breakpoint["line"].as_i64().unwrap_or(0))
        .collect();
    // 1 `label:` → 2; 5 `endif` → 6 `yield`; 8 `label:` → 9; 18 (the empty line after
    // the final newline of the 17-line file) → the last line with code, 17.
    assert_eq!(lines, [2, 6, 9, 17]);
    assert!(body["breakpoints"]
        .as_array()
        .expect("breakpoints")
        .iter()
        .all(|breakpoint| breakpoint["verified"] == true));
    let other = client.ok(
        "setBreakpoints",
        json!({ "source": { "path": "/elsewhere/other.gbas" }, "breakpoints": [{ "line": 2 }] }),
    );
    assert_eq!(other["breakpoints"][0]["verified"], false);
}

#[test]
fn breakpoints_outside_the_file_or_with_a_broken_condition_are_unverified() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    let body = client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [
            { "line": 99 }, { "line": 0 }, { "line": 2, "condition": "m_depth >" },
            { "line": 2, "condition": "no_such_name > 1" }, { "line": 2, "condition": "m_depth > 15" }
        ] }),
    );
    let breakpoints = body["breakpoints"].as_array().expect("breakpoints");
    let message = |index: usize| {
        breakpoints[index]["message"]
            .as_str()
            .unwrap_or("")
            .to_string()
    };
    // fig3.gbas has 17 lines (18 with the empty one after its final newline).
    assert_eq!(breakpoints[0]["verified"], false);
    assert!(
        message(0).contains("past the end of fig3.gbas (18 lines)"),
        "{}",
        message(0)
    );
    assert_eq!(breakpoints[1]["verified"], false);
    assert!(message(1).contains("lines start at 1"), "{}", message(1));
    assert_eq!(breakpoints[2]["verified"], false);
    assert!(
        message(2).contains("`m_depth >`")
            && message(2)
                .contains("column 10: expected an expression, found the end of the expression"),
        "{}",
        message(2)
    );
    assert_eq!(breakpoints[3]["verified"], false);
    assert!(message(3).contains("no_such_name"), "{}", message(3));
    assert_eq!(breakpoints[4]["verified"], true, "{}", breakpoints[4]);
}

#[test]
fn stack_trace_honours_start_frame_and_levels() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    let frames = |client: &mut Client, arguments: Value| {
        let body = client.ok("stackTrace", arguments);
        assert_eq!(body["totalFrames"], 1);
        body["stackFrames"].as_array().expect("frames").len()
    };
    assert_eq!(frames(&mut client, json!({ "threadId": 1 })), 1);
    assert_eq!(
        frames(
            &mut client,
            json!({ "threadId": 1, "startFrame": 0, "levels": 0 })
        ),
        1
    );
    assert_eq!(
        frames(
            &mut client,
            json!({ "threadId": 1, "startFrame": 0, "levels": 20 })
        ),
        1
    );
    // The one frame is frame 0: a page from frame 1 on is empty.
    assert_eq!(
        frames(&mut client, json!({ "threadId": 1, "startFrame": 1 })),
        0
    );
    assert_eq!(
        frames(
            &mut client,
            json!({ "threadId": 1, "startFrame": 1, "levels": 20 })
        ),
        0
    );
}

#[test]
fn disassemble_returns_exactly_instruction_count_entries() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    for (reference, offset, count) in [
        ("0x0", 0, 4),
        ("0x0", -10, 30),
        ("0x0", 5000, 7),
        ("0x7fffffffffffffff", 0, 5),
        ("0x0", 0, 100_000),
    ] {
        let body = client.ok(
            "disassemble",
            json!({ "memoryReference": reference, "instructionOffset": offset, "instructionCount": count }),
        );
        let instructions = body["instructions"].as_array().expect("instructions");
        assert_eq!(
            instructions.len(),
            count as usize,
            "{reference}{offset:+} × {count}"
        );
    }
    // Before pc 0: invalid entries; then the code from pc 0.
    let body = client.ok(
        "disassemble",
        json!({ "memoryReference": "0x0", "instructionOffset": -2, "instructionCount": 3 }),
    );
    assert_eq!(body["instructions"][0]["presentationHint"], "invalid");
    assert_eq!(body["instructions"][2]["instruction"], "loads 444,r0");
    let refused = client.request(
        "disassemble",
        Some(json!({ "memoryReference": "0x0", "instructionCount": 100_001 })),
    );
    assert_eq!(refused["success"], false, "{refused}");
}

#[test]
fn loaded_sources_is_advertised() {
    let mut client = Client::start();
    let body = client.ok("initialize", json!({ "adapterID": "gloc" }));
    assert_eq!(body["supportsLoadedSourcesRequest"], true);
}

#[test]
fn next_advances_exactly_one_cycle() {
    let program = fixture("fig3.gbas");
    let boundaries = reference(&program, None, 10);
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    for (previous, expected) in boundaries[..5].iter().zip(&boundaries[1..6]) {
        client.ok("next", json!({ "threadId": 1 }));
        let stop = stopped(&mut client);
        assert_eq!(stop["reason"], "step");
        assert_eq!(cycle(&mut client), expected.cycle);
        let present: f64 = value(&mut client, VEHICLE, "m_present_time")
            .parse()
            .expect("time");
        assert_eq!(present, expected.present_time);
        // fig2.mi sets u_cycle_time to 4 s; a cycle lasts that plus the
        // simulator's overrun, 0.51 ± 0.13 s (comet's): within six spreads.
        let period = present - previous.present_time;
        assert!((3.73..5.29).contains(&period), "{period}");
    }
}

#[test]
fn conditional_breakpoint_stops_when_the_condition_first_holds() {
    let program = fixture("fig3.gbas");
    let expected = reference(&program, None, 400)
        .into_iter()
        .find(|boundary| boundary.depth > 10.0 && boundary.behs == 0.0)
        .expect("the reference run goes below 10 m");
    let mut client = start(json!({ "program": program }));
    client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [{ "line": 2, "condition": "m_depth > 10 and sci_ruhp_behs = 0" }] }),
    );
    client.ok("configurationDone", json!({}));
    assert_eq!(stopped(&mut client)["reason"], "breakpoint");
    assert_eq!(cycle(&mut client), expected.cycle);
    let body = client.ok("evaluate", json!({ "expression": "m_depth > 10 and sci_ruhp_behs = 0", "frameId": 1, "context": "watch" }));
    assert_eq!(body["result"], "1");
    let body = client.ok(
        "evaluate",
        json!({ "expression": "m_depth * 2", "context": "hover" }),
    );
    assert_eq!(
        body["result"]
            .as_str()
            .and_then(|text| text.parse::<f64>().ok()),
        Some(expected.depth * 2.0)
    );
    let response = client.request("evaluate", Some(json!({ "expression": "m_dpth > 1" })));
    assert_eq!(response["success"], false);
    assert!(response["message"]
        .as_str()
        .unwrap_or_default()
        .contains("m_dpth"));
}

#[test]
fn hit_counts_and_logpoints() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program }));
    // Line 7 (`goto state1`) runs at every boundary from cycle 1 on: the 5th hit is cycle 5.
    client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [
            { "line": 7, "hitCondition": "5" },
            { "line": 2, "logMessage": "depth is {m_depth}" }
        ] }),
    );
    client.ok("configurationDone", json!({}));
    assert_eq!(stopped(&mut client)["reason"], "breakpoint");
    assert_eq!(cycle(&mut client), 5);
    let logged: Vec<String> = client
        .received
        .iter()
        .filter(|message| message["event"] == "output" && message["body"]["category"] == "console")
        .filter_map(|message| message["body"]["output"].as_str().map(str::to_string))
        .filter(|text| text.starts_with("depth is"))
        .collect();
    // Line 2 runs in cycles 0..=4 before the stop at the boundary of cycle 5.
    assert_eq!(logged.len(), 5, "{logged:?}");
}

#[test]
fn data_breakpoint_on_sci_ruhp_behs_stops_after_each_change() {
    let program = fixture("fig3.gbas");
    let boundaries = reference(&program, None, 400);
    let changes: Vec<Boundary> = boundaries
        .windows(2)
        .filter(|pair| pair[0].behs != pair[1].behs)
        .map(|pair| pair[1])
        .collect();
    assert!(
        changes.len() >= 2,
        "the reference run sets and clears the hook bits: {changes:?}"
    );
    let mut client = start(json!({ "program": program }));
    let info = client.ok(
        "dataBreakpointInfo",
        json!({ "variablesReference": SENSORS, "name": "sci_ruhp_behs" }),
    );
    let data_id = info["dataId"]
        .as_str()
        .expect("a sensor can be watched")
        .to_string();
    let body = client.ok(
        "setDataBreakpoints",
        json!({ "breakpoints": [{ "dataId": data_id, "accessType": "write" }] }),
    );
    assert_eq!(body["breakpoints"][0]["verified"], true);
    let not_sensor = client.ok(
        "dataBreakpointInfo",
        json!({ "variablesReference": 2, "name": "r1" }),
    );
    assert_eq!(not_sensor["dataId"], Value::Null);
    client.ok("configurationDone", json!({}));
    for change in &changes[..2] {
        let stop = stopped(&mut client);
        assert_eq!(stop["reason"], "data breakpoint");
        assert_eq!(cycle(&mut client), change.cycle);
        assert_eq!(sensor(&mut client, "sci_ruhp_behs"), change.behs);
        client.ok("continue", json!({ "threadId": 1 }));
    }
}

fn snapshot(client: &mut Client) -> Vec<Vec<(String, String)>> {
    let mut all = Vec::new();
    for reference in 1..=4 {
        all.push(values(client, reference));
    }
    let page = client.ok("variables", json!({ "variablesReference": 5 }));
    all.push(
        page["variables"]
            .as_array()
            .expect("all sensors")
            .iter()
            .map(|variable| (variable["name"].to_string(), variable["value"].to_string()))
            .collect(),
    );
    all.push(vec![("line".into(), top_line(client).to_string())]);
    all
}

#[test]
fn step_back_returns_to_the_same_variables_and_sensors() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    let mut seen = Vec::new();
    for _ in 0..40 {
        seen.push(snapshot(&mut client));
        client.ok("next", json!({ "threadId": 1 }));
        stopped(&mut client);
    }
    // Back through every cycle, each one exactly as it was, sensors included.
    for expected in seen.iter().rev().take(35) {
        client.ok("stepBack", json!({ "threadId": 1 }));
        assert_eq!(stopped(&mut client)["reason"], "step");
        assert_eq!(&snapshot(&mut client), expected);
    }
    // And forward again to the same states.
    let here = seen.len() - 35;
    for expected in &seen[here + 1..here + 5] {
        client.ok("next", json!({ "threadId": 1 }));
        stopped(&mut client);
        assert_eq!(&snapshot(&mut client), expected);
    }
}

#[test]
fn step_back_from_inside_a_cycle_returns_to_its_boundary() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    for _ in 0..3 {
        client.ok("next", json!({ "threadId": 1 }));
        stopped(&mut client);
    }
    let boundary = snapshot(&mut client);
    client.ok("stepIn", json!({ "threadId": 1 }));
    stopped(&mut client);
    client.ok("stepIn", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_ne!(snapshot(&mut client), boundary);
    client.ok("stepBack", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(snapshot(&mut client), boundary);
}

#[test]
fn reverse_continue_runs_back_to_the_previous_breakpoint_hit() {
    let program = fixture("fig3.gbas");
    let boundaries = reference(&program, None, 400);
    let first_deep = boundaries
        .iter()
        .find(|boundary| boundary.depth > 15.0)
        .expect("deep");
    let mut client = start(json!({ "program": program }));
    client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [{ "line": 3 }] }),
    );
    client.ok(
        "setFunctionBreakpoints",
        json!({ "breakpoints": [{ "name": "cycle 120" }] }),
    );
    client.ok("configurationDone", json!({}));
    assert_eq!(stopped(&mut client)["reason"], "breakpoint");
    let at_breakpoint = snapshot(&mut client);
    client.ok("continue", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "function breakpoint");
    assert_eq!(cycle(&mut client), 120);
    client.ok("reverseContinue", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "breakpoint");
    assert_eq!(cycle(&mut client), first_deep.cycle);
    assert_eq!(snapshot(&mut client), at_breakpoint);
    // Nothing earlier: back to the start of the run.
    client.ok("reverseContinue", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(cycle(&mut client), 0);
}

#[test]
fn cycle_breakpoints_every_n() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program }));
    let body = client.ok(
        "setFunctionBreakpoints",
        json!({ "breakpoints": [{ "name": "every 50" }, { "name": "main" }, { "name": "cycle 0" }] }),
    );
    assert_eq!(body["breakpoints"][0]["verified"], true);
    assert_eq!(body["breakpoints"][1]["verified"], false);
    client.ok("configurationDone", json!({}));
    for expected in [0, 50, 100, 150] {
        assert_eq!(stopped(&mut client)["reason"], "function breakpoint");
        assert_eq!(cycle(&mut client), expected);
        client.ok("continue", json!({ "threadId": 1 }));
    }
}

#[test]
fn set_variable_on_a_sensor_changes_the_scripts_course() {
    let program = fixture("fig3.gbas");
    let boundaries = reference(&program, None, 5);
    // Unmodified, the glider is far above 15 m early on and the hook is not commanded.
    assert!(boundaries[1].depth < 15.0 && boundaries[1].behs == 0.0);
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    let body = client.ok(
        "setVariable",
        json!({ "variablesReference": SENSORS, "name": "m_depth", "value": "20" }),
    );
    assert_eq!(body["value"], "20.0");
    client.ok("stepOut", json!({ "threadId": 1 }));
    stopped(&mut client);
    // The script saw 20 m, took the `then` branch and commanded a climb (bit 128)...
    assert_eq!(sensor(&mut client, "sci_ruhp_behs"), 128.0);
    client.ok("next", json!({ "threadId": 1 }));
    stopped(&mut client);
    // ...and went on to `state2`: the next cycle resumes at line 14 (`goto state2`), not
    // at line 7 (`goto state1`) where the unmodified run is.
    assert_eq!(cycle(&mut client), 1);
    assert_eq!(top_line(&mut client), 14);
    // stepBack and forward replays the injected value.
    client.ok("stepBack", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(sensor(&mut client, "m_depth"), 20.0);
    client.ok("next", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(top_line(&mut client), 14);
    // Registers and the Vehicle scope.
    let body = client.ok(
        "setVariable",
        json!({ "variablesReference": 2, "name": "r3", "value": "7" }),
    );
    assert_eq!(body["value"], "7");
    let response = client.request(
        "setVariable",
        Some(json!({ "variablesReference": VEHICLE, "name": "cycle", "value": "3" })),
    );
    assert_eq!(response["success"], false);
}

#[test]
fn a_trap_stops_on_the_gbasic_line() {
    let program = fixture("trap.gbas");
    let mut client = start(json!({ "program": program }));
    client.ok("configurationDone", json!({}));
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "exception");
    assert!(
        stop["text"].as_str().unwrap_or_default().contains("line 7"),
        "{stop}"
    );
    assert_eq!(top_line(&mut client), 7);
    assert_eq!(cycle(&mut client), 3);
    assert_eq!(value(&mut client, 1, "left"), "0");
    let info = client.ok("exceptionInfo", json!({ "threadId": 1 }));
    assert!(
        info["description"]
            .as_str()
            .unwrap_or_default()
            .contains("zero"),
        "{info}"
    );
    let printed: Vec<String> = client
        .received
        .iter()
        .filter(|message| message["event"] == "output" && message["body"]["category"] == "stdout")
        .filter_map(|message| message["body"]["output"].as_str().map(str::to_string))
        .collect();
    assert_eq!(printed, ["50\n", "100\n"]);
}

#[test]
fn trap_filter_off_runs_to_the_end() {
    let program = fixture("trap.gbas");
    let mut client = start(json!({ "program": program, "history": false }));
    client.ok("setExceptionBreakpoints", json!({ "filters": ["overrun"] }));
    client.ok("configurationDone", json!({}));
    let ended = client.event("terminated");
    assert_eq!(ended["event"], "terminated");
    let bad = client.request(
        "setExceptionBreakpoints",
        Some(json!({ "filters": ["nope"] })),
    );
    assert_eq!(bad["success"], false);
}

#[test]
fn step_in_and_step_out_inside_a_cycle() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    assert_eq!(top_line(&mut client), 2);
    // m_depth is 0 at cycle 0: the `if` is false and control goes to `yield` on line 6.
    client.ok("stepIn", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(top_line(&mut client), 6);
    client.ok("stepIn", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(top_line(&mut client), 7);
    assert_eq!(cycle(&mut client), 1);
    // One instruction at a time.
    client.ok(
        "stepIn",
        json!({ "threadId": 1, "granularity": "instruction" }),
    );
    stopped(&mut client);
    let frame = client.ok("stackTrace", json!({ "threadId": 1 }));
    assert_eq!(
        frame["stackFrames"][0]["instructionPointerReference"],
        "0x0"
    );
    // stepOut: to the script's yield in this cycle, before the vehicle moves.
    client.ok("stepOut", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(top_line(&mut client), 6);
    assert_eq!(cycle(&mut client), 1);
    assert_eq!(value(&mut client, VEHICLE, "phase"), "script yielded");
}

#[test]
fn disassemble_and_instruction_breakpoints() {
    let program = fixture("fig3.gbas");
    let boundaries = reference(&program, None, 400);
    let first_deep = boundaries
        .iter()
        .find(|boundary| boundary.depth > 15.0)
        .expect("deep");
    let mut client = start(json!({ "program": program }));
    let body = client.ok(
        "disassemble",
        json!({ "memoryReference": "0x0", "instructionCount": 4 }),
    );
    let texts: Vec<&str> = body["instructions"]
        .as_array()
        .expect("instructions")
        .iter()
        .filter_map(|instruction| instruction["instruction"].as_str())
        .collect();
    // The paper's Fig. 2, lines 5–8: what Fig. 3's line 2 compiles to.
    assert_eq!(
        texts,
        [
            "loads 444,r0",
            "loadd 15.0,r1",
            "cmpgt r0,r1,r2",
            "cbr r2,3,4"
        ]
    );
    // Fig. 2 line 11, `stores r3,1387`, is the 6th instruction (pc 5).
    let body = client.ok(
        "setInstructionBreakpoints",
        json!({ "breakpoints": [{ "instructionReference": "0x5" }] }),
    );
    assert_eq!(body["breakpoints"][0]["verified"], true);
    client.ok("configurationDone", json!({}));
    assert_eq!(stopped(&mut client)["reason"], "instruction breakpoint");
    assert_eq!(cycle(&mut client), first_deep.cycle);
}

#[test]
fn restart_goes_back_to_entry_with_the_breakpoints() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    client.ok(
        "setFunctionBreakpoints",
        json!({ "breakpoints": [{ "name": "cycle 7" }] }),
    );
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    client.ok("continue", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(cycle(&mut client), 7);
    client.ok("restart", json!({}));
    assert_eq!(stopped(&mut client)["reason"], "entry");
    assert_eq!(cycle(&mut client), 0);
    client.ok("continue", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(cycle(&mut client), 7);
}

#[test]
fn the_mission_end_terminates_with_a_summary() {
    let program = fixture("fig3.gbas");
    let cycles = reference(&program, None, usize::MAX).len();
    let mut client = start(json!({ "program": program }));
    client.ok("configurationDone", json!({}));
    client.event("terminated");
    let summary = client
        .received
        .iter()
        .filter(|message| message["event"] == "output")
        .filter_map(|message| message["body"]["output"].as_str())
        .find(|text| text.contains("mission"))
        .expect("a summary")
        .to_string();
    assert!(
        summary.contains(&format!("after {cycles} cycles")),
        "{summary} vs {cycles}"
    );
    let response = client.request("disconnect", None);
    assert_eq!(response["success"], true);
    assert!(client.join());
}

#[test]
fn disconnect_mid_run_ends_the_session() {
    let program = fixture("fig3.gbas");
    let mission = fixture("endless.mi");
    let mut client = start(json!({ "program": program, "mission": mission }));
    client.ok("configurationDone", json!({}));
    let response = client.request("disconnect", None);
    assert_eq!(response["success"], true);
    assert!(client.join(), "the adapter kept running after disconnect");
}

#[test]
fn pause_stops_a_running_mission_at_a_boundary() {
    let program = fixture("fig3.gbas");
    let mission = fixture("endless.mi");
    let mut client = start(json!({ "program": program, "mission": mission }));
    client.ok("configurationDone", json!({}));
    std::thread::sleep(std::time::Duration::from_millis(50));
    client.ok("pause", json!({ "threadId": 1 }));
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "pause");
    assert_eq!(value(&mut client, VEHICLE, "phase"), "cycle boundary");
}

#[test]
fn launch_errors_say_what_is_wrong() {
    let mut client = Client::start();
    client.ok("initialize", json!({}));
    let response = client.request("launch", Some(json!({ "program": "/no/such/file.gbas" })));
    assert_eq!(response["success"], false);
    assert!(response["message"]
        .as_str()
        .unwrap_or_default()
        .contains("/no/such/file.gbas"));
    let bad = std::env::temp_dir().join(format!("gloc-dap-bad-{}.gbas", std::process::id()));
    std::fs::write(&bad, "if m_dpth > 3 then\nendif\n").expect("temp file");
    let response = client.request("launch", Some(json!({ "program": bad })));
    let message = response["message"].as_str().unwrap_or_default().to_string();
    let _ = std::fs::remove_file(&bad);
    assert_eq!(response["success"], false);
    assert!(message.contains(":1:"), "{message}");
    assert!(message.contains("m_dpth"), "{message}");
}

#[test]
fn cycle_overrun_is_an_exception_stop_in_gloc() {
    let program = fixture("overrun.gloc");
    let mut client = start(json!({ "program": program, "cycleBudget": 1000 }));
    client.ok("configurationDone", json!({}));
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "exception");
    assert!(
        stop["description"]
            .as_str()
            .unwrap_or_default()
            .contains("overrun"),
        "{stop}"
    );
    // Worked out in tests/fixtures/README.md: the 1,000th instruction leaves pc 4, line 11.
    assert_eq!(top_line(&mut client), 11);
    assert_eq!(cycle(&mut client), 0);
}

#[test]
fn step_in_a_gloc_file_is_one_instruction() {
    let program = fixture("overrun.gloc");
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    assert_eq!(top_line(&mut client), 6);
    for expected in [7, 9, 10, 11, 12, 9] {
        client.ok("stepIn", json!({ "threadId": 1 }));
        stopped(&mut client);
        assert_eq!(top_line(&mut client), expected);
    }
    let body = client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [{ "line": 8 }, { "line": 13 }] }),
    );
    // `label 1` (line 8) has no code: line 9. `label 2` (line 13): line 14 (`yield`).
    assert_eq!(body["breakpoints"][0]["line"], 9);
    assert_eq!(body["breakpoints"][1]["line"], 14);
}

#[test]
fn an_abend_is_an_exception_stop_then_the_mission_ends() {
    let program = fixture("fig3.gbas");
    let mission = fixture("abend.mi");
    // The simulator alone: the cycle in which abend aborts the mission.
    let sensors = SensorList::embedded();
    let text = std::fs::read_to_string(&program).expect("fixture");
    let loaded = load_script(&text, Language::Gbasic, &sensors, &LoadOptions::default());
    let mut sim = Simulation::new(
        &Mission::load(std::path::Path::new(&mission)),
        Arc::new(sensors),
        loaded.program,
        &SimConfig::default(),
    )
    .expect("simulation");
    while sim.end().is_none() && sim.step_cycle() {}
    let end = sim.end().expect("the mission aborts");
    assert!(end.depth > 10.0);
    let mut client = start(json!({ "program": program, "mission": mission }));
    client.ok("configurationDone", json!({}));
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "exception");
    assert!(
        stop["text"]
            .as_str()
            .unwrap_or_default()
            .contains("MS_ABORT_OVERDEPTH"),
        "{stop}"
    );
    // Abend decides while cycle `end.cycle` finishes; the run stops at the next boundary.
    assert_eq!(cycle(&mut client), end.cycle + 1);
    client.ok("continue", json!({ "threadId": 1 }));
    client.event("terminated");
}

#[test]
fn reverse_continue_finds_hits_on_snapshot_boundaries() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program }));
    // Cycle 32 is a multiple of the snapshot spacing (16): its boundary is where a
    // replay segment starts.
    client.ok(
        "setFunctionBreakpoints",
        json!({ "breakpoints": [{ "name": "cycle 32" }, { "name": "cycle 50" }] }),
    );
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    assert_eq!(cycle(&mut client), 32);
    client.ok("continue", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(cycle(&mut client), 50);
    client.ok("reverseContinue", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "function breakpoint");
    assert_eq!(cycle(&mut client), 32);
}

#[test]
fn set_variable_on_a_gbasic_variable_avoids_the_trap() {
    let program = fixture("trap.gbas");
    let mut client = start(json!({ "program": program }));
    client.ok(
        "setFunctionBreakpoints",
        json!({ "breakpoints": [{ "name": "cycle 2" }] }),
    );
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    // At the boundary of cycle 2, left is 1 (3, then 2 in cycle 0, 1 in cycle 1).
    assert_eq!(value(&mut client, 1, "left"), "1");
    let body = client.ok(
        "setVariable",
        json!({ "variablesReference": 1, "name": "left", "value": "50" }),
    );
    assert_eq!(body["value"], "50");
    client.ok(
        "setFunctionBreakpoints",
        json!({ "breakpoints": [{ "name": "cycle 6" }] }),
    );
    client.ok("continue", json!({ "threadId": 1 }));
    // No trap: 100 \ 50 in cycle 2, then left counts down from 49.
    assert_eq!(stopped(&mut client)["reason"], "function breakpoint");
    assert_eq!(value(&mut client, 1, "left"), "46");
    // Back before the edit and forward again: the edit is replayed, still no trap.
    client.ok("reverseContinue", json!({ "threadId": 1 }));
    stopped(&mut client);
    assert_eq!(cycle(&mut client), 0);
    client.ok("continue", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "function breakpoint");
    assert_eq!(value(&mut client, 1, "left"), "46");
}

#[test]
fn history_off_means_no_step_back() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "stopOnEntry": true, "history": false }));
    assert!(client
        .unclaimed
        .iter()
        .all(|event| event["event"] != "capabilities"));
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    assert!(client
        .received
        .iter()
        .all(|message| message["event"] != "capabilities"));
    let response = client.request("stepBack", Some(json!({ "threadId": 1 })));
    assert_eq!(response["success"], false);
    assert!(
        response["message"]
            .as_str()
            .unwrap_or_default()
            .contains("history"),
        "{response}"
    );
}

/// The end-of-run summary of a run cut short by `maxCycles`.
fn cut_short_summary(client: &Client) -> String {
    client
        .received
        .iter()
        .filter(|message| message["event"] == "output")
        .filter_map(|message| message["body"]["output"].as_str())
        .find(|text| text.contains("maxCycles"))
        .expect("a summary")
        .to_string()
}

#[test]
fn max_cycles_ends_the_session_with_a_summary() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "maxCycles": 10 }));
    client.ok("configurationDone", json!({}));
    client.event("terminated");
    let summary = cut_short_summary(&client);
    assert!(summary.contains("after 10 cycles"), "{summary}");
}

#[test]
fn masterdata_and_profile_are_used() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({
        "program": program,
        "masterdata": fixture("three.cac"),
        "profile": fixture("profile.csv"),
        "stopOnEntry": true,
    }));
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    let body = client.ok("variables", json!({ "variablesReference": SENSORS }));
    assert_eq!(body["variables"][0]["name"], "m_depth");
    assert_eq!(body["variables"][0]["type"], "sensor 1");
    assert_eq!(body["variables"][1]["type"], "sensor 2");
    // The file's 3 sensors, then the 3 hook sensors it lacks (appended).
    assert_eq!(body["variables"][2]["indexedVariables"], 3 + 3);
    // fig2.mi sets u_cycle_time, which three.cac lacks: the simulator's warning is shown.
    assert!(
        client
            .received
            .iter()
            .any(|message| message["event"] == "output"
                && message["body"]["category"] == "important"
                && message["body"]["output"]
                    .as_str()
                    .unwrap_or_default()
                    .contains("u_cycle_time")),
        "no setup warning"
    );
    let disassembly = client.ok(
        "disassemble",
        json!({ "memoryReference": "0x0", "instructionCount": 1 }),
    );
    assert_eq!(disassembly["instructions"][0]["instruction"], "loads 1,r0");
    // A sensor list without the script's sensor: a launch error naming it.
    let mut client = Client::start();
    client.ok("initialize", json!({}));
    let response = client.request(
        "launch",
        Some(json!({ "program": program, "masterdata": fixture("fig3.gbas") })),
    );
    assert_eq!(response["success"], false);
    let response = client.request(
        "launch",
        Some(json!({ "program": program, "profile": "/no/profile.csv" })),
    );
    assert_eq!(response["success"], false);
    assert!(response["message"]
        .as_str()
        .unwrap_or_default()
        .contains("/no/profile.csv"));
}

#[test]
fn arrays_are_expandable_evaluable_and_settable() {
    let program = fixture("arrays.gbas");
    let mut client = start(json!({ "program": program }));
    client.ok(
        "setFunctionBreakpoints",
        json!({ "breakpoints": [{ "name": "cycle 4" }] }),
    );
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    // Cycles 0–3 each stored one a(i) = i * 10; the sum has not run yet.
    let variables = client.ok("variables", json!({ "variablesReference": 1 }));
    let array = variables["variables"]
        .as_array()
        .expect("variables")
        .iter()
        .find(|variable| variable["name"] == "a")
        .expect("a")
        .clone();
    assert_eq!(array["indexedVariables"], 4);
    let reference = array["variablesReference"].as_i64().expect("expandable");
    let elements = values(&mut client, reference);
    assert_eq!(
        elements,
        [("[0]", "0"), ("[1]", "10"), ("[2]", "20"), ("[3]", "30")]
            .map(|(name, value)| (name.to_string(), value.to_string()))
    );
    assert_eq!(value(&mut client, 1, "total"), "0");
    let body = client.ok(
        "evaluate",
        json!({ "expression": "a(2) + a(3)", "context": "watch" }),
    );
    assert_eq!(body["result"], "50");
    let body = client.ok(
        "setVariable",
        json!({ "variablesReference": reference, "name": "[1]", "value": "100" }),
    );
    assert_eq!(body["value"], "100");
    client.ok("stepOut", json!({ "threadId": 1 }));
    stopped(&mut client);
    // 0 + 100 + 20 + 30.
    assert_eq!(value(&mut client, 1, "total"), "150");
    let response = client.request(
        "setVariable",
        Some(json!({ "variablesReference": reference, "name": "a(9)", "value": "1" })),
    );
    assert_eq!(response["success"], false);
}

/// The output events of category `category` received so far, their texts in order.
fn outputs(client: &Client, category: &str) -> Vec<String> {
    client
        .received
        .iter()
        .filter(|message| message["event"] == "output" && message["body"]["category"] == category)
        .map(|message| {
            message["body"]["output"]
                .as_str()
                .unwrap_or_default()
                .to_string()
        })
        .collect()
}

#[test]
fn behavior_changes_are_output_events() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program, "history": false }));
    client.ok("configurationDone", json!({}));
    client.event("terminated");
    let behaviors: Vec<String> = outputs(&client, "console")
        .into_iter()
        .filter(|text| text.starts_with("behavior: "))
        .collect();
    // The embedded Fig. 2 mission: the yo has start_when 0 (immediately), so it starts in
    // the first cycle, cycle 0, before anything else changes.
    assert_eq!(
        behaviors.first().map(String::as_str),
        Some("behavior: cycle 0: yo started\n"),
        "{behaviors:?}"
    );
    // The yo does num_half_cycles_to_do 6 half cycles, each ending in a turn, dive first:
    // a dive turns once at or below d_target_depth 25 m, a climb at or above c_target_depth
    // 2 m. After the 6th turn it completes, the stack is idle and surface (start_when 1,
    // stack idle) starts after that.
    let turns: Vec<f64> = behaviors
        .iter()
        .filter_map(|text| text.split(": yo turned at ").nth(1))
        .map(|rest| rest.trim_end_matches(" m\n").parse().expect("a depth"))
        .collect();
    assert_eq!(turns.len(), 6, "{behaviors:?}");
    for (index, depth) in turns.iter().enumerate() {
        if index % 2 == 0 {
            assert!(*depth >= 25.0, "dive {index} turned at {depth}");
        } else {
            assert!(*depth <= 2.0, "climb {index} turned at {depth}");
        }
    }
    let position = |suffix: &str| {
        behaviors
            .iter()
            .position(|text| text.ends_with(suffix))
            .unwrap_or_else(|| panic!("no `{suffix}` in {behaviors:?}"))
    };
    assert!(position(": yo completed\n") < position(": surface started\n"));
}

#[test]
fn conditional_breakpoint_on_a_gbasic_variable() {
    let program = fixture("states.gbas");
    let boundaries = reference(&program, None, 400);
    // The script sets state 2 in the cycle whose boundary first sees more than 15 m
    // (`dived`); line 7 runs first in every cycle, so it sees state 2 from the next cycle
    // until the cycle after the first boundary above 5 m (`climbed`, state 3 from then).
    let dived = boundaries
        .iter()
        .find(|boundary| boundary.depth > 15.0)
        .expect("the reference run goes below 15 m")
        .cycle;
    let climbed = boundaries
        .iter()
        .find(|boundary| boundary.cycle > dived && boundary.depth < 5.0)
        .expect("the reference run climbs above 5 m")
        .cycle;
    let expected = boundaries
        .iter()
        .find(|boundary| boundary.cycle > dived && boundary.depth > 10.0)
        .expect("deeper than 10 m in state 2");
    assert!(expected.cycle <= climbed);
    // Without the `state = 2` part the breakpoint would stop earlier, on the way down.
    let deeper_than_10 = boundaries
        .iter()
        .find(|boundary| boundary.depth > 10.0)
        .expect("below 10 m")
        .cycle;
    assert!(deeper_than_10 < expected.cycle);
    let mut client = start(json!({ "program": program }));
    let body = client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [{ "line": 7, "condition": "m_depth > 10 and state = 2" }] }),
    );
    assert_eq!(body["breakpoints"][0]["verified"], true);
    client.ok("configurationDone", json!({}));
    assert_eq!(stopped(&mut client)["reason"], "breakpoint");
    assert_eq!(top_line(&mut client), 7);
    assert_eq!(cycle(&mut client), expected.cycle);
    assert_eq!(value(&mut client, 1, "state"), "2");
    assert_eq!(sensor(&mut client, "m_depth"), expected.depth);
    // It holds again in the next cycle if that one is still deeper than 10 m, and never
    // once state 3 is reached: continue either stops there or ends the mission.
    let next = boundaries
        .iter()
        .find(|boundary| boundary.cycle == expected.cycle + 1)
        .expect("a next cycle");
    client.ok("continue", json!({ "threadId": 1 }));
    if next.depth > 10.0 && next.cycle <= climbed {
        assert_eq!(stopped(&mut client)["reason"], "breakpoint");
        assert_eq!(cycle(&mut client), next.cycle);
    }
}

#[test]
fn abend_filter_off_does_not_stop_on_it() {
    let program = fixture("fig3.gbas");
    let mission = fixture("abend.mi");
    let mut client = start(json!({ "program": program, "mission": mission, "history": false }));
    client.ok(
        "setExceptionBreakpoints",
        json!({ "filters": ["trap", "overrun"] }),
    );
    client.ok("configurationDone", json!({}));
    client.event("terminated");
    assert!(
        !client
            .received
            .iter()
            .any(|message| message["event"] == "stopped"),
        "no stop with the abend filter off"
    );
    // abend.mi's overdepth is 10 m: the abort is still reported, in the console.
    let important = outputs(&client, "important");
    assert!(
        important
            .iter()
            .any(|text| text.starts_with("abend: ") && text.contains("MS_ABORT_OVERDEPTH")),
        "{important:?}"
    );
}

#[test]
fn abend_filter_on_alone_stops_on_it() {
    let program = fixture("fig3.gbas");
    let mission = fixture("abend.mi");
    let mut client = start(json!({ "program": program, "mission": mission, "history": false }));
    client.ok("setExceptionBreakpoints", json!({ "filters": ["abend"] }));
    client.ok("configurationDone", json!({}));
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "exception");
    assert!(
        stop["text"]
            .as_str()
            .unwrap_or_default()
            .contains("MS_ABORT_OVERDEPTH"),
        "{stop}"
    );
    // The abort comes from going below 10 m.
    assert!(sensor(&mut client, "m_depth") > 10.0);
    client.ok("continue", json!({ "threadId": 1 }));
    client.event("terminated");
}

#[test]
fn vehicle_scope_shows_depth_pitch_behaviors_and_energy() {
    let program = fixture("fig3.gbas");
    let mut client = start(json!({ "program": program }));
    client.ok(
        "setFunctionBreakpoints",
        json!({ "breakpoints": [{ "name": "cycle 40" }] }),
    );
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    let vehicle = values(&mut client, VEHICLE);
    let names: Vec<&str> = vehicle.iter().map(|(name, _)| name.as_str()).collect();
    // docs/dap.md: cycle, phase, mission time, m_present_time, depth, pitch, active
    // behaviors, energy, charge, water depth.
    assert_eq!(
        names,
        [
            "cycle",
            "phase",
            "mission time (s)",
            "m_present_time",
            "depth (m)",
            "pitch (rad)",
            "pitch (deg)",
            "active behaviors",
            "energy (J)",
            "charge used (Ah)",
            "water depth (m)"
        ]
    );
    let get = |name: &str| {
        vehicle
            .iter()
            .find(|(known, _)| known == name)
            .map(|(_, value)| value.clone())
            .expect("listed")
    };
    assert_eq!(get("cycle"), "40");
    // At a boundary the sensors were just written from the vehicle: m_depth is its depth
    // and m_pitch its pitch, exactly.
    let depth: f64 = get("depth (m)").parse().expect("a number");
    assert_eq!(depth, sensor(&mut client, "m_depth"));
    let pitch: f64 = get("pitch (rad)").parse().expect("a number");
    let m_pitch = client.ok(
        "evaluate",
        json!({ "expression": "m_pitch", "frameId": 1, "context": "watch" }),
    );
    assert_eq!(
        Some(pitch),
        m_pitch["result"]
            .as_str()
            .and_then(|text| text.parse().ok())
    );
    let degrees: f64 = get("pitch (deg)").parse().expect("a number");
    assert!(
        (degrees - pitch.to_degrees()).abs() <= 0.005,
        "{degrees} vs {pitch} rad"
    );
    // 160 s into Fig. 2: the yo (start_when 0) is flying, the gloc script behavior and
    // abend are always there; the mission has not ended, so surface is not active.
    let active = get("active behaviors");
    assert!(active.split(", ").any(|name| name == "yo"), "{active}");
    assert!(
        !active.split(", ").any(|name| name == "surface"),
        "{active}"
    );
    // 40 cycles of flying spent energy.
    let energy: f64 = get("energy (J)").parse().expect("a number");
    assert!(energy > 0.0, "{energy}");
    assert_eq!(get("water depth (m)").parse::<f64>().ok(), Some(40.0));
}

#[test]
fn reverse_history_keeps_a_bounded_number_of_snapshots() {
    use gloc_dap::debugger::{Debugger, HistoryConfig, Progress, RunMode, Slice};
    use gloc_dap::target::Target;
    use gloc_dap::world::{self, LaunchConfig};

    let config = LaunchConfig {
        program: fixture("fig3.gbas").into(),
        mission: Some(fixture("endless.mi").into()),
        ..LaunchConfig::default()
    };
    let (world, info) = world::launch(&config).expect("launch");
    let history = HistoryConfig {
        max_snapshots: 8,
        interval: 4,
    };
    let mut debugger = Debugger::new(world, info, Some(history));
    // docs/dap.md: a snapshot at a boundary every K cycles, at most `max_snapshots` kept,
    // K doubling when full (every other one dropped). By hand, with 8 kept and K = 4 from
    // cycle 0: 0,4,…,28 are 8; at 32 a 9th, so K = 8 and 0,8,16,24,32 stay (5); 40,48,56
    // make 8; at 64 K = 16 (0,16,32,48,64); … at 512 K = 128 (0,128,256,384,512), then
    // 640, 768, 896: 8 at cycle 1000, and never more than 8 on the way.
    let mut most = 0;
    for _ in 0..1000 {
        let start = debugger.clock();
        loop {
            match debugger.run(RunMode::Next, start, Slice::steps(100_000)) {
                Progress::Running => continue,
                Progress::Stopped(_) => break,
                Progress::Ended { summary } => panic!("endless.mi ended: {summary}"),
            }
        }
        most = most.max(debugger.snapshot_count());
    }
    assert_eq!(debugger.target.cycle(), 1000);
    assert_eq!(most, 8);
    assert_eq!(debugger.snapshot_count(), 8);
    // Stepping back from cycle 1000 replays from the snapshot at 896.
    debugger.step_back().expect("stepBack");
    assert_eq!(debugger.target.cycle(), 999);
}

#[test]
fn a_while_line_is_hit_once_per_test_not_again_at_its_jump_back() {
    let program = fixture("loop.gbas");
    let mut client = start(json!({ "program": program, "history": false }));
    client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [{ "line": 5, "hitCondition": "5" }] }),
    );
    client.ok("configurationDone", json!({}));
    // Line 5 (`while i < 3`) is tested with i = 0, 1, 2, 3 in cycle 0: four hits. The 5th
    // is the first test of cycle 1, with i = 0 again. (Counting the `wend`'s jump back,
    // which the compiler attributes to line 5, the 5th would be cycle 0 with i = 2.)
    assert_eq!(stopped(&mut client)["reason"], "breakpoint");
    assert_eq!(top_line(&mut client), 5);
    assert_eq!(cycle(&mut client), 1);
    assert_eq!(value(&mut client, 1, "i"), "0");
}

/// The `line` of every `stdout` output event received so far, with its text.
fn printed_lines(client: &Client) -> Vec<(String, Option<i64>)> {
    client
        .received
        .iter()
        .filter(|message| message["event"] == "output" && message["body"]["category"] == "stdout")
        .map(|message| {
            (
                message["body"]["output"]
                    .as_str()
                    .unwrap_or_default()
                    .to_string(),
                message["body"]["line"].as_i64(),
            )
        })
        .collect()
}

#[test]
fn a_printed_line_names_the_line_of_its_print() {
    // `print "three", x` is on line 3 of the fixture (by hand); line 4 follows it.
    let program = fixture("print_line.gbas");
    let expected = vec![("three 0\n".to_string(), Some(3))];
    // A run to the end (the fast path), then the same by single steps.
    let mut client = start(json!({ "program": program, "maxCycles": 3 }));
    client.ok("configurationDone", json!({}));
    client.event("terminated");
    assert_eq!(printed_lines(&client), expected);
    let mut client = start(json!({ "program": program, "stopOnEntry": true }));
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    for _ in 0..3 {
        client.ok("stepIn", json!({ "threadId": 1 }));
        stopped(&mut client);
    }
    assert_eq!(printed_lines(&client), expected);
    // A line breakpoint elsewhere makes the run step up to it; the print still names 3.
    let mut client = start(json!({ "program": program, "maxCycles": 3 }));
    client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [{ "line": 5, "condition": "x < 0" }] }),
    );
    client.ok("configurationDone", json!({}));
    client.event("terminated");
    assert_eq!(printed_lines(&client), expected);
}

#[test]
fn a_trap_summary_names_the_line_the_stop_named() {
    // `x = 1 \ zero` is line 5 of a six-line script (by hand).
    let program = fixture("trap6.gbas");
    let mut client = start(json!({ "program": program, "maxCycles": 2 }));
    client.ok("configurationDone", json!({}));
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "exception");
    let text = stop["text"].as_str().unwrap_or_default().to_string();
    assert!(text.contains("at line 5 "), "{text}");
    assert_eq!(top_line(&mut client), 5);
    client.ok("continue", json!({ "threadId": 1 }));
    client.event("terminated");
    let summary = cut_short_summary(&client);
    assert!(summary.contains("script trapped"), "{summary}");
    assert!(summary.contains("line 5"), "{summary}");
    assert!(!summary.contains("line 7"), "{summary}");
}

#[test]
fn an_array_index_out_of_bounds_is_named_as_gloc_run_names_it() {
    // `print a(i)` with i = 5 and `dim a(4)` is line 5 (by hand); compiled GBASIC
    // checks the index by reading address -1, which `gloc run` calls an array index
    // out of bounds (cli/src/simulate.rs, through `LoadedScript::trap_message`).
    let program = fixture("bounds.gbas");
    let mut client = start(json!({ "program": program, "maxCycles": 2 }));
    client.ok("configurationDone", json!({}));
    let stop = stopped(&mut client);
    let text = stop["text"].as_str().unwrap_or_default().to_string();
    assert!(
        text.starts_with("array index out of bounds at line 5 "),
        "{text}"
    );
    let info = client.ok("exceptionInfo", json!({ "threadId": 1 }));
    assert!(
        info["description"]
            .as_str()
            .unwrap_or_default()
            .starts_with("array index out of bounds"),
        "{info}"
    );
    client.ok("continue", json!({ "threadId": 1 }));
    client.event("terminated");
    let summary = cut_short_summary(&client);
    assert!(
        summary.contains("script trapped: array index out of bounds at line 5 "),
        "{summary}"
    );
}

#[test]
fn prints_from_two_sites_name_their_own_lines_in_a_fused_run() {
    // prints.gbas (by hand): `print "odd", n, i` is on line 9, `print "third", n` on
    // line 11. In cycle c (n = c + 1), i from 1 to 3 prints when n + i is odd; a third
    // line follows when n is a multiple of 3.
    let program = fixture("prints.gbas");
    let mut client = start(json!({ "program": program, "maxCycles": 3 }));
    client.ok("configurationDone", json!({}));
    client.event("terminated");
    let expected: Vec<(String, Option<i64>)> = [
        ("odd 1 2\n", 9),
        ("odd 2 1\n", 9),
        ("odd 2 3\n", 9),
        ("odd 3 2\n", 9),
        ("third 3\n", 11),
    ]
    .into_iter()
    .map(|(text, line)| (text.to_string(), Some(line)))
    .collect();
    assert_eq!(printed_lines(&client), expected);
}
