//! Static debug information about the loaded script: which source line each GLOC
//! instruction comes from, where statements start, and the GLOC text for disassembly.

use std::collections::BTreeSet;
use std::path::PathBuf;

/// The source language the user debugs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Language {
    Gbasic,
    Gloc,
}

#[derive(Clone, Debug)]
pub struct DebugInfo {
    pub path: PathBuf,
    pub language: Language,
    /// 1-based source line of each instruction (`None`: generated code with no line).
    pub line_of_pc: Vec<Option<u32>>,
    /// The GLOC text of each instruction, for `disassemble`.
    pub instruction_text: Vec<String>,
    lines_with_code: BTreeSet<u32>,
    /// Lines of the source as an editor shows them (the empty line after a final
    /// newline included), when known: a breakpoint past them is refused.
    pub source_lines: Option<u32>,
}

impl DebugInfo {
    pub fn new(
        path: PathBuf,
        language: Language,
        line_of_pc: Vec<Option<u32>>,
        instruction_text: Vec<String>,
    ) -> DebugInfo {
        let lines_with_code = line_of_pc.iter().flatten().copied().collect();
        DebugInfo {
            path,
            language,
            line_of_pc,
            instruction_text,
            lines_with_code,
            source_lines: None,
        }
    }

    /// The source's line count, as an editor counts lines of `text`.
    pub fn with_source_text(mut self, text: &str) -> DebugInfo {
        self.source_lines = Some(u32::try_from(text.split('\n').count()).unwrap_or(u32::MAX));
        self
    }

    pub fn instruction_count(&self) -> usize {
        self.line_of_pc.len()
    }

    pub fn line(&self, pc: usize) -> Option<u32> {
        self.line_of_pc.get(pc).copied().flatten()
    }

    /// True when `pc` opens a statement: its line differs from the previous
    /// instruction's, or a jump can land on it with the same line (we treat every first
    /// instruction of a run of one line as the statement start).
    pub fn is_statement_start(&self, pc: usize) -> bool {
        match self.line(pc) {
            None => false,
            Some(line) => pc == 0 || self.line(pc - 1) != Some(line),
        }
    }

    /// Where a line breakpoint on this pc's line stops: a statement start that is not a
    /// jump the compiler attributes to a line whose code began earlier (the jump out of an
    /// `if` block, or a `while`'s jump back to its test). Those would stop a second time
    /// on the same line in the same pass, after the line's code already ran.
    pub fn is_line_entry(&self, pc: usize) -> bool {
        if !self.is_statement_start(pc) {
            return false;
        }
        let is_jump = self
            .instruction_text
            .get(pc)
            .is_some_and(|text| text.trim_start().starts_with("jumpi "));
        let began_earlier = self.line_of_pc[..pc]
            .iter()
            .any(|line| *line == self.line_of_pc[pc]);
        !(is_jump && began_earlier)
    }

    /// Moves a requested breakpoint line to the nearest line with code: the first one at
    /// or after it, else the last one before it.
    pub fn resolve_line(&self, requested: u32) -> Option<u32> {
        self.lines_with_code
            .range(requested..)
            .next()
            .or_else(|| self.lines_with_code.range(..requested).next_back())
            .copied()
    }

    pub fn lines_with_code(&self) -> impl Iterator<Item = u32> + '_ {
        self.lines_with_code.iter().copied()
    }

    pub fn is_same_source(&self, path: &str) -> bool {
        let requested = PathBuf::from(path);
        if requested == self.path {
            return true;
        }
        match (requested.canonicalize(), self.path.canonicalize()) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        }
    }

    pub fn source_name(&self) -> String {
        self.path
            .file_name()
            .map(|name| name.to_string_lossy().into_owned())
            .unwrap_or_else(|| self.path.display().to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_move_to_the_nearest_line_with_code() {
        let info = DebugInfo::new(
            PathBuf::from("a.gbas"),
            Language::Gbasic,
            vec![Some(2), Some(2), Some(3), None, Some(6)],
            vec![String::new(); 5],
        );
        assert_eq!(info.resolve_line(1), Some(2));
        assert_eq!(info.resolve_line(4), Some(6));
        assert_eq!(info.resolve_line(9), Some(6));
        assert!(info.is_statement_start(0));
        assert!(!info.is_statement_start(1));
        assert!(info.is_statement_start(2));
        assert!(!info.is_statement_start(3));
    }

    #[test]
    fn a_jump_back_into_an_earlier_line_is_not_its_entry() {
        // `while i < 3` (line 2) / `i = i + 1` (line 3) / `wend`: the jump back to the
        // test is attributed to line 2, after line 3's code.
        let text = [
            "loadi 3,r1",
            "cmplt r0,r1,r2",
            "cbr r2,1,2",
            "add r0,r3,r0",
            "jumpi 0",
            "jumpi 7",
        ];
        let info = DebugInfo::new(
            PathBuf::from("a.gbas"),
            Language::Gbasic,
            vec![Some(2), Some(2), Some(2), Some(3), Some(2), Some(5)],
            text.iter().map(|text| text.to_string()).collect(),
        );
        assert!(info.is_line_entry(0));
        assert!(info.is_line_entry(3));
        // A statement start, but line 2 began at pc 0.
        assert!(info.is_statement_start(4));
        assert!(!info.is_line_entry(4));
        // A `goto` on its own line is that line's entry.
        assert!(info.is_line_entry(5));
    }
}
