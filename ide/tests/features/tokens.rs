//! Semantic tokens: one line per token, `line:column text type modifiers`.

use gloc_ide::tokens::{modifiers, semantic_tokens};

use super::*;

fn check_tokens(language: Language, fixture: &str, expect: Expect) {
    let fixture = Fixture::new(language, fixture);
    let mut rendered = String::new();
    for token in semantic_tokens(&fixture.analysis, &fixture.context) {
        let names: Vec<&str> = modifiers::NAMES
            .iter()
            .enumerate()
            .filter(|(bit, _)| token.modifiers & (1 << bit) != 0)
            .map(|(_, name)| *name)
            .collect();
        rendered.push_str(&format!(
            "{} {} {:?}",
            fixture.position(token.span.start as usize),
            &fixture.text[token.span.range()],
            token.token_type
        ));
        if !names.is_empty() {
            rendered.push_str(&format!(" {}", names.join("|")));
        }
        rendered.push('\n');
    }
    expect.assert_eq(&rendered);
}

#[test]
fn gbasic_every_kind_of_token() {
    // Sensors are properties from the standard library; `m_depth` is read-only and
    // `SCI_RUHP_BEHS` is written here; both comment forms are comments, and the `'`
    // inside the string is part of the string.
    check_tokens(
        Gbasic,
        "dim n as integer ' count\nif m_depth > 1.5 then\n  SCI_RUHP_BEHS = n\nendif\nrem the end\nprint \"it's\", abs(n)\nyield\n",
        expect![[r#"
            0:0 dim Keyword
            0:4 n Variable
            0:6 as Keyword
            0:9 integer Keyword
            0:17 ' count Comment
            1:0 if Keyword
            1:3 m_depth Property readonly|defaultLibrary
            1:11 > Operator
            1:13 1.5 Number
            1:17 then Keyword
            2:2 SCI_RUHP_BEHS Property modification|defaultLibrary
            2:16 = Operator
            2:18 n Variable
            3:0 endif Keyword
            4:0 rem the end Comment
            5:0 print Keyword
            5:6 "it's" String
            5:14 abs Function defaultLibrary
            5:18 n Variable
            6:0 yield Keyword
        "#]],
    );
}

#[test]
fn gbasic_constants_and_labels() {
    check_tokens(
        Gbasic,
        "const N = 2\nlabel: top\nprint N\ngoto top\n",
        expect![[r#"
            0:0 const Keyword
            0:6 N Variable readonly
            0:8 = Operator
            0:10 2 Number
            1:0 label Keyword
            1:7 top Label
            2:0 print Keyword
            2:6 N Variable readonly
            3:0 goto Keyword
            3:5 top Label
        "#]],
    );
}

#[test]
fn gloc_every_kind_of_token() {
    // Directives are macros; a sensor index read is read-only (m_depth) and a store
    // is a modification; registers carry the `register` modifier; label numbers
    // after `label` and as jump targets are labels.
    check_tokens(
        Gloc,
        "nregs 1\nnblbs 1\nninstr 5\nlabel 0   # top\nloads 444,r0\nstores r0,1387\nyield\njumpi 0\n",
        expect![[r#"
            0:0 nregs Macro
            0:6 1 Number
            1:0 nblbs Macro
            1:6 1 Number
            2:0 ninstr Macro
            2:7 5 Number
            3:0 label Keyword
            3:6 0 Label
            3:10 # top Comment
            4:0 loads Keyword
            4:6 444 Property readonly|defaultLibrary
            4:10 r0 Variable register
            5:0 stores Keyword
            5:7 r0 Variable register
            5:10 1387 Property modification|defaultLibrary
            6:0 yield Keyword
            7:0 jumpi Keyword
            7:6 0 Label
        "#]],
    );
}

#[test]
fn gloc_numbers_and_strings() {
    check_tokens(
        Gloc,
        "nregs 1\nnblbs 1\nninstr 4\nlabel 0\nloadd 1.5,r0\nwrites \"it's\"\nyield\n",
        expect![[r#"
            0:0 nregs Macro
            0:6 1 Number
            1:0 nblbs Macro
            1:6 1 Number
            2:0 ninstr Macro
            2:7 4 Number
            3:0 label Keyword
            3:6 0 Label
            4:0 loadd Keyword
            4:6 1.5 Number
            4:10 r0 Variable register
            5:0 writes Keyword
            5:7 "it's" String
            6:0 yield Keyword
        "#]],
    );
}

#[test]
fn gbasic_comments_end_before_a_crlf() {
    // The `\r` of a CRLF line end is no part of either comment form.
    check_tokens(
        Gbasic,
        "rem top\r\nyield ' wait\r\n",
        expect![[r#"
            0:0 rem top Comment
            1:0 yield Keyword
            1:6 ' wait Comment
        "#]],
    );
}
