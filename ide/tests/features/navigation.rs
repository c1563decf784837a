//! Go to definition, find references and document highlights.

use gloc_ide::references::{definition, highlights, references, HighlightKind};

use super::*;

fn check_definition(language: Language, fixture: &str, expect: Expect) {
    let fixture = Fixture::new(language, fixture);
    let notes: Vec<(Span, String)> = definition(&fixture.analysis, fixture.cursor())
        .into_iter()
        .map(|span| (span, "definition".to_string()))
        .collect();
    expect.assert_eq(&annotate(&fixture.text, &notes));
}

/// Every occurrence, the definition marked `def`.
fn check_references(language: Language, fixture: &str, expect: Expect) {
    let fixture = Fixture::new(language, fixture);
    let cursor = fixture.cursor();
    let defined = definition(&fixture.analysis, cursor);
    let all = references(&fixture.analysis, cursor, true).unwrap_or_default();
    let uses = references(&fixture.analysis, cursor, false).unwrap_or_default();
    assert_eq!(all.len(), uses.len() + usize::from(defined.is_some()));
    let notes: Vec<(Span, String)> = all
        .into_iter()
        .map(|span| {
            let what = if Some(span) == defined { "def" } else { "ref" };
            (span, what.to_string())
        })
        .collect();
    expect.assert_eq(&annotate(&fixture.text, &notes));
}

fn check_highlights(language: Language, fixture: &str, expect: Expect) {
    let fixture = Fixture::new(language, fixture);
    let notes: Vec<(Span, String)> = highlights(&fixture.analysis, fixture.cursor())
        .unwrap_or_default()
        .into_iter()
        .map(|(span, kind)| {
            let what = match kind {
                HighlightKind::Write => "write",
                HighlightKind::Read => "read",
            };
            (span, what.to_string())
        })
        .collect();
    expect.assert_eq(&annotate(&fixture.text, &notes));
}

const FIG3: &str = include_str!("../../../examples/fig3.gbas");

#[test]
fn gbasic_goto_leads_to_its_label() {
    let fixture = FIG3.replacen("goto state2", "goto sta$0te2", 1);
    check_definition(
        Gbasic,
        &fixture,
        expect![[r#"
            label: state1
            if m_depth > 15.0 then
              SCI_RUHP_BEHS = 128
              goto state2
            endif
            yield
            goto state1
            label: state2
                   ^^^^^^ definition
            if m_depth < 5.0 then
              SCI_RUHP_BEHS = 0
              goto state3
            endif
            yield
            goto state2
            label: state3
            yield
            goto state3
        "#]],
    );
    // A sensor is defined nowhere in the script.
    check_definition(
        Gbasic,
        "if m_$0depth > 1.0 then\nendif\nyield\n",
        expect![[r#"
        if m_depth > 1.0 then
        endif
        yield
    "#]],
    );
}

#[test]
fn gbasic_references_of_a_variable_and_of_a_sensor() {
    check_references(
        Gbasic,
        "dim n as integer\nn = n + 1\nprint $0n\nyield\n",
        expect![[r#"
            dim n as integer
                ^ def
            n = n + 1
            ^ ref
                ^ ref
            print n
                  ^ ref
            yield
        "#]],
    );
    // Case does not matter: `SCI_RUHP_BEHS` and `sci_ruhp_behs` are one sensor.
    check_references(
        Gbasic,
        "SCI_RUHP_BEHS = 128\nsci_ruhp_$0behs = sci_ruhp_behs + 1\nyield\n",
        expect![[r#"
            SCI_RUHP_BEHS = 128
            ^^^^^^^^^^^^^ ref
            sci_ruhp_behs = sci_ruhp_behs + 1
            ^^^^^^^^^^^^^ ref
                            ^^^^^^^^^^^^^ ref
            yield
        "#]],
    );
}

#[test]
fn gbasic_highlights_the_definition_as_the_write() {
    check_highlights(
        Gbasic,
        "label: top\nyield\ngoto t$0op\n",
        expect![[r#"
            label: top
                   ^^^ write
            yield
            goto top
                 ^^^ read
        "#]],
    );
}

const FIG2: &str = include_str!("../../../examples/fig2.gloc");

#[test]
fn gloc_a_jump_target_leads_to_its_label() {
    // `cbr r2,3,4`: the 3 is label 3, defined on the next line.
    let fixture = FIG2.replacen("cbr r2,3,4", "cbr r2,$03,4", 1);
    let fixture = Fixture::new(Gloc, &fixture);
    let span = definition(&fixture.analysis, fixture.cursor()).expect("a definition");
    assert_eq!(fixture.position(span.start as usize), "8:6");
    assert_eq!(&fixture.text[span.range()], "3");
    // Nothing on an instruction or a register.
    let fixture = Fixture::new(Gloc, &FIG2.replacen("loads 444,r0", "lo$0ads 444,r0", 1));
    assert_eq!(definition(&fixture.analysis, fixture.cursor()), None);
    let fixture = Fixture::new(Gloc, &FIG2.replacen("loads 444,r0", "loads 444,r$00", 1));
    assert_eq!(definition(&fixture.analysis, fixture.cursor()), None);
}

#[test]
fn gloc_references_and_highlights_of_a_label() {
    check_references(
        Gloc,
        "nregs 1\nnblbs 2\nninstr 6\nlabel 0\nloadi 1,r0\ncbr r0,1,0\nlabel $01\nyield\njumpi 1\n",
        expect![[r#"
            nregs 1
            nblbs 2
            ninstr 6
            label 0
            loadi 1,r0
            cbr r0,1,0
                   ^ ref
            label 1
                  ^ def
            yield
            jumpi 1
                  ^ ref
        "#]],
    );
    check_highlights(
        Gloc,
        "nregs 1\nnblbs 2\nninstr 6\nlabel 0\nloadi 1,r0\ncbr r0,1,$00\nlabel 1\nyield\njumpi 1\n",
        expect![[r#"
            nregs 1
            nblbs 2
            ninstr 6
            label 0
                  ^ write
            loadi 1,r0
            cbr r0,1,0
                     ^ read
            label 1
            yield
            jumpi 1
        "#]],
    );
}
