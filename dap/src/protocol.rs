//! The wire layer of the Debug Adapter Protocol: `Content-Length` framing, the lenient
//! request envelope, and the one writer that numbers every outgoing message.
//!
//! Hand-written instead of the `dap` crate because that crate rejects messages real
//! clients send (absent or `{}` arguments, unknown commands, extra headers) and emits
//! `null`s and error responses that the official schema rejects.

use std::io::{self, BufRead, Write};

use serde::Serialize;
use serde_json::{json, Value};

/// The largest message body we accept; a bigger `Content-Length` is a protocol error,
/// not an allocation.
pub const MAX_MESSAGE_BYTES: usize = 64 * 1024 * 1024;

/// What the reader found in the next frame.
#[derive(Debug)]
pub enum Frame {
    /// A well-formed request.
    Request(Request),
    /// A frame that is not a usable request; the adapter answers with an error response.
    Malformed(Malformed),
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
    pub request_seq: i64,
    pub command: String,
    pub message: String,
}

/// Reads one frame. Headers other than `Content-Length` (e.g. `Content-Type`) are
/// ignored; an IO error or end of stream is `Closed`.
pub fn read_frame(reader: &mut impl BufRead) -> Frame {
    let mut content_length: Option<usize> = None;
    let mut bad_header: Option<String> = None;
    let mut saw_header = false;
    loop {
        let mut line = Vec::new();
        match reader.read_until(b'\n', &mut line) {
            Ok(0) | Err(_) => return Frame::Closed,
            Ok(_) => {}
        }
        let text = String::from_utf8_lossy(&line);
        let text = text.trim_end_matches(['\r', '\n']);
        if text.is_empty() {
            if saw_header {
                break;
            }
            // Blank lines between messages (some clients add a trailing CRLF) are noise.
            continue;
        }
        saw_header = true;
        if let Some((name, value)) = text.split_once(':') {
            if name.trim().eq_ignore_ascii_case("content-length") {
                match value.trim().parse::<usize>() {
                    Ok(length) if length <= MAX_MESSAGE_BYTES => content_length = Some(length),
                    Ok(length) => {
                        bad_header = Some(format!(
                            "Content-Length {length} is larger than the limit of {MAX_MESSAGE_BYTES} bytes"
                        ))
                    }
                    Err(_) => {
                        bad_header = Some(format!(
                            "Content-Length `{}` is not a number",
                            value.trim()
                        ))
                    }
                }
            }
        } else {
            bad_header = Some(format!("header line `{text}` has no `:`"));
        }
    }
    let Some(length) = content_length else {
        // Without a length the body cannot be skipped; resynchronise at the next header.
        return Frame::Malformed(Malformed {
            request_seq: 0,
            command: String::new(),
            message: bad_header.unwrap_or_else(|| "message has no Content-Length header".into()),
        });
    };
    let mut body = vec![0; length];
    if reader.read_exact(&mut body).is_err() {
        return Frame::Closed;
    }
    if let Some(message) = bad_header {
        return Frame::Malformed(Malformed {
            request_seq: 0,
            command: String::new(),
            message,
        });
    }
    parse_request(&body)
}

/// Turns a body into a request, accepting absent, `null` and `{}` arguments alike.
pub fn parse_request(body: &[u8]) -> Frame {
    let value: Value = match serde_json::from_slice(body) {
        Ok(value) => value,
        Err(error) => {
            // Salvage `seq` and `command` from the broken text so the client can match
            // the error to its request instead of waiting for ever.
            let text = String::from_utf8_lossy(body);
            return Frame::Malformed(Malformed {
                request_seq: salvage(&text, "seq")
                    .and_then(|value| value.parse().ok())
                    .unwrap_or(0),
                command: salvage(&text, "command")
                    .map(|value| value.trim_matches('"').to_string())
                    .unwrap_or_default(),
                message: format!("the message is not valid JSON: {error}"),
            });
        }
    };
    let request_seq = value.get("seq").and_then(Value::as_i64).unwrap_or(0);
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
    if value.get("seq").and_then(Value::as_i64).is_none() {
        return malformed("the request has no integer `seq`".into());
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
        let text = serde_json::to_string(&message).map_err(io::Error::other)?;
        write!(self.sink, "Content-Length: {}\r\n\r\n{}", text.len(), text)?;
        self.sink.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(text: &str) -> Frame {
        read_frame(&mut text.as_bytes())
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
        let mut reader = text.as_bytes();
        assert!(
            matches!(read_frame(&mut reader), Frame::Malformed(m) if m.message.contains("not valid JSON"))
        );
        assert!(matches!(read_frame(&mut reader), Frame::Request(r) if r.seq == 2));
        assert!(matches!(read_frame(&mut reader), Frame::Closed));
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
    fn writer_numbers_messages_and_frames_them() {
        let buffer = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        struct Shared(std::sync::Arc<std::sync::Mutex<Vec<u8>>>);
        impl Write for Shared {
            fn write(&mut self, data: &[u8]) -> io::Result<usize> {
                self.0
                    .lock()
                    .map_err(|_| io::Error::other("poisoned"))?
                    .extend_from_slice(data);
                Ok(data.len())
            }
            fn flush(&mut self) -> io::Result<()> {
                Ok(())
            }
        }
        let mut writer = Writer::new(Box::new(Shared(buffer.clone())));
        writer.event("initialized", ()).expect("write");
        writer
            .respond_error(4, "bogus", "unknown {x}")
            .expect("write");
        let bytes = buffer.lock().expect("lock").clone();
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
