//! `docs/diagnostics.md` and the one registry of codes (`gloc_engine::codes`) say the
//! same: every code in one is in the other, with the same one-line meaning (the
//! second column of the page's tables) and the severity its prefix or its third
//! column states.

use std::collections::BTreeMap;

use gloc_engine::codes::{self, CodeInfo};
use gloc_engine::Severity;

/// The cells of a Markdown table row, splitting on `|` but not on `\|`.
fn cells(row: &str) -> Vec<String> {
    let mut cells = Vec::new();
    let mut cell = String::new();
    let mut chars = row.trim().trim_start_matches('|').chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                cell.push('\\');
                cell.push('|');
                chars.next();
            }
            '|' => cells.push(std::mem::take(&mut cell).trim().to_string()),
            _ => cell.push(c),
        }
    }
    cells
}

fn documented() -> BTreeMap<String, Vec<String>> {
    let page = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../docs/diagnostics.md"
    ))
    .expect("docs/diagnostics.md");
    let mut rows = BTreeMap::new();
    for line in page.lines().filter(|line| line.starts_with("| ")) {
        let cells = cells(line);
        let code = &cells[0];
        let is_code = code.len() == 5
            && matches!(code.as_bytes()[0], b'E' | b'W' | b'S')
            && code[1..].bytes().all(|b| b.is_ascii_digit());
        if is_code {
            assert!(
                rows.insert(code.clone(), cells.clone()).is_none(),
                "{code} is documented twice"
            );
        }
    }
    rows
}

#[test]
fn the_page_and_the_registry_list_the_same_codes_with_the_same_meaning() {
    let documented = documented();
    let registered: BTreeMap<&str, &CodeInfo> =
        codes::ALL.iter().map(|info| (info.code, info)).collect();
    let only_documented: Vec<&String> = documented
        .keys()
        .filter(|code| !registered.contains_key(code.as_str()))
        .collect();
    let only_registered: Vec<&&str> = registered
        .keys()
        .filter(|code| !documented.contains_key(**code))
        .collect();
    assert!(
        only_documented.is_empty() && only_registered.is_empty(),
        "documented but not registered: {only_documented:?}; registered but not documented: {only_registered:?}"
    );
    for (code, cells) in &documented {
        let info = registered[code.as_str()];
        assert_eq!(
            cells[1], info.doc,
            "{code}: the page's meaning differs from the registry's doc"
        );
        if code.starts_with('S') {
            let severity = match info.severity {
                Severity::Error => "error",
                Severity::Warning => "warning",
                Severity::Note => "note",
            };
            assert!(
                cells.get(2).is_some_and(|cell| cell.starts_with(severity)),
                "{code}: the page's severity column should start with `{severity}`"
            );
        }
    }
    assert!(
        documented.len() >= 90,
        "only {} codes documented",
        documented.len()
    );
}

/// The README's count of codes (`gloc explain` lists all N) is the registry's: it
/// said 92 while the registry held 108.
#[test]
fn the_readme_counts_the_codes_the_registry_has() {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md"))
        .expect("README.md");
    let said: usize = readme
        .split("`gloc explain` lists all ")
        .nth(1)
        .and_then(|rest| rest.split(';').next())
        .and_then(|number| number.trim().parse().ok())
        .expect("the README says how many codes `gloc explain` lists");
    assert_eq!(said, codes::ALL.len());
}
