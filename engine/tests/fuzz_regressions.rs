//! Inputs the fuzzers (tests/fuzz) found, kept as regression tests: each one
//! broke an invariant of the parser, printer, checker or interpreter.

use gloc_engine::gloc::{self, ast::LineKind};

/// Printing is idempotent: the canonical text of the canonical text is itself.
fn assert_print_is_idempotent(text: &str) {
    let printed = gloc::print(&gloc::parse(text).file);
    let reprinted = gloc::print(&gloc::parse(&printed).file);
    assert_eq!(reprinted, printed, "for {text:?}");
}

#[test]
fn an_invalid_line_stays_invalid_when_printed() {
    // A vertical tab is Unicode whitespace but not GLOC whitespace: the line
    // is invalid, and trimming it in the printout made `cbr R2,3,4` valid.
    let text = "\n\u{4}nr,r1\ncmpgt r0,r1,r2\ncbr R2,3,4\u{b}\nlabel";
    assert_print_is_idempotent(text);
    let parsed = gloc::parse("cbr r2,3,4\u{b}\n");
    assert!(
        matches!(parsed.file.lines[0].kind, LineKind::Invalid { .. }),
        "{:?}",
        parsed.file.lines[0].kind
    );
    let printed = gloc::print(&parsed.file);
    assert!(
        !gloc::parse(&printed).diagnostics.is_empty(),
        "the printout of an invalid line is still invalid: {printed:?}"
    );
    // Non-breaking spaces after the statement: invalid before and after.
    assert_print_is_idempotent("yield\u{a0}\n");
}
