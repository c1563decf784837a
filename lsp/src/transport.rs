//! Guards the server's input: tower-lsp-server's reader stops for good after
//! the first frame it cannot decode (a `tokio-util` `FramedRead` ends after a
//! decoder error), which would let one malformed message kill the session.
//! This layer re-frames the client's bytes with the framing shared with the
//! debug adapter (`gloc_framing`: bounded headers and bodies, resynchronisation
//! after broken framing) and replaces every message the server must answer
//! with an error by a `gloc/invalidRequest` request carrying the JSON-RPC error
//! code and the request's `id` (`null` when it cannot be read, as JSON-RPC 2.0
//! requires): framing errors and unparsable JSON get −32700, JSON that is not a
//! JSON-RPC message −32600, a request whose method starts with `$/` −32601 (the
//! LSP spec: such requests must be refused; tower-lsp-server drops them).

use std::collections::VecDeque;

use gloc_framing::{Decoder, Event, LIMITS};
use serde_json::{json, Value};
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};
use tower_lsp_server::jsonrpc::{Request, Response};

/// The method a message that gets an error response is turned into.
pub const INVALID_REQUEST_METHOD: &str = "gloc/invalidRequest";

/// JSON-RPC 2.0 error codes used here.
pub const PARSE_ERROR: i64 = -32700;
pub const INVALID_REQUEST: i64 = -32600;
pub const METHOD_NOT_FOUND: i64 = -32601;

/// Copies framed messages from `input` to `output` until `input` ends,
/// repairing the framing and replacing invalid bodies.
pub async fn sanitize<R, W>(mut input: R, mut output: W)
where
    R: AsyncRead + Unpin,
    W: AsyncWrite + Unpin,
{
    let mut decoder = Decoder::new(LIMITS);
    let mut events = VecDeque::new();
    let mut chunk = vec![0; 64 * 1024];
    loop {
        let count = match input.read(&mut chunk).await {
            Ok(0) | Err(_) => return,
            Ok(count) => count,
        };
        decoder.feed(&chunk[..count], &mut events);
        while let Some(event) = events.pop_front() {
            let body = match event {
                Event::Message(body) => check(body),
                Event::Error(error) => replacement(
                    Value::Null,
                    PARSE_ERROR,
                    &format!("broken message framing {error}"),
                ),
            };
            let frame = gloc_framing::encode(&body);
            if output.write_all(&frame).await.is_err() || output.flush().await.is_err() {
                return;
            }
        }
    }
}

/// The body itself when it is a JSON-RPC message, else its replacement.
fn check(body: Vec<u8>) -> Vec<u8> {
    // Lone surrogate escapes (`"\ud83d"`) are valid JavaScript but not JSON that
    // serde accepts: decode them lossily (U+FFFD keeps UTF-16 positions right)
    // rather than drop an edit and apply the next one to stale text.
    let body = gloc_framing::replace_lone_surrogates(&body).unwrap_or(body);
    let Ok(text) = std::str::from_utf8(&body) else {
        return replacement(Value::Null, PARSE_ERROR, "the message is not UTF-8");
    };
    if let Ok(request) = serde_json::from_str::<Request>(text) {
        if let Some(id) = request.id() {
            if request.method().starts_with("$/") {
                let id = serde_json::to_value(id).unwrap_or(Value::Null);
                return replacement(
                    id,
                    METHOD_NOT_FOUND,
                    &format!("unknown request `{}`", request.method()),
                );
            }
        }
        return body;
    }
    if serde_json::from_str::<Response>(text).is_ok() {
        return body;
    }
    match serde_json::from_str::<Value>(text) {
        Err(error) => replacement(
            Value::Null,
            PARSE_ERROR,
            &format!("the message is not JSON: {error}"),
        ),
        Ok(value) => {
            let id = value
                .get("id")
                .filter(|id| id.is_string() || id.is_i64() || id.is_u64())
                .cloned()
                .unwrap_or(Value::Null);
            replacement(
                id,
                INVALID_REQUEST,
                "the message is not a JSON-RPC 2.0 request, notification or response",
            )
        }
    }
}

fn replacement(id: Value, code: i64, reason: &str) -> Vec<u8> {
    json!({ "jsonrpc": "2.0", "id": id, "method": INVALID_REQUEST_METHOD,
            "params": { "reason": reason, "code": code } })
    .to_string()
    .into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    async fn run(input: &[u8]) -> String {
        let mut output = Vec::new();
        sanitize(input, &mut output).await;
        String::from_utf8(output).expect("utf-8")
    }

    #[tokio::test]
    async fn valid_messages_pass_unchanged() {
        let body = r#"{"jsonrpc":"2.0","id":1,"method":"shutdown"}"#;
        let input = format!("Content-Length: {}\r\nContent-Type: application/vscode-jsonrpc; charset=latin1\r\n\r\n{body}", body.len());
        assert_eq!(
            run(input.as_bytes()).await,
            format!("Content-Length: {}\r\n\r\n{body}", body.len())
        );
    }

    #[tokio::test]
    async fn broken_bodies_become_invalid_requests_with_their_id_or_null() {
        let garbage = "{ not json";
        let no_version = r#"{"id":7,"method":"textDocument/hover"}"#;
        let dollar = r#"{"jsonrpc":"2.0","id":8,"method":"$/gloc/secret"}"#;
        let input = format!(
            "Content-Length: {}\r\n\r\n{garbage}Content-Length: {}\r\n\r\n{no_version}Content-Length: {}\r\n\r\n{dollar}",
            garbage.len(),
            no_version.len(),
            dollar.len()
        );
        let output = run(input.as_bytes()).await;
        assert!(output.contains(r#""id":null"#), "{output}");
        assert!(output.contains(r#""code":-32700"#), "{output}");
        assert!(output.contains(r#""id":7"#), "{output}");
        assert!(output.contains(r#""code":-32600"#), "{output}");
        assert!(output.contains(r#""id":8"#), "{output}");
        assert!(output.contains(r#""code":-32601"#), "{output}");
        assert_eq!(output.matches(INVALID_REQUEST_METHOD).count(), 3);
    }

    #[tokio::test]
    async fn a_dollar_notification_passes_for_the_server_to_ignore() {
        let body = r#"{"jsonrpc":"2.0","method":"$/setTrace","params":{"value":"off"}}"#;
        let input = format!("Content-Length: {}\r\n\r\n{body}", body.len());
        assert!(run(input.as_bytes()).await.ends_with(body));
    }

    #[tokio::test]
    async fn a_lone_surrogate_is_decoded_lossily() {
        let body = r#"{"jsonrpc":"2.0","method":"x","params":{"t":"a\ud83db"}}"#;
        let input = format!("Content-Length: {}\r\n\r\n{body}", body.len());
        assert!(run(input.as_bytes()).await.contains(r#""a\ufffdb""#));
    }

    #[tokio::test]
    async fn missing_length_is_reported_and_truncated_input_ends_quietly() {
        assert!(run(b"X-Whatever: 1\r\n\r\n")
            .await
            .contains("has no Content-Length"));
        assert_eq!(run(b"Content-Length: 50\r\n\r\n{\"jsonrpc\"").await, "");
        assert_eq!(run(b"").await, "");
    }
}
