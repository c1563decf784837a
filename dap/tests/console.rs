//! The debug console and Watch panel over the protocol, every message schema-checked:
//! completions, evaluate with children, setExpression (journaled), goto, hex values,
//! exception filter conditions and cancel. Expected values are worked out by hand from
//! the fixtures (dap/tests/fixtures/README.md).

mod support;

use serde_json::{json, Value};
use support::{stopped, Client};

fn fixture(name: &str) -> String {
    format!("{}/tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Launches and stops on entry (cycle 0, before the script ran).
fn start(arguments: Value) -> Client {
    let mut client = Client::start();
    client.ok(
        "initialize",
        json!({ "adapterID": "gloc", "linesStartAt1": true, "columnsStartAt1": true,
                "supportsProgressReporting": true }),
    );
    let mut arguments = arguments;
    arguments["stopOnEntry"] = json!(true);
    client.ok("launch", arguments);
    client.event("initialized");
    client.ok("configurationDone", json!({}));
    assert_eq!(stopped(&mut client)["reason"], "entry");
    client
}

fn watch() -> Client {
    start(json!({ "program": fixture("watch.gbas") }))
}

/// `next` to the following cycle boundary.
fn next(client: &mut Client) {
    client.ok("next", json!({ "threadId": 1 }));
    assert_eq!(stopped(client)["reason"], "step");
}

fn evaluate(client: &mut Client, expression: &str, context: &str) -> Value {
    client.ok(
        "evaluate",
        json!({ "expression": expression, "context": context, "frameId": 1 }),
    )
}

fn result(client: &mut Client, expression: &str) -> String {
    evaluate(client, expression, "watch")["result"]
        .as_str()
        .expect("a result")
        .to_string()
}

fn labels(body: &Value) -> Vec<String> {
    body["targets"]
        .as_array()
        .expect("targets")
        .iter()
        .map(|item| item["label"].as_str().unwrap_or_default().to_string())
        .collect()
}

fn top_line(client: &mut Client) -> i64 {
    let body = client.ok("stackTrace", json!({ "threadId": 1 }));
    body["stackFrames"][0]["line"].as_i64().expect("line")
}

#[test]
fn the_new_capabilities_are_announced() {
    let mut client = Client::start();
    let body = client.ok("initialize", json!({ "adapterID": "gloc" }));
    for capability in [
        "supportsCompletionsRequest",
        "supportsSetExpression",
        "supportsGotoTargetsRequest",
        "supportsValueFormattingOptions",
        "supportsCancelRequest",
        "supportsExceptionFilterOptions",
    ] {
        assert_eq!(body[capability], true, "{capability}: {body}");
    }
    let filters = body["exceptionBreakpointFilters"]
        .as_array()
        .expect("filters");
    let ids: Vec<&str> = filters
        .iter()
        .map(|filter| filter["filter"].as_str().unwrap_or_default())
        .collect();
    assert_eq!(ids, ["trap", "overrun", "abend", "waypoint", "surfacing"]);
    assert!(filters
        .iter()
        .all(|filter| filter["supportsCondition"] == true));
}

#[test]
fn completions_filter_by_the_typed_word_and_are_capped() {
    let mut client = watch();
    // `m_dep|`: the embedded list's m_depth family, m_depth first (shortest).
    let body = client.ok(
        "completions",
        json!({ "frameId": 1, "text": "m_dep", "column": 6 }),
    );
    let items = body["targets"].as_array().expect("targets");
    assert_eq!(items[0]["label"], "m_depth");
    assert_eq!(items[0]["type"], "field");
    assert!(items
        .iter()
        .all(|item| item["label"].as_str().unwrap_or_default().contains("dep")));
    // The word typed so far is what the item replaces: columns 1 to 5.
    assert_eq!(
        (items[0]["start"].clone(), items[0]["length"].clone()),
        (json!(1), json!(5))
    );
    // Variables, arrays, constants and built-ins, after an operator.
    let body = client.ok(
        "completions",
        json!({ "frameId": 1, "text": "ts", "column": 3 }),
    );
    assert_eq!(labels(&body)[0], "tsum");
    let body = client.ok(
        "completions",
        json!({ "frameId": 1, "text": "grad(1) + ab", "column": 13 }),
    );
    assert_eq!(labels(&body), ["abs"]);
    assert_eq!(body["targets"][0]["type"], "function");
    assert_eq!(body["targets"][0]["start"], 11);
    let body = client.ok(
        "completions",
        json!({ "frameId": 1, "text": "N", "column": 2 }),
    );
    let constant = body["targets"]
        .as_array()
        .expect("targets")
        .iter()
        .find(|item| item["label"] == "N")
        .cloned()
        .expect("the constant N");
    assert_eq!(constant["detail"], "const N = 4");
    // `m_` matches hundreds of sensors: the answer is capped at 100.
    let body = client.ok(
        "completions",
        json!({ "frameId": 1, "text": "m_", "column": 3 }),
    );
    assert_eq!(labels(&body).len(), 100);
    // A number is not a name; a column past the text completes its last word.
    let body = client.ok(
        "completions",
        json!({ "frameId": 1, "text": "12", "column": 3 }),
    );
    assert!(labels(&body).is_empty());
    let body = client.ok(
        "completions",
        json!({ "frameId": 1, "text": "grad", "column": 99 }),
    );
    assert_eq!(labels(&body)[0], "grad");
}

#[test]
fn a_watched_array_expands_and_values_are_the_print_text() {
    let mut client = watch();
    for _ in 0..4 {
        next(&mut client);
    }
    let body = evaluate(&mut client, "tsum", "watch");
    // float(i) * 0.1 for i = 0..3: 3 × 0.1 is the double 0.30000000000000004.
    assert_eq!(body["result"], "[0.0, 0.1, 0.2, 0.30000000000000004]");
    assert_eq!(body["indexedVariables"], 4);
    let reference = body["variablesReference"].as_i64().expect("a reference");
    assert!(reference > 0);
    let children = client.ok("variables", json!({ "variablesReference": reference }));
    let values: Vec<&str> = children["variables"]
        .as_array()
        .expect("variables")
        .iter()
        .map(|variable| variable["value"].as_str().unwrap_or_default())
        .collect();
    assert_eq!(values, ["0.0", "0.1", "0.2", "0.30000000000000004"]);
    // `dim tsum(4) as float`: every element is a float.
    for variable in children["variables"].as_array().expect("variables") {
        assert_eq!(variable["type"], "float", "{variable}");
    }
    // The same text on hover: it reads back to the same double.
    assert_eq!(
        evaluate(&mut client, "tsum(3)", "hover")["result"],
        "0.30000000000000004"
    );
    assert_eq!(result(&mut client, "grad(3)"), "9");
    assert_eq!(
        evaluate(&mut client, "grad(3)", "watch")["variablesReference"],
        0
    );
}

#[test]
fn set_expression_edits_an_element_and_reverse_and_replay_keep_it() {
    let mut client = watch();
    for _ in 0..4 {
        next(&mut client);
    }
    // At cycle 4's boundary grad(3) is 9; the Watch panel sets it to 7.
    let body = client.ok(
        "setExpression",
        json!({ "expression": "grad(3)", "value": "7", "frameId": 1 }),
    );
    assert_eq!(body["value"], "7");
    assert_eq!(result(&mut client, "grad(3)"), "7");
    // An index given as an expression (i is still 3: the loop resumes after the
    // boundary), a value given as one.
    client.ok(
        "setExpression",
        json!({ "expression": "grad(i - 1)", "value": "grad(3) * 2", "frameId": 1 }),
    );
    assert_eq!(result(&mut client, "grad(2)"), "14");
    // Back one cycle: before cycle 3 ran, grad(3) was 0; forward again replays the
    // edits at the clock they were made.
    client.ok("stepBack", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "step");
    assert_eq!(result(&mut client, "grad(3)"), "0");
    next(&mut client);
    assert_eq!(result(&mut client, "grad(3)"), "7");
    assert_eq!(result(&mut client, "grad(2)"), "14");
    // A sensor from hex; a whole array or a bad place is refused with the reason.
    let body = client.ok(
        "setExpression",
        json!({ "expression": "sci_ruhp_behs", "value": "0xc0", "frameId": 1 }),
    );
    assert_eq!(body["value"], "192.0");
    for (expression, reason) in [
        ("grad", "is an array"),
        ("grad(1.5)", "integer"),
        ("nosuch", "cannot be assigned"),
        ("abs(1)", "not an array"),
        ("N", "is a constant"),
        ("grad(1) +", "not an expression"),
        ("grad(1) + 1", "cannot be assigned"),
        ("grad(1, 2)", "one index"),
    ] {
        let response = client.request(
            "setExpression",
            Some(json!({ "expression": expression, "value": "1", "frameId": 1 })),
        );
        assert_eq!(response["success"], false, "{expression}");
        let message = response["message"].as_str().unwrap_or_default();
        assert!(message.contains(reason), "{expression}: {message}");
    }
}

#[test]
fn hex_shows_the_bits_of_whole_values() {
    let mut client = watch();
    for _ in 0..4 {
        next(&mut client);
    }
    // Cycle 4 stores 192 = 0xc0, bits 64 and 128 (seen before the vehicle's hook
    // behavior answers it at the next boundary).
    client.ok("stepOut", json!({ "threadId": 1 }));
    stopped(&mut client);
    let hex = json!({ "hex": true });
    let body = client.ok(
        "evaluate",
        json!({ "expression": "sci_ruhp_behs", "context": "watch", "format": hex }),
    );
    assert_eq!(body["result"], "0xc0");
    let body = client.ok(
        "evaluate",
        json!({ "expression": "grad", "context": "watch", "format": hex }),
    );
    assert_eq!(body["result"], "[0x0, 0x3, 0x6, 0x9]");
    // Fractions stay decimal.
    let body = client.ok(
        "evaluate",
        json!({ "expression": "tsum(1)", "context": "watch", "format": hex }),
    );
    assert_eq!(body["result"], "0.1");
    let body = client.ok(
        "variables",
        json!({ "variablesReference": 3, "format": hex }),
    );
    let behs = body["variables"]
        .as_array()
        .expect("variables")
        .iter()
        .find(|variable| variable["name"] == "sci_ruhp_behs")
        .cloned()
        .expect("sci_ruhp_behs in the Sensors scope");
    assert_eq!(behs["value"], "0xc0");
    // Without the format, the decimal print text.
    assert_eq!(result(&mut client, "sci_ruhp_behs"), "192.0");
    // The stack frame's pc in hex.
    let body = client.ok(
        "stackTrace",
        json!({ "threadId": 1, "format": { "hex": true } }),
    );
    let name = body["stackFrames"][0]["name"].as_str().unwrap_or_default();
    let pointer = body["stackFrames"][0]["instructionPointerReference"]
        .as_str()
        .unwrap_or_default();
    assert!(
        name.contains(&format!("· {pointer}:")),
        "{name} / {pointer}"
    );
}

#[test]
fn goto_jumps_within_the_cycle_and_replays_after_reverse() {
    let path = fixture("watch.gbas");
    let mut client = watch();
    // Line 11 is `label: done` (no code): its target is line 12, the store.
    let body = client.ok(
        "gotoTargets",
        json!({ "source": { "path": path }, "line": 11 }),
    );
    let targets = body["targets"].as_array().expect("targets").clone();
    assert_eq!(targets.len(), 1);
    assert_eq!(targets[0]["line"], 12);
    client.ok(
        "goto",
        json!({ "threadId": 1, "targetId": targets[0]["id"] }),
    );
    assert_eq!(stopped(&mut client)["reason"], "goto");
    assert_eq!(top_line(&mut client), 12);
    // The loop never runs: at cycle 2, grad(1) is still 0 (3 without the jump).
    next(&mut client);
    next(&mut client);
    assert_eq!(result(&mut client, "grad(1)"), "0");
    // Back to the start: the state there is the edited one (the jump was made at that
    // clock), and forward again the loop still never runs.
    client.ok("reverseContinue", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "entry");
    assert_eq!(top_line(&mut client), 12);
    next(&mut client);
    next(&mut client);
    assert_eq!(result(&mut client, "grad(1)"), "0");
    // After the script's `yield` a jump would leave the cycle: refused, with what to do.
    client.ok("stepOut", json!({ "threadId": 1 }));
    stopped(&mut client);
    let response = client.request(
        "goto",
        Some(json!({ "threadId": 1, "targetId": targets[0]["id"] })),
    );
    assert_eq!(response["success"], false);
    let message = response["message"].as_str().unwrap_or_default();
    assert!(
        message.contains("yielded") && message.contains("next"),
        "{message}"
    );
    // Another file, or an id that is no instruction, is refused.
    let response = client.request(
        "gotoTargets",
        Some(json!({ "source": { "path": "/elsewhere.gbas" }, "line": 3 })),
    );
    assert_eq!(response["success"], false);
    let response = client.request("goto", Some(json!({ "threadId": 1, "targetId": 99_999 })));
    assert_eq!(response["success"], false);
}

#[test]
fn exception_filters_stop_only_where_their_condition_holds() {
    // trap.gbas traps in cycle 3 with left = 0 (its first comment).
    let program = fixture("trap.gbas");
    let conditional = |condition: &str| -> Value {
        let mut client = start(json!({ "program": program, "maxCycles": 6 }));
        let body = client.ok(
            "setExceptionBreakpoints",
            json!({ "filters": [], "filterOptions": [{ "filterId": "trap", "condition": condition }] }),
        );
        assert_eq!(body["breakpoints"][0]["verified"], true, "{body}");
        client.ok("continue", json!({ "threadId": 1 }));
        loop {
            let message = client.next_message();
            if message["type"] == "event"
                && (message["event"] == "stopped" || message["event"] == "terminated")
            {
                break message;
            }
        }
    };
    let stop = conditional("left = 0");
    assert_eq!(stop["event"], "stopped");
    assert_eq!(stop["body"]["reason"], "exception");
    // The condition is false at the trap: the run goes on to its end.
    assert_eq!(conditional("left = 5")["event"], "terminated");
    // A condition that is not an expression is refused, the filter stays off.
    let mut client = start(json!({ "program": program }));
    let body = client.ok(
        "setExceptionBreakpoints",
        json!({ "filters": ["overrun"], "filterOptions": [{ "filterId": "trap", "condition": "left = (" }] }),
    );
    assert_eq!(body["breakpoints"][0]["verified"], true);
    assert_eq!(body["breakpoints"][1]["verified"], false);
    let response = client.request(
        "setExceptionBreakpoints",
        Some(json!({ "filters": [], "filterOptions": [{ "filterId": "segfault" }] })),
    );
    assert_eq!(response["success"], false);
}

#[test]
fn cancel_stops_a_long_forward_run_through_its_progress() {
    // The default battery ends endless.mi after about 500,000 cycles, which a fast
    // machine flies in under the second a progress update waits for: a gloc.toml
    // beside the script gives it the largest battery allowed (100,000 Wh, about
    // 14 million cycles), so the run lasts until it is cancelled.
    let folder = gloc_testsupport::scratch_dir("dap-cancel");
    std::fs::create_dir_all(&folder).expect("temporary folder");
    std::fs::copy(fixture("fig3.gbas"), folder.join("fig3.gbas")).expect("copy the script");
    std::fs::write(
        folder.join("gloc.toml"),
        "[simulator]\nbattery_wh = 100000\n",
    )
    .expect("write gloc.toml");
    let mut client = start(json!({
        "program": folder.join("fig3.gbas"),
        "mission": fixture("endless.mi"),
    }));
    client.ok("continue", json!({ "threadId": 1 }));
    let progress = client.event("progressStart");
    assert_eq!(progress["body"]["cancellable"], true);
    let id = progress["body"]["progressId"].clone();
    // Once a second the progress says which cycle the run is in.
    let update = client.event("progressUpdate");
    assert_eq!(update["body"]["progressId"], id);
    let message = update["body"]["message"].as_str().unwrap_or_default();
    let cycle: u64 = message
        .strip_prefix("cycle ")
        .and_then(|number| number.parse().ok())
        .unwrap_or_else(|| panic!("{message}"));
    assert!(cycle > 0, "{message}");
    client.ok("cancel", json!({ "progressId": id }));
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "pause");
    assert!(stop["description"]
        .as_str()
        .unwrap_or_default()
        .contains("cancelled"));
    let end = client.event("progressEnd");
    assert_eq!(end["body"]["progressId"], id);
    // Stopped where the run was: the program goes on from there.
    client.ok("stackTrace", json!({ "threadId": 1 }));
}

#[test]
fn cancel_stops_a_reverse_run() {
    let mut client = start(json!({
        "program": fixture("fig3.gbas"),
        "mission": fixture("endless.mi"),
    }));
    for _ in 0..40 {
        next(&mut client);
    }
    // The cancel is read before the reverse run starts (it names the run's seq in
    // advance), so the run gives up at its first look: where it started, all checked.
    let reverse = client.next_seq_peek();
    let seq = client.send("cancel", Some(json!({ "requestId": reverse + 1 })));
    assert_eq!(seq, reverse);
    let reverse_seq = client.send("reverseContinue", Some(json!({ "threadId": 1 })));
    assert_eq!(reverse_seq, reverse + 1);
    assert_eq!(client.response(reverse_seq)["success"], true);
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "pause");
    assert!(
        stop["description"]
            .as_str()
            .unwrap_or_default()
            .contains("cancelled at cycle 40"),
        "{stop}"
    );
    // Without a cancel the same run goes back to the start.
    client.ok("reverseContinue", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "entry");
}

#[test]
fn overrun_and_abend_filters_take_conditions_too() {
    /// The first `stopped` or `terminated` after `continue`.
    fn outcome(client: &mut Client) -> Value {
        client.ok("continue", json!({ "threadId": 1 }));
        loop {
            let message = client.next_message();
            if message["type"] == "event"
                && (message["event"] == "stopped" || message["event"] == "terminated")
            {
                return message;
            }
        }
    }
    // overrun.gloc with a budget of 1,000 traps on its 1,000th instruction, the add of
    // the 250th pass (2 loads, then 4 instructions a pass: 4 × 250 = 1,000): r0 = 250.
    for (condition, expected) in [("r0 = 250", "stopped"), ("r0 = 249", "terminated")] {
        let mut client = start(json!({
            "program": fixture("overrun.gloc"), "cycleBudget": 1000, "maxCycles": 3,
        }));
        client.ok(
            "setExceptionBreakpoints",
            json!({ "filters": [], "filterOptions": [{ "filterId": "overrun", "condition": condition }] }),
        );
        let event = outcome(&mut client);
        assert_eq!(event["event"], expected, "{condition}: {event}");
        if expected == "stopped" {
            assert_eq!(event["body"]["reason"], "exception");
        }
    }
    // abend.mi aborts for overdepth at 10 m (dap/tests/debugging.rs checks the depth).
    for (condition, expected) in [("m_depth > 5", "stopped"), ("m_depth < 0", "terminated")] {
        let mut client = start(json!({
            "program": fixture("fig3.gbas"), "mission": fixture("abend.mi"), "history": false,
        }));
        client.ok(
            "setExceptionBreakpoints",
            json!({ "filters": [], "filterOptions": [{ "filterId": "abend", "condition": condition }] }),
        );
        let event = outcome(&mut client);
        assert_eq!(event["event"], expected, "{condition}: {event}");
    }
}

#[test]
fn vehicle_values_are_not_rounded() {
    // Fig. 3 under the default mission: by cycle 40 the glider dives, pitched down.
    let mut client = start(json!({ "program": fixture("fig3.gbas") }));
    for _ in 0..40 {
        next(&mut client);
    }
    let vehicle = support::values(&mut client, support::VEHICLE);
    let get = |name: &str| -> f64 {
        vehicle
            .iter()
            .find(|(known, _)| known == name)
            .and_then(|(_, value)| value.parse().ok())
            .unwrap_or_else(|| panic!("no number for `{name}` in {vehicle:?}"))
    };
    let radians = get("pitch (rad)");
    assert!(radians != 0.0);
    // Both are the shortest texts that read back exactly, so the degrees are the
    // radians' `to_degrees` to the last bit (two decimals, as before, are not).
    assert_eq!(get("pitch (deg)").to_bits(), radians.to_degrees().to_bits());
}

#[test]
fn cancel_names_a_forward_run_by_its_request() {
    // No progress reporting: the run is named by the `continue` that started it.
    let mut client = Client::start();
    client.ok("initialize", json!({ "adapterID": "gloc" }));
    client.ok(
        "launch",
        json!({ "program": fixture("fig3.gbas"), "mission": fixture("endless.mi"), "stopOnEntry": true }),
    );
    client.event("initialized");
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    let run = client.send("continue", Some(json!({ "threadId": 1 })));
    assert_eq!(client.response(run)["success"], true);
    client.ok("cancel", json!({ "requestId": run }));
    let stop = stopped(&mut client);
    assert_eq!(stop["reason"], "pause");
    let description = stop["description"].as_str().unwrap_or_default();
    assert!(
        description.starts_with("Run cancelled at cycle "),
        "{description}"
    );
    assert!(
        !client
            .received
            .iter()
            .any(|message| message["event"] == "progressStart"),
        "no progress for a client that did not ask for them"
    );
    // A cancel of what is over changes nothing: the next run goes on until cancelled.
    client.ok("cancel", json!({ "requestId": 1 }));
    client.ok("next", json!({ "threadId": 1 }));
    assert_eq!(stopped(&mut client)["reason"], "step");
}
