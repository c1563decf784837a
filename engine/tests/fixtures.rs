//! The GLOC fixture folders: `tests/fixtures/gloc/ok` must check clean and
//! print back byte for byte; each file in `tests/fixtures/gloc/err` has its
//! expected diagnostics beside it in `NAME.err`, drawn under the lines in the one
//! format of every test (`gloc_testsupport::annotate`; written by hand, reviewed). Plus generated inputs: an empty file, binary garbage, a 10 MB
//! file and CRLF line ends. Nothing may panic.

use std::path::{Path, PathBuf};

use gloc_engine::gloc::{self, Bound, CheckOptions, Checked};
use gloc_engine::sensors::SensorList;
use gloc_engine::LineIndex;

fn fixture_dir(kind: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures/gloc")
        .join(kind)
}

fn gloc_files(kind: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(fixture_dir(kind))
        .expect("fixture folder exists")
        .map(|entry| entry.expect("readable entry").path())
        .filter(|path| {
            path.extension()
                .is_some_and(|extension| extension == "gloc")
        })
        .collect();
    files.sort();
    files
}

fn check_text(text: &str) -> Checked {
    let parsed = gloc::parse(text);
    gloc::check(&parsed, &SensorList::embedded(), &CheckOptions::default())
}

/// `(code, line, column)` of every diagnostic, after checking the spans are
/// inside the text and on character boundaries.
fn located(text: &str, checked: &Checked) -> Vec<(String, usize, usize)> {
    let index = LineIndex::new(text);
    checked
        .diagnostics
        .iter()
        .map(|diagnostic| {
            for span in std::iter::once(diagnostic.span)
                .chain(diagnostic.labels.iter().map(|label| label.span))
            {
                assert!(span.start <= span.end, "{diagnostic:?}");
                assert!((span.end as usize) <= text.len(), "{diagnostic:?}");
                assert!(text.is_char_boundary(span.start as usize), "{diagnostic:?}");
                assert!(text.is_char_boundary(span.end as usize), "{diagnostic:?}");
            }
            let (line, column) = index.line_col(text, diagnostic.span.start as usize);
            (diagnostic.code.to_string(), line, column)
        })
        .collect()
}

#[test]
fn ok_fixtures_check_clean_and_round_trip() {
    let files = gloc_files("ok");
    assert!(
        files.len() >= 5,
        "expected the ok fixtures, found {files:?}"
    );
    for path in files {
        let text = std::fs::read_to_string(&path).expect("fixture is UTF-8");
        let checked = check_text(&text);
        assert!(
            checked.diagnostics.is_empty(),
            "{}: {:?}",
            path.display(),
            checked.diagnostics
        );
        assert!(checked.program.is_some(), "{}", path.display());
        let printed = gloc::print(&gloc::parse(&text).file);
        assert_eq!(printed, text, "{} is not canonical", path.display());
    }
}

#[test]
fn err_fixtures_give_their_expected_diagnostics() {
    let files = gloc_files("err");
    assert!(
        files.len() >= 20,
        "expected the err fixtures, found {files:?}"
    );
    for path in files {
        let text = std::fs::read_to_string(&path).expect("fixture is UTF-8");
        let checked = check_text(&text);
        let found = located(&text, &checked);
        assert!(!found.is_empty(), "{} checks clean", path.display());
        gloc_testsupport::expect_diagnostics(&path, &text, &checked.diagnostics);
        let has_error = found.iter().any(|(code, _, _)| code.starts_with('E'));
        assert_eq!(checked.program.is_none(), has_error, "{}", path.display());
        // Printing is idempotent even for broken files, and loses no line.
        let printed = gloc::print(&gloc::parse(&text).file);
        assert_eq!(gloc::print(&gloc::parse(&printed).file), printed);
        assert_eq!(printed.lines().count(), text.lines().count());
    }
}

#[test]
fn duplicate_label_points_at_the_first_definition() {
    let text = std::fs::read_to_string(fixture_dir("err").join("duplicate_label.gloc"))
        .expect("fixture exists");
    let checked = check_text(&text);
    let diagnostic = &checked.diagnostics[0];
    assert_eq!(diagnostic.labels.len(), 1);
    let index = LineIndex::new(&text);
    // `label 0` first appears on line 4; its number is at column 7.
    assert_eq!(
        index.line_col(&text, diagnostic.labels[0].span.start as usize),
        (4, 7)
    );
    assert_eq!(diagnostic.labels[0].message, "first defined here");
}

#[test]
fn an_empty_file_asks_for_the_header() {
    for text in ["", "\n\n", "# only a comment\n"] {
        let checked = check_text(text);
        assert_eq!(located(text, &checked), vec![("E0010".to_string(), 1, 1)]);
        assert!(checked.program.is_none());
    }
    assert!(check_text("").diagnostics[0]
        .message
        .starts_with("empty file"));
}

#[test]
fn binary_garbage_is_an_error_not_a_panic() {
    // A deterministic byte soup, starting with DEL so the first diagnostic is known.
    let mut rng = gloc_testsupport::Rng::new(0x2545_f491);
    let mut bytes = vec![0x7f];
    bytes.extend((0..200_000).map(|_| rng.next_u64() as u8));
    let text = String::from_utf8_lossy(&bytes).into_owned();
    let checked = check_text(&text);
    assert!(checked.program.is_none());
    let diagnostics = located(&text, &checked);
    assert_eq!(diagnostics[0], ("E0002".to_string(), 1, 1));
    // Parse errors are capped, with one closing summary.
    assert!(
        checked.diagnostics.len() <= 1100,
        "{}",
        checked.diagnostics.len()
    );
    let _ = gloc::print(&gloc::parse(&text).file);
}

#[test]
fn a_six_megabyte_script_checks_and_points_at_its_last_line() {
    // 500,000 lines: within the 2^19-line cap.
    let body_lines = 500_000;
    let mut text = String::with_capacity(7_000_000);
    text.push_str(&format!(
        "nregs 3\nnblbs 1\nninstr {}\nlabel 0\n",
        body_lines + 4
    ));
    for _ in 0..body_lines {
        text.push_str("add r0,r1,r2\n");
    }
    text.push_str("yield\njumpi 0\nloadi 1,r9\n");
    assert!(text.len() > 6_000_000);
    let checked = check_text(&text);
    // Header (3) + label (1) + adds + yield + jumpi, then the bad line.
    let bad_line = 3 + 1 + body_lines + 2 + 1;
    assert_eq!(
        located(&text, &checked),
        vec![("E0101".to_string(), bad_line, 9)]
    );

    // Without the bad line it checks clean; the worst case is counted by hand:
    // from the start the adds and the yield, after the yield also `jumpi 0`.
    let fixed = text.replace("loadi 1,r9\n", "");
    let fixed = fixed.replacen(
        &format!("ninstr {}", body_lines + 4),
        &format!("ninstr {}", body_lines + 3),
        1,
    );
    let checked = check_text(&fixed);
    assert!(checked.diagnostics.is_empty(), "{:?}", checked.diagnostics);
    let worst = checked.stats.worst_case.expect("analysed");
    assert_eq!(worst.from_start, Bound::Finite(body_lines as u64 + 1));
    assert_eq!(worst.max, Bound::Finite(body_lines as u64 + 2));
}

#[test]
fn crlf_line_ends_and_a_byte_order_mark_are_accepted() {
    let fig2 = include_str!("../../examples/fig2.gloc");
    let crlf = fig2.replace('\n', "\r\n");
    let checked = check_text(&crlf);
    assert!(checked.diagnostics.is_empty(), "{:?}", checked.diagnostics);
    assert_eq!(gloc::print(&gloc::parse(&crlf).file), fig2);

    // A byte-order mark is skipped; the text after it is Fig. 2.
    let with_bom = format!("\u{feff}{fig2}");
    let checked = check_text(&with_bom);
    assert!(checked.diagnostics.is_empty(), "{:?}", checked.diagnostics);
    assert_eq!(gloc::print(&gloc::parse(&with_bom).file), fig2);

    // Columns do not count the `\r`; the error is on line 4 at the `r9`.
    let bad = "nregs 2\r\nnblbs 0\r\nninstr 2\r\nloadi 1,r9\r\nyield\r\n";
    let checked = check_text(bad);
    assert_eq!(located(bad, &checked), vec![("E0101".to_string(), 4, 9)]);
}
