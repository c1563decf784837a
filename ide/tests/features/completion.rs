//! Completion: the candidates at the cursor whose label (or filter text) starts
//! with the word typed before it, in the order given, with kind, detail and
//! what is inserted when that is not the label.

use super::*;
use gloc_ide::analysis::Insert;

fn check_completion(language: Language, fixture: &str, expect: Expect) {
    let fixture = Fixture::new(language, fixture);
    let cursor = fixture.cursor();
    let typed = fixture.text[..cursor]
        .rsplit(|character: char| !character.is_ascii_alphanumeric() && character != '_')
        .next()
        .unwrap_or("")
        .to_ascii_lowercase();
    let items = gloc_ide::completion::completions(
        fixture.language,
        &fixture.text,
        cursor,
        &fixture.analysis,
        &fixture.context,
    );
    let mut rendered = String::new();
    for item in items {
        let matched = item.filter_text.as_deref().unwrap_or(&item.label);
        if !matched.to_ascii_lowercase().starts_with(&typed) {
            continue;
        }
        rendered.push_str(&format!("{} [{:?}]", item.label, item.kind));
        if let Some(detail) = &item.detail {
            rendered.push_str(&format!(" {detail}"));
        }
        if let Some(Insert::Snippet(insert) | Insert::Text(insert)) = &item.insert {
            rendered.push_str(&format!(" => {insert}"));
        }
        rendered.push('\n');
    }
    expect.assert_eq(&rendered);
}

#[test]
fn gbasic_labels_after_goto() {
    // Labels in order of definition, numbered so in GLOC.
    check_completion(
        Gbasic,
        "label: top\nyield\ngoto $0\nlabel: done\nyield\ngoto done\n",
        expect![[r#"
            top [Label] label: top (GLOC label 0)
            done [Label] label: done (GLOC label 1)
        "#]],
    );
}

#[test]
fn gbasic_types_after_as() {
    check_completion(
        Gbasic,
        "dim n as $0\n",
        expect![[r#"
            integer [Keyword]
            float [Keyword]
        "#]],
    );
}

#[test]
fn gbasic_expressions_offer_every_sensor_statements_mark_read_only_ones() {
    // In a condition: any sensor (the embedded list's m_depth* by index).
    check_completion(
        Gbasic,
        "if m_dept$0\n",
        expect![[r#"
            m_depth_subsampled [Sensor] sensor 165 (m), read-only
            m_depth_rate [Sensor] sensor 166 (m/s), read-only
            m_depth_rate_subsampled [Sensor] sensor 167 (m/s), read-only
            m_depth_state [Sensor] sensor 170 (enum), read-only
            m_depth [Sensor] sensor 444 (m), read-only
            m_depth_rejected [Sensor] sensor 446 (bool), read-only
        "#]],
    );
    // At the start of a statement: a store target. The read-only `m_` sensors are
    // still offered (a user looking for m_depth finds it), marked as not storable;
    // ranking puts the writable ones first (`completion::rank`).
    check_completion(
        Gbasic,
        "  m_dept$0\n",
        expect![[r#"
            m_depth_subsampled [Sensor] sensor 165 (m), read-only: cannot be stored
            m_depth_rate [Sensor] sensor 166 (m/s), read-only: cannot be stored
            m_depth_rate_subsampled [Sensor] sensor 167 (m/s), read-only: cannot be stored
            m_depth_state [Sensor] sensor 170 (enum), read-only: cannot be stored
            m_depth [Sensor] sensor 444 (m), read-only: cannot be stored
            m_depth_rejected [Sensor] sensor 446 (bool), read-only: cannot be stored
        "#]],
    );
    // The writable hook sensors.
    check_completion(
        Gbasic,
        "  sci_ruhp$0\n",
        expect![[r#"
            sci_ruhp_dive_depth [Sensor] sensor 1385 (m), writable
            sci_ruhp_climb_depth [Sensor] sensor 1386 (m), writable
            sci_ruhp_behs [Sensor] sensor 1387 (enum), writable
            sci_ruhp_heading [Sensor] sensor 1388 (rad), writable
        "#]],
    );
}

#[test]
fn gbasic_declared_names_and_builtins_in_expressions() {
    check_completion(
        Gbasic,
        "dim depth_sum as float\nconst DEPTH_MAX = 100.0\ndepth_sum = dep$0\n",
        expect![[r#"
            depth_sum [Variable] dim depth_sum as float
            DEPTH_MAX [Constant] const DEPTH_MAX = 100.0
        "#]],
    );
    check_completion(
        Gbasic,
        "dim n as integer\nn = a$0\n",
        expect![[r#"
            abs [Function] abs(x): |x|, same type as x => abs($1)
            and [Keyword]
        "#]],
    );
}

#[test]
fn gbasic_nothing_in_comments_and_strings_but_after_a_string_with_a_quote() {
    check_completion(Gbasic, "yield ' m_dept$0\n", expect![[""]]);
    check_completion(Gbasic, "rem m_dept$0\n", expect![[""]]);
    check_completion(Gbasic, "print \"m_dept$0\n", expect![[""]]);
    // The `'` is inside the string: after it, an expression.
    check_completion(
        Gbasic,
        "print \"it's\", m_depth_ra$0\n",
        expect![[r#"
            m_depth_rate [Sensor] sensor 166 (m/s), read-only
            m_depth_rate_subsampled [Sensor] sensor 167 (m/s), read-only
        "#]],
    );
}

const SIMPLE_GLOC: &str =
    "nregs 2\nnblbs 2\nninstr 6\nlabel 0\nloads 444,r0\nstores r0,1387\nyield\nlabel 1\njumpi 0\n";

#[test]
fn gloc_first_word_instructions_label_and_directives() {
    let text = format!("{SIMPLE_GLOC}st$0\n");
    check_completion(
        Gloc,
        &text,
        expect![[r#"
            stores [Instruction] stores r,SENSOR => stores ${1:r0},${2:0}
            storem [Instruction] storem r,ADDR => storem ${1:r0},${2:r0}
        "#]],
    );
    let text = format!("{SIMPLE_GLOC}n$0\n");
    check_completion(
        Gloc,
        &text,
        expect![[r#"
            neg [Instruction] neg r,r => neg ${1:r0},${2:r0}
            not [Instruction] not r,r => not ${1:r0},${2:r0}
            nop [Instruction] nop => nop
            nregs [Keyword] => nregs ${1:0}
            nblbs [Keyword] => nblbs ${1:0}
            nlbls [Keyword] => nlbls ${1:0}
            ninstr [Keyword] => ninstr ${1:0}
            nmem [Keyword] => nmem ${1:0}
        "#]],
    );
}

#[test]
fn gloc_operands_registers_labels_and_sensors_by_name() {
    // `nregs 2`: r0 and r1.
    let text = format!("{SIMPLE_GLOC}mov r$0\n");
    check_completion(
        Gloc,
        &text,
        expect![[r#"
            r0 [Register] register
            r1 [Register] register
        "#]],
    );
    // Defined labels, with the number of jumps to each.
    let text = format!("{SIMPLE_GLOC}jumpi $0\n");
    check_completion(
        Gloc,
        &text,
        expect![[r#"
            0 [Label] label 0 (1 jumps)
            1 [Label] label 1 (0 jumps)
        "#]],
    );
    // A store takes a writable sensor; its name is inserted (GLOC takes names).
    let text = format!("{SIMPLE_GLOC}stores r0,sci_ruhp_b$0\n");
    check_completion(
        Gloc,
        &text,
        expect![[r#"
            sci_ruhp_behs [Sensor] sensor 1387 (enum), writable
        "#]],
    );
    // A read-only sensor after `stores` is still offered, marked as not storable.
    let text = format!("{SIMPLE_GLOC}stores r0,m_dept$0\n");
    check_completion(
        Gloc,
        &text,
        expect![[r#"
            m_depth_subsampled [Sensor] sensor 165 (m), read-only: cannot be stored
            m_depth_rate [Sensor] sensor 166 (m/s), read-only: cannot be stored
            m_depth_rate_subsampled [Sensor] sensor 167 (m/s), read-only: cannot be stored
            m_depth_state [Sensor] sensor 170 (enum), read-only: cannot be stored
            m_depth [Sensor] sensor 444 (m), read-only: cannot be stored
            m_depth_rejected [Sensor] sensor 446 (bool), read-only: cannot be stored
        "#]],
    );
    let text = format!("{SIMPLE_GLOC}loads m_depth_s$0\n");
    check_completion(
        Gloc,
        &text,
        expect![[r#"
            m_depth_subsampled [Sensor] sensor 165 (m), read-only
            m_depth_state [Sensor] sensor 170 (enum), read-only
        "#]],
    );
    // Nothing in a comment.
    let text = format!("{SIMPLE_GLOC}yield # st$0\n");
    check_completion(Gloc, &text, expect![[""]]);
}
