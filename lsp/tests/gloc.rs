//! Protocol tests on GLOC documents, driven through framed JSON-RPC like a real
//! client: each LSP method for what the conversion decides (UTF-16 ranges, LSP
//! kinds, the relative encoding of semantic tokens, edits, refusals as errors)
//! and the settings a document is analysed with. What each feature answers is
//! tested on fixtures in gloc-ide (ide/tests/features). Expected values are
//! worked out by hand from the paper's Fig. 2 (m_depth is sensor 444,
//! sci_ruhp_behs 1387 in the embedded 2008 list).

mod support;

use serde_json::{json, Value};
use support::{at, TestClient};

const FIG2: &str = "nregs 8\nnblbs 7\nninstr 27\nlabel 0\nloads 444,r0\nloadd 15.0,r1\ncmpgt r0,r1,r2\ncbr r2,3,4\nlabel 3\nloadi 128,r3\nstores r3,1387\njumpi 1\nlabel 4\nyield\njumpi 0\nlabel 1\nloads 444,r4\nloadd 5.0,r5\ncmplt r4,r5,r6\ncbr r6,5,6\nlabel 5\nloadi 0,r7\nstores r7,1387\njumpi 2\nlabel 6\nyield\njumpi 1\nlabel 2\nyield\njumpi 2\n";

const URI: &str = "file:///project/fig2.gloc";

async fn fig2() -> TestClient {
    let mut client = TestClient::initialized().await;
    let diagnostics = client.open(URI, "gloc", FIG2).await;
    assert_eq!(diagnostics["diagnostics"], json!([]), "Fig. 2 is clean");
    assert_eq!(diagnostics["version"], 1);
    client
}

fn labels(items: &Value) -> Vec<String> {
    items
        .as_array()
        .expect("array")
        .iter()
        .map(|item| item["label"].as_str().expect("label").to_string())
        .collect()
}

fn range(l1: u32, c1: u32, l2: u32, c2: u32) -> Value {
    json!({ "start": { "line": l1, "character": c1 }, "end": { "line": l2, "character": c2 } })
}

#[tokio::test]
async fn diagnostics_have_codes_and_related_information() {
    let mut client = TestClient::initialized().await;
    let text = "nregs 1\nnblbs 1\nninstr 4\nlabel 0\nlods 444,r0\nlabel 0\nyield\n";
    let published = client.open("file:///p/dup.gloc", "gloc", text).await;
    let diagnostics = published["diagnostics"].as_array().expect("array").clone();
    let unknown = diagnostics
        .iter()
        .find(|d| d["code"] == "E0001")
        .expect("unknown instruction");
    assert_eq!(unknown["range"], range(4, 0, 4, 4));
    assert!(unknown["message"]
        .as_str()
        .expect("message")
        .contains("did you mean `loads`?"));
    let duplicate = diagnostics
        .iter()
        .find(|d| d["code"] == "E0103")
        .expect("duplicate label");
    assert_eq!(duplicate["range"]["start"]["line"], 5);
    let related = &duplicate["relatedInformation"][0];
    assert_eq!(related["location"]["uri"], "file:///p/dup.gloc");
    assert_eq!(
        related["location"]["range"]["start"]["line"], 3,
        "points at the first `label 0`"
    );
    assert_eq!(duplicate["severity"], 1);
    assert_eq!(duplicate["source"], "gloc");
}

#[tokio::test]
async fn completion_after_incremental_edits_snippets_and_sensor_indices() {
    let mut client = fig2().await;
    // Start of a new line: mnemonics with operand shapes, `label`, directives.
    let result = client
        .request("textDocument/completion", at(URI, 30, 0))
        .await;
    assert!(labels(&result["items"]).contains(&"label".to_string()));
    assert!(labels(&result["items"]).contains(&"nregs".to_string()));
    assert_eq!(result["isIncomplete"], false);
    // `st|`: what starts with it.
    client
        .notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": URI, "version": 2 },
            "contentChanges": [{ "range": range(30, 0, 30, 0), "text": "st" }] }),
        )
        .await;
    let result = client
        .request("textDocument/completion", at(URI, 30, 2))
        .await;
    let items = &result["items"];
    let stores = items
        .as_array()
        .expect("items")
        .iter()
        .find(|i| i["label"] == "stores")
        .expect("stores");
    assert_eq!(stores["detail"], "stores r,SENSOR");
    // The typed `st` is replaced through an edit; no `insertText`.
    assert_eq!(stores["textEdit"]["newText"], "stores ${1:r0},${2:0}");
    assert_eq!(stores["textEdit"]["range"], range(30, 0, 30, 2));
    assert!(stores.get("insertText").is_none());
    assert!(!labels(items).contains(&"label".to_string()));

    // Where a store expects a sensor: writable ones first (the first 100 of
    // them, nothing typed), inserting the index.
    client
        .notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": URI, "version": 3 },
            "contentChanges": [{ "range": range(30, 0, 30, 2), "text": "stores r3," }] }),
        )
        .await;
    let result = client
        .request("textDocument/completion", at(URI, 30, 10))
        .await;
    assert_eq!(result["isIncomplete"], true);
    let items = result["items"].as_array().expect("items");
    assert!(items
        .iter()
        .all(|i| !i["filterText"].as_str().unwrap_or("").starts_with("m_")));
    client
        .notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": URI, "version": 4 },
            "contentChanges": [{ "range": range(30, 10, 30, 10), "text": "sci_ru" }] }),
        )
        .await;
    let result = client
        .request("textDocument/completion", at(URI, 30, 16))
        .await;
    let items = result["items"].as_array().expect("items");
    let behs = items
        .iter()
        .find(|i| i["label"] == "sci_ruhp_behs")
        .expect("hook sensor");
    // The label is the name the user types; the edit puts the name over `sci_ru`.
    assert_eq!(behs["textEdit"]["newText"], "sci_ruhp_behs");
    assert_eq!(behs["textEdit"]["range"], range(30, 10, 30, 16));
    assert!(behs["detail"]
        .as_str()
        .expect("detail")
        .contains("writable"));

    // A load may read any sensor.
    let result = client
        .request("textDocument/completion", at(URI, 4, 9))
        .await;
    let depth = result["items"]
        .as_array()
        .expect("items")
        .iter()
        .find(|i| i["label"] == "m_depth")
        .cloned()
        .expect("m_depth");
    assert_eq!(depth["detail"], "sensor 444 (m), read-only");
    assert!(depth["documentation"]["value"]
        .as_str()
        .expect("docs")
        .contains("Measured depth"));

    // Labels after jumpi / cbr; registers where a register goes.
    let result = client
        .request("textDocument/completion", at(URI, 11, 6))
        .await;
    assert_eq!(
        labels(&result["items"]),
        ["0", "1", "2", "3", "4", "5", "6"]
    );
    let result = client
        .request("textDocument/completion", at(URI, 7, 7))
        .await;
    assert_eq!(
        labels(&result["items"]).len(),
        7,
        "cbr's true target is a label"
    );
    let result = client
        .request("textDocument/completion", at(URI, 6, 6))
        .await;
    assert_eq!(
        labels(&result["items"]),
        ["r0", "r1", "r2", "r3", "r4", "r5", "r6", "r7"]
    );
}

#[tokio::test]
async fn hover_range_is_the_sensor_index() {
    let mut client = fig2().await;
    let hover = client.request("textDocument/hover", at(URI, 4, 7)).await;
    let text = hover["contents"]["value"].as_str().expect("markdown");
    assert!(
        text.starts_with("**m_depth** (m)\n\nsensor 444 · read-only"),
        "{text}"
    );
    assert_eq!(hover["range"], range(4, 6, 4, 9));
    assert_eq!(hover["contents"]["kind"], "markdown");
}

#[tokio::test]
async fn label_navigation_definition_references_highlight_and_rename() {
    let mut client = fig2().await;
    // `cbr r2,3,4`: the 3 at column 7 → `label 3` on line 8.
    let definition = client
        .request("textDocument/definition", at(URI, 7, 7))
        .await;
    assert_eq!(
        definition,
        json!({ "uri": URI, "range": range(8, 6, 8, 7) })
    );
    // `jumpi 1` (line 11) and `jumpi 1` (line 26) jump to label 1 (line 15).
    let references = client
        .request("textDocument/references", json!({ "textDocument": { "uri": URI }, "position": { "line": 15, "character": 6 }, "context": { "includeDeclaration": true } }))
        .await;
    let lines: Vec<u64> = references
        .as_array()
        .expect("locations")
        .iter()
        .map(|l| l["range"]["start"]["line"].as_u64().expect("line"))
        .collect();
    assert_eq!(lines, [15, 11, 26]);
    let highlights = client
        .request("textDocument/documentHighlight", at(URI, 11, 6))
        .await;
    assert_eq!(highlights.as_array().expect("highlights").len(), 3);
    assert_eq!(highlights[0]["kind"], 3, "the definition is the write");

    let prepared = client
        .request("textDocument/prepareRename", at(URI, 11, 6))
        .await;
    assert_eq!(
        prepared,
        json!({ "range": range(11, 6, 11, 7), "placeholder": "1" })
    );
    let taken = client
        .request_raw("textDocument/rename", json!({ "textDocument": { "uri": URI }, "position": { "line": 11, "character": 6 }, "newName": "5" }))
        .await;
    assert!(taken["error"]["message"]
        .as_str()
        .expect("message")
        .contains("label 5 already exists"));
    let not_a_number = client
        .request_raw("textDocument/rename", json!({ "textDocument": { "uri": URI }, "position": { "line": 11, "character": 6 }, "newName": "top" }))
        .await;
    assert_eq!(not_a_number["error"]["code"], -32602);
}

#[tokio::test]
async fn symbols_folding_semantic_tokens_and_inlay_hints() {
    let mut client = fig2().await;
    let document = json!({ "textDocument": { "uri": URI } });
    let symbols = client
        .request("textDocument/documentSymbol", document.clone())
        .await;
    let names: Vec<&str> = symbols
        .as_array()
        .expect("symbols")
        .iter()
        .map(|s| s["name"].as_str().expect("name"))
        .collect();
    assert_eq!(names, ["0", "1", "2", "3", "4", "5", "6"]);
    // label 0 (line 3) runs to `cbr r2,3,4` (line 7).
    let label0 = &symbols[0];
    assert_eq!(label0["range"], range(3, 0, 7, 10));
    assert_eq!(label0["selectionRange"], range(3, 6, 3, 7));

    let folds = client
        .request("textDocument/foldingRange", document.clone())
        .await;
    let spans: Vec<(u64, u64)> = folds
        .as_array()
        .expect("folds")
        .iter()
        .map(|f| {
            (
                f["startLine"].as_u64().expect("s"),
                f["endLine"].as_u64().expect("e"),
            )
        })
        .collect();
    assert_eq!(
        spans,
        [
            (3, 7),
            (8, 11),
            (12, 14),
            (15, 19),
            (20, 23),
            (24, 26),
            (27, 29)
        ]
    );

    let tokens = client
        .request("textDocument/semanticTokens/full", document.clone())
        .await;
    let data: Vec<u64> = tokens["data"]
        .as_array()
        .expect("data")
        .iter()
        .map(|v| v.as_u64().expect("n"))
        .collect();
    let decoded = decode(&data);
    // `loads 444,r0` on line 4: keyword, sensor read (property, readonly+defaultLibrary), register.
    let line4: Vec<_> = decoded.iter().filter(|t| t.0 == 4).collect();
    assert_eq!(
        line4,
        [&(4, 0, 5, 0, 0), &(4, 6, 3, 8, 1 | 4), &(4, 10, 2, 3, 8)]
    );
    // `stores r3,1387` on line 10: the sensor is written (modification).
    let line10: Vec<_> = decoded.iter().filter(|t| t.0 == 10).collect();
    assert_eq!(line10[2], &(10, 10, 4, 8, 2 | 4));
    // `nregs 8`: a directive (macro) and a number.
    assert_eq!(decoded[0], (0, 0, 5, 1, 0));
    assert_eq!(decoded[1], (0, 6, 1, 4, 0));
    // `cbr r2,3,4`: the targets are labels.
    let line7: Vec<_> = decoded.iter().filter(|t| t.0 == 7).map(|t| t.3).collect();
    assert_eq!(line7, [0, 3, 9, 9]);

    let hints = client
        .request(
            "textDocument/inlayHint",
            json!({ "textDocument": { "uri": URI }, "range": range(0, 0, 30, 0) }),
        )
        .await;
    let hints: Vec<(u64, u64, String)> = hints
        .as_array()
        .expect("hints")
        .iter()
        .map(|h| {
            (
                h["position"]["line"].as_u64().expect("l"),
                h["position"]["character"].as_u64().expect("c"),
                h["label"].as_str().expect("label").to_string(),
            )
        })
        .collect();
    assert!(hints.contains(&(4, 9, ":m_depth".to_string())), "{hints:?}");
    assert!(
        hints.contains(&(10, 14, ":sci_ruhp_behs".to_string())),
        "{hints:?}"
    );
    // Fig. 2's longest first cycle, counted by hand: label 0's block (4) → label 3's (3) →
    // label 1's (4) → label 5's (3) → label 2's `yield` (1) = 15.
    assert!(
        hints.contains(&(4, 12, "first cycle ≤ 15 instr".to_string())),
        "{hints:?}"
    );
    assert!(
        hints
            .iter()
            .any(|h| h.0 == 13 && h.2.starts_with("next cycle ≤ ")),
        "{hints:?}"
    );
}

/// (line, start, length, type, modifiers) from the relative encoding.
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

#[tokio::test]
async fn code_actions_are_quick_fixes_with_workspace_edits() {
    let mut client = TestClient::initialized().await;
    let uri = "file:///p/spin.gloc";
    let text = "nregs 1\nnblbs 1\nninstr 3\nlabel 0\nloadi 1,r0\njumpi 0\n";
    let published = client.open(uri, "gloc", text).await;
    let diagnostic = published["diagnostics"]
        .as_array()
        .expect("d")
        .iter()
        .find(|d| d["code"] == "E0111")
        .cloned()
        .expect("loop without yield");
    let actions = client
        .request("textDocument/codeAction", json!({ "textDocument": { "uri": uri }, "range": diagnostic["range"], "context": { "diagnostics": [diagnostic] } }))
        .await;
    let titles: Vec<&str> = actions
        .as_array()
        .expect("actions")
        .iter()
        .map(|a| a["title"].as_str().expect("t"))
        .collect();
    assert_eq!(titles, ["insert `yield` in this loop", "update `ninstr`"]);
    let insert = &actions[0]["edit"]["changes"][uri][0];
    assert_eq!(
        insert,
        &json!({ "range": range(5, 0, 5, 0), "newText": "yield\n" })
    );
    let ninstr = &actions[1]["edit"]["changes"][uri][0];
    assert_eq!(
        ninstr,
        &json!({ "range": range(2, 7, 2, 8), "newText": "4" })
    );
    assert_eq!(actions[0]["kind"], "quickfix");
    assert_eq!(actions[0]["diagnostics"][0]["code"], "E0111");
}

#[tokio::test]
async fn formatting_and_signature_help() {
    let mut client = TestClient::initialized().await;
    let uri = "file:///p/messy.gloc";
    client
        .open(
            uri,
            "gloc",
            "nregs 1\nnblbs 0\nninstr 2\nLOADS  444 , r0   # depth\nyield\n",
        )
        .await;
    let edits = client
        .request("textDocument/formatting", json!({ "textDocument": { "uri": uri }, "options": { "tabSize": 4, "insertSpaces": true } }))
        .await;
    assert_eq!(
        edits,
        json!([{ "range": range(3, 0, 4, 0), "newText": "loads 444,r0 # depth\n" }])
    );

    let help = client
        .request("textDocument/signatureHelp", at(uri, 3, 12))
        .await;
    assert_eq!(help["signatures"][0]["label"], "loads SENSOR,r");
    assert_eq!(help["activeParameter"], 1);
    assert_eq!(
        help["signatures"][0]["parameters"][1]["label"],
        json!([13, 14])
    );
}

#[tokio::test]
async fn gloc_toml_sets_the_cycle_budget_and_bad_files_are_diagnostics() {
    let root = gloc_testsupport::scratch_dir("lsp-config");
    let scripts = root.join("scripts");
    std::fs::create_dir_all(&scripts).expect("dirs");
    std::fs::write(root.join("gloc.toml"), "cycle_budget = 10\n").expect("write");
    let script_uri = format!("file://{}/fig2.gloc", scripts.display());
    let config_uri = format!("file://{}/gloc.toml", root.display());

    let mut client = TestClient::initialized().await;
    let published = client.open(&script_uri, "gloc", FIG2).await;
    let warning = &published["diagnostics"][0];
    assert_eq!(warning["code"], "W2302");
    assert!(
        warning["message"]
            .as_str()
            .expect("m")
            .contains("16 instructions, more than the budget of 10"),
        "{warning}"
    );

    // Open the config in the editor and break it: a diagnostic on gloc.toml, defaults for the script.
    client
        .notify("textDocument/didOpen", json!({ "textDocument": { "uri": config_uri, "languageId": "toml", "version": 1, "text": "cycle_budget = 10\n" } }))
        .await;
    client
        .notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": config_uri, "version": 2 },
            "contentChanges": [{ "range": range(0, 0, 0, 12), "text": "cycle_budgte" }] }),
        )
        .await;
    let script = client.latest_diagnostics(&script_uri).await;
    assert_eq!(
        script["diagnostics"],
        json!([]),
        "defaults while the file is broken"
    );
    let config = client.latest_diagnostics(&config_uri).await;
    assert_eq!(config["diagnostics"][0]["code"], "E0901");
    assert_eq!(config["diagnostics"][0]["range"], range(0, 0, 0, 12));
    // Fixing it clears the file's diagnostics and brings the budget back.
    client
        .notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": config_uri, "version": 3 },
            "contentChanges": [{ "range": range(0, 0, 0, 12), "text": "cycle_budget" }] }),
        )
        .await;
    assert_eq!(
        client.latest_diagnostics(&config_uri).await["diagnostics"],
        json!([])
    );
    assert_eq!(
        client.latest_diagnostics(&script_uri).await["diagnostics"][0]["code"],
        "W2302"
    );
    std::fs::remove_dir_all(&root).expect("cleanup");
}

#[tokio::test]
async fn client_settings_override_gloc_toml() {
    let mut client =
        TestClient::initialized_with(json!({}), json!({ "gloc": { "cycleBudget": 12 } })).await;
    let published = client.open("file:///nowhere/fig2.gloc", "gloc", FIG2).await;
    assert!(published["diagnostics"][0]["message"]
        .as_str()
        .expect("m")
        .contains("budget of 12"));
    client
        .notify(
            "workspace/didChangeConfiguration",
            json!({ "settings": { "gloc": { "cycleBudget": 100 } } }),
        )
        .await;
    assert_eq!(
        client.latest_diagnostics("file:///nowhere/fig2.gloc").await["diagnostics"],
        json!([])
    );

    // workspace/configuration is asked when the client supports it.
    let mut client = TestClient::start();
    client.configuration = json!({ "cycleBudget": 11 });
    client
        .request("initialize", json!({ "processId": null, "capabilities": { "workspace": { "configuration": true } } }))
        .await;
    client.notify("initialized", json!({})).await;
    client.open("file:///nowhere/fig2.gloc", "gloc", FIG2).await;
    let mut message = String::new();
    for _ in 0..50 {
        let latest = client.latest_diagnostics("file:///nowhere/fig2.gloc").await;
        message = latest["diagnostics"][0]["message"]
            .as_str()
            .unwrap_or("")
            .to_string();
        if message.contains("budget of 11") {
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(20)).await;
    }
    assert!(message.contains("budget of 11"), "{message}");
}

#[tokio::test]
async fn masterdata_from_gloc_toml_changes_sensor_indices_and_bad_files_are_reported() {
    let root = gloc_testsupport::scratch_dir("lsp-masterdata");
    std::fs::create_dir_all(&root).expect("dir");
    std::fs::write(
        root.join("masterdata.mi"),
        "sensor: m_depth(m) 0   # out, depth\nsensor: c_target(m) 5.0  # in\n",
    )
    .expect("write");
    std::fs::write(root.join("gloc.toml"), "masterdata = \"masterdata.mi\"\n").expect("write");
    let uri = format!("file://{}/a.gloc", root.display());
    let mut client = TestClient::initialized().await;
    let text = "nregs 1\nnblbs 0\nninstr 3\nloads 0,r0\nstores r0,1\nyield\n";
    let published = client.open(&uri, "gloc", text).await;
    // Against a list other than the embedded one, a file without `# sensors:` gets
    // one warning at its first sensor index (issue 14), and nothing else.
    let diagnostics = published["diagnostics"].as_array().expect("diagnostics");
    assert_eq!(diagnostics.len(), 1, "{published}");
    assert_eq!(diagnostics[0]["code"], "W0114");
    assert_eq!(
        diagnostics[0]["range"]["start"],
        json!({ "line": 3, "character": 6 })
    );
    let hover = client.request("textDocument/hover", at(&uri, 3, 6)).await;
    assert!(
        hover["contents"]["value"]
            .as_str()
            .expect("md")
            .starts_with("**m_depth** (m)\n\nsensor 0 · read-only"),
        "{hover}"
    );
    let hover = client.request("textDocument/hover", at(&uri, 4, 10)).await;
    assert!(
        hover["contents"]["value"]
            .as_str()
            .expect("md")
            .contains("default 5.0"),
        "{hover}"
    );
    client
        .notify(
            "textDocument/didClose",
            json!({ "textDocument": { "uri": uri } }),
        )
        .await;

    // A masterdata path that does not exist: the script says so and uses the embedded list.
    std::fs::write(root.join("gloc.toml"), "masterdata = \"missing.mi\"\n").expect("write");
    client
        .notify("workspace/didChangeWatchedFiles", json!({ "changes": [] }))
        .await;
    let published = client
        .open(&format!("file://{}/b.gloc", root.display()), "gloc", text)
        .await;
    let problem = published["diagnostics"]
        .as_array()
        .expect("d")
        .iter()
        .find(|d| d["code"] == "E0903")
        .cloned()
        .expect("E0903");
    assert!(
        problem["message"]
            .as_str()
            .expect("m")
            .contains("missing.mi"),
        "{problem}"
    );
    std::fs::remove_dir_all(&root).expect("cleanup");
}

#[tokio::test]
async fn settings_files_on_disk_are_watched_when_the_client_allows_it() {
    let mut client = TestClient::initialized_with(
        json!({ "workspace": { "didChangeWatchedFiles": { "dynamicRegistration": true } } }),
        Value::Null,
    )
    .await;
    let mut registration = None;
    for _ in 0..100 {
        client.latest_diagnostics("file:///none.gloc").await;
        registration = client
            .notifications
            .iter()
            .find(|message| message["method"] == "client/registerCapability")
            .cloned();
        if registration.is_some() {
            break;
        }
    }
    let registration = registration.expect("the server registered file watchers");
    let registered = &registration["params"]["registrations"][0];
    assert_eq!(registered["method"], "workspace/didChangeWatchedFiles");
    let patterns: Vec<&str> = registered["registerOptions"]["watchers"]
        .as_array()
        .expect("watchers")
        .iter()
        .map(|watcher| watcher["globPattern"].as_str().expect("pattern"))
        .collect();
    assert_eq!(patterns, ["**/gloc.toml", "**/*.cac", "**/masterdata*"]);

    // Without the capability, nothing is registered.
    let mut client = TestClient::initialized().await;
    client.latest_diagnostics("file:///none.gloc").await;
    assert!(!client
        .notifications
        .iter()
        .any(|message| message["method"] == "client/registerCapability"));
}

/// Emacs with eglot 1.9: one language id (`gbasic`) for every file of the
/// server, completion matched against the label (no filter on `insertText`), no
/// snippets, no related information, plain-text hover.
#[tokio::test]
async fn an_eglot_client_gets_what_it_declared_and_the_language_of_the_extension() {
    let mut client = TestClient::initialized_with(support::eglot_capabilities(), Value::Null).await;
    // Fig. 2 sent as `gbasic` is still GLOC (its extension): clean.
    let published = client.open(URI, "gbasic", FIG2).await;
    assert_eq!(published["diagnostics"], json!([]), "{published}");

    // `loads m_dep`: the label is the name typed; the index goes in through an
    // edit over `m_dep` (line 4 is `loads 444,r0`; make it `loads m_dep`).
    client
        .notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": URI, "version": 2 },
            "contentChanges": [{ "range": range(4, 6, 4, 12), "text": "m_dep" }] }),
        )
        .await;
    let result = client
        .request("textDocument/completion", at(URI, 4, 11))
        .await;
    let depth = result["items"]
        .as_array()
        .expect("items")
        .iter()
        .find(|i| i["label"] == "m_depth")
        .cloned()
        .expect("m_depth offered under its name");
    assert_eq!(depth["textEdit"]["newText"], "m_depth");
    assert_eq!(depth["textEdit"]["range"], range(4, 6, 4, 11));
    assert!(depth.get("insertText").is_none(), "{depth}");
    // Eglot 1.9 lists no documentation format: plain text, without code marks.
    assert_eq!(depth["documentation"]["kind"], "plaintext", "{depth}");
    let documentation = depth["documentation"]["value"].as_str().expect("docs");
    assert!(!documentation.contains('`'), "{documentation}");
    // A mnemonic is plain text without snippet support: no tab stops, no format.
    let result = client
        .request("textDocument/completion", at(URI, 30, 0))
        .await;
    let stores = result["items"]
        .as_array()
        .expect("items")
        .iter()
        .find(|i| i["label"] == "stores")
        .cloned()
        .expect("stores");
    assert_eq!(stores["textEdit"]["newText"], "stores r0,0");
    assert!(stores.get("insertTextFormat").is_none(), "{stores}");

    // Hover on `loadd` (line 5) in plain text: no markdown marks.
    let hover = client.request("textDocument/hover", at(URI, 5, 1)).await;
    assert_eq!(hover["contents"]["kind"], "plaintext");
    let value = hover["contents"]["value"].as_str().expect("hover text");
    assert!(value.contains("from the paper"), "{value}");
    assert!(!value.contains('*') && !value.contains('`'), "{value}");

    // A duplicate label: the first one's place is in the message, not in
    // `relatedInformation`, which the client did not declare.
    let text = "nregs 1\nnblbs 1\nninstr 3\nlabel 0\nlabel 0\nyield\n";
    let published = client.open("file:///p/dup.gloc", "gbasic", text).await;
    let duplicate = published["diagnostics"]
        .as_array()
        .expect("array")
        .iter()
        .find(|d| d["code"] == "E0103")
        .cloned()
        .expect("duplicate label");
    assert!(duplicate.get("relatedInformation").is_none(), "{duplicate}");
    assert!(
        duplicate["message"]
            .as_str()
            .expect("message")
            .contains("\n4:7: first defined here"),
        "{duplicate}"
    );
}
