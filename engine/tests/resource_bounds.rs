//! Resource bounds (hardening): inputs far beyond any real script are refused
//! with a clear message instead of being read into gigabytes of memory.

use gloc_engine::gloc::{self, CheckOptions, MAX_SOURCE_BYTES, MAX_SOURCE_LINES};
use gloc_engine::sensors::SensorList;

fn check(text: &str) -> gloc::Checked {
    gloc::check(
        &gloc::parse(text),
        &SensorList::embedded(),
        &CheckOptions::default(),
    )
}

#[test]
fn a_100_mb_script_is_refused_with_one_clear_error() {
    let body = "nop\n".repeat(25 << 20);
    let text = format!("nregs 1\nnblbs 0\nninstr {}\n{body}", 25 << 20);
    assert!(text.len() > 100 << 20);
    let checked = check(&text);
    assert!(checked.program.is_none());
    let codes: Vec<&str> = checked.diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(codes, ["E0013"], "{:?}", checked.diagnostics);
    let message = &checked.diagnostics[0].message;
    assert!(
        message.contains("100.0 MB") && message.contains("at most 16 MB"),
        "{message}"
    );
}

#[test]
fn a_script_of_more_than_2_pow_19_lines_is_refused_and_one_of_2_pow_19_is_read() {
    let header = "nregs 1\nnblbs 0\nninstr 1\nyield\n";
    // The header's four lines and the blank lines make exactly the limit: read.
    let text = format!("{header}{}", "\n".repeat(MAX_SOURCE_LINES - 4));
    let checked = check(&text);
    assert!(checked.program.is_some(), "{:?}", checked.diagnostics);
    // One line more, even without a final line end: refused, however short.
    let text = format!("{header}{}#", "\n".repeat(MAX_SOURCE_LINES - 4));
    let checked = check(&text);
    let codes: Vec<&str> = checked.diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(codes, ["E0013"], "{:?}", checked.diagnostics);
    assert!(
        checked.diagnostics[0]
            .message
            .contains("524289 lines; gloc reads scripts of at most 524288 lines"),
        "{}",
        checked.diagnostics[0].message
    );
}

#[test]
fn a_script_just_under_the_limit_is_read() {
    let header = "nregs 1\nnblbs 0\nninstr 1\n";
    let comment = "x".repeat(MAX_SOURCE_BYTES - header.len() - "yield #\n".len());
    let text = format!("{header}yield #{comment}\n");
    assert_eq!(text.len(), MAX_SOURCE_BYTES);
    let checked = check(&text);
    assert!(checked.diagnostics.is_empty(), "{:?}", checked.diagnostics);
    assert!(checked.program.is_some());
}

#[test]
fn nregs_1000000_is_refused_before_anything_is_allocated() {
    let checked = check("nregs 1000000\nnblbs 0\nninstr 1\nyield\n");
    assert!(checked.program.is_none());
    let refusal = checked
        .diagnostics
        .iter()
        .find(|diagnostic| diagnostic.code == "E0012")
        .unwrap_or_else(|| panic!("E0012 for nregs: {:?}", checked.diagnostics));
    assert!(
        refusal.message.contains("65536"),
        "the message names the limit: {}",
        refusal.message
    );
    // The same for labels and memory cells.
    for header in [
        "nregs 1\nnblbs 100000000\nninstr 1\nyield\n",
        "nregs 1\nnblbs 0\nnmem 100000000\nninstr 1\nyield\n",
    ] {
        let checked = check(header);
        assert!(checked.program.is_none(), "{header}");
        assert!(
            checked.diagnostics.iter().any(|d| d.code == "E0012"),
            "{header}: {:?}",
            checked.diagnostics
        );
    }
}
