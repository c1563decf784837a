//! Diagnostics: what `gloc check` reports, on the same spans, with the notes
//! that point elsewhere (drawn as `note`).

use super::*;

fn check_diagnostics(language: Language, fixture: &str, expect: Expect) {
    check_diagnostics_in(Fixture::new(language, fixture), expect);
}

fn check_diagnostics_in(fixture: Fixture, expect: Expect) {
    let notes = gloc_testsupport::diagnostic_notes(&fixture.analysis.diagnostics);
    expect.assert_eq(&annotate(&fixture.text, &notes));
}

#[test]
fn gbasic_names_that_are_not_declared_and_read_only_sensors() {
    // docs/gbasic.md: an undeclared name gets a "did you mean" from variables,
    // constants and sensors (`m_dpth` is one edit from `m_depth`; nothing is within
    // one edit of `x`); `m_` sensors are read-only.
    check_diagnostics(
        Gbasic,
        "dim count as integer\ncount = count + 1\nif m_dpth > 3.0 then\n  m_depth = 1\nendif\nx = 2\nyield\n",
        expect![[r#"
            dim count as integer
            count = count + 1
            if m_dpth > 3.0 then
               ^^^^^^ E2101 error: `m_dpth` is not declared and is not a sensor (help: did you mean `m_depth`?)
              m_depth = 1
              ^^^^^^^ E2105 error: the sensor `m_depth` is read-only (help: `m_` (measured) and `x_` (computed) sensors are written by the glider; write a `c_`, `u_` or `sci_` sensor instead)
            endif
            x = 2
            ^ E2101 error: `x` is not declared and is not a sensor (help: declare it with `dim x as integer` (or `as float`))
            yield
        "#]],
    );
}

#[test]
fn gbasic_findings_on_the_compiled_gloc_land_on_the_whole_statement() {
    // GLOC: label 0, yield, jumpi 0, then the print (GLOC line 7 after the three
    // header lines) that nothing reaches. The `'` inside the string is no comment.
    check_diagnostics(
        Gbasic,
        "label: a\nyield\ngoto a\nprint \"it's\" ' never\n",
        expect![[r#"
            label: a
            yield
            goto a
            print "it's" ' never
            ^^^^^^^^^^^^ W0112 warning: unreachable instruction: no path from the start of the script reaches it (compiled GLOC line 7) (help: remove it, or add a label and jump to it)
        "#]],
    );
}

#[test]
fn gbasic_a_float_assigned_to_an_integer_until_int() {
    // docs/gbasic.md: a float becomes an integer only through int(); sensors are
    // floats, so `m_depth * 2.0` is a float and may not go into `n` (E2201, on the
    // expression).
    check_diagnostics(
        Gbasic,
        "dim n as integer\nn = m_depth * 2.0\nyield\n",
        expect![[r#"
            dim n as integer
            n = m_depth * 2.0
                ^^^^^^^^^^^^^ E2201 error: this assignment needs an integer, but this is a float (help: convert with `int(…)`, which truncates toward zero)
            yield
        "#]],
    );
    check_diagnostics(
        Gbasic,
        "dim n as integer\nn = int(m_depth * 2.0)\nyield\n",
        expect![[r#"
            dim n as integer
            n = int(m_depth * 2.0)
            yield
        "#]],
    );
}

#[test]
fn gbasic_a_duplicate_label_points_at_the_first() {
    check_diagnostics(
        Gbasic,
        "label: a\nyield\nlabel: a\ngoto a\n",
        expect![[r#"
            label: a
                   ^ E2104 note: first defined here
            yield
            label: a
                   ^ E2104 error: the label `a` is defined twice (help: rename one of the labels)
            goto a
        "#]],
    );
}

#[test]
fn gloc_unknown_instructions_and_duplicate_labels() {
    // docs/gloc.md: an unknown word gets the closest instruction; a label number
    // defined twice points at its first definition.
    check_diagnostics(
        Gloc,
        "nregs 1\nnblbs 1\nninstr 4\nlabel 0\nlods 444,r0\nlabel 0\nyield\n",
        expect![[r#"
            nregs 1
            nblbs 1
            ninstr 4
            label 0
                  ^ E0103 note: first defined here
            lods 444,r0
            ^^^^ E0001 error: unknown instruction `lods` (help: did you mean `loads`?)
            label 0
                  ^ E0103 error: label 0 is defined twice (help: give this label a number of its own)
            yield
        "#]],
    );
}

#[test]
fn gloc_a_cycle_over_the_budget_is_a_warning() {
    // The longest cycle: after the yield, jumpi 0, loads, stores, yield = 4 > 3.
    let context = Context {
        cycle_budget: Some(3),
        cycle_budget_from: None,
        ..context()
    };
    check_diagnostics_in(
        Fixture::with_context(
            Gloc,
            "nregs 1\nnblbs 2\nninstr 6\nlabel 0\nloads 444,r0\nstores r0,1387\nyield\nlabel 1\njumpi 0\n",
            context,
        ),
        expect![[r#"
            nregs 1
            | W2302 warning: a control cycle may execute 4 instructions, more than the budget of 3 (help: add a `yield` inside long loops, or raise the budget)
            nblbs 2
            ninstr 6
            label 0
            loads 444,r0
            stores r0,1387
            yield
            label 1
            jumpi 0
        "#]],
    );
}

#[test]
fn a_clean_script_has_none_in_either_language() {
    check_diagnostics(
        Gloc,
        "nregs 1\nnblbs 2\nninstr 6\nlabel 0\nloads 444,r0\nstores r0,1387\nyield\nlabel 1\njumpi 0\n",
        expect![[r#"
            nregs 1
            nblbs 2
            ninstr 6
            label 0
            loads 444,r0
            stores r0,1387
            yield
            label 1
            jumpi 0
        "#]],
    );
    check_diagnostics(
        Gbasic,
        "label: top\nif m_depth > 15.0 then\n  SCI_RUHP_BEHS = 128\nendif\nyield\ngoto top\n",
        expect![[r#"
            label: top
            if m_depth > 15.0 then
              SCI_RUHP_BEHS = 128
            endif
            yield
            goto top
        "#]],
    );
}

#[test]
fn gloc_a_loop_that_never_yields_names_where_it_jumps_back() {
    // docs/diagnostics.md E0111: a loop without `yield` and without a way out. The
    // loop starts at its first instruction; the note is on the jump back.
    check_diagnostics(
        Gloc,
        "nregs 1\nnblbs 1\nninstr 3\nlabel 0\nloadi 1,r0\njumpi 0\n",
        expect![[r#"
            nregs 1
            nblbs 1
            ninstr 3
            label 0
            loadi 1,r0
            ^^^^^^^^^^ E0111 error: this loop never yields and has no way out: it would hang the vehicle's control cycle (help: add a `yield` inside the loop)
            jumpi 0
            ^^^^^^^ E0111 note: the loop jumps back from here
        "#]],
    );
}
