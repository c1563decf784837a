//! Protocol tests on GBASIC documents: each LSP method through framed JSON-RPC,
//! for what the conversion decides (UTF-16 ranges, LSP kinds and severities,
//! related information, snippets, workspace edits, refusals as errors). What each
//! feature answers is tested on fixtures in gloc-ide (ide/tests/features). The
//! program is the paper's Fig. 3; its compiled GLOC must be the paper's Fig. 2.

mod support;

use serde_json::{json, Value};
use support::{at, TestClient};

const FIG3: &str = "label: state1\nif m_depth > 15.0 then\n  SCI_RUHP_BEHS = 128\n  goto state2\nendif\nyield\ngoto state1\nlabel: state2\nif m_depth < 5.0 then\n  SCI_RUHP_BEHS = 0\n  goto state3\nendif\nyield\ngoto state2\nlabel: state3\nyield\ngoto state3\n";

const FIG2: &str = "nregs 8\nnblbs 7\nninstr 27\nlabel 0\nloads 444,r0\nloadd 15.0,r1\ncmpgt r0,r1,r2\ncbr r2,3,4\nlabel 3\nloadi 128,r3\nstores r3,1387\njumpi 1\nlabel 4\nyield\njumpi 0\nlabel 1\nloads 444,r4\nloadd 5.0,r5\ncmplt r4,r5,r6\ncbr r6,5,6\nlabel 5\nloadi 0,r7\nstores r7,1387\njumpi 2\nlabel 6\nyield\njumpi 1\nlabel 2\nyield\njumpi 2\n";

const URI: &str = "file:///project/fig3.gbas";

async fn fig3() -> TestClient {
    let mut client = TestClient::initialized().await;
    let published = client.open(URI, "gbasic", FIG3).await;
    assert_eq!(published["diagnostics"], json!([]), "Fig. 3 is clean");
    client
}

fn range(l1: u32, c1: u32, l2: u32, c2: u32) -> Value {
    json!({ "start": { "line": l1, "character": c1 }, "end": { "line": l2, "character": c2 } })
}

fn labels(result: &Value) -> Vec<String> {
    result["items"]
        .as_array()
        .expect("items")
        .iter()
        .map(|item| item["label"].as_str().expect("label").to_string())
        .collect()
}

async fn change(client: &mut TestClient, uri: &str, version: i32, text: &str) {
    client
        .notify("textDocument/didChange", json!({ "textDocument": { "uri": uri, "version": version }, "contentChanges": [{ "text": text }] }))
        .await;
}

#[tokio::test]
async fn compiled_gloc_command_returns_fig2() {
    let mut client = fig3().await;
    let gloc = client
        .request(
            "workspace/executeCommand",
            json!({ "command": "gloc.compiledGloc", "arguments": [URI] }),
        )
        .await;
    assert_eq!(gloc, json!(FIG2));
    let by_object = client
        .request(
            "workspace/executeCommand",
            json!({ "command": "gloc.compiledGloc", "arguments": [{ "uri": URI }] }),
        )
        .await;
    assert_eq!(by_object, json!(FIG2));
    change(&mut client, URI, 2, "x = 1\n").await;
    let error = client
        .request_raw(
            "workspace/executeCommand",
            json!({ "command": "gloc.compiledGloc", "arguments": [URI] }),
        )
        .await;
    assert_eq!(error["error"]["code"], -32602);
    assert_eq!(
        error["error"]["message"],
        "the program has 1 error; fix it to see its GLOC"
    );
}

#[tokio::test]
async fn diagnostics_and_quick_fixes() {
    let mut client = TestClient::initialized().await;
    let uri = "file:///p/bad.gbas";
    let text = "dim count as integer\ncount = count + 1\nif m_dpth > 3.0 then\n  m_depth = 1\nendif\nx = 2\nyield\n";
    let published = client.open(uri, "gbasic", text).await;
    let diagnostics = published["diagnostics"].as_array().expect("d").clone();
    let codes: Vec<&str> = diagnostics
        .iter()
        .map(|d| d["code"].as_str().expect("code"))
        .collect();
    assert_eq!(codes, ["E2101", "E2105", "E2101"], "{diagnostics:#?}");
    assert_eq!(diagnostics[0]["range"], range(2, 3, 2, 9));
    assert_eq!(diagnostics[0]["severity"], 1);
    assert_eq!(diagnostics[0]["source"], "gloc");
    // The help follows the message on a line of its own.
    assert_eq!(
        diagnostics[0]["message"],
        "`m_dpth` is not declared and is not a sensor\nhelp: did you mean `m_depth`?"
    );

    // "did you mean `m_depth`?"
    let actions = client
        .request("textDocument/codeAction", json!({ "textDocument": { "uri": uri }, "range": range(2, 4, 2, 4), "context": { "diagnostics": [] } }))
        .await;
    assert_eq!(actions[0]["title"], "replace with `m_depth`");
    assert_eq!(actions[0]["kind"], "quickfix");
    assert_eq!(actions[0]["isPreferred"], true);
    assert_eq!(actions[0]["diagnostics"][0]["code"], "E2101");
    assert_eq!(
        actions[0]["edit"]["changes"][uri][0],
        json!({ "range": range(2, 3, 2, 9), "newText": "m_depth" })
    );
    // Two places: a duplicate label points at the first.
    let published = client
        .open(
            "file:///p/dup.gbas",
            "gbasic",
            "label: a\nyield\nlabel: a\ngoto a\n",
        )
        .await;
    let duplicate = &published["diagnostics"][0];
    assert_eq!(duplicate["code"], "E2104");
    assert_eq!(
        duplicate["relatedInformation"][0]["location"]["range"]["start"]["line"],
        0
    );
}

#[tokio::test]
async fn completion_items_carry_detail_snippets_and_sort_text() {
    let mut client = fig3().await;
    // `goto st|` on line 3 → the labels.
    let result = client
        .request("textDocument/completion", at(URI, 3, 9))
        .await;
    assert_eq!(labels(&result), ["state1", "state2", "state3"]);
    assert_eq!(result["isIncomplete"], false);
    // Start of the statement on line 2 (`  |SCI_RUHP_BEHS = 128`): a store target,
    // nothing typed yet: keywords, then writable sensors, cut at the limit (100).
    let result = client
        .request("textDocument/completion", at(URI, 2, 2))
        .await;
    let items = labels(&result);
    assert_eq!(items.len(), 100);
    assert_eq!(result["isIncomplete"], true);
    assert!(items.contains(&"dim".to_string()) && items.contains(&"while".to_string()));
    assert!(
        !items.contains(&"m_depth".to_string()),
        "read-only sensors rank after the writable ones"
    );
    // `SC|`: only what matches, prefix matches first.
    let result = client
        .request("textDocument/completion", at(URI, 2, 4))
        .await;
    let items = labels(&result);
    assert!(items.contains(&"sci_ruhp_behs".to_string()));
    assert!(items[0].starts_with("sc"), "{items:?}");
    assert!(!items.contains(&"c_pitch".to_string()), "no s in c_pitch");
    // In the condition of line 1 (`if m_de|`): every sensor.
    let result = client
        .request("textDocument/completion", at(URI, 1, 8))
        .await;
    let items = result["items"].as_array().expect("items");
    let depth = items
        .iter()
        .find(|i| i["label"] == "m_depth")
        .expect("m_depth");
    assert_eq!(depth["detail"], "sensor 444 (m), read-only");
    // A store target typed as `m_dep`: m_depth is offered although read-only
    // (every `m_` sensor is, so the shortest prefix match comes first), and marked.
    change(&mut client, URI, 2, "m_dep\n").await;
    let result = client
        .request("textDocument/completion", at(URI, 0, 5))
        .await;
    let first = &result["items"][0];
    assert_eq!(first["label"], "m_depth");
    assert_eq!(
        first["detail"],
        "sensor 444 (m), read-only: cannot be stored"
    );
    // Built-ins in an expression, as snippets.
    change(&mut client, URI, 3, "dim x as float\nx = ab\n").await;
    let result = client
        .request("textDocument/completion", at(URI, 1, 6))
        .await;
    let items = result["items"].as_array().expect("items");
    let abs = items.iter().find(|i| i["label"] == "abs").expect("abs");
    assert_eq!(abs["textEdit"]["newText"], "abs($1)");
    assert_eq!(abs["insertTextFormat"], 2);
    // Declared variables come first and carry their type.
    change(
        &mut client,
        URI,
        4,
        "dim depth_sum as float\ndepth_sum = depth_sum + \n",
    )
    .await;
    let result = client
        .request("textDocument/completion", at(URI, 1, 24))
        .await;
    let sum = &result["items"][0];
    assert_eq!(sum["label"], "depth_sum");
    assert_eq!(sum["detail"], "dim depth_sum as float");
    assert_eq!(sum["sortText"], "00000");
    // After `as`: the types (same match and group: the shorter first).
    change(&mut client, URI, 5, "dim n as \n").await;
    assert_eq!(
        labels(
            &client
                .request("textDocument/completion", at(URI, 0, 9))
                .await
        ),
        ["float", "integer"]
    );
}

#[tokio::test]
async fn hover_is_markdown_over_the_token() {
    let mut client = TestClient::initialized().await;
    let uri = "file:///p/h.gbas";
    let text = "dim n as integer\nn = abs(n) + 1\nif m_depth > 1.0 then\n  SCI_RUHP_BEHS = n\nendif\nyield\n";
    client.open(uri, "gbasic", text).await;
    let hover = client.request("textDocument/hover", at(uri, 2, 5)).await;
    assert!(hover["contents"]["value"]
        .as_str()
        .expect("md")
        .starts_with("**m_depth** (m)\n\nsensor 444 · read-only"));
    assert_eq!(hover["contents"]["kind"], "markdown");
    assert_eq!(hover["range"], range(2, 3, 2, 10));
    let hover = client.request("textDocument/hover", at(uri, 1, 0)).await;
    assert_eq!(
        hover["contents"]["value"],
        "variable `n`: dim n as integer\n\n3 uses"
    );
}

#[tokio::test]
async fn navigation_and_rename_of_labels_and_variables() {
    let mut client = fig3().await;
    // `goto state2` (line 3) → `label: state2` (line 7).
    let definition = client
        .request("textDocument/definition", at(URI, 3, 8))
        .await;
    assert_eq!(
        definition,
        json!({ "uri": URI, "range": range(7, 7, 7, 13) })
    );
    let references = client
        .request("textDocument/references", json!({ "textDocument": { "uri": URI }, "position": { "line": 7, "character": 8 }, "context": { "includeDeclaration": false } }))
        .await;
    let lines: Vec<u64> = references
        .as_array()
        .expect("l")
        .iter()
        .map(|l| l["range"]["start"]["line"].as_u64().expect("line"))
        .collect();
    assert_eq!(lines, [3, 13]);
    let highlights = client
        .request("textDocument/documentHighlight", at(URI, 13, 6))
        .await;
    assert_eq!(highlights.as_array().expect("h").len(), 3);
    // DocumentHighlightKind: the definition is a write (3), a use a read (2).
    assert_eq!(highlights[0]["kind"], 3);
    assert_eq!(highlights[1]["kind"], 2);
    let prepared = client
        .request("textDocument/prepareRename", at(URI, 13, 6))
        .await;
    assert_eq!(
        prepared,
        json!({ "range": range(13, 5, 13, 11), "placeholder": "state2" })
    );
    let edit = client
        .request("textDocument/rename", json!({ "textDocument": { "uri": URI }, "position": { "line": 13, "character": 6 }, "newName": "climbing" }))
        .await;
    let edits = edit["changes"][URI].as_array().expect("edits");
    assert_eq!(edits.len(), 3);
    assert!(edits.iter().all(|e| e["newText"] == "climbing"));
    // A refused name is an invalid-params error carrying the reason.
    let refused = client
        .request_raw("textDocument/rename", json!({ "textDocument": { "uri": URI }, "position": { "line": 13, "character": 6 }, "newName": "state1" }))
        .await;
    assert_eq!(refused["error"]["code"], -32602);
    assert_eq!(refused["error"]["message"], "`state1` is already declared");
    // Sensors are not renamable; variables are.
    assert_eq!(
        client
            .request("textDocument/prepareRename", at(URI, 1, 5))
            .await,
        Value::Null
    );
}

#[tokio::test]
async fn symbols_folding_tokens_hints_formatting_and_signatures() {
    let mut client = fig3().await;
    let document = json!({ "textDocument": { "uri": URI } });
    let symbols = client
        .request("textDocument/documentSymbol", document.clone())
        .await;
    let names: Vec<(&str, u64)> = symbols
        .as_array()
        .expect("s")
        .iter()
        .map(|s| {
            (
                s["name"].as_str().expect("n"),
                s["kind"].as_u64().expect("k"),
            )
        })
        .collect();
    assert_eq!(names, [("state1", 12), ("state2", 12), ("state3", 12)]);
    assert_eq!(
        symbols[0]["range"],
        range(0, 0, 6, 11),
        "label state1's section"
    );

    let folds = client
        .request("textDocument/foldingRange", document.clone())
        .await;
    let mut spans: Vec<(u64, u64)> = folds
        .as_array()
        .expect("f")
        .iter()
        .map(|f| {
            (
                f["startLine"].as_u64().expect("s"),
                f["endLine"].as_u64().expect("e"),
            )
        })
        .collect();
    spans.sort();
    assert_eq!(spans, [(0, 6), (1, 4), (7, 13), (8, 11), (14, 16)]);

    let tokens = client
        .request("textDocument/semanticTokens/full", document.clone())
        .await;
    let data: Vec<u64> = tokens["data"]
        .as_array()
        .expect("d")
        .iter()
        .map(|v| v.as_u64().expect("n"))
        .collect();
    let decoded = decode(&data);
    // `if m_depth > 15.0 then`: keyword, sensor read (readonly), operator, number, keyword.
    let line1: Vec<_> = decoded
        .iter()
        .filter(|t| t.0 == 1)
        .map(|t| (t.1, t.2, t.3, t.4))
        .collect();
    assert_eq!(
        line1,
        [
            (0, 2, 0, 0),
            (3, 7, 8, 1 | 4),
            (11, 1, 7, 0),
            (13, 4, 4, 0),
            (18, 4, 0, 0)
        ]
    );
    // `  SCI_RUHP_BEHS = 128`: a sensor written.
    assert_eq!(
        decoded
            .iter()
            .find(|t| t.0 == 2)
            .map(|t| (t.1, t.2, t.3, t.4)),
        Some((2, 13, 8, 2 | 4))
    );
    // `goto state2`: keyword, label.
    let line3: Vec<_> = decoded.iter().filter(|t| t.0 == 3).map(|t| t.3).collect();
    assert_eq!(line3, [0, 9]);

    let hints = client
        .request(
            "textDocument/inlayHint",
            json!({ "textDocument": { "uri": URI }, "range": range(0, 0, 17, 0) }),
        )
        .await;
    let hints: Vec<(u64, String)> = hints
        .as_array()
        .expect("h")
        .iter()
        .map(|h| {
            (
                h["position"]["line"].as_u64().expect("l"),
                h["label"].as_str().expect("l").to_string(),
            )
        })
        .collect();
    // Same figures as Fig. 2 (first cycle 15, worst 16), shown on GBASIC lines.
    // The first cycle starts at the first statement that runs: the `if` on line 1.
    assert!(
        hints.contains(&(1, "first cycle ≤ 15 instr".to_string())),
        "{hints:?}"
    );
    assert!(
        hints.contains(&(5, "next cycle ≤ 16 instr".to_string())),
        "{hints:?}"
    );
    assert_eq!(
        hints
            .iter()
            .filter(|h| h.1.starts_with("next cycle"))
            .count(),
        3,
        "{hints:?}"
    );

    change(
        &mut client,
        URI,
        2,
        "while 1\nif m_depth > 1.0 then\nyield\nelse\n      yield\nendif\nwend\n",
    )
    .await;
    let edits = client
        .request("textDocument/formatting", json!({ "textDocument": { "uri": URI }, "options": { "tabSize": 2, "insertSpaces": true } }))
        .await;
    assert_eq!(
        edits,
        json!([{ "range": range(1, 0, 6, 0), "newText": "  if m_depth > 1.0 then\n    yield\n  else\n    yield\n  endif\n" }])
    );

    change(
        &mut client,
        URI,
        3,
        "dim a as float\na = max(1.0, sqrt(2.0), \n",
    )
    .await;
    let help = client
        .request("textDocument/signatureHelp", at(URI, 1, 23))
        .await;
    assert_eq!(help["signatures"][0]["label"], "max(a, b)");
    assert_eq!(help["activeParameter"], 1);
    assert_eq!(
        help["signatures"][0]["documentation"]["value"],
        "the larger; float if either is"
    );
}

fn decode(data: &[u64]) -> Vec<(u64, u64, u64, u64, u64)> {
    let mut line = 0;
    let mut start = 0;
    data.chunks(5)
        .map(|chunk| {
            if chunk[0] > 0 {
                line += chunk[0];
                start = chunk[1];
            } else {
                start += chunk[1];
            }
            (line, start, chunk[2], chunk[3], chunk[4])
        })
        .collect()
}

/// Constants, variables, an array, two labels and one block of each kind, with a `yield`
/// in every loop that needs one, so the program is clean.
const BLOCKS: &str = "const LIMIT = 3\nconst G = -9.81\ndim count as integer\ndim i as integer\ndim depths(4) as float\nlabel: top\nif count < LIMIT then\n  count = count + 1\nendif\nwhile count > 0\n  count = count - 1\n  yield\nwend\nfor i = 0 to 3\n  depths(i) = m_depth * G\nnext i\ndo\n  count = count + 1\n  yield\nloop until count >= LIMIT\nif count = LIMIT then goto done\nyield\ngoto top\nlabel: done\nyield\ngoto done\n";

#[tokio::test]
async fn symbol_kinds_of_variables_constants_arrays_and_labels() {
    let uri = "file:///project/blocks.gbas";
    let mut client = TestClient::initialized().await;
    let published = client.open(uri, "gbasic", BLOCKS).await;
    assert_eq!(published["diagnostics"], json!([]), "the program is clean");
    let document = json!({ "textDocument": { "uri": uri } });
    let symbols = client
        .request("textDocument/documentSymbol", document.clone())
        .await;
    let mut names: Vec<(&str, u64)> = symbols
        .as_array()
        .expect("symbols")
        .iter()
        .map(|s| {
            (
                s["name"].as_str().expect("n"),
                s["kind"].as_u64().expect("k"),
            )
        })
        .collect();
    names.sort();
    // LSP SymbolKind: Function 12 (labels, as for Fig. 3), Variable 13, Constant 14,
    // Array 18.
    assert_eq!(
        names,
        [
            ("G", 14),
            ("LIMIT", 14),
            ("count", 13),
            ("depths", 18),
            ("done", 12),
            ("i", 13),
            ("top", 12)
        ]
    );
}

#[tokio::test]
async fn a_broken_gloc_toml_that_is_not_open_is_a_diagnostic() {
    let root = gloc_testsupport::scratch_dir("lsp-closed-config");
    let scripts = root.join("scripts");
    std::fs::create_dir_all(&scripts).expect("dirs");
    // An unknown key (a typo of cycle_budget): E0901 at the key, characters 0 to 12.
    std::fs::write(root.join("gloc.toml"), "cycle_budgte = 10\n").expect("write");
    let script_uri = format!("file://{}/fig3.gbas", scripts.display());
    let config_uri = format!("file://{}/gloc.toml", root.display());
    let mut client = TestClient::initialized().await;
    client.open(&script_uri, "gbasic", FIG3).await;
    let config = client.diagnostics(&config_uri).await;
    std::fs::remove_dir_all(&root).expect("cleanup");
    assert_eq!(config["diagnostics"][0]["code"], "E0901", "{config}");
    assert_eq!(config["diagnostics"][0]["range"], range(0, 0, 0, 12));
    assert!(config.get("version").is_none_or(Value::is_null), "{config}");
}
