//! Code actions: the quick fixes at the cursor or range, each shown with the
//! text it gives; and the compiled GLOC of a document.

use super::*;

fn check_actions(language: Language, fixture: &str, expect: Expect) {
    let fixture = Fixture::new(language, fixture);
    let fixes = gloc_ide::actions::quick_fixes(&fixture.analysis, fixture.range());
    let rendered: Vec<String> = fixes
        .iter()
        .map(|fix| {
            format!(
                "{}{} (fixes {})\n{}",
                fix.title,
                if fix.preferred { ", preferred" } else { "" },
                fixture.analysis.diagnostics[fix.diagnostic].code,
                apply(&fixture.text, std::slice::from_ref(&fix.edit))
            )
        })
        .collect();
    expect.assert_eq(&rendered.join("---\n"));
}

#[test]
fn gbasic_did_you_mean_is_the_one_preferred_fix() {
    check_actions(
        Gbasic,
        "if m_dp$0th > 3.0 then\nendif\nyield\n",
        expect![[r#"
            replace with `m_depth`, preferred (fixes E2101)
            if m_depth > 3.0 then
            endif
            yield
        "#]],
    );
}

#[test]
fn gbasic_declare_an_undeclared_name_above_its_line_with_its_indent() {
    check_actions(
        Gbasic,
        "while 1\n  $0x = 2\n  yield\nwend\n",
        expect![[r#"
            declare `x` with `dim x as integer` (fixes E2101)
            while 1
              dim x as integer
              x = 2
              yield
            wend
            ---
            declare `x` with `dim x as float` (fixes E2101)
            while 1
              dim x as float
              x = 2
              yield
            wend
        "#]],
    );
}

#[test]
fn gbasic_insert_yield_before_the_loops_closing_line() {
    check_actions(
        Gbasic,
        "dim n as integer\n$0while 1\n  n = n + 1\nwend\n",
        expect![[r#"
            insert `yield` in this loop, preferred (fixes W0111)
            dim n as integer
            while 1
              n = n + 1
              yield
            wend
        "#]],
    );
    // No diagnostic where the cursor is: no fix.
    check_actions(
        Gbasic,
        "dim n as integer\nwhile 1\n  n = n + 1\n  yield\nwend\n$0",
        expect![[""]],
    );
}

#[test]
fn gloc_insert_yield_and_keep_ninstr_true() {
    // The loop `label 0 … jumpi 0` never yields (reported on its first instruction);
    // the `yield` goes before the jump back, and adds a line, so `ninstr 3` must
    // become 4.
    check_actions(
        Gloc,
        "nregs 1\nnblbs 1\nninstr 3\nlabel 0\n$0loadi 1,r0\njumpi 0\n",
        expect![[r#"
            insert `yield` in this loop (fixes E0111)
            nregs 1
            nblbs 1
            ninstr 3
            label 0
            loadi 1,r0
            yield
            jumpi 0
            ---
            update `ninstr` (fixes E0111)
            nregs 1
            nblbs 1
            ninstr 4
            label 0
            loadi 1,r0
            jumpi 0
        "#]],
    );
}

#[test]
fn gloc_a_misspelt_instruction() {
    check_actions(
        Gloc,
        "nregs 1\nnblbs 0\nninstr 2\nl$0ods 444,r0\nyield\n",
        expect![[r#"
            replace with `loads`, preferred (fixes E0001)
            nregs 1
            nblbs 0
            ninstr 2
            loads 444,r0
            yield
        "#]],
    );
}

#[test]
fn compiled_gloc_of_each_language() {
    // The paper: Fig. 3 compiles to Fig. 2, byte for byte.
    let fig3 = include_str!("../../../examples/fig3.gbas");
    let fig2 = include_str!("../../../examples/fig2.gloc");
    let fixture = Fixture::new(Gbasic, fig3);
    assert_eq!(
        gloc_ide::actions::compiled_gloc(Gbasic, fig3, &fixture.analysis).as_deref(),
        Ok(fig2)
    );
    // A GLOC document is its own GLOC.
    let fixture = Fixture::new(Gloc, fig2);
    assert_eq!(
        gloc_ide::actions::compiled_gloc(Gloc, fig2, &fixture.analysis).as_deref(),
        Ok(fig2)
    );
    // A program with errors has none.
    let fixture = Fixture::new(Gbasic, "x = 1\ny = 2\n");
    assert_eq!(
        gloc_ide::actions::compiled_gloc(Gbasic, "x = 1\ny = 2\n", &fixture.analysis),
        Err("the program has 2 errors; fix them to see its GLOC".to_string())
    );
}
