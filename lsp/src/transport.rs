//! Guards the server's input: tower-lsp-server's reader stops for good after
//! the first frame it cannot decode (a `tokio-util` `FramedRead` ends after a
//! decoder error), which would let one malformed message kill the session.
//! This layer re-frames the client's bytes and replaces every message that is
//! not valid JSON-RPC by a `gloc/invalidMessage` request or notification that
//! the server answers with an error or a log message.

use serde_json::{json, Value};
use tokio::io::{AsyncBufReadExt, AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt, BufReader};
use tower_lsp_server::jsonrpc::{Request, Response};

/// The method a broken request (one whose `id` could be read) is turned into.
pub const INVALID_REQUEST_METHOD: &str = "gloc/invalidRequest";
/// The method any other broken message is turned into.
pub const INVALID_NOTIFICATION_METHOD: &str = "gloc/invalidMessage";

/// Bodies larger than this are discarded unread (and reported).
const MAX_BODY: usize = 256 << 20;

/// Copies framed messages from `input` to `output` until `input` ends,
/// repairing the framing and replacing invalid bodies.
pub async fn sanitize<R, W>(input: R, mut output: W)
where
    R: AsyncRead + Unpin,
    W: AsyncWrite + Unpin,
{
    let mut input = BufReader::new(input);
    loop {
        let length = match read_headers(&mut input).await {
            Some(Some(length)) => length,
            // A header block without Content-Length: nothing to frame; go on.
            Some(None) => continue,
            None => return,
        };
        let body = if length > MAX_BODY {
            let skipped = tokio::io::copy(
                &mut (&mut input).take(length as u64),
                &mut tokio::io::sink(),
            )
            .await;
            if skipped.map_or(true, |count| count < length as u64) {
                return;
            }
            replacement(None, &format!("a message of {length} bytes is too large"))
        } else {
            let mut body = vec![0; length];
            if input.read_exact(&mut body).await.is_err() {
                return;
            }
            check(body)
        };
        let frame = format!("Content-Length: {}\r\n\r\n", body.len());
        if output.write_all(frame.as_bytes()).await.is_err()
            || output.write_all(&body).await.is_err()
            || output.flush().await.is_err()
        {
            return;
        }
    }
}

/// Reads one header block. `None` at end of input; `Some(None)` for a block
/// without a usable `Content-Length`.
async fn read_headers<R: AsyncRead + Unpin>(input: &mut BufReader<R>) -> Option<Option<usize>> {
    let mut length = None;
    let mut seen_any = false;
    loop {
        let mut line = Vec::new();
        let read = input.read_until(b'\n', &mut line).await.ok()?;
        if read == 0 {
            return None;
        }
        let line = String::from_utf8_lossy(&line);
        let line = line.trim();
        if line.is_empty() {
            if seen_any {
                return Some(length);
            }
            continue;
        }
        seen_any = true;
        if let Some((name, value)) = line.split_once(':') {
            if name.trim().eq_ignore_ascii_case("content-length") {
                length = value.trim().parse::<usize>().ok();
            }
        }
    }
}

/// The body itself when it is a JSON-RPC message, else its replacement.
fn check(body: Vec<u8>) -> Vec<u8> {
    let Ok(text) = std::str::from_utf8(&body) else {
        return replacement(None, "the message is not UTF-8");
    };
    if serde_json::from_str::<Response>(text).is_ok()
        || serde_json::from_str::<Request>(text).is_ok()
    {
        return body;
    }
    match serde_json::from_str::<Value>(text) {
        Err(error) => replacement(None, &format!("the message is not JSON: {error}")),
        Ok(value) => {
            let id = value
                .get("id")
                .filter(|id| id.is_string() || id.is_i64() || id.is_u64())
                .cloned();
            replacement(
                id,
                "the message is not a JSON-RPC 2.0 request, notification or response",
            )
        }
    }
}

fn replacement(id: Option<Value>, reason: &str) -> Vec<u8> {
    let message = match id {
        Some(id) => {
            json!({ "jsonrpc": "2.0", "id": id, "method": INVALID_REQUEST_METHOD, "params": { "reason": reason } })
        }
        None => {
            json!({ "jsonrpc": "2.0", "method": INVALID_NOTIFICATION_METHOD, "params": { "reason": reason } })
        }
    };
    message.to_string().into_bytes()
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
    async fn broken_bodies_become_invalid_message_notifications_or_requests() {
        let garbage = "{ not json";
        let no_version = r#"{"id":7,"method":"textDocument/hover"}"#;
        let input = format!(
            "Content-Length: {}\r\n\r\n{garbage}Content-Length: {}\r\n\r\n{no_version}",
            garbage.len(),
            no_version.len()
        );
        let output = run(input.as_bytes()).await;
        assert!(
            output.contains(r#""method":"gloc/invalidMessage""#),
            "{output}"
        );
        assert!(output.contains(r#""id":7"#), "{output}");
        assert!(
            output.contains(r#""method":"gloc/invalidRequest""#),
            "{output}"
        );
        assert_eq!(output.matches("Content-Length").count(), 2);
    }

    #[tokio::test]
    async fn missing_length_and_truncated_input_end_quietly() {
        assert_eq!(run(b"X-Whatever: 1\r\n\r\n").await, "");
        assert_eq!(run(b"Content-Length: 50\r\n\r\n{\"jsonrpc\"").await, "");
        assert_eq!(run(b"").await, "");
    }
}
