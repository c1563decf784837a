//! One truth behind every surface: a corpus of scripts × project settings goes through
//! `gloc check`, `gloc run`, the language server (`gloc lsp` over stdio, as an editor
//! drives it) and a debugger launch (`gloc dap` over stdio), and every surface reports
//! the same codes on the same lines, or refuses in the same words.
//!
//! The expected codes are worked out by hand from the rules, not taken from output:
//!
//! - `fig2.gloc` (the paper's Fig. 2) runs at most 16 instructions in one control cycle:
//!   after the `yield` of label 4, `jumpi 0` (1), label 0's four (loads, loadd, cmpgt,
//!   cbr), label 3's three (loadi, stores, jumpi), label 1's four, label 5's three, and
//!   the `yield` of label 2 (1): 1 + 4 + 3 + 4 + 3 + 1 = 16 (from the start, 15). So a
//!   budget of 5 or 10 gives W2302, which a GLOC file gets on line 1 (the whole file);
//!   10,000 (the default) and 1,000,000,000 give nothing.
//! - `sum.gbas` adds 1 to 100 in a `for` loop (bounded, constant limits) without a
//!   `yield`: at least two instructions per turn, so more than 200 and far fewer than
//!   10,000 in its one cycle; W2302 for 5 and 10, reported on GBASIC at the end of the
//!   text, line 8 of a 7-line file.
//! - `yeild.gbas` has `yeild` alone on line 3: not a statement, so E2001 (expected `=`)
//!   there, on every surface, whatever the budget.
//! - `store0.gloc` stores to sensor 0 on line 6. With tests/fixtures/sensors/edge.masterdata
//!   in file order sensor 0 is `m_present_time`, read-only: E0108 on line 6; sorted by
//!   name it is `c_pitch`, writable. Either way the list is neither the embedded one nor
//!   stated in the file: W0114 on line 6.
//! - A refused setting is refused by every surface in the same words: a budget of 0
//!   (in gloc.toml, or given as a flag, an editor setting or a launch attribute), a
//!   masterdata file that does not exist, a gloc.toml that is not valid.

mod support;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{json, Value};
use support::peer::{uri, Peer};

const GLOC: &str = env!("CARGO_BIN_EXE_gloc");

const SUM_GBAS: &str =
    "dim i as integer\ndim s as integer\nfor i = 1 to 100\n  s = s + i\nnext\nprint s\nyield\n";
const YEILD_GBAS: &str = "dim x as integer\nx = 1\nyeild\n";
const STORE0_GLOC: &str =
    "nregs 1\nnblbs 1\nninstr 5\nlabel 0\nloadi 1,r0\nstores r0,0\nyield\njumpi 0\n";

/// What every surface must report.
#[derive(Clone, Debug)]
enum Expect {
    /// These (code, line) pairs, errors and warnings, on the script.
    Codes(&'static [(&'static str, u32)]),
    /// A refusal containing these words (and, per surface, the origin named).
    Refused(String),
}

/// Where the override of a case is given, on every surface alike.
#[derive(Clone, Copy, Debug)]
enum Override {
    None,
    /// A cycle budget given as `--cycle-budget`, `gloc.cycleBudget`, `cycleBudget`.
    Budget(u64),
}

struct Case {
    name: &'static str,
    script: &'static str,
    text: &'static str,
    /// The gloc.toml beside the script, if any (`{repo}` is the repository).
    toml: Option<String>,
    overriding: Override,
    expect: Expect,
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

const BUDGET_WORDS: &str = "the cycle budget must be 1 to 1000000000 instructions per cycle, not 0";

fn corpus() -> Vec<Case> {
    let fig2: &'static str = Box::leak(
        std::fs::read_to_string(repo().join("examples/fig2.gloc"))
            .expect("examples/fig2.gloc")
            .into_boxed_str(),
    );
    let mut cases = Vec::new();
    for (script, text, over_5_and_10) in [
        ("fig2.gloc", fig2, &[("W2302", 1u32)] as &[(&str, u32)]),
        ("sum.gbas", SUM_GBAS, &[("W2302", 8)]),
        ("yeild.gbas", YEILD_GBAS, &[("E2001", 3)]),
    ] {
        let quiet: &'static [(&str, u32)] = if script == "yeild.gbas" {
            &[("E2001", 3)]
        } else {
            &[]
        };
        let budget = |budget: &str| Some(format!("cycle_budget = {budget}\n"));
        cases.extend([
            Case {
                name: "defaults",
                script,
                text,
                toml: None,
                overriding: Override::None,
                expect: Expect::Codes(quiet),
            },
            Case {
                name: "budget 5",
                script,
                text,
                toml: budget("5"),
                overriding: Override::None,
                expect: Expect::Codes(over_5_and_10),
            },
            Case {
                name: "budget 10",
                script,
                text,
                toml: budget("10"),
                overriding: Override::None,
                expect: Expect::Codes(over_5_and_10),
            },
            Case {
                name: "the largest budget",
                script,
                text,
                toml: budget("1000000000"),
                overriding: Override::None,
                expect: Expect::Codes(quiet),
            },
            Case {
                name: "budget 0 in gloc.toml",
                script,
                text,
                // `cycle_budget = ` is 15 characters: the value is at 1:16.
                toml: budget("0"),
                overriding: Override::None,
                expect: Expect::Refused(format!(
                    "gloc.toml:1:16: invalid gloc.toml `cycle_budget`: {BUDGET_WORDS}"
                )),
            },
            Case {
                name: "budget 0 given to the surface",
                script,
                text,
                toml: budget("10"),
                overriding: Override::Budget(0),
                expect: Expect::Refused(BUDGET_WORDS.to_string()),
            },
            Case {
                name: "a budget given to the surface wins over gloc.toml",
                script,
                text,
                toml: budget("1000000000"),
                overriding: Override::Budget(10),
                expect: Expect::Codes(over_5_and_10),
            },
            Case {
                name: "a masterdata file that does not exist",
                script,
                text,
                // `masterdata = ` is 13 characters: the value is at 1:14.
                toml: Some("masterdata = \"nosuch.mi\"\n".to_string()),
                overriding: Override::None,
                expect: Expect::Refused("gloc.toml:1:14: cannot read the sensor list `".into()),
            },
            Case {
                name: "a broken gloc.toml",
                script,
                text,
                toml: Some("cycle_budget = \"ten\"\n".to_string()),
                overriding: Override::None,
                expect: Expect::Refused("gloc.toml:1:16: invalid gloc.toml".into()),
            },
        ]);
    }
    for (order, expect) in [
        ("sorted", &[("W0114", 6u32)] as &[(&str, u32)]),
        ("file", &[("E0108", 6), ("W0114", 6)]),
    ] {
        cases.push(Case {
            name: if order == "sorted" {
                "sorted sensor order"
            } else {
                "file sensor order"
            },
            script: "store0.gloc",
            text: STORE0_GLOC,
            // gloc.toml names files inside its folder only (issue 28): `folder_for`
            // copies the list in.
            toml: Some(format!(
                "masterdata = \"edge.masterdata\"\nsensor_order = \"{order}\"\n"
            )),
            overriding: Override::None,
            expect: Expect::Codes(expect),
        });
    }
    cases
}

/// `path:LINE:COL: error[CODE]` / `warning[CODE]` headers about `script` in `text`.
fn codes_in(text: &str, script: &str) -> BTreeSet<(String, u32)> {
    let mut found = BTreeSet::new();
    for line in text.lines() {
        let Some(at) = line.find(script) else {
            continue;
        };
        let rest = &line[at + script.len()..];
        let mut parts = rest.splitn(4, ':');
        let (Some(""), Some(line_number), Some(_column), Some(tail)) =
            (parts.next(), parts.next(), parts.next(), parts.next())
        else {
            continue;
        };
        let Ok(line_number) = line_number.parse::<u32>() else {
            continue;
        };
        let tail = tail.trim_start();
        for severity in ["error[", "warning["] {
            if let Some(code) = tail.strip_prefix(severity) {
                if let Some(end) = code.find(']') {
                    found.insert((code[..end].to_string(), line_number));
                }
            }
        }
    }
    found
}

fn expected(codes: &[(&str, u32)]) -> BTreeSet<(String, u32)> {
    codes
        .iter()
        .map(|(code, line)| (code.to_string(), *line))
        .collect()
}

fn folder_for(case: &Case, index: usize) -> PathBuf {
    let folder =
        std::env::temp_dir().join(format!("gloc-consistency-{}-{index}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).expect("folder");
    std::fs::write(folder.join(case.script), case.text).expect("script");
    // gloc.toml may name only files inside its project (issue 28): the cases that use
    // the edge masterdata get a copy beside the script.
    std::fs::copy(
        repo().join("tests/fixtures/sensors/edge.masterdata"),
        folder.join("edge.masterdata"),
    )
    .expect("edge.masterdata");
    if let Some(toml) = &case.toml {
        std::fs::write(folder.join("gloc.toml"), toml).expect("gloc.toml");
    }
    std::fs::copy(
        repo().join("tests/fixtures/sensors/edge.masterdata"),
        folder.join("edge.masterdata"),
    )
    .expect("edge.masterdata");
    folder
}

// ------------------------------------------------------------------ the CLI

struct CliAnswer {
    code: Option<i32>,
    text: String,
}

fn cli(folder: &Path, arguments: &[String]) -> CliAnswer {
    let output = Command::new(GLOC)
        .args(arguments)
        .current_dir(folder)
        .output()
        .expect("gloc runs");
    CliAnswer {
        code: output.status.code(),
        text: format!(
            "{}{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        ),
    }
}

fn budget_flag(overriding: Override) -> Vec<String> {
    match overriding {
        Override::None => Vec::new(),
        Override::Budget(budget) => vec!["--cycle-budget".into(), budget.to_string()],
    }
}

// ----------------------------------------------------------- the language server

/// Every diagnostic the language server publishes once the script is open: per URI,
/// the latest list.
fn lsp(folder: &Path, case: &Case) -> Vec<(String, Value)> {
    let mut server = Peer::start("lsp", folder);
    let options = match case.overriding {
        Override::None => json!({}),
        Override::Budget(budget) => json!({ "cycleBudget": budget }),
    };
    server.send(json!({ "jsonrpc": "2.0", "id": 1, "method": "initialize",
        "params": { "processId": null, "rootUri": uri(folder), "capabilities": {},
                    "initializationOptions": options } }));
    server.until(|seen| seen.iter().any(|message| message["id"] == 1));
    server.send(json!({ "jsonrpc": "2.0", "method": "initialized", "params": {} }));
    let script = folder.join(case.script);
    let language = if case.script.ends_with(".gbas") {
        "gbasic"
    } else {
        "gloc"
    };
    server.send(json!({ "jsonrpc": "2.0", "method": "textDocument/didOpen",
        "params": { "textDocument": { "uri": uri(&script), "languageId": language,
                                      "version": 1, "text": case.text } } }));
    let script_uri = uri(&script);
    let toml_uri = uri(&folder.join("gloc.toml"));
    let refused_in_toml = matches!(&case.expect, Expect::Refused(words) if words.starts_with("gloc.toml:1:16: invalid"));
    server.until(|seen| {
        let published = |wanted: &str| {
            seen.iter().any(|message| {
                message["method"] == "textDocument/publishDiagnostics"
                    && message["params"]["uri"] == wanted
            })
        };
        published(&script_uri) && (!refused_in_toml || published(&toml_uri))
    });
    let mut latest: Vec<(String, Value)> = Vec::new();
    for message in &server.seen {
        if message["method"] == "textDocument/publishDiagnostics" {
            let at = message["params"]["uri"].as_str().unwrap_or("").to_string();
            latest.retain(|(uri, _)| *uri != at);
            latest.push((at, message["params"]["diagnostics"].clone()));
        }
    }
    server.send(json!({ "jsonrpc": "2.0", "id": 2, "method": "shutdown" }));
    server.until(|seen| seen.iter().any(|message| message["id"] == 2));
    server.send(json!({ "jsonrpc": "2.0", "method": "exit" }));
    latest
}

fn lsp_codes(published: &[(String, Value)], script_uri: &str) -> BTreeSet<(String, u32)> {
    published
        .iter()
        .filter(|(uri, _)| uri == script_uri)
        .flat_map(|(_, diagnostics)| diagnostics.as_array().cloned().unwrap_or_default())
        .filter(|diagnostic| matches!(diagnostic["severity"].as_u64(), Some(1 | 2)))
        .map(|diagnostic| {
            (
                diagnostic["code"].as_str().unwrap_or("").to_string(),
                diagnostic["range"]["start"]["line"].as_u64().unwrap_or(0) as u32 + 1,
            )
        })
        .collect()
}

// ------------------------------------------------------------------- the debugger

struct Launch {
    success: bool,
    message: String,
    outputs: String,
}

fn dap(folder: &Path, case: &Case) -> Launch {
    let mut adapter = Peer::start("dap", folder);
    adapter.send(
        json!({ "seq": 1, "type": "request", "command": "initialize",
        "arguments": { "adapterID": "gloc", "linesStartAt1": true, "columnsStartAt1": true } }),
    );
    adapter.until(|seen| seen.iter().any(|message| message["request_seq"] == 1));
    let mut arguments = json!({ "program": folder.join(case.script).display().to_string(),
                                "stopOnEntry": true });
    if let Override::Budget(budget) = case.overriding {
        arguments["cycleBudget"] = json!(budget);
    }
    adapter
        .send(json!({ "seq": 2, "type": "request", "command": "launch", "arguments": arguments }));
    adapter.until(|seen| seen.iter().any(|message| message["request_seq"] == 2));
    let response = adapter
        .seen
        .iter()
        .find(|message| message["request_seq"] == 2)
        .cloned()
        .unwrap_or(Value::Null);
    let success = response["success"] == true;
    if success {
        adapter.send(json!({ "seq": 3, "type": "request", "command": "configurationDone" }));
        adapter.until(|seen| seen.iter().any(|message| message["event"] == "stopped"));
    }
    let outputs: String = adapter
        .seen
        .iter()
        .filter(|message| message["event"] == "output")
        .filter_map(|message| message["body"]["output"].as_str())
        .map(|text| format!("{text}\n"))
        .collect();
    adapter.send(json!({ "seq": 4, "type": "request", "command": "disconnect" }));
    Launch {
        success,
        message: response["message"].as_str().unwrap_or("").to_string(),
        outputs,
    }
}

// ----------------------------------------------------------------------- the test

#[test]
fn every_surface_reports_the_same_codes_on_the_same_lines_or_the_same_refusal() {
    let mut failures = Vec::new();
    for (index, case) in corpus().iter().enumerate() {
        let folder = folder_for(case, index);
        let label = format!("{} × {}", case.script, case.name);
        let script = folder.join(case.script);
        let script_text = script.display().to_string();
        let mut check_args = vec!["check".to_string(), script_text.clone()];
        check_args.extend(budget_flag(case.overriding));
        let mut run_args = vec![
            "run".to_string(),
            script_text.clone(),
            "--cycles".into(),
            "1".into(),
        ];
        run_args.extend(budget_flag(case.overriding));
        let check = cli(&folder, &check_args);
        let run = cli(&folder, &run_args);
        let published = lsp(&folder, case);
        let launch = dap(&folder, case);
        match &case.expect {
            Expect::Codes(codes) => {
                let want = expected(codes);
                let has_error = codes.iter().any(|(code, _)| code.starts_with('E'));
                let surfaces = [
                    (
                        "gloc check",
                        codes_in(&check.text, case.script),
                        &check.text,
                    ),
                    ("gloc run", codes_in(&run.text, case.script), &run.text),
                    (
                        "the language server",
                        lsp_codes(&published, &uri(&script)),
                        &format!("{published:?}"),
                    ),
                    (
                        "the debugger",
                        codes_in(
                            &format!("{}\n{}", launch.message, launch.outputs),
                            case.script,
                        ),
                        &format!("{}\n{}", launch.message, launch.outputs),
                    ),
                ];
                for (surface, found, shown) in surfaces {
                    if found != want {
                        failures.push(format!(
                            "{label}: {surface} reports {found:?}, not {want:?}:\n{shown}"
                        ));
                    }
                }
                let check_code = if has_error { 1 } else { 0 };
                if check.code != Some(check_code) {
                    failures.push(format!("{label}: gloc check exits {:?}", check.code));
                }
                if launch.success == has_error {
                    failures.push(format!(
                        "{label}: the launch {} ({})",
                        if launch.success { "succeeds" } else { "fails" },
                        launch.message
                    ));
                }
            }
            Expect::Refused(words) => {
                let named = match case.overriding {
                    Override::Budget(_) => Some([
                        "--cycle-budget: ",
                        "--cycle-budget: ",
                        "editor setting gloc.cycleBudget: ",
                        "launch attribute cycleBudget: ",
                    ]),
                    Override::None => None,
                };
                // `FILE:LINE:COL: message` of each published diagnostic, as the CLI
                // writes a position (a gloc.toml problem is published on gloc.toml).
                let lsp_messages: String = published
                    .iter()
                    .flat_map(|(uri, diagnostics)| {
                        let file = uri.rsplit('/').next().unwrap_or("").to_string();
                        diagnostics
                            .as_array()
                            .cloned()
                            .unwrap_or_default()
                            .into_iter()
                            .map(move |diagnostic| {
                                let start = &diagnostic["range"]["start"];
                                format!(
                                    "{file}:{}:{}: {}",
                                    start["line"].as_u64().unwrap_or(0) + 1,
                                    start["character"].as_u64().unwrap_or(0) + 1,
                                    diagnostic["message"].as_str().unwrap_or("")
                                )
                            })
                    })
                    .collect::<Vec<_>>()
                    .join("\n");
                let surfaces = [
                    ("gloc check", &check.text),
                    ("gloc run", &run.text),
                    ("the language server", &lsp_messages),
                    ("the debugger", &launch.message),
                ];
                for (at, (surface, said)) in surfaces.iter().enumerate() {
                    let words = match named {
                        Some(origins) => format!("{}{words}", origins[at]),
                        None => words.clone(),
                    };
                    if !said.contains(&words) {
                        failures.push(format!(
                            "{label}: {surface} does not say `{words}`:\n{said}"
                        ));
                    }
                }
                // Exit codes by cause: 2 a setting, 3 an input that cannot be read.
                let code = if words.contains("cannot read") { 3 } else { 2 };
                for (command, answer) in [("check", &check), ("run", &run)] {
                    if answer.code != Some(code) {
                        failures.push(format!(
                            "{label}: gloc {command} exits {:?}, not {code}",
                            answer.code
                        ));
                    }
                }
                if launch.success {
                    failures.push(format!("{label}: the launch succeeds"));
                }
            }
        }
        let _ = std::fs::remove_dir_all(&folder);
    }
    assert!(
        failures.is_empty(),
        "{} disagreements:\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}
