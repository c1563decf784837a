//! Document symbols: each defined name, its kind and detail, drawn under its
//! name, with the lines its definition covers.

use super::*;

fn check_symbols(language: Language, fixture: &str, expect: Expect) {
    let fixture = Fixture::new(language, fixture);
    let notes: Vec<(Span, String)> = gloc_ide::symbols::document_symbols(&fixture.analysis)
        .into_iter()
        .map(|symbol| {
            let first = fixture.line_of(symbol.extent.start as usize);
            let last = fixture.line_of(symbol.extent.end as usize);
            let detail = symbol
                .detail
                .map(|detail| format!(" `{detail}`"))
                .unwrap_or_default();
            (
                symbol.selection,
                format!(
                    "{} {:?}{detail}, lines {first}..={last}",
                    symbol.name, symbol.kind
                ),
            )
        })
        .collect();
    expect.assert_eq(&annotate(&fixture.text, &notes));
}

#[test]
fn gbasic_variables_arrays_constants_and_label_sections() {
    // A declaration covers its line; a label's section runs to the line before the
    // next label (or the end). Sensors are used, never defined: no symbol.
    check_symbols(
        Gbasic,
        "const LIMIT = 3\ndim count as integer\ndim depths(4) as float\nlabel: top\ncount = count + LIMIT\ndepths(0) = m_depth\nyield\ngoto top\nlabel: done\nyield\ngoto done\n",
        expect![[r#"
            const LIMIT = 3
                  ^^^^^ LIMIT Constant `const LIMIT = 3`, lines 0..=0
            dim count as integer
                ^^^^^ count Variable `dim count as integer`, lines 1..=1
            dim depths(4) as float
                ^^^^^^ depths Array `dim depths(4) as float`, lines 2..=2
            label: top
                   ^^^ top Label `label: top (GLOC label 0)`, lines 3..=7
            count = count + LIMIT
            depths(0) = m_depth
            yield
            goto top
            label: done
                   ^^^^ done Label `label: done (GLOC label 1)`, lines 8..=10
            yield
            goto done
        "#]],
    );
}

#[test]
fn gloc_labels_and_their_sections() {
    // A label's section runs to the last statement before the next label; a label
    // only jumped to (label 2 here, never defined) is no symbol.
    check_symbols(
        Gloc,
        "nregs 1\nnblbs 3\nninstr 5\nlabel 0\nloads 444,r0\nyield\n\nlabel 1\njumpi 2\n",
        expect![[r#"
            nregs 1
            nblbs 3
            ninstr 5
            label 0
                  ^ 0 Label `label 0`, lines 3..=5
            loads 444,r0
            yield

            label 1
                  ^ 1 Label `label 1`, lines 7..=8
            jumpi 2
        "#]],
    );
}
