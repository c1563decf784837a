//! Signature help: the signature with the active parameter in `<…>`, and its
//! documentation.

use super::*;

fn check_signature(language: Language, fixture: &str, expect: Expect) {
    let fixture = Fixture::new(language, fixture);
    let rendered = match gloc_ide::signature::signature_help(
        fixture.language,
        &fixture.text,
        fixture.cursor(),
    ) {
        Some(signature) => {
            let (start, end) = signature.parameters[signature.active_parameter];
            format!(
                "{}<{}>{}\n{}\n",
                &signature.label[..start],
                &signature.label[start..end],
                &signature.label[end..],
                signature.documentation
            )
        }
        None => "no signature\n".to_string(),
    };
    expect.assert_eq(&rendered);
}

#[test]
fn gbasic_builtins_count_commas_at_their_own_depth() {
    // The comma inside `sqrt(2.0)` is not max's; the cursor is on max's second.
    check_signature(
        Gbasic,
        "dim a as float\na = max(1.0, sqrt(2.0), $0\n",
        expect![[r#"
            max(a, <b>)
            the larger; float if either is
        "#]],
    );
    check_signature(
        Gbasic,
        "dim a as float\na = max(1.0, sqrt($0\n",
        expect![[r#"
            sqrt(<x>)
            square root, a float
        "#]],
    );
    check_signature(
        Gbasic,
        "dim a as float\na = (1.0 + $0\n",
        expect![[r#"
        no signature
    "#]],
    );
}

#[test]
fn gloc_operands_of_the_instruction() {
    check_signature(
        Gloc,
        "nregs 1\nnblbs 1\nninstr 3\nlabel 0\nloads 444,$0\n",
        expect![[r#"
            loads SENSOR,<r>
            dst := sensor[S] (always a float)
        "#]],
    );
    check_signature(
        Gloc,
        "cbr $0\n",
        expect![[r#"
            cbr <r>,LABEL,LABEL
            goto (c != 0 ? Ltrue : Lfalse)
        "#]],
    );
    // No operands, no signature; none in a comment.
    check_signature(
        Gloc,
        "yield $0\n",
        expect![[r#"
        no signature
    "#]],
    );
    check_signature(
        Gloc,
        "yield # loads $0\n",
        expect![[r#"
        no signature
    "#]],
    );
}
