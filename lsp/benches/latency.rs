//! Latency of the language server on a 10,000-line GBASIC file, measured
//! through the real protocol (framed JSON-RPC over in-memory pipes):
//! `didChange` → `publishDiagnostics`, completion / hover round trips, and how fast a
//! queue of cancelled requests drains.
//!
//! Run: `cargo bench -p gloc-lsp --bench latency` (prints figures; asserts nothing
//! about speed).

#[path = "../tests/support/mod.rs"]
mod support;

use std::time::{Duration, Instant};

use serde_json::json;
use support::{at, TestClient};

/// A realistic program: declarations, then 500 labelled sections with
/// blocks, sensor reads and writes, arithmetic and `yield`s. 10,000 lines.
fn program() -> String {
    let mut lines = vec![
        "' 10,000-line benchmark program".to_string(),
        "dim depth_sum as float".to_string(),
        "dim count as integer".to_string(),
        "dim bins(40) as float".to_string(),
    ];
    let sections = 500;
    for section in 0..sections {
        let next = (section + 1) % sections;
        lines.extend([
            format!("label: section{section}"),
            "if m_depth > 15.0 then".to_string(),
            "  SCI_RUHP_BEHS = 128".to_string(),
            "  depth_sum = depth_sum + m_depth".to_string(),
            "elseif m_depth < 5.0 then".to_string(),
            "  SCI_RUHP_BEHS = 0".to_string(),
            "else".to_string(),
            "  count = count + 1".to_string(),
            "endif".to_string(),
            "while count < 3".to_string(),
            "  count = count + 1".to_string(),
            "  bins(count) = sci_water_temp".to_string(),
            "  yield".to_string(),
            "wend".to_string(),
            "print \"section\", count, depth_sum".to_string(),
            "count = 0".to_string(),
            "c_pitch = max(-0.4, min(0.4, m_pitch * 2.0))".to_string(),
            "yield".to_string(),
            format!("goto section{next}"),
            "' end of section".to_string(),
        ]);
    }
    lines.truncate(10_000);
    lines.join("\n") + "\n"
}

fn summary(name: &str, mut samples: Vec<Duration>) {
    samples.sort();
    let median = samples[samples.len() / 2];
    let p90 = samples[samples.len() * 9 / 10];
    let max = samples[samples.len() - 1];
    println!(
        "{name:<44} median {:>8.2} ms   p90 {:>8.2} ms   max {:>8.2} ms   (n={})",
        median.as_secs_f64() * 1e3,
        p90.as_secs_f64() * 1e3,
        max.as_secs_f64() * 1e3,
        samples.len()
    );
}

fn main() {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    runtime.block_on(run());
}

async fn run() {
    let text = program();
    assert_eq!(text.lines().count(), 10_000);
    let uri = "file:///bench/big.gbas";
    let mut client = TestClient::initialized().await;

    let started = Instant::now();
    let published = client.open(uri, "gbasic", &text).await;
    let open_time = started.elapsed();
    let count = published["diagnostics"].as_array().map_or(0, Vec::len);
    println!(
        "10,000-line GBASIC file ({} bytes): didOpen → diagnostics {:.2} ms ({count} diagnostics)",
        text.len(),
        open_time.as_secs_f64() * 1e3
    );

    // Typing: insert then delete a character in the middle of the file, each
    // edit waiting for its diagnostics.
    let rounds = 30;
    let mut change_samples = Vec::new();
    for round in 0..rounds {
        let version = 2 + round;
        let (range, new_text) = if round % 2 == 0 {
            (
                json!({ "start": { "line": 5007, "character": 2 }, "end": { "line": 5007, "character": 2 } }),
                "x",
            )
        } else {
            (
                json!({ "start": { "line": 5007, "character": 2 }, "end": { "line": 5007, "character": 3 } }),
                "",
            )
        };
        let started = Instant::now();
        client
            .notify("textDocument/didChange", json!({ "textDocument": { "uri": uri, "version": version }, "contentChanges": [{ "range": range, "text": new_text }] }))
            .await;
        loop {
            let params = client.diagnostics(uri).await;
            if params["version"] == json!(version) {
                break;
            }
        }
        change_samples.push(started.elapsed());
    }
    summary("didChange → publishDiagnostics", change_samples);

    let mut completion_samples = Vec::new();
    let mut hover_samples = Vec::new();
    let mut items = 0;
    for _ in 0..rounds {
        // Start of a statement (writable sensors, variables, keywords).
        let started = Instant::now();
        let result = client
            .request("textDocument/completion", at(uri, 5006, 2))
            .await;
        completion_samples.push(started.elapsed());
        items = result["items"].as_array().map_or(0, Vec::len);
        let started = Instant::now();
        let hover = client.request("textDocument/hover", at(uri, 5005, 6)).await;
        hover_samples.push(started.elapsed());
        assert!(hover["contents"]["value"]
            .as_str()
            .is_some_and(|value| value.contains("m_depth")));
    }
    summary(
        &format!("completion (statement start, {items} items)"),
        completion_samples,
    );
    summary("hover (sensor)", hover_samples);

    // After an edit, the first request pays for the analysis (no waiting for diagnostics).
    let mut stale_samples = Vec::new();
    for round in 0..rounds {
        let version = 100 + round;
        client
            .notify("textDocument/didChange", json!({ "textDocument": { "uri": uri, "version": version }, "contentChanges": [{ "range": { "start": { "line": 5003, "character": 0 }, "end": { "line": 5003, "character": 0 } }, "text": " " }] }))
            .await;
        let started = Instant::now();
        client.request("textDocument/hover", at(uri, 5005, 6)).await;
        stale_samples.push(started.elapsed());
    }
    summary("hover right after an edit", stale_samples);

    // A queue of cancelled requests: 100 `semanticTokens/full`, each followed by its
    // `$/cancelRequest`, all sent at once; the time until the last answer.
    let started = Instant::now();
    client
        .request(
            "textDocument/semanticTokens/full",
            json!({ "textDocument": { "uri": uri } }),
        )
        .await;
    let one = started.elapsed();
    let first_id = 10_000;
    let count = 100;
    let started = Instant::now();
    for id in first_id..first_id + count {
        client
            .send_raw(&json!({ "jsonrpc": "2.0", "id": id, "method": "textDocument/semanticTokens/full", "params": { "textDocument": { "uri": uri } } }).to_string())
            .await;
        client.notify("$/cancelRequest", json!({ "id": id })).await;
    }
    let mut answered = 0;
    let mut cancelled = 0;
    while answered < count {
        let message = client.receive().await;
        let id = message["id"].as_i64().unwrap_or(0);
        if message.get("method").is_none() && (first_id..first_id + count).contains(&id) {
            answered += 1;
            if message["error"]["code"] == json!(-32800) {
                cancelled += 1;
            }
        }
    }
    println!(
        "{count} cancelled semanticTokens requests drain in {:.2} ms ({cancelled} answered RequestCancelled; one uncancelled request: {:.2} ms)",
        started.elapsed().as_secs_f64() * 1e3,
        one.as_secs_f64() * 1e3
    );
    client.shutdown_and_exit().await;
}
