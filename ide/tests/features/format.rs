//! Formatting: the edit (which lines it replaces) and the text it gives, which
//! formats to itself.

use super::*;

fn check_format(language: Language, before: &str, expect: Expect) {
    let rendered = match gloc_ide::format::formatting(language, before) {
        None => "cannot be formatted\n".to_string(),
        Some(edits) if edits.is_empty() => "already formatted\n".to_string(),
        Some(edits) => {
            let fixture = Fixture::new(language, before);
            let after = apply(before, &edits);
            assert_eq!(
                gloc_ide::format::formatting(language, &after),
                Some(Vec::new()),
                "formatting twice changes nothing"
            );
            let spans: Vec<String> = edits
                .iter()
                .map(|edit| {
                    format!(
                        "{}..{}",
                        fixture.position(edit.span.start as usize),
                        fixture.position(edit.span.end as usize)
                    )
                })
                .collect();
            format!("replaces {}\n{after}", spans.join(", "))
        }
    };
    expect.assert_eq(&rendered);
}

#[test]
fn gbasic_indents_two_spaces_a_block_and_touches_only_changed_lines() {
    // The first and last lines are already right: the edit runs from line 1 to the
    // start of line 6.
    check_format(
        Gbasic,
        "while 1\nif m_depth > 1.0 then\nyield\nelse\n      yield\nendif\nwend\n",
        expect![[r#"
            replaces 1:0..6:0
            while 1
              if m_depth > 1.0 then
                yield
              else
                yield
              endif
            wend
        "#]],
    );
}

#[test]
fn gbasic_a_comment_after_then_still_opens_the_block() {
    check_format(
        Gbasic,
        "dim x as integer\nif x then ' positive\nx = 1\nendif\n",
        expect![[r#"
            replaces 2:0..3:0
            dim x as integer
            if x then ' positive
              x = 1
            endif
        "#]],
    );
}

#[test]
fn gbasic_crlf_stays_crlf() {
    let edits =
        gloc_ide::format::formatting(Gbasic, "while 1\r\nyield\r\nwend\r\n").expect("formats");
    assert_eq!(
        apply("while 1\r\nyield\r\nwend\r\n", &edits),
        "while 1\r\n  yield\r\nwend\r\n"
    );
}

#[test]
fn gloc_canonical_spelling_and_spacing_comment_kept() {
    // docs/gloc.md: instructions are lower case, operands separated by a bare comma.
    check_format(
        Gloc,
        "nregs 1\nnblbs 0\nninstr 2\nLOADS  444 , r0   # depth\nyield\n",
        expect![[r#"
            replaces 3:0..4:0
            nregs 1
            nblbs 0
            ninstr 2
            loads 444,r0 # depth
            yield
        "#]],
    );
    check_format(
        Gloc,
        "nregs 1\nnblbs 0\nninstr 1\nyield\n",
        expect![[r#"
        already formatted
    "#]],
    );
}
