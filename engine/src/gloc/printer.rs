//! The canonical GLOC printer: lower-case mnemonics, one space after the
//! mnemonic, operands separated by `,` without spaces, comments kept, one
//! line per source line, `\n` line ends. Printing the parse of Fig. 2 gives
//! Fig. 2 byte for byte.

use std::fmt::Write;

use crate::gloc::ast::{File, LineKind, Operand, OperandKind};

pub fn print_file(file: &File) -> String {
    let mut out = String::with_capacity(file.lines.len() * 16);
    for line in &file.lines {
        let start = out.len();
        match &line.kind {
            LineKind::Blank => {}
            LineKind::Directive(directive) => {
                let _ = write!(out, "{} {}", directive.kind.keyword(), directive.value);
            }
            LineKind::Label(label) => {
                let _ = write!(out, "label {}", label.number);
            }
            LineKind::Instruction(instruction) => {
                out.push_str(instruction.opcode.name());
                for (position, operand) in instruction.operands.iter().enumerate() {
                    out.push(if position == 0 { ' ' } else { ',' });
                    print_operand(&mut out, operand);
                }
            }
            LineKind::Invalid { text } => out.push_str(text),
        }
        if let Some(comment) = &line.comment {
            if out.len() > start {
                out.push(' ');
            }
            out.push_str(comment.trim_end());
        }
        out.push('\n');
    }
    out
}

fn print_operand(out: &mut String, operand: &Operand) {
    match &operand.kind {
        OperandKind::Register(register) => {
            let _ = write!(out, "r{register}");
        }
        OperandKind::Integer(value) => {
            let _ = write!(out, "{value}");
        }
        OperandKind::Float(value) => {
            let _ = write!(out, "{value:?}");
        }
        OperandKind::Text(text) => write_quoted(out, text),
        OperandKind::Name(name) => out.push_str(name),
    }
}

/// Appends `text` as a GLOC string literal: in quotes, `"` and `\` escaped, every
/// other character as it is. A GLOC string ends at its line, so `text` holds no line
/// break (neither a parsed GLOC string nor a GBASIC one can).
pub fn write_quoted(out: &mut String, text: &str) {
    out.reserve(text.len() + 2);
    out.push('"');
    for character in text.chars() {
        if matches!(character, '"' | '\\') {
            out.push('\\');
        }
        out.push(character);
    }
    out.push('"');
}
