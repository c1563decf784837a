//! Soak test: thousands of random incremental edits (non-ASCII text, line
//! breaks, CRLF) sent back to back to one open document; the diagnostics
//! published for the last version must equal those of a fresh check of the
//! final text, computed here directly with the core and converted to UTF-16
//! positions by this file's own converter (not the server's).

mod support;

use gloc_compiler::loader::{load_script, Language, LoadOptions};
use gloc_engine::sensors::SensorList;
use gloc_testsupport::Rng;
use serde_json::{json, Value};
use support::TestClient;

/// LSP position of a byte offset, counted independently of the server: lines
/// end at `\n`, `\r\n` or a lone `\r`; columns count UTF-16 units.
fn position(text: &str, offset: usize) -> (u64, u64) {
    let mut line = 0;
    let mut column = 0;
    // Look ahead in the whole text: a `\r` just before `offset` may be the
    // first half of a CRLF (then `offset` is the end of its line).
    let characters = text.char_indices().take_while(|(at, _)| *at < offset);
    for (at, character) in characters {
        match character {
            '\r' if text[at + 1..].starts_with('\n') => {}
            '\n' | '\r' => {
                line += 1;
                column = 0;
            }
            other => column += other.len_utf16() as u64,
        }
    }
    (line, column)
}

fn char_boundary(text: &str, random: &mut Rng) -> usize {
    let boundaries: Vec<usize> = text
        .char_indices()
        .map(|(at, _)| at)
        .chain([text.len()])
        .collect();
    let mut at = boundaries[random.index(boundaries.len())];
    // Never split a "\r\n" pair: the server sees it as one line break.
    if at > 0 && text[..at].ends_with('\r') && text[at..].starts_with('\n') {
        at -= 1;
    }
    at
}

const GBASIC_PIECES: [&str; 16] = [
    "yield\n",
    "é",
    "𝄞",
    "goto a\n",
    "label: a\n",
    "x = 1\n",
    "\r\n",
    "if m_depth > 1 then\n",
    "endif\n",
    "dim x as integer\n",
    " ",
    "' comment ü 🐟\n",
    "while x < 3\n",
    "wend\n",
    "m_dpth",
    "print \"Zürich\", x\n",
];
const GLOC_PIECES: [&str; 14] = [
    "yield\n",
    "é",
    "𝄞",
    "jumpi 0\n",
    "label 0\n",
    "loads 444,r0\n",
    "\r\n",
    "nregs 2\n",
    "ninstr 3\n",
    "nblbs 1\n",
    " ",
    "# ü 🐟\n",
    "stores r0,1387\n",
    "cbr r0,0,1\n",
];

async fn soak(uri: &str, language_id: &str, language: Language, pieces: &[&str], seed: u64) {
    let mut random = Rng::new(seed);
    let mut client = TestClient::initialized().await;
    let mut text = String::from(pieces[0]);
    client.open(uri, language_id, &text).await;
    let edits = 2000;
    for version in 2..(2 + edits) {
        let mut start = char_boundary(&text, &mut random);
        let mut end = char_boundary(&text, &mut random);
        if start > end {
            std::mem::swap(&mut start, &mut end);
        }
        // A third of the edits replace or delete a short range (possibly
        // across lines); the rest insert, so the document grows.
        if random.index(2) != 0 || end - start > 24 {
            end = start;
        }
        let insert = match random.index(5) {
            0 if end > start => String::new(),
            _ => pieces[random.index(pieces.len())].to_string(),
        };
        let (start_line, start_column) = position(&text, start);
        let (end_line, end_column) = position(&text, end);
        text.replace_range(start..end, &insert);
        client
            .notify(
                "textDocument/didChange",
                json!({ "textDocument": { "uri": uri, "version": version },
                        "contentChanges": [{ "range": {
                            "start": { "line": start_line, "character": start_column },
                            "end": { "line": end_line, "character": end_column } },
                          "text": insert }] }),
            )
            .await;
    }
    let final_version = 1 + edits;
    let published = loop {
        let params = client.diagnostics(uri).await;
        if params["version"] == json!(final_version) {
            break params;
        }
    };
    let sensors = SensorList::embedded();
    let fresh = load_script(&text, language, &sensors, &LoadOptions::default());
    let expected: Vec<Value> = fresh
        .diagnostics
        .iter()
        .map(|diagnostic| {
            let (start_line, start_column) = position(&text, diagnostic.span.start as usize);
            let (end_line, end_column) = position(&text, diagnostic.span.end as usize);
            let mut message = diagnostic.message.clone();
            if let Some(help) = &diagnostic.help {
                message = format!("{message}\nhelp: {help}");
            }
            json!([
                start_line,
                start_column,
                end_line,
                end_column,
                diagnostic.code,
                message
            ])
        })
        .collect();
    let actual: Vec<Value> = published["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .map(|d| {
            let range = &d["range"];
            json!([
                range["start"]["line"],
                range["start"]["character"],
                range["end"]["line"],
                range["end"]["character"],
                d["code"],
                d["message"]
            ])
        })
        .collect();
    assert!(
        text.len() > 100,
        "the edits built a real document: {text:?}"
    );
    if let Some(first) =
        (0..actual.len().max(expected.len())).find(|&at| actual.get(at) != expected.get(at))
    {
        panic!(
            "diagnostic {first} of {} differs:\n  server: {:?}\n  fresh:  {:?}\nstart of the final text: {:?}",
            expected.len(),
            actual.get(first),
            expected.get(first),
            text.chars().take(120).collect::<String>()
        );
    }
    // The server's own text is the same as ours.
    if language == Language::Gloc {
        let server_text = client
            .request(
                "workspace/executeCommand",
                json!({ "command": "gloc.compiledGloc", "arguments": [uri] }),
            )
            .await;
        assert_eq!(server_text, json!(text));
    }
}

#[tokio::test]
async fn thousands_of_random_gbasic_edits_end_where_a_fresh_parse_does() {
    soak(
        "file:///soak/random.gbas",
        "gbasic",
        Language::Gbasic,
        &GBASIC_PIECES,
        0x9E37_79B9_7F4A_7C15,
    )
    .await;
}

#[tokio::test]
async fn thousands_of_random_gloc_edits_end_where_a_fresh_parse_does() {
    soak(
        "file:///soak/random.gloc",
        "gloc",
        Language::Gloc,
        &GLOC_PIECES,
        0xD1B5_4A32_D192_ED03,
    )
    .await;
}
