//! Protocol tests that hold for any language: lifecycle, robustness against
//! odd clients, incremental sync with non-ASCII text, and configuration.

mod support;

use serde_json::{json, Value};
use support::{at, TestClient};

#[tokio::test]
async fn initialize_advertises_incremental_utf16_and_every_feature() {
    let mut client = TestClient::start();
    let result = client
        .request(
            "initialize",
            json!({ "processId": null, "rootUri": null, "capabilities": {} }),
        )
        .await;
    let capabilities = &result["capabilities"];
    assert_eq!(capabilities["positionEncoding"], "utf-16");
    assert_eq!(capabilities["textDocumentSync"]["change"], 2, "incremental");
    for feature in [
        "completionProvider",
        "hoverProvider",
        "definitionProvider",
        "referencesProvider",
        "documentHighlightProvider",
        "renameProvider",
        "documentSymbolProvider",
        "foldingRangeProvider",
        "semanticTokensProvider",
        "inlayHintProvider",
        "codeActionProvider",
        "documentFormattingProvider",
        "signatureHelpProvider",
        "executeCommandProvider",
    ] {
        assert!(
            !capabilities[feature].is_null(),
            "{feature} missing: {capabilities}"
        );
    }
    assert_eq!(capabilities["renameProvider"]["prepareProvider"], true);
    assert_eq!(
        capabilities["executeCommandProvider"]["commands"],
        json!(["gloc.compiledGloc"])
    );
    client.notify("initialized", json!({})).await;
    assert_eq!(client.shutdown_and_exit().await, gloc_lsp::Ending::Clean);
}

#[tokio::test]
async fn exit_without_shutdown_is_not_clean() {
    let mut client = TestClient::initialized().await;
    client.notify("exit", Value::Null).await;
    let ending = tokio::time::timeout(std::time::Duration::from_secs(20), client.server)
        .await
        .expect("stopped")
        .expect("task");
    assert_eq!(ending, gloc_lsp::Ending::WithoutShutdown);
}

#[tokio::test]
async fn requests_after_shutdown_are_refused_and_before_initialize_too() {
    let mut client = TestClient::start();
    let early = client
        .request_raw("textDocument/hover", at("file:///a.gloc", 0, 0))
        .await;
    assert_eq!(
        early["error"]["code"], -32002,
        "server not initialized: {early}"
    );
    client
        .request(
            "initialize",
            json!({ "processId": null, "rootUri": null, "capabilities": {} }),
        )
        .await;
    client.request("shutdown", Value::Null).await;
    let late = client
        .request_raw("textDocument/hover", at("file:///a.gloc", 0, 0))
        .await;
    assert_eq!(
        late["error"]["code"], -32600,
        "invalid request after shutdown: {late}"
    );
    client.notify("exit", Value::Null).await;
}

#[tokio::test]
async fn unknown_documents_and_odd_requests_never_crash() {
    let mut client = TestClient::initialized().await;
    let uri = "file:///nowhere/x.gloc";
    // Edits and closes for a document never opened are ignored.
    client
        .notify("textDocument/didChange", json!({ "textDocument": { "uri": uri, "version": 2 },
            "contentChanges": [{ "range": { "start": { "line": 0, "character": 0 }, "end": { "line": 0, "character": 0 } }, "text": "x" }] }))
        .await;
    client
        .notify(
            "textDocument/didClose",
            json!({ "textDocument": { "uri": uri } }),
        )
        .await;
    for method in [
        "textDocument/hover",
        "textDocument/completion",
        "textDocument/definition",
        "textDocument/documentHighlight",
        "textDocument/prepareRename",
        "textDocument/signatureHelp",
    ] {
        let result = client.request(method, at(uri, 3, 4)).await;
        assert_eq!(result, Value::Null, "{method}");
    }
    let doc = json!({ "textDocument": { "uri": uri } });
    for method in [
        "textDocument/documentSymbol",
        "textDocument/foldingRange",
        "textDocument/semanticTokens/full",
    ] {
        assert_eq!(
            client.request(method, doc.clone()).await,
            Value::Null,
            "{method}"
        );
    }
    let formatting = json!({ "textDocument": { "uri": uri }, "options": { "tabSize": 2, "insertSpaces": true } });
    assert_eq!(
        client.request("textDocument/formatting", formatting).await,
        Value::Null
    );
    // A language the server does not know is not tracked.
    client
        .notify("textDocument/didOpen", json!({ "textDocument": { "uri": "file:///a.rs", "languageId": "rust", "version": 1, "text": "fn main() {}" } }))
        .await;
    // Malformed JSON, wrong params and unknown methods get errors, not a crash.
    client.send_raw("{ this is not json").await;
    client.send_raw("[1,2]").await;
    let broken = client
        .request_raw_body(r#"{"id":4242,"method":"textDocument/hover"}"#, 4242)
        .await;
    assert_eq!(broken["error"]["code"], -32600, "{broken}");
    let wrong = client
        .request_raw("textDocument/hover", json!({ "textDocument": 5 }))
        .await;
    assert_eq!(wrong["error"]["code"], -32602, "{wrong}");
    let unknown = client.request_raw("gloc/noSuchThing", json!({})).await;
    assert_eq!(unknown["error"]["code"], -32601, "{unknown}");
    let command = client
        .request_raw(
            "workspace/executeCommand",
            json!({ "command": "gloc.compiledGloc", "arguments": [uri] }),
        )
        .await;
    assert!(
        command["error"]["message"]
            .as_str()
            .unwrap_or("")
            .contains("is not open"),
        "{command}"
    );
    let command = client
        .request_raw(
            "workspace/executeCommand",
            json!({ "command": "gloc.compiledGloc", "arguments": [] }),
        )
        .await;
    assert!(
        command["error"]["message"]
            .as_str()
            .unwrap_or("")
            .contains("takes one argument"),
        "{command}"
    );
    assert_eq!(client.shutdown_and_exit().await, gloc_lsp::Ending::Clean);
}

/// The document text as the server sees it (a GLOC document's "compiled GLOC" is itself).
async fn server_text(client: &mut TestClient, uri: &str) -> String {
    let result = client
        .request(
            "workspace/executeCommand",
            json!({ "command": "gloc.compiledGloc", "arguments": [uri] }),
        )
        .await;
    result.as_str().expect("text").to_string()
}

fn edit(uri: &str, version: i32, changes: Value) -> Value {
    json!({ "textDocument": { "uri": uri, "version": version }, "contentChanges": changes })
}

fn range(l1: u32, c1: u32, l2: u32, c2: u32) -> Value {
    json!({ "start": { "line": l1, "character": c1 }, "end": { "line": l2, "character": c2 } })
}

#[tokio::test]
async fn incremental_edits_with_non_ascii_text_keep_utf16_positions() {
    let mut client = TestClient::initialized().await;
    let uri = "file:///tmp/edits.gloc";
    client
        .open(uri, "gloc", "prints \"Zürich 𝄞\"\nyield\n")
        .await;
    // 'ü' is at UTF-16 column 9; '𝄞' occupies columns 15..17.
    client
        .notify(
            "textDocument/didChange",
            edit(
                uri,
                2,
                json!([
                    { "range": range(0, 9, 0, 10), "text": "u" },
                    { "range": range(0, 15, 0, 17), "text": "♫é" },
                    { "range": range(1, 5, 1, 5), "text": " # ✓ done" },
                ]),
            ),
        )
        .await;
    assert_eq!(
        server_text(&mut client, uri).await,
        "prints \"Zurich ♫é\"\nyield # ✓ done\n"
    );
    // A request sent right after many edits sees all of them (ordering).
    for version in 3..300 {
        client
            .notify(
                "textDocument/didChange",
                edit(
                    uri,
                    version,
                    json!([{ "range": range(2, 0, 2, 0), "text": "é" }]),
                ),
            )
            .await;
    }
    let text = server_text(&mut client, uri).await;
    assert_eq!(text.matches('é').count(), 1 + 297, "{text}");
    // Full-text replacement.
    client
        .notify(
            "textDocument/didChange",
            edit(uri, 400, json!([{ "text": "halt\n" }])),
        )
        .await;
    assert_eq!(server_text(&mut client, uri).await, "halt\n");
    client
        .notify(
            "textDocument/didClose",
            json!({ "textDocument": { "uri": uri } }),
        )
        .await;
    let last = client.latest_diagnostics(uri).await;
    assert_eq!(last["diagnostics"], json!([]));
    assert_eq!(
        last["version"],
        Value::Null,
        "a close clears without a version"
    );
    let closed = client
        .request_raw(
            "workspace/executeCommand",
            json!({ "command": "gloc.compiledGloc", "arguments": [uri] }),
        )
        .await;
    assert!(
        closed.get("error").is_some(),
        "closed documents are forgotten: {closed}"
    );
}

/// Every request at every position of odd documents (binary garbage, lone
/// surrogates' replacement characters, CRLF, huge lines) answers without
/// killing the server.
#[tokio::test]
async fn every_request_everywhere_on_odd_documents() {
    let mut client = TestClient::initialized().await;
    let documents = [
        (
            "gloc",
            "nregs 1\r\nnblbs 1\r\nninstr 2\r\nlabel 0\r\njumpi 0\r\n",
        ),
        (
            "gloc",
            "\u{0}\u{1}\u{7f}loads 𝄞,r0\n\"\"\"\ncbr r9999999999999,1,\n",
        ),
        (
            "gbasic",
            "if m_dépth > 1 then\r\n  x = \"𝄞\r\nlabel: é\ngoto é\nfor i = 1 to\n(((((\n",
        ),
        (
            "gbasic",
            "\u{feff}print 1e999, 99999999999999999999999 ' ü\nrem 𝄞\n\r\r\n",
        ),
    ];
    for (index, (language, text)) in documents.iter().enumerate() {
        let uri = format!(
            "file:///odd/{index}.{}",
            if *language == "gloc" { "gloc" } else { "gbas" }
        );
        client.open(&uri, language, text).await;
        let lines = text.split('\n').count() as u32 + 1;
        for line in 0..lines {
            for character in [0u32, 1, 2, 3, 5, 8, 13, 40, 1000] {
                for method in [
                    "textDocument/hover",
                    "textDocument/completion",
                    "textDocument/definition",
                    "textDocument/documentHighlight",
                    "textDocument/prepareRename",
                    "textDocument/signatureHelp",
                ] {
                    let response = client.request_raw(method, at(&uri, line, character)).await;
                    assert!(
                        response.get("error").is_none(),
                        "{method} {line}:{character} on {text:?}: {response}"
                    );
                }
                let rename = client
                    .request_raw("textDocument/rename", json!({ "textDocument": { "uri": uri }, "position": { "line": line, "character": character }, "newName": "z9" }))
                    .await;
                assert!(
                    rename.get("result").is_some() || rename["error"]["code"] == -32602,
                    "{rename}"
                );
            }
        }
        let document = json!({ "textDocument": { "uri": uri } });
        for method in [
            "textDocument/documentSymbol",
            "textDocument/foldingRange",
            "textDocument/semanticTokens/full",
        ] {
            let response = client.request_raw(method, document.clone()).await;
            assert!(
                response["result"].is_array() || response["result"]["data"].is_array(),
                "{method}: {response}"
            );
        }
        let whole = json!({ "start": { "line": 0, "character": 0 }, "end": { "line": 99, "character": 0 } });
        for (method, params) in [
            (
                "textDocument/inlayHint",
                json!({ "textDocument": { "uri": uri }, "range": whole }),
            ),
            (
                "textDocument/codeAction",
                json!({ "textDocument": { "uri": uri }, "range": whole, "context": { "diagnostics": [] } }),
            ),
            (
                "textDocument/formatting",
                json!({ "textDocument": { "uri": uri }, "options": { "tabSize": 2, "insertSpaces": true } }),
            ),
        ] {
            let response = client.request_raw(method, params).await;
            assert!(response.get("error").is_none(), "{method}: {response}");
        }
    }
    assert_eq!(client.shutdown_and_exit().await, gloc_lsp::Ending::Clean);
}
