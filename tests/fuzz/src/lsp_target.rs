//! LSP edit handling: a random sequence of `didChange` edits applied by the
//! server equals the same edits applied by an independent model of the LSP
//! rules, and the diagnostics of the edited document equal those of a fresh
//! document opened with the final text.

use serde_json::{json, Value};
use tokio::io::{AsyncWriteExt, BufReader, DuplexStream};

/// At most this many edits per input, so one execution stays fast.
const MAX_EDITS: usize = 24;

#[derive(Debug)]
pub struct Session {
    pub gbasic: bool,
    pub initial: String,
    pub edits: Vec<Edit>,
    /// Send all edits in one `didChange` (the server applies them in order).
    pub one_batch: bool,
}

#[derive(Debug)]
pub struct Edit {
    pub start: (u8, u8),
    pub end: (u8, u8),
    pub text: String,
    /// A change without a range replaces the whole document.
    pub whole: bool,
}

/// Decodes a fuzz input, a format simple enough to seed from real files:
/// byte 0 holds flags (bit 0: GBASIC, bit 1: one batch); the rest, split at
/// NUL bytes, is the initial text and then one edit per chunk: five bytes
/// (start line, start character, end line, end character, flags with bit 0 =
/// replace the whole document) and the new text. Text is decoded lossily.
pub fn decode(data: &[u8]) -> Option<Session> {
    let (&flags, rest) = data.split_first()?;
    let mut chunks = rest.split(|&byte| byte == 0);
    let initial = String::from_utf8_lossy(chunks.next().unwrap_or_default()).into_owned();
    let edits = chunks
        .filter_map(|chunk| {
            let (header, text) = chunk.split_at_checked(5)?;
            Some(Edit {
                start: (header[0], header[1]),
                end: (header[2], header[3]),
                whole: header[4] & 1 == 1,
                text: String::from_utf8_lossy(text).into_owned(),
            })
        })
        .take(MAX_EDITS)
        .collect();
    Some(Session {
        gbasic: flags & 1 == 1,
        one_batch: flags & 2 == 2,
        initial,
        edits,
    })
}

pub fn check_lsp_edits_bytes(data: &[u8]) {
    if let Some(session) = decode(data) {
        check_lsp_edits(&session);
    }
}

/// The document text after the edits, by the LSP rules as the server
/// documents them: positions past a line's end clamp to it, a line past the
/// document clamps to its end, a position inside a surrogate pair rounds
/// down, and an end before the start is the start.
pub fn apply_model(initial: &str, edits: &[Edit]) -> String {
    let mut chars: Vec<char> = initial.chars().collect();
    for edit in edits {
        if edit.whole {
            chars = edit.text.chars().collect();
            continue;
        }
        let start = char_index(&chars, edit.start).unwrap_or(chars.len());
        let end = char_index(&chars, edit.end)
            .unwrap_or(chars.len())
            .max(start);
        chars.splice(start..end, edit.text.chars());
    }
    chars.into_iter().collect()
}

/// Start and end (before the break) of each line; breaks are `\n`, `\r\n`, `\r`.
fn lines(chars: &[char]) -> Vec<(usize, usize)> {
    let mut lines = Vec::new();
    let mut start = 0;
    let mut index = 0;
    while index < chars.len() {
        match chars[index] {
            '\r' if chars.get(index + 1) == Some(&'\n') => {
                lines.push((start, index));
                index += 2;
                start = index;
            }
            '\n' | '\r' => {
                lines.push((start, index));
                index += 1;
                start = index;
            }
            _ => index += 1,
        }
    }
    lines.push((start, chars.len()));
    lines
}

fn char_index(chars: &[char], (line, character): (u8, u8)) -> Option<usize> {
    let (start, end) = *lines(chars).get(usize::from(line))?;
    let wanted = usize::from(character);
    let mut index = start;
    let mut units = 0;
    while index < end && units + chars[index].len_utf16() <= wanted {
        units += chars[index].len_utf16();
        index += 1;
    }
    Some(index)
}

pub fn check_lsp_edits(session: &Session) {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("a tokio runtime");
    runtime.block_on(drive(session));
}

const EDITED: &str = "untitled:fuzz/edited";
const FRESH: &str = "untitled:fuzz/fresh";

async fn drive(session: &Session) {
    let (language, extension) = if session.gbasic {
        ("gbasic", "gbas")
    } else {
        ("gloc", "gloc")
    };
    let edited = format!("{EDITED}.{extension}");
    let fresh = format!("{FRESH}.{extension}");
    let expected_text = apply_model(&session.initial, &session.edits);

    let (client_side, server_side) = tokio::io::duplex(1 << 16);
    let (server_read, server_write) = tokio::io::split(server_side);
    let server = tokio::spawn(gloc_lsp::serve(server_read, server_write));
    let (read, write) = tokio::io::split(client_side);
    // A reader of its own, so that a server writing much output never
    // blocks on a full pipe while the client is still sending edits.
    let (sender, receiver) = tokio::sync::mpsc::unbounded_channel();
    tokio::spawn(read_messages(BufReader::new(read), sender));
    let mut client = Client {
        writer: write,
        messages: receiver,
        next_id: 1,
        diagnostics: Default::default(),
    };

    client
        .request(
            "initialize",
            json!({ "processId": null, "rootUri": null, "capabilities": {} }),
        )
        .await;
    client.notify("initialized", json!({})).await;
    client
        .notify(
            "textDocument/didOpen",
            json!({ "textDocument": { "uri": edited, "languageId": language,
                                      "version": 1, "text": session.initial } }),
        )
        .await;
    let changes: Vec<Value> = session
        .edits
        .iter()
        .map(|edit| {
            if edit.whole {
                json!({ "text": edit.text })
            } else {
                json!({ "range": {
                            "start": { "line": edit.start.0, "character": edit.start.1 },
                            "end": { "line": edit.end.0, "character": edit.end.1 } },
                        "text": edit.text })
            }
        })
        .collect();
    if session.one_batch {
        client.change(&edited, 2, changes).await;
    } else {
        for (version, change) in (2..).zip(changes) {
            client.change(&edited, version, vec![change]).await;
        }
    }
    client
        .notify(
            "textDocument/didOpen",
            json!({ "textDocument": { "uri": fresh, "languageId": language,
                                      "version": 1, "text": expected_text } }),
        )
        .await;

    let edited_gloc = client.compiled_gloc(&edited).await;
    let fresh_gloc = client.compiled_gloc(&fresh).await;
    if !session.gbasic {
        assert_eq!(
            edited_gloc,
            json!({ "result": expected_text }),
            "the server's text after the edits equals the model's"
        );
    }
    assert_eq!(
        strip_uri(&edited_gloc, &edited, &fresh),
        fresh_gloc,
        "the edited and the fresh document compile alike"
    );
    let edited_diagnostics = client.diagnostics.get(&edited).cloned();
    let fresh_diagnostics = client.diagnostics.get(&fresh).cloned();
    assert!(
        fresh_diagnostics.is_some(),
        "diagnostics were published on open"
    );
    assert_eq!(
        edited_diagnostics.map(|value| strip_uri(&value, &edited, &fresh)),
        fresh_diagnostics,
        "incremental diagnostics equal those of a fresh parse"
    );

    client.request("shutdown", Value::Null).await;
    client.notify("exit", Value::Null).await;
    let ending = tokio::time::timeout(std::time::Duration::from_secs(20), server)
        .await
        .expect("the server exits after `exit`")
        .expect("the server task did not panic");
    assert_eq!(ending, gloc_lsp::Ending::Clean);
}

/// The same JSON with the edited document's URI written as the fresh one's.
fn strip_uri(value: &Value, edited: &str, fresh: &str) -> Value {
    let text = value.to_string().replace(edited, fresh);
    serde_json::from_str(&text).expect("JSON stays JSON")
}

struct Client {
    writer: tokio::io::WriteHalf<DuplexStream>,
    messages: tokio::sync::mpsc::UnboundedReceiver<Value>,
    next_id: i64,
    /// The last diagnostics published for each URI.
    diagnostics: std::collections::HashMap<String, Value>,
}

impl Client {
    async fn send(&mut self, message: Value) {
        let body = message.to_string();
        let frame = format!("Content-Length: {}\r\n\r\n{body}", body.len());
        self.writer
            .write_all(frame.as_bytes())
            .await
            .expect("the server reads its input");
    }

    async fn notify(&mut self, method: &str, params: Value) {
        self.send(json!({ "jsonrpc": "2.0", "method": method, "params": params }))
            .await;
    }

    async fn change(&mut self, uri: &str, version: i32, changes: Vec<Value>) {
        self.notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": uri, "version": version },
                    "contentChanges": changes }),
        )
        .await;
    }

    async fn compiled_gloc(&mut self, uri: &str) -> Value {
        let response = self
            .request_raw(
                "workspace/executeCommand",
                json!({ "command": gloc_lsp::COMPILED_GLOC_COMMAND, "arguments": [uri] }),
            )
            .await;
        match response.get("error") {
            // The message is what matters; the code too.
            Some(error) => json!({ "error": error }),
            None => json!({ "result": response["result"] }),
        }
    }

    async fn request(&mut self, method: &str, params: Value) -> Value {
        let response = self.request_raw(method, params).await;
        assert!(response.get("error").is_none(), "{method}: {response}");
        response["result"].clone()
    }

    async fn request_raw(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        self.send(json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params }))
            .await;
        loop {
            let message =
                tokio::time::timeout(std::time::Duration::from_secs(20), self.messages.recv())
                    .await
                    .expect("the server answers in time")
                    .expect("the server keeps its output open");
            match (message.get("id"), message.get("method").and_then(Value::as_str)) {
                (Some(got), None) if *got == json!(id) => return message,
                (Some(request_id), Some(_)) => {
                    let request_id = request_id.clone();
                    self.send(json!({ "jsonrpc": "2.0", "id": request_id, "result": null }))
                        .await;
                }
                (None, Some("textDocument/publishDiagnostics")) => {
                    let params = &message["params"];
                    let uri = params["uri"].as_str().unwrap_or_default().to_string();
                    self.diagnostics.insert(uri, params["diagnostics"].clone());
                }
                _ => {}
            }
        }
    }
}

async fn read_messages(
    mut reader: BufReader<tokio::io::ReadHalf<DuplexStream>>,
    sender: tokio::sync::mpsc::UnboundedSender<Value>,
) {
    while let Some(message) = read_message(&mut reader).await {
        if sender.send(message).is_err() {
            return;
        }
    }
}

/// One framed message; `None` at the end of the server's output.
async fn read_message(reader: &mut BufReader<tokio::io::ReadHalf<DuplexStream>>) -> Option<Value> {
    let body = gloc_testsupport::read_frame(reader).await?;
    Some(serde_json::from_slice(&body).expect("valid JSON from the server"))
}
