//! Malformed input never crashes the adapter: each bad message gets an error response
//! (validated against the schema, with `command`), and the session goes on.

mod support;

use serde_json::json;
use support::Client;

fn initialize(client: &mut Client) {
    let body = client.ok(
        "initialize",
        json!({ "clientID": "test", "adapterID": "gloc", "linesStartAt1": true }),
    );
    assert_eq!(body["supportsConfigurationDoneRequest"], true);
}

#[test]
fn bad_json_gets_an_error_response_and_the_session_goes_on() {
    let mut client = Client::start();
    client.send_body("{\"seq\": 1, \"type\": \"request\", \"command\": \"threads\", ");
    let response = client.next_message();
    assert_eq!(response["type"], "response");
    assert_eq!(response["success"], false);
    assert_eq!(response["request_seq"], 1);
    assert_eq!(response["command"], "threads");
    assert!(
        response["message"]
            .as_str()
            .unwrap_or_default()
            .contains("not valid JSON"),
        "{response}"
    );
    // With no recoverable seq there is no request to answer: the error is reported as output.
    client.send_body("{{{");
    let event = client.next_message();
    assert_eq!(event["event"], "output");
    assert!(
        event["body"]["output"]
            .as_str()
            .unwrap_or_default()
            .contains("not valid JSON"),
        "{event}"
    );
    initialize(&mut client);
}

#[test]
fn a_message_that_is_not_a_request_gets_an_error() {
    let mut client = Client::start();
    client.send_body(r#"{"seq":5,"type":"event","event":"stopped"}"#);
    let response = client.next_message();
    assert_eq!(response["success"], false);
    assert_eq!(response["request_seq"], 5);
    client.send_body(r#"{"seq":6,"type":"request","command":["threads"]}"#);
    let response = client.next_message();
    assert_eq!(response["success"], false);
    assert_eq!(response["request_seq"], 6);
    assert!(
        response["message"]
            .as_str()
            .unwrap_or_default()
            .contains("command"),
        "{response}"
    );
    client.send_body(r#"{"type":"request","command":"threads"}"#);
    let event = client.next_message();
    assert_eq!(event["event"], "output");
    assert!(
        event["body"]["output"]
            .as_str()
            .unwrap_or_default()
            .contains("seq"),
        "{event}"
    );
    client.send_body("[]");
    assert_eq!(client.next_message()["event"], "output");
}

#[test]
fn unknown_commands_get_an_error_naming_the_command() {
    let mut client = Client::start();
    initialize(&mut client);
    let response = client.request("gloc/frobnicate", None);
    assert_eq!(response["success"], false);
    assert_eq!(response["command"], "gloc/frobnicate");
    assert!(response["message"]
        .as_str()
        .unwrap_or_default()
        .contains("unknown command"));
    let response = client.request("locations", Some(json!({ "locationReference": 3 })));
    assert_eq!(response["success"], false);
    assert_eq!(response["command"], "locations");
}

#[test]
fn wrong_argument_types_get_an_error() {
    let mut client = Client::start();
    let response = client.request("initialize", Some(json!({ "linesStartAt1": "yes" })));
    assert_eq!(response["success"], false);
    assert!(
        response["message"]
            .as_str()
            .unwrap_or_default()
            .contains("invalid arguments"),
        "{response}"
    );
    initialize(&mut client);
    let response = client.request("launch", Some(json!({ "program": 42 })));
    assert_eq!(response["success"], false);
    let response = client.request(
        "launch",
        Some(json!({ "program": "x.gbas", "seed": "seven" })),
    );
    assert_eq!(response["success"], false);
    let response = client.request("setBreakpoints", Some(json!({ "source": { "path": 3 } })));
    assert_eq!(response["success"], false);
    let response = client.request("next", Some(json!({ "threadId": "one" })));
    assert_eq!(response["success"], false);
    let response = client.request("launch", Some(json!([1, 2])));
    assert_eq!(response["success"], false);
}

#[test]
fn requests_before_launch_get_an_error_each() {
    let mut client = Client::start();
    let response = client.request("launch", Some(json!({ "program": "a.gbas" })));
    assert_eq!(
        response["success"], false,
        "launch before initialize: {response}"
    );
    initialize(&mut client);
    for command in [
        "configurationDone",
        "continue",
        "next",
        "stepIn",
        "stepOut",
        "stepBack",
        "reverseContinue",
        "pause",
        "stackTrace",
        "scopes",
        "variables",
        "evaluate",
        "setVariable",
        "disassemble",
        "dataBreakpointInfo",
        "restart",
    ] {
        let response = client.request(command, Some(json!({ "threadId": 1 })));
        assert_eq!(response["success"], false, "{command}: {response}");
        assert!(
            response["message"]
                .as_str()
                .unwrap_or_default()
                .contains("launch"),
            "{command}: {response}"
        );
    }
    // Threads are always answerable.
    let body = client.ok("threads", json!({}));
    assert_eq!(body["threads"][0]["id"], 1);
}

#[test]
fn launch_without_program_says_what_to_do() {
    let mut client = Client::start();
    initialize(&mut client);
    let response = client.request("launch", Some(json!({})));
    assert_eq!(response["success"], false);
    assert!(
        response["message"]
            .as_str()
            .unwrap_or_default()
            .contains("`program`"),
        "{response}"
    );
    let response = client.request(
        "launch",
        Some(json!({ "program": "x.gbas", "history": "lots" })),
    );
    assert_eq!(response["success"], false);
    assert!(
        response["message"]
            .as_str()
            .unwrap_or_default()
            .contains("history"),
        "{response}"
    );
}

#[test]
fn absent_null_and_empty_arguments_all_work() {
    let mut client = Client::start();
    initialize(&mut client);
    for arguments in [None, Some(serde_json::Value::Null), Some(json!({}))] {
        let response = client.request("threads", arguments);
        assert_eq!(response["success"], true, "{response}");
    }
    let response = client.request("disconnect", None);
    assert_eq!(response["success"], true);
    assert!(client.join(), "the adapter did not stop after disconnect");
}

#[test]
fn extra_headers_are_accepted() {
    let mut client = Client::start();
    let body =
        r#"{"seq":1,"type":"request","command":"initialize","arguments":{"adapterID":"gloc"}}"#;
    let framed = format!(
        "Content-Type: application/vscode-jsonrpc; charset=utf-8\r\nContent-Length: {}\r\n\r\n{}",
        body.len(),
        body
    );
    client.send_raw(framed.as_bytes());
    let response = client.next_message();
    assert_eq!(response["success"], true, "{response}");
}

#[test]
fn closing_the_stream_ends_the_session() {
    let mut client = Client::start();
    initialize(&mut client);
    client.close();
    assert!(
        client.join(),
        "the adapter did not stop when its input closed"
    );
}

#[test]
fn garbage_bytes_do_not_crash() {
    let mut client = Client::start();
    client.send_raw(b"\xff\xfe garbage without headers\r\n\r\n");
    assert_eq!(client.next_message()["event"], "output");
    client.send_raw(b"Content-Length: 4\r\n\r\n\xff\xff\xff\xff");
    assert_eq!(client.next_message()["event"], "output");
    initialize(&mut client);
}

/// Every command the adapter knows, after launch, with arguments of the wrong shape or
/// absurd values: an answer each (validated), never a crash, and the session still works.
#[test]
fn hostile_arguments_after_launch_never_crash() {
    let mut client = Client::start();
    initialize(&mut client);
    let program = format!("{}/tests/fixtures/fig3.gbas", env!("CARGO_MANIFEST_DIR"));
    client.ok("launch", json!({ "program": program, "stopOnEntry": true }));
    client.ok("configurationDone", json!({}));
    client.event("stopped");
    let commands = [
        "setBreakpoints",
        "setFunctionBreakpoints",
        "setExceptionBreakpoints",
        "setInstructionBreakpoints",
        "dataBreakpointInfo",
        "setDataBreakpoints",
        "breakpointLocations",
        "stackTrace",
        "scopes",
        "variables",
        "setVariable",
        "evaluate",
        "exceptionInfo",
        "disassemble",
        "loadedSources",
        "threads",
    ];
    let hostile = [
        json!({ "threadId": "one", "variablesReference": [], "source": 5, "breakpoints": "all" }),
        json!({ "variablesReference": -7, "start": -5, "count": -1, "name": "", "value": "" }),
        json!({ "variablesReference": i64::MAX, "start": i64::MAX, "count": i64::MAX }),
        json!({ "memoryReference": "0xffffffffffffffffff", "instructionCount": i64::MAX, "offset": i64::MIN }),
        json!({ "memoryReference": "-0x10", "instructionOffset": -3, "instructionCount": 5 }),
        json!({ "expression": "(((((", "name": "m_depth", "value": "1e999", "variablesReference": 3 }),
        json!({ "breakpoints": [{ "line": -1 }, { "line": i64::MAX, "hitCondition": "% 0" }], "source": { "path": program } }),
        json!({ "breakpoints": [{ "name": "cycle -1" }, { "name": "every 0" }, { "dataId": "sensor:nope" }, { "instructionReference": "zz" }] }),
        json!({ "filters": [1, 2] }),
        json!(null),
        json!([]),
        json!("text"),
    ];
    for command in commands {
        for arguments in &hostile {
            let response = client.request(command, Some(arguments.clone()));
            assert_eq!(response["command"], command);
        }
    }
    // Still debugging.
    client.ok("next", json!({ "threadId": 1 }));
    let stop = client.event("stopped");
    assert_eq!(stop["body"]["reason"], "step");
    let body = client.ok("stackTrace", json!({ "threadId": 1 }));
    assert_eq!(body["stackFrames"][0]["line"], 7);
}

#[test]
fn a_seq_outside_the_schema_range_is_reported_and_not_run() {
    let mut client = Client::start();
    initialize(&mut client);
    // 0 and −1 are below the schema's minimum of 1; 2^63 and 2^31 do not fit its int32.
    for seq in ["0", "-1", "9223372036854775808", "2147483648"] {
        client.send_body(&format!(
            r#"{{"seq":{seq},"type":"request","command":"disconnect"}}"#
        ));
        // No response can name the request: an output event does, with the seq as sent.
        let event = client.next_message();
        assert_eq!(event["event"], "output", "{event}");
        assert_eq!(event["body"]["data"]["seq"].to_string(), seq, "{event}");
        assert_eq!(event["body"]["data"]["command"], "disconnect", "{event}");
        assert!(
            event["body"]["output"]
                .as_str()
                .unwrap_or_default()
                .contains("not run"),
            "{event}"
        );
    }
    // The `disconnect`s were not run: the session still answers.
    let response = client.request("threads", None);
    assert_eq!(response["success"], true, "{response}");
}

#[test]
fn a_lone_surrogate_in_a_request_is_decoded_lossily() {
    let mut client = Client::start();
    initialize(&mut client);
    client.send_body(
        r#"{"seq":50,"type":"request","command":"evaluate","arguments":{"expression":"x\ud83d"}}"#,
    );
    let response = client.response(50);
    // Answered (nothing is launched), not refused as broken JSON.
    assert_eq!(response["command"], "evaluate", "{response}");
    assert!(
        !response["message"]
            .as_str()
            .unwrap_or_default()
            .contains("not valid JSON"),
        "{response}"
    );
}
