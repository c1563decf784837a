//! Protocol abuse of the real `gloc lsp` and `gloc dap` processes: truncated
//! frames, wrong `Content-Length`, huge messages, invalid UTF-8, requests out
//! of order and a client that vanishes. Each case must end in an error
//! response or a clean exit: no hang (every wait has a deadline), no panic
//! (stderr is checked), no process left behind (every child is waited for).
//! Every message `gloc dap` sends is validated against the official DAP JSON schema
//! with the adapter tests' own validator.

use std::io::{Read, Write};
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::thread;
use std::time::{Duration, Instant};

use serde_json::{json, Value};

#[path = "../../dap/tests/support/schema.rs"]
mod dap_schema;

/// Far longer than any case needs; only a hang reaches it.
const DEADLINE: Duration = Duration::from_secs(30);

/// A running `gloc` server with its output read on background threads.
struct Server {
    child: Child,
    stdin: Option<ChildStdin>,
    messages: Receiver<Value>,
    stderr: Receiver<String>,
    /// The DAP schema for `gloc dap`, whose every message is validated.
    schema: Option<dap_schema::Schema>,
    /// Messages validated so far.
    validated: usize,
    /// Every message taken from the server so far, in order.
    received: Vec<Value>,
}

impl Server {
    fn start(subcommand: &str) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_gloc"))
            .arg(subcommand)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start gloc");
        let stdin = child.stdin.take();
        let mut stdout = child.stdout.take().expect("stdout is piped");
        let mut stderr = child.stderr.take().expect("stderr is piped");
        let (message_sender, messages) = mpsc::channel();
        thread::spawn(move || {
            let mut bytes = Vec::new();
            let mut chunk = [0u8; 1 << 16];
            loop {
                match stdout.read(&mut chunk) {
                    Ok(0) | Err(_) => return,
                    Ok(count) => bytes.extend_from_slice(&chunk[..count]),
                }
                while let Some((message, used)) = take_frame(&bytes) {
                    bytes.drain(..used);
                    if message_sender.send(message).is_err() {
                        return;
                    }
                }
            }
        });
        let (stderr_sender, stderr_receiver) = mpsc::channel();
        thread::spawn(move || {
            let mut text = Vec::new();
            let _ = stderr.read_to_end(&mut text);
            let _ = stderr_sender.send(String::from_utf8_lossy(&text).into_owned());
        });
        Server {
            child,
            stdin,
            messages,
            stderr: stderr_receiver,
            schema: (subcommand == "dap").then(dap_schema::Schema::dap),
            validated: 0,
            received: Vec::new(),
        }
    }

    /// Writes raw bytes; a server that already exited is not an error here
    /// (the test then checks how it exited).
    fn send_bytes(&mut self, bytes: &[u8]) {
        if let Some(stdin) = &mut self.stdin {
            let _ = stdin.write_all(bytes).and_then(|()| stdin.flush());
        }
    }

    fn send(&mut self, message: &Value) {
        self.send_bytes(&frame(message.to_string().as_bytes()));
    }

    /// The next message that satisfies `wanted`, skipping others.
    fn wait_for(&mut self, what: &str, wanted: impl Fn(&Value) -> bool) -> Value {
        let deadline = Instant::now() + DEADLINE;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.messages.recv_timeout(left) {
                Ok(message) => {
                    self.check(&message);
                    if wanted(&message) {
                        return message;
                    }
                }
                Err(RecvTimeoutError::Timeout) => {
                    self.kill();
                    panic!("no {what} within {DEADLINE:?}: the server hangs");
                }
                Err(RecvTimeoutError::Disconnected) => {
                    let ending = self.finish();
                    panic!("the server closed its output before {what}: {ending:?}");
                }
            }
        }
    }

    /// Closes stdin and waits for the exit; returns its status and stderr.
    fn finish(&mut self) -> (ExitStatus, String) {
        self.stdin = None;
        let deadline = Instant::now() + DEADLINE;
        loop {
            if let Some(status) = self.child.try_wait().expect("wait for gloc") {
                let stderr = self
                    .stderr
                    .recv_timeout(DEADLINE)
                    .expect("stderr closes with the process");
                // What was sent but not waited for is validated too.
                while let Ok(message) = self.messages.recv_timeout(DEADLINE) {
                    self.check(&message);
                }
                assert!(
                    !stderr.contains("panicked"),
                    "the server panicked: {stderr}"
                );
                return (status, stderr);
            }
            if Instant::now() > deadline {
                self.kill();
                panic!("the server did not exit within {DEADLINE:?} after its input closed");
            }
            thread::sleep(Duration::from_millis(20));
        }
    }

    /// For `gloc dap`: the message must satisfy the DAP schema.
    fn check(&mut self, message: &Value) {
        if let Some(schema) = &self.schema {
            let errors = schema.validate_message(message);
            assert!(
                errors.is_empty(),
                "message violates the DAP schema: {message}\n{}",
                errors.join("\n")
            );
            self.validated += 1;
        }
        self.received.push(message.clone());
    }

    fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        // A failed assertion must not leave a process behind either.
        if matches!(self.child.try_wait(), Ok(None)) {
            self.kill();
        }
    }
}

fn frame(body: &[u8]) -> Vec<u8> {
    let mut bytes = format!("Content-Length: {}\r\n\r\n", body.len()).into_bytes();
    bytes.extend_from_slice(body);
    bytes
}

/// One complete frame from the front of `bytes`, as JSON, and its length.
fn take_frame(bytes: &[u8]) -> Option<(Value, usize)> {
    let header_end = bytes.windows(4).position(|window| window == b"\r\n\r\n")?;
    let header = std::str::from_utf8(&bytes[..header_end]).expect("ASCII headers");
    let length: usize = header
        .lines()
        .find_map(|line| line.strip_prefix("Content-Length: "))
        .expect("every frame from the server has a Content-Length")
        .trim()
        .parse()
        .expect("a numeric Content-Length");
    let body_start = header_end + 4;
    let body = bytes.get(body_start..body_start + length)?;
    let message = serde_json::from_slice(body).expect("the server writes valid JSON");
    Some((message, body_start + length))
}

fn clean_exit(status: ExitStatus) -> bool {
    // An exit code (0 or 1), never a signal such as SIGABRT from a panic=abort.
    status.code().is_some_and(|code| code == 0 || code == 1)
}

// ---------------------------------------------------------------- LSP

fn lsp_request(id: i64, method: &str, params: Value) -> Value {
    json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params })
}

fn lsp_response(server: &mut Server, id: i64) -> Value {
    server.wait_for(&format!("a response to request {id}"), |message| {
        message.get("id") == Some(&json!(id)) && message.get("method").is_none()
    })
}

fn lsp_initialized() -> Server {
    let mut server = Server::start("lsp");
    server.send(&lsp_request(
        1,
        "initialize",
        json!({ "processId": null, "rootUri": null, "capabilities": {} }),
    ));
    let response = lsp_response(&mut server, 1);
    assert!(response["result"]["capabilities"].is_object(), "{response}");
    server.send(&json!({ "jsonrpc": "2.0", "method": "initialized", "params": {} }));
    server
}

/// The server still works: a request after the abuse gets its answer.
fn lsp_still_answers(server: &mut Server, id: i64) {
    server.send(&lsp_request(
        id,
        "workspace/executeCommand",
        json!({ "command": "gloc.noSuchCommand", "arguments": [] }),
    ));
    let response = lsp_response(server, id);
    assert!(response["error"]["message"].is_string(), "{response}");
}

fn lsp_shutdown_and_exit(mut server: Server, id: i64) {
    server.send(&lsp_request(id, "shutdown", Value::Null));
    let response = lsp_response(&mut server, id);
    assert!(response.get("error").is_none(), "{response}");
    server.send(&json!({ "jsonrpc": "2.0", "method": "exit" }));
    let (status, _) = server.finish();
    assert_eq!(status.code(), Some(0), "exit after shutdown is exit code 0");
}

#[test]
fn lsp_truncated_frame_then_end_of_input_exits_cleanly() {
    let mut server = lsp_initialized();
    server.send_bytes(b"Content-Length: 200\r\n\r\n{\"jsonrpc\":\"2.0\",\"id\":7,");
    let (status, _) = server.finish();
    assert!(clean_exit(status), "{status:?}");
}

#[test]
fn lsp_truncated_header_then_end_of_input_exits_cleanly() {
    let mut server = lsp_initialized();
    server.send_bytes(b"Content-Len");
    let (status, _) = server.finish();
    assert!(clean_exit(status), "{status:?}");
}

#[test]
fn lsp_wrong_content_length_too_short_gets_an_error_and_the_server_goes_on() {
    let mut server = lsp_initialized();
    let body = lsp_request(2, "shutdown", Value::Null).to_string();
    // Ten bytes too few: the body is cut (invalid JSON) and its tail is
    // left in front of the next header.
    let mut bytes = format!("Content-Length: {}\r\n\r\n", body.len() - 10).into_bytes();
    bytes.extend_from_slice(body.as_bytes());
    // The cut tail joins the next header block; a blank line ends that block
    // so that the next real frame is read (without it that frame is lost,
    // which is all a server can do once a client breaks the framing).
    bytes.extend_from_slice(b"\r\n\r\n");
    server.send_bytes(&bytes);
    lsp_still_answers(&mut server, 3);
    lsp_shutdown_and_exit(server, 4);
}

#[test]
fn lsp_wrong_content_length_too_long_swallows_the_next_message_only() {
    let mut server = lsp_initialized();
    let body = lsp_request(2, "gloc/nothing", Value::Null).to_string();
    let next = lsp_request(3, "gloc/nothing", Value::Null).to_string();
    // The length covers this body and the whole next frame: one bad message.
    let mut bytes = format!(
        "Content-Length: {}\r\n\r\n",
        body.len() + frame(next.as_bytes()).len()
    )
    .into_bytes();
    bytes.extend_from_slice(body.as_bytes());
    bytes.extend_from_slice(&frame(next.as_bytes()));
    server.send_bytes(&bytes);
    lsp_still_answers(&mut server, 4);
    lsp_shutdown_and_exit(server, 5);
}

#[test]
fn lsp_non_numeric_and_missing_content_length_are_skipped() {
    let mut server = lsp_initialized();
    server.send_bytes(b"Content-Length: lots\r\n\r\n");
    server.send_bytes(b"Content-Type: text/plain\r\n\r\n");
    lsp_still_answers(&mut server, 2);
    lsp_shutdown_and_exit(server, 3);
}

#[test]
fn lsp_invalid_utf8_body_is_skipped_and_the_server_goes_on() {
    let mut server = lsp_initialized();
    let mut body =
        br#"{"jsonrpc":"2.0","id":2,"method":"textDocument/hover","params":{"x":""#.to_vec();
    body.extend_from_slice(&[0xff, 0xfe, 0xc3]);
    body.extend_from_slice(br#""}}"#);
    server.send_bytes(&frame(&body));
    // The broken body has no readable id, so no response can name it; what
    // matters is that the next request is answered.
    lsp_still_answers(&mut server, 3);
    lsp_shutdown_and_exit(server, 4);
}

#[test]
fn lsp_invalid_utf8_in_a_document_does_not_kill_the_server() {
    let mut server = lsp_initialized();
    let mut body = br#"{"jsonrpc":"2.0","method":"textDocument/didOpen","params":{"textDocument":{"uri":"file:///tmp/abuse.gloc","languageId":"gloc","version":1,"text":"nregs 1\n"#.to_vec();
    body.extend_from_slice(&[0xc0, 0x80, 0xed, 0xa0, 0x80]);
    body.extend_from_slice(br#""}}}"#);
    server.send_bytes(&frame(&body));
    lsp_still_answers(&mut server, 2);
    lsp_shutdown_and_exit(server, 3);
}

#[test]
fn lsp_huge_declared_length_is_refused_without_reading_it() {
    let mut server = lsp_initialized();
    // 10 GB announced, nothing sent: the server must neither allocate it nor
    // wait for it forever once the input ends.
    server.send_bytes(b"Content-Length: 10000000000\r\n\r\n{}");
    let (status, _) = server.finish();
    assert!(clean_exit(status), "{status:?}");
}

#[test]
fn lsp_huge_message_is_handled() {
    let mut server = lsp_initialized();
    // A 32 MB document (one long comment line plus a valid header).
    let text = format!(
        "nregs 1\nnblbs 0\nninstr 1\nyield # {}\n",
        "x".repeat(32 << 20)
    );
    server.send(&json!({ "jsonrpc": "2.0", "method": "textDocument/didOpen",
        "params": { "textDocument": { "uri": "file:///tmp/huge.gloc", "languageId": "gloc",
                                      "version": 1, "text": text } } }));
    let published = server.wait_for("diagnostics for the huge document", |message| {
        message["method"] == "textDocument/publishDiagnostics"
            && message["params"]["uri"] == "file:///tmp/huge.gloc"
    });
    assert!(published["params"]["diagnostics"].is_array(), "{published}");
    lsp_still_answers(&mut server, 2);
    lsp_shutdown_and_exit(server, 3);
}

#[test]
fn lsp_requests_before_initialize_are_refused() {
    let mut server = Server::start("lsp");
    server.send(&lsp_request(
        1,
        "textDocument/hover",
        json!({ "textDocument": { "uri": "file:///tmp/a.gloc" },
                "position": { "line": 0, "character": 0 } }),
    ));
    let response = lsp_response(&mut server, 1);
    // -32002: ServerNotInitialized.
    assert_eq!(response["error"]["code"], json!(-32002), "{response}");
    server.send(&lsp_request(2, "shutdown", Value::Null));
    let response = lsp_response(&mut server, 2);
    assert!(response.get("error").is_some(), "{response}");
    let (status, _) = server.finish();
    assert!(clean_exit(status), "{status:?}");
}

#[test]
fn lsp_requests_after_shutdown_are_refused() {
    let mut server = lsp_initialized();
    server.send(&lsp_request(2, "shutdown", Value::Null));
    lsp_response(&mut server, 2);
    server.send(&lsp_request(
        3,
        "textDocument/hover",
        json!({ "textDocument": { "uri": "file:///tmp/a.gloc" },
                "position": { "line": 0, "character": 0 } }),
    ));
    let response = lsp_response(&mut server, 3);
    // -32600: InvalidRequest after shutdown.
    assert!(response.get("error").is_some(), "{response}");
    server.send(&json!({ "jsonrpc": "2.0", "method": "exit" }));
    let (status, _) = server.finish();
    assert_eq!(status.code(), Some(0));
}

#[test]
fn lsp_second_initialize_and_edits_to_unopened_documents_are_harmless() {
    let mut server = lsp_initialized();
    server.send(&lsp_request(
        2,
        "initialize",
        json!({ "processId": null, "rootUri": null, "capabilities": {} }),
    ));
    let response = lsp_response(&mut server, 2);
    assert!(response.get("error").is_some(), "{response}");
    server.send(
        &json!({ "jsonrpc": "2.0", "method": "textDocument/didChange",
        "params": { "textDocument": { "uri": "file:///tmp/never-opened.gloc", "version": 9 },
                    "contentChanges": [{ "text": "yield\n" }] } }),
    );
    server.send(
        &json!({ "jsonrpc": "2.0", "method": "textDocument/didClose",
        "params": { "textDocument": { "uri": "file:///tmp/never-opened.gloc" } } }),
    );
    lsp_still_answers(&mut server, 3);
    lsp_shutdown_and_exit(server, 4);
}

#[test]
fn lsp_client_that_vanishes_mid_session_leaves_no_process() {
    let mut server = lsp_initialized();
    server.send(&json!({ "jsonrpc": "2.0", "method": "textDocument/didOpen",
        "params": { "textDocument": { "uri": "file:///tmp/gone.gloc", "languageId": "gloc",
                                      "version": 1, "text": "nregs 1\n" } } }));
    // Half a request, then the client is gone (stdin closed, stdout unread).
    server.send_bytes(b"Content-Length: 90\r\n\r\n{\"jsonrpc\"");
    let (status, _) = server.finish();
    assert_eq!(
        status.code(),
        Some(1),
        "exit without shutdown is exit code 1"
    );
}

// ---------------------------------------------------------------- DAP

fn dap_request(seq: i64, command: &str, arguments: Value) -> Value {
    json!({ "seq": seq, "type": "request", "command": command, "arguments": arguments })
}

fn dap_response(server: &mut Server, seq: i64) -> Value {
    server.wait_for(&format!("a response to request {seq}"), |message| {
        message["type"] == "response" && message["request_seq"] == json!(seq)
    })
}

fn dap_initialized() -> Server {
    let mut server = Server::start("dap");
    server.send(&dap_request(
        1,
        "initialize",
        json!({ "adapterID": "gloc", "linesStartAt1": true, "columnsStartAt1": true }),
    ));
    let response = dap_response(&mut server, 1);
    assert_eq!(response["success"], json!(true), "{response}");
    server
}

/// The adapter still works: a request after the abuse gets its answer.
fn dap_still_answers(server: &mut Server, seq: i64) {
    server.send(&dap_request(seq, "threads", json!({})));
    let response = dap_response(server, seq);
    assert!(response["success"].is_boolean(), "{response}");
}

/// The text of the `output` event that reports an ignored malformed message.
fn dap_malformed_report(server: &mut Server) -> String {
    let event = server.wait_for("an output event about the malformed message", |message| {
        message["type"] == "event"
            && message["event"] == "output"
            && message["body"]["output"]
                .as_str()
                .is_some_and(|text| text.contains("malformed"))
    });
    event["body"]["output"]
        .as_str()
        .unwrap_or_default()
        .to_string()
}

fn dap_disconnect(mut server: Server, seq: i64) {
    server.send(&dap_request(seq, "disconnect", json!({})));
    let response = dap_response(&mut server, seq);
    assert_eq!(response["success"], json!(true), "{response}");
    let (status, _) = server.finish();
    assert!(clean_exit(status), "{status:?}");
    // At least initialize's response and this disconnect's were checked.
    assert!(
        server.validated >= 2,
        "{} messages validated",
        server.validated
    );
}

#[test]
fn dap_truncated_frame_then_end_of_input_exits_cleanly() {
    let mut server = dap_initialized();
    server.send_bytes(b"Content-Length: 300\r\n\r\n{\"seq\":2,\"type\":\"requ");
    let (status, _) = server.finish();
    assert!(clean_exit(status), "{status:?}");
}

#[test]
fn dap_wrong_content_length_too_short_gets_an_error_and_the_adapter_goes_on() {
    let mut server = dap_initialized();
    let body = dap_request(2, "threads", json!({})).to_string();
    let mut bytes = format!("Content-Length: {}\r\n\r\n", body.len() - 5).into_bytes();
    bytes.extend_from_slice(body.as_bytes());
    // The cut tail becomes the start of the next header block; a blank line
    // ends that block so the next real frame can be read.
    bytes.extend_from_slice(b"\r\n\r\n");
    server.send_bytes(&bytes);
    let error = server.wait_for("an error response for the cut body", |message| {
        message["type"] == "response" && message["success"] == json!(false)
    });
    assert!(error["message"].is_string(), "{error}");
    dap_still_answers(&mut server, 3);
    dap_disconnect(server, 4);
}

#[test]
fn dap_wrong_content_length_too_long_swallows_the_next_message_only() {
    let mut server = dap_initialized();
    let body = dap_request(2, "threads", json!({})).to_string();
    let next = dap_request(3, "threads", json!({})).to_string();
    // The length covers this body and the whole next frame: one bad message, whose
    // `seq` (2) can be read from its text, so it gets an error response.
    let mut bytes = format!(
        "Content-Length: {}\r\n\r\n",
        body.len() + frame(next.as_bytes()).len()
    )
    .into_bytes();
    bytes.extend_from_slice(body.as_bytes());
    bytes.extend_from_slice(&frame(next.as_bytes()));
    server.send_bytes(&bytes);
    let error = dap_response(&mut server, 2);
    assert_eq!(error["success"], json!(false), "{error}");
    dap_still_answers(&mut server, 4);
    dap_disconnect(server, 5);
}

#[test]
fn dap_wrong_content_length_too_long_then_end_of_input_exits_cleanly() {
    let mut server = dap_initialized();
    let body = dap_request(2, "threads", json!({})).to_string();
    // 100 bytes more than the body: the adapter waits for bytes that never come, until
    // the client closes its input; then it must exit, not hang or crash.
    let mut bytes = format!("Content-Length: {}\r\n\r\n", body.len() + 100).into_bytes();
    bytes.extend_from_slice(body.as_bytes());
    server.send_bytes(&bytes);
    let (status, _) = server.finish();
    assert!(clean_exit(status), "{status:?}");
    // The cut request was never answered as if it were complete.
    assert!(
        !server
            .received
            .iter()
            .any(|message| message["request_seq"] == json!(2) && message["success"] == json!(true)),
        "{:?}",
        server.received
    );
}

#[test]
fn dap_non_numeric_content_length_gets_an_error() {
    let mut server = dap_initialized();
    server.send_bytes(b"Content-Length: many\r\n\r\n");
    // Without a readable `seq` there is no request to answer: the adapter
    // says what it ignored in an `output` event.
    let report = dap_malformed_report(&mut server);
    assert!(report.contains("not a number"), "{report}");
    dap_still_answers(&mut server, 2);
    dap_disconnect(server, 3);
}

#[test]
fn dap_invalid_utf8_body_gets_an_error_response() {
    let mut server = dap_initialized();
    let mut body =
        br#"{"seq":2,"type":"request","command":"evaluate","arguments":{"expression":""#.to_vec();
    body.extend_from_slice(&[0xff, 0xfe]);
    body.extend_from_slice(br#""}}"#);
    server.send_bytes(&frame(&body));
    let error = server.wait_for("an error response for invalid UTF-8", |message| {
        message["type"] == "response" && message["success"] == json!(false)
    });
    assert!(error["message"].is_string(), "{error}");
    dap_still_answers(&mut server, 3);
    dap_disconnect(server, 4);
}

#[test]
fn dap_huge_declared_length_is_refused() {
    let mut server = dap_initialized();
    server.send_bytes(b"Content-Length: 10000000000\r\n\r\n");
    let report = dap_malformed_report(&mut server);
    assert!(report.contains("limit"), "{report}");
    dap_still_answers(&mut server, 2);
    dap_disconnect(server, 3);
}

#[test]
fn dap_huge_message_is_answered() {
    let mut server = dap_initialized();
    // A 16 MB expression: a real body under the 64 MB limit.
    let expression = "1+".repeat(8 << 20) + "1";
    server.send(&dap_request(
        2,
        "evaluate",
        json!({ "expression": expression, "context": "repl" }),
    ));
    let response = dap_response(&mut server, 2);
    assert!(response["success"].is_boolean(), "{}", response["message"]);
    dap_still_answers(&mut server, 3);
    dap_disconnect(server, 4);
}

#[test]
fn dap_requests_out_of_order_get_error_responses() {
    let mut server = Server::start("dap");
    // Stepping, reading variables and continuing before initialize or launch.
    for (seq, command, arguments) in [
        (1, "next", json!({ "threadId": 1 })),
        (2, "variables", json!({ "variablesReference": 7 })),
        (3, "continue", json!({ "threadId": 1 })),
        (4, "stackTrace", json!({ "threadId": 1 })),
        (5, "launch", json!({ "program": "/nonexistent/none.gloc" })),
    ] {
        server.send(&dap_request(seq, command, arguments));
        let response = dap_response(&mut server, seq);
        assert_eq!(
            response["success"],
            json!(false),
            "{command} out of order: {response}"
        );
        assert!(response["message"].is_string(), "{response}");
    }
    let (status, _) = server.finish();
    assert!(clean_exit(status), "{status:?}");
}

#[test]
fn dap_client_that_vanishes_leaves_no_process() {
    let mut server = dap_initialized();
    server.send_bytes(b"Content-Length: 40\r\n\r\n{\"seq\"");
    let (status, _) = server.finish();
    assert!(clean_exit(status), "{status:?}");
}

// ------------------------------------------- LSP: what the spec requires (issue 16)

/// The next message that is a response with `id` null.
fn lsp_null_id_error(server: &mut Server) -> Value {
    server.wait_for("an error response with id null", |message| {
        message.get("id") == Some(&Value::Null) && message.get("error").is_some()
    })
}

#[test]
fn lsp_malformed_json_gets_a_parse_error_with_id_null() {
    let mut server = lsp_initialized();
    server.send_bytes(&frame(b"{ this is not json"));
    let error = lsp_null_id_error(&mut server);
    assert_eq!(error["error"]["code"], json!(-32700), "{error}");
    // Broken framing too: a non-numeric Content-Length, then the server resynchronises.
    server.send_bytes(b"Content-Length: many\r\n\r\n");
    let error = lsp_null_id_error(&mut server);
    assert_eq!(error["error"]["code"], json!(-32700), "{error}");
    assert!(
        error["error"]["message"]
            .as_str()
            .is_some_and(|text| text.contains("`many` is not a number")),
        "{error}"
    );
    lsp_still_answers(&mut server, 2);
    lsp_shutdown_and_exit(server, 3);
}

#[test]
fn lsp_dollar_requests_get_method_not_found() {
    let mut server = lsp_initialized();
    server.send(&lsp_request(2, "$/gloc/unknown", json!({})));
    let response = lsp_response(&mut server, 2);
    assert_eq!(response["error"]["code"], json!(-32601), "{response}");
    // A `$/` notification is ignored, as the spec allows.
    server.send(&json!({ "jsonrpc": "2.0", "method": "$/unknownNotification", "params": {} }));
    lsp_still_answers(&mut server, 3);
    lsp_shutdown_and_exit(server, 4);
}

#[test]
fn lsp_shutdown_then_exit_at_once_exits_zero_every_time() {
    for run in 0..20 {
        let mut server = lsp_initialized();
        // Both in one write, as a client that does not wait for the answer sends them.
        let mut bytes = frame(
            lsp_request(2, "shutdown", Value::Null)
                .to_string()
                .as_bytes(),
        );
        bytes.extend(frame(
            json!({ "jsonrpc": "2.0", "method": "exit" })
                .to_string()
                .as_bytes(),
        ));
        server.send_bytes(&bytes);
        let (status, _) = server.finish();
        assert_eq!(status.code(), Some(0), "run {run}");
    }
}

/// The text the server holds for a GLOC document (its "compiled GLOC" is itself).
fn lsp_text(server: &mut Server, id: i64, uri: &str) -> String {
    server.send(&lsp_request(
        id,
        "workspace/executeCommand",
        json!({ "command": "gloc.compiledGloc", "arguments": [uri] }),
    ));
    let response = lsp_response(server, id);
    response["result"].as_str().unwrap_or_default().to_string()
}

fn lsp_open(server: &mut Server, uri: &str, text: &str) {
    server.send(&json!({ "jsonrpc": "2.0", "method": "textDocument/didOpen",
        "params": { "textDocument": { "uri": uri, "languageId": "gloc", "version": 1, "text": text } } }));
}

#[test]
fn lsp_a_version_going_backwards_is_ignored_and_logged() {
    let mut server = lsp_initialized();
    let uri = "file:///tmp/versions.gloc";
    lsp_open(&mut server, uri, "nregs 0\n# one\n");
    let change = |version: i32, text: &str| {
        json!({ "jsonrpc": "2.0", "method": "textDocument/didChange",
            "params": { "textDocument": { "uri": uri, "version": version },
                        "contentChanges": [{ "text": text }] } })
    };
    server.send(&change(3, "nregs 0\n# three\n"));
    server.send(&change(2, "nregs 0\n# two\n"));
    let log = server.wait_for("a log message about the old version", |message| {
        message["method"] == "window/logMessage"
            && message["params"]["message"]
                .as_str()
                .is_some_and(|text| text.contains("version 2") && text.contains("version 3"))
    });
    assert_eq!(log["params"]["type"], json!(2), "a warning: {log}");
    assert_eq!(lsp_text(&mut server, 2, uri), "nregs 0\n# three\n");
    lsp_shutdown_and_exit(server, 3);
}

#[test]
fn lsp_a_lone_surrogate_in_an_edit_becomes_a_replacement_character() {
    let mut server = lsp_initialized();
    let uri = "file:///tmp/surrogate.gloc";
    lsp_open(&mut server, uri, "nregs 0\n# x\n");
    // `\ud83d` alone is what JSON.stringify writes for half an emoji; the edit must
    // not be lost, or the next one lands on stale text.
    let body = format!(
        r#"{{"jsonrpc":"2.0","method":"textDocument/didChange","params":{{"textDocument":{{"uri":"{uri}","version":2}},"contentChanges":[{{"range":{{"start":{{"line":1,"character":3}},"end":{{"line":1,"character":3}}}},"text":"\ud83d"}}]}}}}"#
    );
    server.send_bytes(&frame(body.as_bytes()));
    // One UTF-16 unit further: after the replacement character.
    server.send(&json!({ "jsonrpc": "2.0", "method": "textDocument/didChange",
        "params": { "textDocument": { "uri": uri, "version": 3 },
                    "contentChanges": [{ "range": { "start": { "line": 1, "character": 4 }, "end": { "line": 1, "character": 4 } }, "text": "Z" }] } }));
    assert_eq!(lsp_text(&mut server, 2, uri), "nregs 0\n# x\u{FFFD}Z\n");
    lsp_shutdown_and_exit(server, 3);
}

#[test]
fn lsp_cancelled_requests_in_the_queue_answer_request_cancelled() {
    let mut server = lsp_initialized();
    let uri = "file:///tmp/cancel.gloc";
    let lines = 20_000;
    let text = format!(
        "nregs 1\nnblbs 0\nninstr {lines}\n{}",
        "loadi 1,r0\n".repeat(lines)
    );
    lsp_open(&mut server, uri, &text);
    // Each semanticTokens request is cancelled right after it is sent, all in one write.
    let mut bytes = Vec::new();
    for id in 10..30 {
        bytes.extend(frame(
            lsp_request(
                id,
                "textDocument/semanticTokens/full",
                json!({ "textDocument": { "uri": uri } }),
            )
            .to_string()
            .as_bytes(),
        ));
        bytes.extend(frame(
            json!({ "jsonrpc": "2.0", "method": "$/cancelRequest", "params": { "id": id } })
                .to_string()
                .as_bytes(),
        ));
    }
    server.send_bytes(&bytes);
    let cancelled = (10..30)
        .filter(|id| lsp_response(&mut server, *id)["error"]["code"] == json!(-32800))
        .count();
    // The first may already be running when its cancel is read; the queued ones
    // never run (tower-lsp-server alone cancelled none of them).
    assert!(cancelled >= 18, "{cancelled} of 20 requests cancelled");
    lsp_shutdown_and_exit(server, 40);
}

// ------------------------------ both servers: resynchronisation after broken framing

/// A bad length followed by its body, then three good frames: each frame after the
/// bad one is glued to the previous body (no newline between), which kept the old
/// line-based readers out of step for good.
fn bad_length_then_frames(bad_body: &str, good: &[String]) -> Vec<u8> {
    let mut bytes = format!("Content-Length: many\r\n\r\n{bad_body}").into_bytes();
    for body in good {
        bytes.extend(frame(body.as_bytes()));
    }
    bytes
}

#[test]
fn lsp_resynchronises_after_a_non_numeric_content_length_with_a_body() {
    let mut server = lsp_initialized();
    let good: Vec<String> = (2..5)
        .map(|id| {
            lsp_request(
                id,
                "workspace/executeCommand",
                json!({ "command": "gloc.none" }),
            )
            .to_string()
        })
        .collect();
    server.send_bytes(&bad_length_then_frames(&good[0], &good));
    for id in 2..5 {
        lsp_response(&mut server, id);
    }
    lsp_shutdown_and_exit(server, 5);
}

#[test]
fn dap_resynchronises_after_a_non_numeric_content_length_with_a_body() {
    let mut server = dap_initialized();
    let good: Vec<String> = (2..5)
        .map(|seq| dap_request(seq, "threads", json!({})).to_string())
        .collect();
    server.send_bytes(&bad_length_then_frames(&good[0], &good));
    let report = dap_malformed_report(&mut server);
    assert!(report.contains("`many` is not a number"), "{report}");
    for seq in 2..5 {
        dap_response(&mut server, seq);
    }
    dap_disconnect(server, 5);
}
