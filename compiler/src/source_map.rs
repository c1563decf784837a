//! The source map: each GLOC line → the GBASIC text it came from, and each variable →
//! its register or memory cells. Serializable (`gloc compile --emit-map` writes it as
//! JSON) and used by the debugger and for runtime errors.

use gloc_engine::{LineIndex, Span};

use crate::codegen::Storage;
use crate::ir::{Code, Instr};
use crate::typed::{Symbols, Ty};

/// Where one GLOC line came from. Lines and columns are 1-based, offsets are bytes.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Origin {
    /// 1-based line in the GLOC text.
    pub gloc_line: u32,
    /// True for a `label N` line (not an instruction the machine executes).
    pub is_label: bool,
    pub start: u32,
    pub end: u32,
    /// 1-based GBASIC line and column of `start`.
    pub line: u32,
    pub column: u32,
}

impl Origin {
    pub fn span(&self) -> Span {
        Span {
            start: self.start,
            end: self.end,
        }
    }
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct VariableLocation {
    pub name: String,
    #[serde(rename = "type")]
    pub ty: Ty,
    pub storage: Storage,
    /// 1-based GBASIC line of the declaration.
    pub line: u32,
}

/// A `const` of the script and its value, for the debugger's expressions.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ConstantValue {
    pub name: String,
    #[serde(rename = "type")]
    pub ty: Ty,
    /// As GBASIC prints it (`45`, `4.0`).
    pub value: String,
}

impl ConstantValue {
    /// The value as a literal (`None` only for a value the checker never writes).
    pub fn literal(&self) -> Option<crate::ast::Literal> {
        match self.ty {
            Ty::Integer => self.value.parse().ok().map(crate::ast::Literal::Int),
            Ty::Float => self.value.parse().ok().map(crate::ast::Literal::Float),
            Ty::Error => None,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct LabelLocation {
    pub name: String,
    /// The GLOC label number.
    pub number: u32,
}

#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct SourceMap {
    /// One per GLOC line after the header, in order.
    pub lines: Vec<Origin>,
    pub variables: Vec<VariableLocation>,
    pub constants: Vec<ConstantValue>,
    pub labels: Vec<LabelLocation>,
    /// The number of lines before the first instruction: the header (3, or 4 with
    /// `nmem`), plus the `# sensors:` line when there is one.
    pub header_lines: u32,
}

impl SourceMap {
    pub(crate) fn build(
        code: &Code,
        storage: &[Storage],
        symbols: &Symbols,
        text: &str,
    ) -> SourceMap {
        let index = LineIndex::new(text);
        let header_lines = code.line_of_instr(0) as u32;
        let lines = code
            .instrs
            .iter()
            .zip(&code.spans)
            .enumerate()
            .map(|(position, (instr, span))| {
                let (line, column) = index.line_col(text, span.start as usize);
                Origin {
                    gloc_line: header_lines + position as u32 + 1,
                    is_label: matches!(instr, Instr::Label(_)),
                    start: span.start,
                    end: span.end,
                    line: line as u32,
                    column: column as u32,
                }
            })
            .collect();
        let variables = symbols
            .variables
            .iter()
            .zip(storage)
            .map(|(variable, storage)| VariableLocation {
                name: variable.name.clone(),
                ty: variable.ty,
                storage: *storage,
                line: index.line_col(text, variable.definition.start as usize).0 as u32,
            })
            .collect();
        let constants = symbols
            .constants
            .iter()
            .map(|constant| ConstantValue {
                name: constant.name.clone(),
                ty: constant.ty,
                value: constant.value.clone(),
            })
            .collect();
        let labels = symbols
            .labels
            .iter()
            .enumerate()
            .map(|(number, label)| LabelLocation {
                name: label.name.clone(),
                number: number as u32,
            })
            .collect();
        SourceMap {
            lines,
            variables,
            constants,
            labels,
            header_lines,
        }
    }

    /// Where the 1-based GLOC line `gloc_line` came from.
    pub fn origin_of_gloc_line(&self, gloc_line: u32) -> Option<&Origin> {
        let position = gloc_line.checked_sub(self.header_lines + 1)?;
        self.lines.get(position as usize)
    }

    /// Where the executed instruction `pc` came from. A GLOC `Program` numbers its
    /// instructions without the label lines; this counts the same way.
    pub fn origin_of_pc(&self, pc: u32) -> Option<&Origin> {
        self.pc_origins().nth(pc as usize)
    }

    /// The origin of each pc in order (the `label` lines are no instruction).
    pub fn pc_origins(&self) -> impl Iterator<Item = &Origin> {
        self.lines.iter().filter(|origin| !origin.is_label)
    }

    /// The origin of each of a program's `count` pcs, in one pass; `None` for a pc
    /// the map does not reach.
    pub fn origins_of_pcs(&self, count: usize) -> impl Iterator<Item = Option<&Origin>> {
        let mut origins = self.pc_origins();
        (0..count).map(move |_| origins.next())
    }

    /// The first pc (labels not counted) whose GBASIC line is `line` or later, for
    /// breakpoints set on GBASIC lines.
    pub fn pc_at_or_after_line(&self, line: u32) -> Option<u32> {
        self.pc_origins()
            .enumerate()
            .filter(|(_, origin)| origin.line >= line)
            .min_by_key(|(pc, origin)| (origin.line, *pc))
            .map(|(pc, _)| pc as u32)
    }

    /// Every pc (labels not counted) whose GBASIC line is exactly `line`.
    pub fn pcs_of_line(&self, line: u32) -> Vec<u32> {
        self.pc_origins()
            .enumerate()
            .filter(|(_, origin)| origin.line == line)
            .map(|(pc, _)| pc as u32)
            .collect()
    }

    pub fn variable(&self, name: &str) -> Option<&VariableLocation> {
        self.variables
            .iter()
            .find(|variable| variable.name.eq_ignore_ascii_case(name))
    }

    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self)
            .unwrap_or_else(|error| format!("{{\"error\":\"{error}\"}}"))
    }
}
