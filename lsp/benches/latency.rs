//! Latency of the language server on a 10,000-line GBASIC file, measured
//! through the real protocol (framed JSON-RPC over in-memory pipes): p50 and p99
//! of every request type with an edit before each request (so each one pays for
//! the analysis of the new text), `didChange` → `publishDiagnostics`, how fast a
//! queue of cancelled requests drains, and the process's memory after opening a
//! 30,000-line file (GBASIC's 1 MB cap: 100,000 lines are 3 MB).
//!
//! Run: `cargo bench -p gloc-lsp --bench latency` (prints figures, the request table
//! in markdown; asserts nothing about speed). `GLOC_BENCH_ROUNDS` sets the requests
//! per type (default 200), `GLOC_BENCH_RUNS` the semantic-token runs (default 21).

#[path = "../tests/support/mod.rs"]
mod support;

use std::time::{Duration, Instant};

use serde_json::json;
use support::{at, TestClient};

/// A realistic program: declarations, then 500 labelled sections with
/// blocks, sensor reads and writes, arithmetic and `yield`s. 10,000 lines.
fn program() -> String {
    program_of(10_000)
}

/// The same shape, `line_count` lines long.
fn program_of(line_count: usize) -> String {
    let mut lines = vec![
        "' 10,000-line benchmark program".to_string(),
        "dim depth_sum as float".to_string(),
        "dim count as integer".to_string(),
        "dim bins(40) as float".to_string(),
    ];
    let sections = line_count.div_ceil(20);
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
    lines.truncate(line_count);
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

/// The nearest-rank percentile `p` (0–100) of sorted samples, in ms.
fn percentile(sorted: &[Duration], p: usize) -> f64 {
    let rank = (sorted.len() * p).div_ceil(100).max(1);
    sorted[rank - 1].as_secs_f64() * 1e3
}

/// CPU time of this thread, which runs both the client and the server (a
/// current-thread runtime): unlike wall time, it does not grow with the load of
/// the machine.
fn thread_cpu() -> Duration {
    let mut now = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes one timespec through the valid pointer given.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut now) };
    assert_eq!(
        status, 0,
        "clock_gettime(CLOCK_THREAD_CPUTIME_ID) works on Linux"
    );
    Duration::new(now.tv_sec as u64, now.tv_nsec as u32)
}

/// This process's resident memory in MB (Linux `/proc/self/status`).
fn rss_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|line| line.starts_with("VmRSS:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

fn main() {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    // First, while the process is fresh: memory after opening 30,000 lines.
    runtime.block_on(memory());
    // Semantic tokens on 50,000 lines, outside the protocol (the computation alone).
    let big = program_of(50_000);
    let runs = std::env::var("GLOC_BENCH_RUNS")
        .ok()
        .and_then(|text| text.parse().ok())
        .unwrap_or(21);
    let (count, times) = gloc_lsp::time_semantic_tokens(&big, runs);
    summary(
        &format!("semantic tokens, 50,000 lines ({count} tokens)"),
        times,
    );
    runtime.block_on(run());
    runtime.block_on(requests());
}

/// The process's resident memory before a server starts and once it has opened
/// (and analysed) a 30,000-line GBASIC file. Client and server share the
/// process: the figure includes the client's copy of the text (about 3 MB).
async fn memory() {
    let before = rss_mb();
    let text = program_of(30_000);
    let mut client = TestClient::initialized().await;
    let started = Instant::now();
    let published = client
        .open("file:///bench/huge.gbas", "gbasic", &text)
        .await;
    let open_time = started.elapsed();
    let after = rss_mb();
    let count = published["diagnostics"].as_array().map_or(0, Vec::len);
    match (before, after) {
        (Some(before), Some(after)) => println!(
            "memory: 30,000-line GBASIC file ({:.1} MB) open and analysed: RSS {after:.1} MB (process before the server started: {before:.1} MB; +{:.1} MB); didOpen → diagnostics {:.0} ms ({count} diagnostics)",
            text.len() as f64 / 1e6,
            after - before,
            open_time.as_secs_f64() * 1e3
        ),
        _ => println!("memory: /proc/self/status is not readable here"),
    }
    client.shutdown_and_exit().await;
}

/// One request per round, each after an edit (a character typed, then deleted,
/// on line 5,007), on a client with pull diagnostics, completion resolve and the
/// code lens commands: p50 and p99 per request type, and the answer's size.
async fn requests() {
    let rounds: usize = std::env::var("GLOC_BENCH_ROUNDS")
        .ok()
        .and_then(|text| text.parse().ok())
        .unwrap_or(200);
    let text = program();
    let uri = "file:///bench/big.gbas";
    let mut capabilities = support::editor_capabilities();
    capabilities["textDocument"]["diagnostic"] = json!({ "dynamicRegistration": false });
    capabilities["textDocument"]["completion"]["completionItem"]["resolveSupport"] =
        json!({ "properties": ["documentation"] });
    capabilities["experimental"] =
        json!({ "commands": { "commands": ["gloc.runMission", "gloc.debugScript"] } });
    let mut client = TestClient::initialized_with(capabilities, serde_json::Value::Null).await;
    client
        .notify(
            "textDocument/didOpen",
            json!({ "textDocument": { "uri": uri, "languageId": "gbasic", "version": 1, "text": text } }),
        )
        .await;
    let document = json!({ "textDocument": { "uri": uri } });
    let screen = json!({ "start": { "line": 5000, "character": 0 }, "end": { "line": 5060, "character": 0 } });
    let with = |extra: serde_json::Value| {
        let mut params = document.clone();
        if let (Some(params), Some(extra)) = (params.as_object_mut(), extra.as_object()) {
            params.extend(extra.clone());
        }
        params
    };
    // Line 5,004 is `label: section250`; see `program_of` for the lines after it.
    let cases: Vec<(&str, &str, serde_json::Value)> = vec![
        (
            "textDocument/diagnostic (pull)",
            "textDocument/diagnostic",
            document.clone(),
        ),
        (
            "completion, `if m_de|` (expression)",
            "textDocument/completion",
            at(uri, 5005, 7),
        ),
        (
            "completion, statement start (nothing typed)",
            "textDocument/completion",
            at(uri, 5006, 2),
        ),
        (
            "completionItem/resolve",
            "completionItem/resolve",
            serde_json::Value::Null,
        ),
        ("hover (sensor)", "textDocument/hover", at(uri, 5005, 6)),
        (
            "signatureHelp (in `max(`)",
            "textDocument/signatureHelp",
            at(uri, 5020, 14),
        ),
        (
            "definition (label)",
            "textDocument/definition",
            at(uri, 5022, 6),
        ),
        (
            "references (label)",
            "textDocument/references",
            with(
                json!({ "position": { "line": 5022, "character": 6 }, "context": { "includeDeclaration": true } }),
            ),
        ),
        (
            "documentHighlight (`count`, ~2,000 uses)",
            "textDocument/documentHighlight",
            at(uri, 5019, 1),
        ),
        (
            "prepareRename",
            "textDocument/prepareRename",
            at(uri, 5019, 1),
        ),
        (
            "rename (`count`, ~2,000 edits)",
            "textDocument/rename",
            with(json!({ "position": { "line": 5019, "character": 1 }, "newName": "counter" })),
        ),
        (
            "documentSymbol",
            "textDocument/documentSymbol",
            document.clone(),
        ),
        (
            "foldingRange",
            "textDocument/foldingRange",
            document.clone(),
        ),
        (
            "semanticTokens/full",
            "textDocument/semanticTokens/full",
            document.clone(),
        ),
        (
            "semanticTokens/full/delta",
            "textDocument/semanticTokens/full/delta",
            serde_json::Value::Null,
        ),
        (
            "semanticTokens/range (60 lines)",
            "textDocument/semanticTokens/range",
            with(json!({ "range": screen })),
        ),
        (
            "inlayHint (60 lines)",
            "textDocument/inlayHint",
            with(json!({ "range": screen })),
        ),
        (
            "codeAction (the edited line)",
            "textDocument/codeAction",
            with(
                json!({ "range": { "start": { "line": 5007, "character": 0 }, "end": { "line": 5007, "character": 5 } }, "context": { "diagnostics": [] } }),
            ),
        ),
        ("codeLens", "textDocument/codeLens", document.clone()),
        (
            "selectionRange",
            "textDocument/selectionRange",
            with(json!({ "positions": [{ "line": 5020, "character": 30 }] })),
        ),
        (
            "formatting",
            "textDocument/formatting",
            with(json!({ "options": { "tabSize": 2, "insertSpaces": true } })),
        ),
        (
            "rangeFormatting (20 lines)",
            "textDocument/rangeFormatting",
            with(
                json!({ "range": { "start": { "line": 5000, "character": 0 }, "end": { "line": 5020, "character": 0 } }, "options": { "tabSize": 2, "insertSpaces": true } }),
            ),
        ),
        (
            "documentLink",
            "textDocument/documentLink",
            document.clone(),
        ),
        (
            "workspace/symbol (`section25`)",
            "workspace/symbol",
            json!({ "query": "section25" }),
        ),
    ];
    let mut version = 1;
    let mut resolvable = serde_json::Value::Null;
    let mut tokens_id = String::new();
    println!();
    println!(
        "| request (10,000-line GBASIC file, an edit before each) | p50 ms | p99 ms | CPU p50 ms | CPU p99 ms | answer |"
    );
    println!("|---|---:|---:|---:|---:|---:|");
    for (name, method, params) in cases {
        let mut samples = Vec::with_capacity(rounds);
        let mut cpu_samples = Vec::with_capacity(rounds);
        let mut bytes = 0;
        for _ in 0..rounds {
            version += 1;
            let (end, new_text) = if version % 2 == 0 { (2, "x") } else { (3, "") };
            client
                .notify("textDocument/didChange", json!({ "textDocument": { "uri": uri, "version": version }, "contentChanges": [{ "range": { "start": { "line": 5007, "character": 2 }, "end": { "line": 5007, "character": end } }, "text": new_text }] }))
                .await;
            let params = match method {
                "completionItem/resolve" => resolvable.clone(),
                "textDocument/semanticTokens/full/delta" => {
                    with(json!({ "previousResultId": tokens_id }))
                }
                _ => params.clone(),
            };
            let started = Instant::now();
            let cpu_started = thread_cpu();
            let result = client.request(method, params).await;
            samples.push(started.elapsed());
            cpu_samples.push(thread_cpu().saturating_sub(cpu_started));
            bytes = result.to_string().len();
            match method {
                "textDocument/completion" => resolvable = result["items"][0].clone(),
                "textDocument/semanticTokens/full" | "textDocument/semanticTokens/full/delta" => {
                    tokens_id = result["resultId"].as_str().unwrap_or_default().to_string();
                }
                _ => {}
            }
        }
        samples.sort();
        cpu_samples.sort();
        println!(
            "| {name} | {:.1} | {:.1} | {:.1} | {:.1} | {} |",
            percentile(&samples, 50),
            percentile(&samples, 99),
            percentile(&cpu_samples, 50),
            percentile(&cpu_samples, 99),
            if bytes >= 10_000 {
                format!("{:.0} KB", bytes as f64 / 1e3)
            } else {
                format!("{bytes} B")
            }
        );
    }
    println!("(n = {rounds} per request type)");
    client.shutdown_and_exit().await;
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
