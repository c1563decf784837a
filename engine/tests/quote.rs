//! `gloc::quote`, the one GLOC string quoter, read back by the GLOC parser: every
//! character a string can hold (all but the line break) comes back as it was.

use gloc_engine::gloc::{self, ast::LineKind, ast::OperandKind};

/// Parses `prints <quoted>` and returns the string the parser read, or its diagnostics.
fn read_back(text: &str) -> Result<String, String> {
    let line = format!("prints {}\n", gloc::quote(text));
    let parsed = gloc::parse(&line);
    if !parsed.diagnostics.is_empty() {
        return Err(format!("{line:?}: {:?}", parsed.diagnostics));
    }
    let reprinted = gloc::print(&parsed.file);
    if reprinted != line {
        return Err(format!("printed again as {reprinted:?}, not {line:?}"));
    }
    match &parsed.file.lines[0].kind {
        LineKind::Instruction(instruction) => match &instruction.operands[..] {
            [operand] => match &operand.kind {
                OperandKind::Text(read) => Ok(read.clone()),
                other => Err(format!("{line:?}: read as {other:?}")),
            },
            other => Err(format!("{line:?}: operands {other:?}")),
        },
        other => Err(format!("{line:?}: read as {other:?}")),
    }
}

#[test]
fn quotes_backslashes_and_comment_signs_round_trip() {
    for text in [
        "",
        "\"",
        "\\",
        "\\\"",
        "\"\\",
        "a\\\\b",
        "say \"hi\"",
        "ends in a backslash \\",
        "# not a comment",
        "x\" # y",
        "\\\" # \\",
    ] {
        assert_eq!(read_back(text).as_deref(), Ok(text));
    }
}

#[test]
fn control_characters_round_trip() {
    // Every control character but the line feed, alone, inside and at both ends
    // (a carriage return last in the string is still before the closing quote).
    for code in (0u32..0x20).chain([0x7f, 0x85, 0x2028, 0x2029]) {
        let Some(character) = char::from_u32(code) else {
            continue;
        };
        if character == '\n' {
            continue;
        }
        for text in [
            character.to_string(),
            format!("a{character}b"),
            format!("{character}x{character}"),
        ] {
            assert_eq!(
                read_back(&text).as_deref(),
                Ok(text.as_str()),
                "U+{code:04X}"
            );
        }
    }
}

#[test]
fn non_ascii_round_trips() {
    for text in [
        "temp °C",
        "ä\"ö\\ü",
        "\u{feff}starts with a byte-order mark",
        "e\u{301} combining",
        "🐟 deep",
        "日本語",
    ] {
        assert_eq!(read_back(text).as_deref(), Ok(text));
    }
}
