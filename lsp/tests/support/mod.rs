//! A small LSP client for in-process protocol tests: it speaks framed
//! JSON-RPC to `gloc_lsp::serve` over in-memory pipes, answers the server's
//! own requests, and keeps every notification it receives.
#![allow(dead_code)]

use std::collections::VecDeque;
use std::time::Duration;

use serde_json::{json, Value};
use tokio::io::{AsyncWriteExt, BufReader, DuplexStream, ReadHalf, WriteHalf};
use tokio::task::JoinHandle;

pub struct TestClient {
    writer: WriteHalf<DuplexStream>,
    reader: BufReader<ReadHalf<DuplexStream>>,
    next_id: i64,
    /// Notifications received while waiting for something else.
    pub notifications: VecDeque<Value>,
    /// What to answer to `workspace/configuration` (one value per item).
    pub configuration: Value,
    pub server: JoinHandle<gloc_lsp::Ending>,
}

const TIMEOUT: Duration = Duration::from_secs(20);

impl TestClient {
    /// Starts a server; does not initialize it.
    pub fn start() -> TestClient {
        // Large enough that a client sending thousands of edits before reading
        // never blocks the server on its output.
        let (client_side, server_side) = tokio::io::duplex(256 << 20);
        let (server_read, server_write) = tokio::io::split(server_side);
        let server = tokio::spawn(gloc_lsp::serve(server_read, server_write));
        let (read, write) = tokio::io::split(client_side);
        TestClient {
            writer: write,
            reader: BufReader::new(read),
            next_id: 1,
            notifications: VecDeque::new(),
            configuration: Value::Null,
            server,
        }
    }

    /// Starts and initializes a server with the given client capabilities.
    pub async fn initialized_with(capabilities: Value, options: Value) -> TestClient {
        let mut client = TestClient::start();
        let result = client
            .request(
                "initialize",
                json!({ "processId": null, "rootUri": null, "capabilities": capabilities,
                        "initializationOptions": options }),
            )
            .await;
        assert!(result["capabilities"].is_object(), "{result}");
        client.notify("initialized", json!({})).await;
        client
    }

    /// A server initialized by a client that shows what editors show: snippets,
    /// markdown, nested document symbols.
    pub async fn initialized() -> TestClient {
        TestClient::initialized_with(editor_capabilities(), Value::Null).await
    }

    pub async fn send_raw(&mut self, body: &str) {
        let frame = format!("Content-Length: {}\r\n\r\n{}", body.len(), body);
        self.writer
            .write_all(frame.as_bytes())
            .await
            .expect("write to server");
        self.writer.flush().await.expect("flush");
    }

    async fn send(&mut self, message: Value) {
        self.send_raw(&message.to_string()).await;
    }

    pub async fn notify(&mut self, method: &str, params: Value) {
        self.send(json!({ "jsonrpc": "2.0", "method": method, "params": params }))
            .await;
    }

    /// Sends a request and returns its whole response (`result` or `error`).
    pub async fn request_raw(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        self.send(json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params }))
            .await;
        loop {
            let message = self.receive().await;
            if message.get("id") == Some(&json!(id)) && message.get("method").is_none() {
                return message;
            }
            self.handle(message).await;
        }
    }

    /// Sends a hand-written body and waits for the response with `id`.
    pub async fn request_raw_body(&mut self, body: &str, id: i64) -> Value {
        self.send_raw(body).await;
        loop {
            let message = self.receive().await;
            if message.get("id") == Some(&json!(id)) && message.get("method").is_none() {
                return message;
            }
            self.handle(message).await;
        }
    }

    /// Sends a request and returns its `result`, failing the test on an error.
    pub async fn request(&mut self, method: &str, params: Value) -> Value {
        let response = self.request_raw(method, params).await;
        assert!(
            response.get("error").is_none(),
            "{method} failed: {response}"
        );
        response["result"].clone()
    }

    /// Reads one message, with a timeout so a hung server fails the test.
    pub async fn receive(&mut self) -> Value {
        tokio::time::timeout(TIMEOUT, self.read_message())
            .await
            .expect("the server answered in time")
    }

    async fn read_message(&mut self) -> Value {
        let body = gloc_testsupport::read_frame(&mut self.reader)
            .await
            .expect("the server keeps its output open");
        serde_json::from_slice(&body).expect("valid JSON from the server")
    }

    /// Answers server requests; keeps notifications.
    async fn handle(&mut self, message: Value) {
        match (
            message.get("id"),
            message.get("method").and_then(Value::as_str),
        ) {
            (Some(id), Some("workspace/configuration")) => {
                let count = message["params"]["items"].as_array().map_or(0, Vec::len);
                let result: Vec<Value> = (0..count).map(|_| self.configuration.clone()).collect();
                let id = id.clone();
                self.send(json!({ "jsonrpc": "2.0", "id": id, "result": result }))
                    .await;
            }
            (Some(id), Some(_)) => {
                let id = id.clone();
                self.send(json!({ "jsonrpc": "2.0", "id": id, "result": null }))
                    .await;
                // Kept so tests can see what the server asked.
                self.notifications.push_back(message);
            }
            _ => self.notifications.push_back(message),
        }
    }

    /// Waits for the next `publishDiagnostics` for `uri` (older ones that were
    /// already received count) and returns its params.
    pub async fn diagnostics(&mut self, uri: &str) -> Value {
        loop {
            let position = self.notifications.iter().position(|message| {
                message["method"] == "textDocument/publishDiagnostics"
                    && message["params"]["uri"] == uri
            });
            if let Some(position) = position {
                let message = self.notifications.remove(position).expect("present");
                return message["params"].clone();
            }
            let message = self.receive().await;
            self.handle(message).await;
        }
    }

    /// The last diagnostics published for `uri` once the server is idle:
    /// sends a harmless request and drains everything before its answer.
    pub async fn latest_diagnostics(&mut self, uri: &str) -> Value {
        self.request("textDocument/hover", at("file:///never/opened.gloc", 0, 0))
            .await;
        // Notifications travel apart from responses inside the server, so one
        // sent before that answer may still arrive after it: wait for quiet.
        while let Ok(message) =
            tokio::time::timeout(Duration::from_millis(150), self.read_message()).await
        {
            self.handle(message).await;
        }
        let mut latest = Value::Null;
        while let Some(position) = self.notifications.iter().position(|message| {
            message["method"] == "textDocument/publishDiagnostics"
                && message["params"]["uri"] == uri
        }) {
            latest = self.notifications.remove(position).expect("present")["params"].clone();
        }
        latest
    }

    pub async fn open(&mut self, uri: &str, language: &str, text: &str) -> Value {
        self.notify(
            "textDocument/didOpen",
            json!({ "textDocument": { "uri": uri, "languageId": language, "version": 1, "text": text } }),
        )
        .await;
        self.diagnostics(uri).await
    }

    pub async fn shutdown_and_exit(mut self) -> gloc_lsp::Ending {
        let result = self.request("shutdown", Value::Null).await;
        assert_eq!(result, Value::Null);
        self.notify("exit", Value::Null).await;
        tokio::time::timeout(TIMEOUT, self.server)
            .await
            .expect("the server stopped after exit")
            .expect("server task")
    }
}

/// `{ "textDocument": { "uri" }, "position": { line, character } }`.
pub fn at(uri: &str, line: u32, character: u32) -> Value {
    json!({ "textDocument": { "uri": uri }, "position": { "line": line, "character": character } })
}

/// The capabilities VS Code and Neovim 0.11 send for what the tests look at.
pub fn editor_capabilities() -> Value {
    json!({
        "textDocument": {
            "completion": { "completionItem": {
                "snippetSupport": true,
                "documentationFormat": ["markdown", "plaintext"],
            } },
            "hover": { "contentFormat": ["markdown", "plaintext"] },
            "documentSymbol": { "hierarchicalDocumentSymbolSupport": true },
            "publishDiagnostics": { "relatedInformation": true },
        }
    })
}

/// What Emacs 28's eglot 1.9 (Debian's `elpa-eglot`) sends for what the tests
/// look at, from its `eglot-client-capabilities`: no snippets without yasnippet,
/// no related information, plain-text hover without markdown-mode.
pub fn eglot_capabilities() -> Value {
    json!({
        "textDocument": {
            "completion": { "completionItem": {
                "snippetSupport": false,
                "deprecatedSupport": true,
                "tagSupport": { "valueSet": [1] },
            }, "contextSupport": true },
            "hover": { "contentFormat": ["plaintext"] },
            "publishDiagnostics": { "relatedInformation": false },
        }
    })
}
