//! The GLOC parser. Line-oriented and total: every line becomes an
//! [`ast::Line`], a line that cannot be read becomes `LineKind::Invalid` with a
//! diagnostic, and parsing resumes at the next line.

// A failed line returns its one diagnostic by value; it is the cold path.
#![allow(clippy::result_large_err)]

use crate::diagnostic::{Diagnostic, Span};
use crate::gloc::ast::{
    Directive, DirectiveKind, File, Instruction, LabelDef, Line, LineKind, Opcode, Operand,
    OperandKind, OperandShape,
};
use crate::suggest;

/// Parse errors are capped so a huge binary file gives a readable report.
const MAX_PARSE_ERRORS: usize = 1000;

/// Parses GLOC text. Never fails.
pub fn parse_file(text: &str) -> (File, Vec<Diagnostic>) {
    let mut parser = Parser {
        diagnostics: Vec::new(),
        suppressed: 0,
        last_span: Span::default(),
    };
    let mut lines = Vec::with_capacity(text.len() / 12 + 1);
    let mut offset = 0usize;
    let mut number = 0u32;
    for raw in text.split_inclusive('\n') {
        number = number.saturating_add(1);
        let content = raw.strip_suffix('\n').unwrap_or(raw);
        let content = content.strip_suffix('\r').unwrap_or(content);
        // A byte-order mark (editors on Windows write one) is not part of the text.
        let (content, skipped) = match content.strip_prefix('\u{feff}') {
            Some(rest) if number == 1 => (rest, '\u{feff}'.len_utf8()),
            _ => (content, 0),
        };
        lines.push(parser.line(content, offset + skipped, number));
        offset += raw.len();
    }
    if parser.suppressed > 0 {
        let span = parser.last_span;
        parser.diagnostics.push(Diagnostic::error(
            crate::codes::gloc::TOO_MANY_PARSE_ERRORS,
            span,
            format!(
                "{} more parse errors not shown (the first {MAX_PARSE_ERRORS} are listed)",
                parser.suppressed
            ),
        ));
    }
    (File { lines }, parser.diagnostics)
}

struct Parser {
    diagnostics: Vec<Diagnostic>,
    suppressed: usize,
    last_span: Span,
}

impl Parser {
    fn report(&mut self, diagnostic: Diagnostic) {
        if self.diagnostics.len() >= MAX_PARSE_ERRORS {
            self.suppressed += 1;
            self.last_span = diagnostic.span;
        } else {
            self.diagnostics.push(diagnostic);
        }
    }

    fn line(&mut self, content: &str, base: usize, number: u32) -> Line {
        let span = Span::new(base, base + content.len());
        let code_end = comment_start(content).unwrap_or(content.len());
        let comment = (code_end < content.len()).then(|| content[code_end..].to_string());
        let code = &content[..code_end];
        let kind = match self.statement(code, base) {
            Ok(kind) => kind,
            Err(diagnostic) => {
                self.report(diagnostic);
                // Trim only what the tokenizer skips too: trimming Unicode
                // whitespace (e.g. a trailing vertical tab) could turn an
                // invalid line into a valid one when the printout is parsed.
                LineKind::Invalid {
                    text: code
                        .trim_matches(|character: char| character.is_ascii_whitespace())
                        .to_string(),
                }
            }
        };
        Line {
            number,
            span,
            kind,
            comment,
        }
    }

    fn statement(&mut self, code: &str, base: usize) -> Result<LineKind, Diagnostic> {
        let word_start = code.len() - code.trim_start().len();
        let rest = &code[word_start..];
        if rest.trim().is_empty() {
            return Ok(LineKind::Blank);
        }
        let word_len = rest
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        if word_len == 0 {
            return Err(unexpected_character(rest, base + word_start));
        }
        let word = &rest[..word_len];
        let word_span = Span::new(base + word_start, base + word_start + word_len);
        let after = &rest[word_len..];
        if !after.is_empty() && !after.starts_with(|c: char| c.is_whitespace()) {
            return Err(unexpected_character(after, base + word_start + word_len));
        }
        let operands_base = base + word_start + word_len;
        let lower: std::borrow::Cow<str> = if word.bytes().any(|byte| byte.is_ascii_uppercase()) {
            word.to_ascii_lowercase().into()
        } else {
            word.into()
        };
        let operands = tokenize(after, operands_base, word)?;

        if let Some(kind) = DirectiveKind::from_keyword(&lower) {
            let [(OperandKind::Integer(value), value_span)] = operands.as_slice() else {
                return Err(expect_single_count(word, word_span, &operands));
            };
            let value = u64::try_from(*value).map_err(|_| {
                Diagnostic::error(
                    crate::codes::gloc::BAD_NUMBER_OR_REGISTER,
                    *value_span,
                    format!("`{word}` needs a count of 0 or more"),
                )
            })?;
            return Ok(LineKind::Directive(Directive {
                kind,
                keyword_span: word_span,
                value,
                value_span: *value_span,
            }));
        }
        if lower == "label" {
            let [(operand, number_span)] = operands.as_slice() else {
                return Err(Diagnostic::error(
                    crate::codes::gloc::OPERAND_COUNT,
                    word_span,
                    format!("`label` takes one label number, found {}", operands.len()),
                )
                .with_help("write `label N`, e.g. `label 0`"));
            };
            let number = label_number(operand, *number_span)?;
            return Ok(LineKind::Label(LabelDef {
                number,
                number_span: *number_span,
            }));
        }
        let Some(opcode) = Opcode::from_name(&lower) else {
            let mut diagnostic = Diagnostic::error(
                crate::codes::gloc::UNKNOWN_INSTRUCTION,
                word_span,
                format!("unknown instruction `{word}`"),
            );
            let candidates = Opcode::ALL
                .iter()
                .map(|opcode| opcode.name())
                .chain(["label", "nregs", "nblbs", "ninstr", "nmem"]);
            if let Some(suggestion) = suggest::closest(word, candidates) {
                diagnostic = diagnostic
                    .with_help(format!("did you mean `{suggestion}`?"))
                    .with_fix(
                        format!("replace with `{suggestion}`"),
                        word_span,
                        suggestion,
                    );
            } else {
                diagnostic =
                    diagnostic.with_help("see docs/gloc.md for the list of GLOC instructions");
            }
            return Err(diagnostic);
        };
        let signature = opcode.signature();
        // Operands that do not fit the instruction: what is wrong, and how to write it.
        let misfit = if operands.len() != signature.len() {
            let span = match operands.get(signature.len()) {
                Some((_, extra)) => *extra,
                None => word_span.cover(operands.last().map_or(word_span, |(_, span)| *span)),
            };
            let plural = if signature.len() == 1 { "" } else { "s" };
            let wrong = format!(
                "takes {} operand{plural}, found {}",
                signature.len(),
                operands.len()
            );
            Some((crate::codes::gloc::OPERAND_COUNT, span, wrong))
        } else {
            operands
                .iter()
                .zip(signature)
                .find(|((kind, _), shape)| !fits(kind, **shape))
                .map(|((kind, span), shape)| {
                    let found = describe_operand(kind);
                    let wrong = format!("expects {} here, found {found}", shape.describe());
                    (crate::codes::gloc::OPERAND_KIND, *span, wrong)
                })
        };
        if let Some((code, span, wrong)) = misfit {
            return Err(
                Diagnostic::error(code, span, format!("`{}` {wrong}", opcode.name()))
                    .with_help(format!("write `{}`", opcode.usage())),
            );
        }
        // Same layout: the collect reuses the allocation.
        let operands = operands
            .into_iter()
            .map(|(kind, span)| Operand { kind, span })
            .collect();
        Ok(LineKind::Instruction(Instruction {
            opcode,
            opcode_span: word_span,
            operands,
        }))
    }
}

fn expect_single_count(
    word: &str,
    word_span: Span,
    operands: &[(OperandKind, Span)],
) -> Diagnostic {
    let span = operands.first().map_or(word_span, |(_, span)| *span);
    Diagnostic::error(
        crate::codes::gloc::OPERAND_COUNT,
        span,
        format!("`{word}` takes one count, a whole number such as `8`"),
    )
    .with_help(format!("write `{} N`", word.to_ascii_lowercase()))
}

fn label_number(operand: &OperandKind, span: Span) -> Result<u32, Diagnostic> {
    match operand {
        OperandKind::Integer(value) => u32::try_from(*value).map_err(|_| {
            Diagnostic::error(
                crate::codes::gloc::BAD_NUMBER_OR_REGISTER,
                span,
                format!("label number {value} is out of range (0 to 4294967295)"),
            )
        }),
        other => Err(Diagnostic::error(
            crate::codes::gloc::OPERAND_KIND,
            span,
            format!(
                "expected a label number such as `3`, found {}",
                describe_operand(other)
            ),
        )),
    }
}

fn fits(kind: &OperandKind, shape: OperandShape) -> bool {
    match (shape, kind) {
        (OperandShape::Register, OperandKind::Register(_)) => true,
        (OperandShape::Sensor | OperandShape::Label, OperandKind::Integer(value)) => {
            u32::try_from(*value).is_ok()
        }
        (OperandShape::Sensor, OperandKind::Name(_)) => true,
        (OperandShape::Integer, OperandKind::Integer(_)) => true,
        (OperandShape::Number, OperandKind::Integer(_) | OperandKind::Float(_)) => true,
        (OperandShape::Address, OperandKind::Register(_)) => true,
        (OperandShape::Address, OperandKind::Integer(value)) => u32::try_from(*value).is_ok(),
        (OperandShape::Text, OperandKind::Text(_)) => true,
        _ => false,
    }
}

fn describe_operand(kind: &OperandKind) -> String {
    match kind {
        OperandKind::Register(register) => format!("register `r{register}`"),
        OperandKind::Integer(value) => format!("`{value}`"),
        OperandKind::Float(value) => format!("`{value:?}`"),
        OperandKind::Text(_) => "a string".to_string(),
        OperandKind::Name(name) => format!("the name `{name}`"),
    }
}

fn unexpected_character(text: &str, at: usize) -> Diagnostic {
    let character = text.chars().next().unwrap_or(' ');
    let span = Span::new(at, at + character.len_utf8());
    if character == '\u{FFFD}' || character.is_control() {
        Diagnostic::error(
            crate::codes::gloc::UNEXPECTED_CHARACTER,
            span,
            format!(
                "unexpected character {:?}: this does not look like GLOC text",
                character
            ),
        )
        .with_help("is this a binary file? GLOC is plain text, one instruction a line")
    } else {
        Diagnostic::error(
            crate::codes::gloc::UNEXPECTED_CHARACTER,
            span,
            format!("unexpected character `{character}`"),
        )
        .with_help("a GLOC line is `instruction operand,operand,…` (comments start with `#`)")
    }
}

/// Byte offset of a `#` that starts a comment (outside a string literal).
fn comment_start(line: &str) -> Option<usize> {
    let mut in_string = false;
    let mut escaped = false;
    for (at, byte) in line.bytes().enumerate() {
        if in_string {
            match byte {
                _ if escaped => escaped = false,
                b'\\' => escaped = true,
                b'"' => in_string = false,
                _ => {}
            }
        } else if byte == b'"' {
            in_string = true;
        } else if byte == b'#' {
            return Some(at);
        }
    }
    None
}

/// Reads `a , b , c` into operands, checking the commas. One allocation
/// per line: this runs for every line of a 10 MB script.
fn tokenize(text: &str, base: usize, word: &str) -> Result<Vec<(OperandKind, Span)>, Diagnostic> {
    let bytes = text.as_bytes();
    let mut operands = Vec::new();
    let mut expect_operand = true;
    let mut last_comma = None;
    let mut at = 0;
    while at < bytes.len() {
        let byte = bytes[at];
        if byte.is_ascii_whitespace() {
            at += 1;
            continue;
        }
        let start = at;
        if byte == b',' {
            at += 1;
            let span = Span::new(base + start, base + at);
            if expect_operand {
                return Err(Diagnostic::error(
                    crate::codes::gloc::COMMA,
                    span,
                    format!("expected an operand of `{word}` before `,`"),
                ));
            }
            expect_operand = true;
            last_comma = Some(span);
            continue;
        }
        let kind = if byte == b'"' {
            let (value, end) = string_literal(text, start, base)?;
            at = end;
            OperandKind::Text(value)
        } else if byte.is_ascii_alphanumeric() || matches!(byte, b'-' | b'+' | b'.' | b'_') {
            at += 1;
            while at < bytes.len() {
                let next = bytes[at];
                let exponent_sign =
                    matches!(next, b'-' | b'+') && matches!(bytes[at - 1], b'e' | b'E');
                if next.is_ascii_alphanumeric() || matches!(next, b'.' | b'_') || exponent_sign {
                    at += 1;
                } else {
                    break;
                }
            }
            operand_word(&text[start..at], Span::new(base + start, base + at))?
        } else {
            return Err(unexpected_character(&text[start..], base + start));
        };
        let span = Span::new(base + start, base + at);
        if !expect_operand {
            return Err(Diagnostic::error(
                crate::codes::gloc::COMMA,
                span,
                "expected `,` between operands",
            )
            .with_help("operands are separated by commas: `cmpgt r0,r1,r2`"));
        }
        if operands.capacity() == 0 {
            operands.reserve_exact(3);
        }
        operands.push((kind, span));
        expect_operand = false;
    }
    if expect_operand {
        if let Some(comma) = last_comma {
            return Err(Diagnostic::error(
                crate::codes::gloc::COMMA,
                comma,
                "trailing `,`: an operand is missing",
            ));
        }
    }
    Ok(operands)
}

fn operand_word(word: &str, span: Span) -> Result<OperandKind, Diagnostic> {
    let first = word.as_bytes()[0];
    if matches!(first, b'r' | b'R') && word.len() > 1 {
        let digits = &word[1..];
        if digits.bytes().all(|byte| byte.is_ascii_digit()) {
            return digits
                .parse::<u32>()
                .map(OperandKind::Register)
                .map_err(|_| {
                    Diagnostic::error(
                        crate::codes::gloc::BAD_NUMBER_OR_REGISTER,
                        span,
                        format!("register `{word}` is out of range"),
                    )
                });
        }
    }
    if first.is_ascii_digit() || matches!(first, b'-' | b'+' | b'.') {
        let is_float = word.contains(['.', 'e', 'E']);
        if is_float {
            if let Ok(value) = word.parse::<f64>() {
                if value.is_finite() {
                    return Ok(OperandKind::Float(value));
                }
            }
        } else if let Ok(value) = word.parse::<i64>() {
            return Ok(OperandKind::Integer(value));
        } else if word.bytes().skip(1).all(|byte| byte.is_ascii_digit()) {
            return Err(Diagnostic::error(
                crate::codes::gloc::BAD_NUMBER_OR_REGISTER,
                span,
                format!("integer `{word}` does not fit in 64 bits"),
            ));
        }
        return Err(Diagnostic::error(
            crate::codes::gloc::BAD_NUMBER_OR_REGISTER,
            span,
            format!("malformed number `{word}`"),
        )
        .with_help("write an integer (`128`, `-3`) or a float (`15.0`, `1.5e-3`)"));
    }
    if (first.is_ascii_alphabetic() || first == b'_')
        && word
            .bytes()
            .all(|byte| byte.is_ascii_alphanumeric() || byte == b'_')
    {
        return Ok(OperandKind::Name(word.to_string()));
    }
    Err(Diagnostic::error(
        crate::codes::gloc::OPERAND_KIND,
        span,
        format!("expected an operand, found `{word}`"),
    )
    .with_help(
        "operands are registers (`r0`), numbers (`444`, `15.0`), strings (\"text\") or sensor names (`m_depth`)",
    ))
}

/// Reads a string literal starting at `start` (the opening quote). Returns
/// the unescaped value and the offset after the closing quote.
fn string_literal(text: &str, start: usize, base: usize) -> Result<(String, usize), Diagnostic> {
    let mut value = String::new();
    let mut chars = text[start + 1..].char_indices();
    while let Some((offset, character)) = chars.next() {
        let at = start + 1 + offset;
        match character {
            '"' => return Ok((value, at + 1)),
            '\\' => match chars.next() {
                Some((_, '"')) => value.push('"'),
                Some((_, '\\')) => value.push('\\'),
                Some((_, other)) => {
                    return Err(Diagnostic::error(
                        crate::codes::gloc::BAD_STRING,
                        Span::new(base + at, base + at + 1 + other.len_utf8()),
                        format!("unknown escape `\\{other}` in a string"),
                    )
                    .with_help("the escapes are `\\\"` and `\\\\`"))
                }
                None => break,
            },
            other => value.push(other),
        }
    }
    Err(Diagnostic::error(
        crate::codes::gloc::BAD_STRING,
        Span::new(base + start, base + text.len()),
        "unterminated string",
    )
    .with_help("close the string with `\"` on the same line"))
}
