//! The wire layer of the Debug Adapter Protocol: `Content-Length` framing, the lenient
//! request envelope, and the one writer that numbers every outgoing message.
//!
//! Hand-written instead of the `dap` crate because that crate rejects messages real
//! clients send (absent or `{}` arguments, unknown commands, extra headers) and emits
//! `null`s and error responses that the official schema rejects.

use std::io::{self, Read, Write};

use gloc_framing::{Event, FrameReader, LIMITS};
use serde::Serialize;
use serde_json::{json, Value};

/// The largest `seq` a request may carry: the DAP schema makes `seq` and `request_seq`
/// `int32` with a minimum of 1, so a request outside `1..=MAX_SEQ` cannot be named by
/// any valid response. It is not run; an `output` event reports it instead.
pub const MAX_SEQ: i64 = i32::MAX as i64;

/// What the reader found in the next frame.
#[derive(Debug)]
pub enum Frame {
    /// A well-formed request.
    Request(Request),
    /// A frame that is not a usable request; the adapter answers with an error response.
    Malformed(Malformed),
    /// Nothing arrived within the connection's read timeout (TCP only); the stream is
    /// still usable.
    Idle,
    /// The client closed the stream.
    Closed,
}

/// A request envelope. `arguments` is `{}` when the client omitted it or sent `null`.
#[derive(Debug, Clone)]
pub struct Request {
    pub seq: i64,
    pub command: String,
    pub arguments: Value,
}

/// A frame we could not turn into a request, with whatever we could recover of it so the
/// error response can still name the request.
#[derive(Debug, Clone)]
pub struct Malformed {
    /// The request's `seq` when it could be read and lies in `1..=MAX_SEQ`, else 0.
    pub request_seq: i64,
    pub command: String,
    pub message: String,
    /// The `seq` as the client wrote it, when it was there but unusable.
    pub raw_seq: Option<Value>,
}

/// Reads frames through the framing shared with the language server
/// (`gloc_framing`: bounded headers and bodies, resynchronisation after a broken
/// frame).
pub struct Reader<R> {
    frames: FrameReader<R>,
}

impl<R: Read> Reader<R> {
    pub fn new(input: R) -> Reader<R> {
        Reader {
            frames: FrameReader::new(input, LIMITS),
        }
    }

    /// Reads with `before` until `flag` is set, then with the full limits.
    pub fn limit_until(
        &mut self,
        before: gloc_framing::Limits,
        flag: std::sync::Arc<std::sync::atomic::AtomicBool>,
    ) {
        self.frames.set_limits(before);
        self.frames.upgrade_when(flag, LIMITS);
    }

    /// The next frame. A read timeout is `Idle`; another IO error or the end of the
    /// stream is `Closed`.
    pub fn next_frame(&mut self) -> Frame {
        match self.frames.next_event() {
            Ok(Some(Event::Message(body))) => parse_request(&body),
            Ok(Some(Event::Error(error))) => Frame::Malformed(Malformed {
                request_seq: 0,
                command: String::new(),
                message: format!("broken message framing {error}"),
                raw_seq: None,
            }),
            Ok(None) => Frame::Closed,
            Err(error)
                if matches!(
                    error.kind(),
                    io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
                ) =>
            {
                Frame::Idle
            }
            Err(_) => Frame::Closed,
        }
    }
}

/// Turns a body into a request, accepting absent, `null` and `{}` arguments alike.
pub fn parse_request(body: &[u8]) -> Frame {
    let repaired = gloc_framing::replace_lone_surrogates(body);
    let body = repaired.as_deref().unwrap_or(body);
    let value: Value = match serde_json::from_slice(body) {
        Ok(value) => value,
        Err(error) => {
            // Salvage `seq` and `command` from the broken text so the client can match
            // the error to its request instead of waiting for ever.
            let text = String::from_utf8_lossy(body);
            return Frame::Malformed(Malformed {
                request_seq: salvage(&text, "seq")
                    .and_then(|value| value.parse().ok())
                    .filter(|seq| (1..=MAX_SEQ).contains(seq))
                    .unwrap_or(0),
                command: salvage(&text, "command")
                    .map(|value| value.trim_matches('"').to_string())
                    .unwrap_or_default(),
                message: format!("the message is not valid JSON: {error}"),
                raw_seq: None,
            });
        }
    };
    let raw_seq = value.get("seq").cloned();
    let request_seq = value
        .get("seq")
        .and_then(Value::as_i64)
        .filter(|seq| (1..=MAX_SEQ).contains(seq))
        .unwrap_or(0);
    let command = value
        .get("command")
        .and_then(Value::as_str)
        .unwrap_or_default()
        .to_owned();
    let malformed = |message: String| {
        Frame::Malformed(Malformed {
            request_seq,
            command: command.clone(),
            message,
            raw_seq: raw_seq.clone().filter(|_| request_seq == 0),
        })
    };
    if !value.is_object() {
        return malformed("the message is not a JSON object".into());
    }
    match value.get("type").and_then(Value::as_str) {
        Some("request") => {}
        Some(other) => {
            return malformed(format!(
                "the adapter only accepts requests, not a `{other}` message"
            ))
        }
        None => return malformed("the message has no `type`".into()),
    }
    match &raw_seq {
        None => return malformed("the request has no `seq`".into()),
        Some(seq) if request_seq == 0 => {
            return malformed(format!(
                "the request's `seq` {seq} is not an integer from 1 to {MAX_SEQ} (the DAP schema's range), so no response could name it; it was not run"
            ))
        }
        Some(_) => {}
    }
    if command.is_empty() {
        return malformed("the request has no `command` string".into());
    }
    let arguments = match value.get("arguments") {
        None | Some(Value::Null) => json!({}),
        Some(arguments) => arguments.clone(),
    };
    Frame::Request(Request {
        seq: request_seq,
        command,
        arguments,
    })
}

/// The raw value after `"key":` in text that failed to parse: digits, or a simple
/// quoted string.
fn salvage(text: &str, key: &str) -> Option<String> {
    let quoted = format!("\"{key}\"");
    let after = &text[text.find(&quoted)? + quoted.len()..];
    let after = after.trim_start().strip_prefix(':')?.trim_start();
    if let Some(rest) = after.strip_prefix('"') {
        let end = rest.find('"')?;
        return Some(rest[..end].to_string());
    }
    let end = after
        .find(|character: char| !character.is_ascii_digit())
        .unwrap_or(after.len());
    (end > 0).then(|| after[..end].to_string())
}

/// Writes framed messages and owns the outgoing `seq` counter, so numbers are unique and
/// increasing whoever sends.
pub struct Writer {
    sink: Box<dyn Write + Send>,
    next_seq: i64,
}

impl Writer {
    pub fn new(sink: Box<dyn Write + Send>) -> Writer {
        Writer { sink, next_seq: 1 }
    }

    /// A successful response; `body` is omitted when it serialises to `null`.
    pub fn respond(&mut self, request: &Request, body: impl Serialize) -> io::Result<()> {
        let body = serde_json::to_value(body).unwrap_or(Value::Null);
        let mut message = json!({
            "type": "response",
            "request_seq": request.seq,
            "success": true,
            "command": request.command,
        });
        if !body.is_null() {
            message["body"] = body;
        }
        self.send(message)
    }

    /// An error response. It carries `command` and a structured `body.error` as the
    /// schema's `ErrorResponse` requires.
    pub fn respond_error(
        &mut self,
        request_seq: i64,
        command: &str,
        message: &str,
    ) -> io::Result<()> {
        let message = json!({
            "type": "response",
            "request_seq": request_seq,
            "success": false,
            "command": command,
            "message": message,
            "body": {
                "error": { "id": 1, "format": message.replace('{', "(").replace('}', ")"), "showUser": true }
            },
        });
        self.send(message)
    }

    /// An event; `body` is omitted when it serialises to `null`.
    pub fn event(&mut self, event: &str, body: impl Serialize) -> io::Result<()> {
        let body = serde_json::to_value(body).unwrap_or(Value::Null);
        let mut message = json!({ "type": "event", "event": event });
        if !body.is_null() {
            message["body"] = body;
        }
        self.send(message)
    }

    fn send(&mut self, mut message: Value) -> io::Result<()> {
        message["seq"] = json!(self.next_seq);
        self.next_seq += 1;
        let text = serde_json::to_vec(&message).map_err(io::Error::other)?;
        // Header and body in one write: over TCP, separate small writes each wait
        // for a delayed ACK.
        self.sink.write_all(&gloc_framing::encode(&text))?;
        self.sink.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(text: &str) -> Frame {
        Reader::new(text.as_bytes()).next_frame()
    }

    fn framed(body: &str) -> String {
        format!("Content-Length: {}\r\n\r\n{}", body.len(), body)
    }

    #[test]
    fn absent_null_and_empty_arguments_are_all_empty_objects() {
        for body in [
            r#"{"seq":3,"type":"request","command":"disconnect"}"#,
            r#"{"seq":3,"type":"request","command":"disconnect","arguments":null}"#,
            r#"{"seq":3,"type":"request","command":"disconnect","arguments":{}}"#,
        ] {
            let Frame::Request(request) = frame(&framed(body)) else {
                panic!("not a request: {body}")
            };
            assert_eq!(request.seq, 3);
            assert_eq!(request.command, "disconnect");
            assert_eq!(request.arguments, json!({}));
        }
    }

    #[test]
    fn extra_headers_are_ignored() {
        let body = r#"{"seq":1,"type":"request","command":"threads"}"#;
        let text = format!(
            "Content-Type: application/vscode-jsonrpc; charset=utf-8\r\ncontent-length: {}\r\n\r\n{}",
            body.len(),
            body
        );
        assert!(matches!(frame(&text), Frame::Request(r) if r.command == "threads"));
    }

    #[test]
    fn bad_json_keeps_the_stream_in_sync() {
        let text =
            framed("{not json") + &framed(r#"{"seq":2,"type":"request","command":"threads"}"#);
        let mut reader = Reader::new(text.as_bytes());
        assert!(
            matches!(reader.next_frame(), Frame::Malformed(m) if m.message.contains("not valid JSON"))
        );
        assert!(matches!(reader.next_frame(), Frame::Request(r) if r.seq == 2));
        assert!(matches!(reader.next_frame(), Frame::Closed));
    }

    #[test]
    fn missing_fields_are_malformed_with_what_was_recovered() {
        let Frame::Malformed(m) = frame(&framed(r#"{"type":"request","command":"next"}"#)) else {
            panic!("accepted a request without seq")
        };
        assert_eq!(m.command, "next");
        assert!(m.message.contains("seq"));
        let Frame::Malformed(m) = frame(&framed(r#"{"seq":9,"type":"request","command":7}"#))
        else {
            panic!("accepted a numeric command")
        };
        assert_eq!(m.request_seq, 9);
        assert!(m.message.contains("command"));
        assert!(matches!(frame(&framed("[1,2]")), Frame::Malformed(_)));
    }

    #[test]
    fn huge_or_bad_lengths_are_malformed_not_allocated() {
        assert!(matches!(
            frame("Content-Length: 99999999999\r\n\r\n"),
            Frame::Malformed(m) if m.message.contains("limit")
        ));
        assert!(matches!(
            frame("Content-Length: ten\r\n\r\n"),
            Frame::Malformed(m) if m.message.contains("not a number")
        ));
    }

    #[test]
    fn a_seq_outside_the_schema_range_is_malformed_with_the_raw_value() {
        for (seq, raw) in [
            ("0", json!(0)),
            ("-1", json!(-1)),
            ("9223372036854775808", json!(9223372036854775808u64)),
            ("2147483648", json!(2147483648u64)),
        ] {
            let body = format!(r#"{{"seq":{seq},"type":"request","command":"threads"}}"#);
            let Frame::Malformed(m) = frame(&framed(&body)) else {
                panic!("seq {seq} accepted")
            };
            assert_eq!(m.request_seq, 0, "{seq}");
            assert_eq!(m.command, "threads");
            assert_eq!(m.raw_seq, Some(raw), "{seq}");
            assert!(m.message.contains("from 1 to 2147483647"), "{}", m.message);
        }
        let body = r#"{"seq":2147483647,"type":"request","command":"threads"}"#;
        assert!(matches!(frame(&framed(body)), Frame::Request(r) if r.seq == 2147483647));
    }

    /// A sink that keeps each write it is given, for the writer's tests.
    #[derive(Clone, Default)]
    struct Writes(std::sync::Arc<std::sync::Mutex<Vec<Vec<u8>>>>);

    impl Write for Writes {
        fn write(&mut self, data: &[u8]) -> io::Result<usize> {
            self.0
                .lock()
                .map_err(|_| io::Error::other("poisoned"))?
                .push(data.to_vec());
            Ok(data.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    impl Writes {
        fn taken(&self) -> Vec<Vec<u8>> {
            self.0.lock().expect("lock").clone()
        }
    }

    #[test]
    fn writer_numbers_messages_and_frames_them() {
        let writes = Writes::default();
        let mut writer = Writer::new(Box::new(writes.clone()));
        writer.event("initialized", ()).expect("write");
        writer
            .respond_error(4, "bogus", "unknown {x}")
            .expect("write");
        let bytes = writes.taken().concat();
        let mut reader = bytes.as_slice();
        let mut bodies = Vec::new();
        while let Some(body) = raw_body(&mut reader) {
            bodies.push(body);
        }
        assert_eq!(bodies.len(), 2);
        assert_eq!(
            bodies[0],
            json!({"seq":1,"type":"event","event":"initialized"})
        );
        assert_eq!(bodies[1]["seq"], 2);
        assert_eq!(bodies[1]["command"], "bogus");
        assert_eq!(bodies[1]["success"], false);
        assert_eq!(bodies[1]["body"]["error"]["format"], "unknown (x)");
    }

    #[test]
    fn writer_sends_each_message_in_one_write() {
        let writes = Writes::default();
        let mut writer = Writer::new(Box::new(writes.clone()));
        writer.event("initialized", ()).expect("write");
        writer.respond_error(4, "bogus", "no").expect("write");
        assert_eq!(writes.taken().len(), 2, "one write per message");
    }

    fn raw_body(reader: &mut &[u8]) -> Option<Value> {
        let text = std::str::from_utf8(reader).ok()?;
        let header_end = text.find("\r\n\r\n")?;
        let length: usize = text[..header_end]
            .strip_prefix("Content-Length: ")?
            .parse()
            .ok()?;
        let body = &reader[header_end + 4..header_end + 4 + length];
        let value = serde_json::from_slice(body).ok();
        *reader = &reader[header_end + 4 + length..];
        value
    }
}
