//! Folding: the regions that span lines, as `first..=last` line numbers with the
//! first line's text.

use super::*;

fn check_folding(language: Language, fixture: &str, expect: Expect) {
    let fixture = Fixture::new(language, fixture);
    let mut folds: Vec<(usize, usize)> =
        gloc_ide::folding::folding_ranges(&fixture.text, &fixture.analysis)
            .into_iter()
            .map(|span| {
                (
                    fixture.line_of(span.start as usize),
                    fixture.line_of(span.end as usize),
                )
            })
            .collect();
    folds.sort();
    let lines: Vec<&str> = fixture.text.lines().collect();
    let rendered: String = folds
        .into_iter()
        .map(|(first, last)| format!("{first}..={last}: {}\n", lines[first]))
        .collect();
    expect.assert_eq(&rendered);
}

#[test]
fn gbasic_label_sections_and_blocks() {
    // Label sections; `if` to `endif`, `while` to `wend`, `for` to `next`, `do` to
    // `loop until`; a one-line `if` does not fold.
    check_folding(
        Gbasic,
        "const LIMIT = 3\ndim count as integer\ndim i as integer\nlabel: top\nif count < LIMIT then\n  count = count + 1\nendif\nwhile count > 0\n  count = count - 1\n  yield\nwend\nfor i = 0 to 3\n  count = i\nnext i\ndo\n  yield\nloop until count >= LIMIT\nif count = LIMIT then goto done\nyield\ngoto top\nlabel: done\nyield\ngoto done\n",
        expect![[r#"
            3..=19: label: top
            4..=6: if count < LIMIT then
            7..=10: while count > 0
            11..=13: for i = 0 to 3
            14..=16: do
            20..=22: label: done
        "#]],
    );
}

#[test]
fn gloc_label_sections() {
    // Each label to the last statement before the next; a label with nothing after
    // it before the next one is one line and does not fold.
    check_folding(
        Gloc,
        "nregs 1\nnblbs 3\nninstr 6\nlabel 0\nloads 444,r0\nyield\nlabel 2\nlabel 1\njumpi 0\n",
        expect![[r#"
            3..=5: label 0
            7..=8: label 1
        "#]],
    );
}

#[test]
fn gbasic_crlf_lines_fold_alike() {
    check_folding(
        Gbasic,
        "label: top\r\nwhile 1\r\n  yield\r\nwend\r\ngoto top\r\n",
        expect![[r#"
            0..=4: label: top
            1..=3: while 1
        "#]],
    );
}
