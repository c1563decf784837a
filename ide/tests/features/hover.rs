//! Hover: the token under the cursor and the markdown shown for it.

use super::*;

fn check_hover(language: Language, fixture: &str, expect: Expect) {
    let fixture = Fixture::new(language, fixture);
    let answer = gloc_ide::hover::hover(
        fixture.language,
        &fixture.text,
        &fixture.analysis,
        &fixture.context,
        fixture.cursor(),
    );
    let rendered = match answer {
        Some(hover) => format!(
            "`{}`\n---\n{}\n",
            &fixture.text[hover.span.range()],
            hover.markdown
        ),
        None => "no hover\n".to_string(),
    };
    expect.assert_eq(&rendered);
}

/// m_depth in the embedded list: index 444, units m, read-only by its `m_` prefix,
/// no default or range, and its line in engine/data/descriptions.txt.
const M_DEPTH: &str = "**m_depth** (m)\n\nsensor 444 · read-only (a script may not write it)\n\nMeasured depth below the surface in metres, from the pressure sensor; 0 at the surface, positive below.";

#[test]
fn gbasic_sensor() {
    let expected = format!("`m_depth`\n---\n{M_DEPTH}\n");
    let fixture = Fixture::new(Gbasic, "if m_de$0pth > 1.0 then\nendif\nyield\n");
    let hover = gloc_ide::hover::hover(
        Gbasic,
        &fixture.text,
        &fixture.analysis,
        &fixture.context,
        fixture.cursor(),
    )
    .expect("a hover");
    assert_eq!(
        format!(
            "`{}`\n---\n{}\n",
            &fixture.text[hover.span.range()],
            hover.markdown
        ),
        expected
    );
}

#[test]
fn gbasic_variable_constant_and_label_with_their_uses() {
    // `n`: the `dim` and three uses (written once, read twice).
    check_hover(
        Gbasic,
        "dim n as integer\n$0n = abs(n) + 1\nprint n\nyield\n",
        expect![[r#"
            `n`
            ---
            variable `n`: dim n as integer

            3 uses
        "#]],
    );
    check_hover(
        Gbasic,
        "const LIMIT = 3\ndim n as integer\nn = LIM$0IT\nyield\n",
        expect![[r#"
            `LIMIT`
            ---
            constant `LIMIT`: const LIMIT = 3

            1 use
        "#]],
    );
    // User labels are numbered first, in order of definition: `top` is GLOC label 0.
    check_hover(
        Gbasic,
        "label: top\nyield\ngoto t$0op\n",
        expect![[r#"
            `top`
            ---
            label `top`: label: top (GLOC label 0)

            1 use
        "#]],
    );
}

#[test]
fn gbasic_keyword_and_builtin() {
    check_hover(
        Gbasic,
        "yi$0eld\n",
        expect![[r#"
            `yield`
            ---
            Ends the script's share of this 4-second control cycle; the script continues here next cycle.
        "#]],
    );
    check_hover(
        Gbasic,
        "dim n as integer\nn = a$0bs(n)\nyield\n",
        expect![[r#"
            `abs`
            ---
            ```gbasic
            abs(x): |x|, same type as x
            ```
        "#]],
    );
    // Nothing in a comment's words, nothing between tokens.
    check_hover(
        Gbasic,
        "yield ' a yi$0eld\n",
        expect![[r#"
        no hover
    "#]],
    );
}

#[test]
fn gloc_sensor_index() {
    let fixture = Fixture::new(
        Gloc,
        "nregs 1\nnblbs 1\nninstr 3\nlabel 0\nloads 4$044,r0\nyield\n",
    );
    let hover = gloc_ide::hover::hover(
        Gloc,
        &fixture.text,
        &fixture.analysis,
        &fixture.context,
        fixture.cursor(),
    )
    .expect("a hover");
    assert_eq!(&fixture.text[hover.span.range()], "444");
    assert_eq!(hover.markdown, M_DEPTH);
}

#[test]
fn gloc_sensor_name_hovers_as_its_index_does() {
    let fixture = Fixture::new(
        Gloc,
        "nregs 1\nnblbs 1\nninstr 3\nlabel 0\nloads m_de$0pth,r0\nyield\n",
    );
    let hover = gloc_ide::hover::hover(
        Gloc,
        &fixture.text,
        &fixture.analysis,
        &fixture.context,
        fixture.cursor(),
    )
    .expect("a hover");
    assert_eq!(&fixture.text[hover.span.range()], "m_depth");
    assert_eq!(hover.markdown, M_DEPTH);
}

#[test]
fn gloc_instruction_register_directive_and_label() {
    // docs/gloc.md: `cbr r,Ltrue,Lfalse` jumps to Ltrue when r is not 0; an instruction
    // of the paper's Fig. 2.
    check_hover(
        Gloc,
        "nregs 1\nnblbs 2\nninstr 6\nlabel 0\nloadi 1,r0\nc$0br r0,1,0\nlabel 1\nyield\njumpi 0\n",
        expect![[r#"
            `cbr`
            ---
            ```gloc
            cbr r,LABEL,LABEL
            ```
            goto (c != 0 ? Ltrue : Lfalse)

            Operands: a register such as `r0`; a label number such as `3`; a label number such as `3`.

            *from the paper (Woithe & Kremer, Fig. 2)*
        "#]],
    );
    check_hover(
        Gloc,
        "nregs 1\nnblbs 1\nninstr 3\nlabel 0\nloadi 1,r$00\nyield\n",
        expect![[r#"
            `r0`
            ---
            register `r0`: holds an integer or a float; starts as integer 0.
        "#]],
    );
    check_hover(
        Gloc,
        "nr$0egs 1\nnblbs 1\nninstr 2\nlabel 0\nyield\n",
        expect![[r#"
            `nregs`
            ---
            `nregs N`: the script uses registers `r0` to `r(N-1)`.
        "#]],
    );
    // Label 1 is the target of the `cbr` (one use).
    check_hover(
        Gloc,
        "nregs 1\nnblbs 2\nninstr 6\nlabel 0\nloadi 1,r0\ncbr r0,1,0\nlabel $01\nyield\njumpi 0\n",
        expect![[r#"
            `1`
            ---
            label `1`: label 1

            1 use
        "#]],
    );
}
