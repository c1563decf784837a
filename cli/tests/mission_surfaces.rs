//! One mission reading behind every surface: the same mission files give the same
//! codes on the same lines in `gloc check`, `gloc run --mission` and `gloc lsp` (the
//! editor's diagnostics on the open `.mi`). Expected codes worked out by hand from the
//! fixtures in `tests/fixtures/missions/check`:
//!
//! - `typos.mi`: `behavior: surfce` (line 4) is S0101; `d_targt_depth` (line 7) S0103.
//! - `deep.mi`: the yo's `d_target_depth` 60 (line 5) is past abend's overdepth 50:
//!   S0122; its `c_target_depth` 65 (line 6) is below the dive target: S0123.

mod support;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde_json::json;
use support::peer::{uri, Peer};
use support::{gloc_in, text};

fn folder() -> PathBuf {
    PathBuf::from(support::repo("tests/fixtures/missions/check"))
}

/// `(code, line)` of every `FILE:LINE:COL: severity[CODE]` line about `file` (a
/// path that ends with it).
fn cli_codes(output: &str, file: &str) -> BTreeSet<(String, u32)> {
    output
        .lines()
        .filter_map(|line| {
            // The file, as given or under a folder (`/tmp/…/shared/x.ma`).
            let at = line.find(&format!("{file}:"))?;
            if line[..at].contains(' ') || !(at == 0 || line[..at].ends_with('/')) {
                return None;
            }
            let rest = &line[at + file.len() + 1..];
            let mut parts = rest.splitn(3, ':');
            let line_number: u32 = parts.next()?.parse().ok()?;
            let _column = parts.next()?;
            let code = rest.split_once('[')?.1.split_once(']')?.0;
            Some((code.to_string(), line_number))
        })
        .collect()
}

fn lsp_codes(mission: &Path) -> BTreeSet<(String, u32)> {
    let root = mission
        .parent()
        .and_then(Path::parent)
        .map_or_else(folder, Path::to_path_buf);
    let mut server = Peer::start("lsp", &root);
    server.send(json!({ "jsonrpc": "2.0", "id": 1, "method": "initialize",
        "params": { "processId": null, "rootUri": uri(&root), "capabilities": {} } }));
    server.until(|seen| seen.iter().any(|message| message["id"] == 1));
    server.send(json!({ "jsonrpc": "2.0", "method": "initialized", "params": {} }));
    let text = std::fs::read_to_string(mission).expect("fixture");
    let mission_uri = uri(mission);
    server.send(json!({ "jsonrpc": "2.0", "method": "textDocument/didOpen",
        "params": { "textDocument": { "uri": mission_uri, "languageId": "slocum_mission",
                                      "version": 1, "text": text } } }));
    server.until(|seen| {
        seen.iter().any(|message| {
            message["method"] == "textDocument/publishDiagnostics"
                && message["params"]["uri"] == mission_uri.as_str()
        })
    });
    let codes = server
        .seen
        .iter()
        .rev()
        .find(|message| {
            message["method"] == "textDocument/publishDiagnostics"
                && message["params"]["uri"] == mission_uri.as_str()
        })
        .and_then(|message| message["params"]["diagnostics"].as_array().cloned())
        .unwrap_or_default()
        .iter()
        .filter(|diagnostic| matches!(diagnostic["severity"].as_u64(), Some(1 | 2)))
        .map(|diagnostic| {
            (
                diagnostic["code"].as_str().unwrap_or("").to_string(),
                diagnostic["range"]["start"]["line"].as_u64().unwrap_or(0) as u32 + 1,
            )
        })
        .collect();
    server.send(json!({ "jsonrpc": "2.0", "id": 2, "method": "shutdown" }));
    server.until(|seen| seen.iter().any(|message| message["id"] == 2));
    server.send(json!({ "jsonrpc": "2.0", "method": "exit" }));
    codes
}

#[test]
fn check_run_and_the_editor_report_the_same_mission_problems() {
    let cases: [(&str, &[(&str, u32)]); 2] = [
        ("missions/typos.mi", &[("S0101", 4), ("S0103", 7)]),
        ("missions/deep.mi", &[("S0122", 5), ("S0123", 6)]),
    ];
    for (file, expected) in cases {
        let expected: BTreeSet<(String, u32)> = expected
            .iter()
            .map(|(code, line)| (code.to_string(), *line))
            .collect();
        let check = gloc_in(&["check", file], &folder());
        assert_eq!(
            cli_codes(&text(&check.stdout), file),
            expected,
            "gloc check {file}:\n{}",
            text(&check.stdout)
        );
        let run = gloc_in(&["run", "--mission", file, "--cycles", "3"], &folder());
        assert_eq!(
            cli_codes(&text(&run.stderr), file),
            expected,
            "gloc run --mission {file}:\n{}",
            text(&run.stderr)
        );
        assert_eq!(
            lsp_codes(&folder().join(file)),
            expected,
            "gloc lsp on {file}"
        );
    }
}

#[test]
fn gloc_tomls_mafiles_reaches_check_run_and_the_editor() {
    // `shared/surfac10.ma` sets when_secs 60, under the release masterdata's
    // `#! min = 120.0`: S0120 on its line 3. Found through gloc.toml's `mafiles`, it is
    // reported by check and run on the `.ma`, and by the editor on the `.mi`'s
    // `args_from_file` line (line 2); without the key every surface would say S0004.
    let temp = support::temp_folder("surfaces-mafiles");
    std::fs::create_dir_all(temp.join("missions")).expect("mkdir");
    std::fs::create_dir_all(temp.join("shared")).expect("mkdir");
    std::fs::write(temp.join("gloc.toml"), "mafiles = \"shared\"\n").expect("write");
    std::fs::write(
        temp.join("missions/m.mi"),
        "behavior: surface\n  b_arg: args_from_file(enum) 10\n",
    )
    .expect("write");
    std::fs::write(
        temp.join("shared/surfac10.ma"),
        "behavior_name=surface\n<start:b_arg>\n  b_arg: when_secs(sec) 60\n<end:b_arg>\n",
    )
    .expect("write");
    let ma = "shared/surfac10.ma";
    let expected: BTreeSet<(String, u32)> = [("S0120".to_string(), 3)].into();
    let check = gloc_in(&["check", "missions/m.mi"], &temp);
    assert_eq!(check.status.code(), Some(0), "{}", text(&check.stdout));
    assert_eq!(
        cli_codes(&text(&check.stdout), ma),
        expected,
        "{}",
        text(&check.stdout)
    );
    let run = gloc_in(
        &["run", "--mission", "missions/m.mi", "--cycles", "3"],
        &temp,
    );
    assert_eq!(
        cli_codes(&text(&run.stderr), ma),
        expected,
        "{}",
        text(&run.stderr)
    );
    let editor: BTreeSet<(String, u32)> = [("S0120".to_string(), 2)].into();
    assert_eq!(lsp_codes(&temp.join("missions/m.mi")), editor);
}
