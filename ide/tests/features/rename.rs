//! Rename: the text after renaming, or why the new name is refused; and what
//! `prepareRename` offers.

use super::*;

fn check_rename(language: Language, fixture: &str, new_name: &str, expect: Expect) {
    let fixture = Fixture::new(language, fixture);
    let answer = gloc_ide::rename::rename(
        fixture.language,
        &fixture.text,
        &fixture.analysis,
        &fixture.context,
        fixture.cursor(),
        new_name,
    );
    let rendered = match answer {
        Ok(Some(edits)) => apply(&fixture.text, &edits),
        Ok(None) => "nothing to rename here\n".to_string(),
        Err(why) => format!("refused: {why}\n"),
    };
    expect.assert_eq(&rendered);
}

fn check_prepare_rename(language: Language, fixture: &str, expect: Expect) {
    let fixture = Fixture::new(language, fixture);
    let rendered = match gloc_ide::rename::prepare_rename(
        &fixture.text,
        &fixture.analysis,
        fixture.cursor(),
    ) {
        Some((span, placeholder)) => {
            annotate(&fixture.text, &[(span, format!("rename `{placeholder}`"))])
        }
        None => "not renamable\n".to_string(),
    };
    expect.assert_eq(&rendered);
}

const LOOP: &str = "label: top\nyield\ngoto t$0op\n";

#[test]
fn gbasic_renames_every_occurrence() {
    check_rename(
        Gbasic,
        LOOP,
        "again",
        expect![[r#"
            label: again
            yield
            goto again
        "#]],
    );
    check_rename(
        Gbasic,
        "dim n as integer\nn = n + 1\nprint $0n\nyield\n",
        "count",
        expect![[r#"
            dim count as integer
            count = count + 1
            print count
            yield
        "#]],
    );
}

#[test]
fn gbasic_refuses_keywords_taken_names_sensors_and_non_names() {
    // docs/gbasic.md: a name may not reuse a keyword, a built-in, a sensor or
    // another declared name of its kind (labels are only reached by `goto`, so they
    // have names of their own); names are identifiers.
    let fixture = "dim other as integer\nlabel: top\nyield\nlabel: again\ngoto t$0op\ngoto again\n";
    check_rename(
        Gbasic,
        fixture,
        "goto",
        expect![[r#"
        refused: `goto` is a GBASIC keyword
    "#]],
    );
    check_rename(
        Gbasic,
        fixture,
        "abs",
        expect![[r#"
        refused: `abs` is a GBASIC keyword
    "#]],
    );
    check_rename(
        Gbasic,
        fixture,
        "again",
        expect![[r#"
        refused: `again` is already declared
    "#]],
    );
    check_rename(
        Gbasic,
        fixture,
        "m_depth",
        expect![[r#"
        refused: `m_depth` is a sensor name
    "#]],
    );
    check_rename(
        Gbasic,
        fixture,
        "9lives",
        expect![[r#"
        refused: `9lives` is not a valid name: use letters, digits and `_`, starting with a letter
    "#]],
    );
    // A variable may not take another variable's name, whatever its case.
    check_rename(
        Gbasic,
        "dim n as integer\ndim other as integer\nn = $0n + other\nyield\n",
        "OTHER",
        expect![[r#"
            refused: `OTHER` is already declared
        "#]],
    );
}

#[test]
fn gbasic_sensors_are_not_renamable() {
    check_prepare_rename(
        Gbasic,
        "if m_de$0pth > 1.0 then\nendif\nyield\n",
        expect![[r#"
        not renamable
    "#]],
    );
    check_rename(
        Gbasic,
        "if m_de$0pth > 1.0 then\nendif\nyield\n",
        "depth",
        expect![[r#"
        refused: `m_depth` cannot be renamed
    "#]],
    );
    check_prepare_rename(
        Gbasic,
        LOOP,
        expect![[r#"
            label: top
            yield
            goto top
                 ^^^ rename `top`
        "#]],
    );
    check_rename(
        Gbasic,
        "yi$0eld\n",
        "x",
        expect![[r#"
        nothing to rename here
    "#]],
    );
}

const GLOC: &str =
    "nregs 1\nnblbs 3\nninstr 6\nlabel 0\nloadi 1,r0\ncbr r0,1,0\nlabel 1\nyield\njumpi $01\n";

#[test]
fn gloc_renaming_a_label_renumbers_it() {
    // `nblbs 3`: labels 0 to 2; 2 is free.
    check_rename(
        Gloc,
        GLOC,
        "2",
        expect![[r#"
            nregs 1
            nblbs 3
            ninstr 6
            label 0
            loadi 1,r0
            cbr r0,2,0
            label 2
            yield
            jumpi 2
        "#]],
    );
}

#[test]
fn gloc_refuses_taken_numbers_numbers_past_nblbs_and_names() {
    check_rename(
        Gloc,
        GLOC,
        "0",
        expect![[r#"
        refused: label 0 already exists
    "#]],
    );
    check_rename(
        Gloc,
        GLOC,
        "3",
        expect![[r#"
        refused: label 3 is out of range: `nblbs 3` allows labels 0 to 2; raise nblbs first
    "#]],
    );
    check_rename(
        Gloc,
        GLOC,
        "top",
        expect![[r#"
        refused: GLOC labels are numbers; `top` is not a label number
    "#]],
    );
    check_prepare_rename(
        Gloc,
        GLOC,
        expect![[r#"
            nregs 1
            nblbs 3
            ninstr 6
            label 0
            loadi 1,r0
            cbr r0,1,0
            label 1
            yield
            jumpi 1
                  ^ rename `1`
        "#]],
    );
    check_prepare_rename(
        Gloc,
        "nregs 1\nnblbs 1\nninstr 3\nlabel 0\nloadi 1,r$00\nyield\n",
        expect![[r#"
        not renamable
    "#]],
    );
}
