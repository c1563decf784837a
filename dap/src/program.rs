//! Static debug information about the loaded script: which source line each GLOC
//! instruction comes from, where statements start, and the GLOC text for disassembly.

use std::collections::{BTreeSet, HashMap};
use std::path::PathBuf;

use gloc_engine::program::{Flow, Program};

/// The source language the user debugs: the compiler's one `Language`.
pub use gloc_compiler::Language;

#[derive(Clone, Debug)]
pub struct DebugInfo {
    pub path: PathBuf,
    pub language: Language,
    /// 1-based source line of each instruction (`None`: generated code with no line).
    pub line_of_pc: Vec<Option<u32>>,
    /// The GLOC text of each instruction, for `disassemble`.
    pub instruction_text: Vec<String>,
    lines_with_code: BTreeSet<u32>,
    /// `is_line_entry` of each pc, computed once (it is asked after every step).
    line_entry: Vec<bool>,
    /// Control flow of each instruction and the pcs of the labels (for `jump rN`); empty
    /// when unknown, and then nothing is run fused.
    flow: Vec<Flow>,
    label_pcs: Vec<usize>,
    print_lines: PrintLines,
    /// Lines of the source as an editor shows them (the empty line after a final
    /// newline included), when known: a breakpoint past them is refused.
    pub source_lines: Option<u32>,
    /// The pc after each `print`/`prints` (where the script stands once it printed).
    print_successors: Vec<usize>,
}

/// The source line the debugger attaches to a printed line: the line of the instruction
/// after the `print` that printed it (where the script stands once it printed).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrintLines {
    /// The script never prints.
    Never,
    /// Every print site gives this line.
    One(Option<u32>),
    /// Print sites give different lines, or they are unknown.
    Several,
}

impl DebugInfo {
    pub fn new(
        path: PathBuf,
        language: Language,
        line_of_pc: Vec<Option<u32>>,
        instruction_text: Vec<String>,
    ) -> DebugInfo {
        let lines_with_code = line_of_pc.iter().flatten().copied().collect();
        let mut info = DebugInfo {
            path,
            language,
            line_of_pc,
            instruction_text,
            lines_with_code,
            line_entry: Vec::new(),
            flow: Vec::new(),
            label_pcs: Vec::new(),
            print_lines: PrintLines::Several,
            source_lines: None,
            print_successors: Vec::new(),
        };
        info.line_entry = info.line_entries();
        info
    }

    /// Adds what the fast path needs from the checked program: control flow and print
    /// sites (`program` is the one `line_of_pc` describes).
    pub fn with_program(mut self, program: &Program) -> DebugInfo {
        if program.instrs.len() != self.line_of_pc.len() {
            return self;
        }
        self.flow = program.instrs.iter().map(|instr| instr.flow()).collect();
        self.label_pcs = program
            .label_pcs
            .iter()
            .flatten()
            .map(|pc| pc.index())
            .collect();
        self.print_successors = program
            .instrs
            .iter()
            .enumerate()
            .filter(|(_, instr)| instr.prints())
            .map(|(pc, _)| pc + 1)
            .collect();
        let mut lines = self.print_successors.iter().map(|pc| self.line(*pc));
        self.print_lines = match lines.next() {
            None => PrintLines::Never,
            Some(first) if lines.all(|line| line == first) => PrintLines::One(first),
            Some(_) => PrintLines::Several,
        };
        self
    }

    pub fn print_lines(&self) -> PrintLines {
        self.print_lines
    }

    pub fn print_successors(&self) -> &[usize] {
        &self.print_successors
    }

    /// True when the control flow is known, so that `stop_reach` can be trusted.
    pub fn knows_flow(&self) -> bool {
        !self.flow.is_empty()
    }

    /// For each pc: the fewest instructions a run from it executes before it lands on
    /// one of `stops` (is about to execute it) within its share of the cycle, which ends
    /// at a `yield` or `halt`; `u64::MAX` when it cannot. A run of fewer instructions
    /// than that passes no stop.
    pub fn steps_to_stop(&self, stops: &[usize]) -> Vec<u64> {
        let count = self.flow.len();
        if stops.is_empty() {
            return vec![u64::MAX; count];
        }
        // Breadth first from the stops over the edges backwards: `distance[pc]` is 0 at a
        // stop, else the fewest instructions from pc to a stop.
        let mut predecessors: Vec<Vec<usize>> = vec![Vec::new(); count];
        let mut indirect = Vec::new();
        for (pc, flow) in self.flow.iter().enumerate() {
            let mut add = |to: usize| {
                if let Some(list) = predecessors.get_mut(to) {
                    list.push(pc);
                }
            };
            match *flow {
                Flow::Next => add(pc + 1),
                Flow::Jump(target) => add(target.index()),
                Flow::Branch(if_true, if_false) => {
                    add(if_true.index());
                    add(if_false.index());
                }
                // `jump rN` may go to any label.
                Flow::Indirect => indirect.push(pc),
                Flow::End => {}
            }
        }
        for &label in &self.label_pcs {
            if let Some(list) = predecessors.get_mut(label) {
                list.extend(&indirect);
            }
        }
        let mut distance = vec![u64::MAX; count];
        let mut queue = std::collections::VecDeque::new();
        for &pc in stops.iter().filter(|pc| **pc < count) {
            distance[pc] = 0;
            queue.push_back(pc);
        }
        while let Some(pc) = queue.pop_front() {
            for &before in &predecessors[pc] {
                if distance[before] == u64::MAX {
                    distance[before] = distance[pc] + 1;
                    queue.push_back(before);
                }
            }
        }
        // From a stop itself the run must first leave it: one instruction to a successor,
        // then that successor's distance.
        let after = |to: usize| distance.get(to).map_or(u64::MAX, |d| d.saturating_add(1));
        let to_labels = self
            .label_pcs
            .iter()
            .map(|&label| after(label))
            .min()
            .unwrap_or(u64::MAX);
        self.flow
            .iter()
            .enumerate()
            .map(|(pc, flow)| match *flow {
                Flow::Next => after(pc + 1),
                Flow::Jump(target) => after(target.index()),
                Flow::Branch(if_true, if_false) => {
                    after(if_true.index()).min(after(if_false.index()))
                }
                Flow::Indirect => to_labels,
                Flow::End => u64::MAX,
            })
            .collect()
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
        self.line_entry.get(pc).copied().unwrap_or(false)
    }

    /// Every pc's `is_line_entry`, in one pass: a line "began earlier" when its first pc
    /// is before this one.
    fn line_entries(&self) -> Vec<bool> {
        let mut first_pc: HashMap<u32, usize> = HashMap::new();
        (0..self.line_of_pc.len())
            .map(|pc| {
                let Some(line) = self.line(pc) else {
                    return false;
                };
                let first = *first_pc.entry(line).or_insert(pc);
                if !self.is_statement_start(pc) {
                    return false;
                }
                let is_jump = self
                    .instruction_text
                    .get(pc)
                    .is_some_and(|text| text.trim_start().starts_with("jumpi "));
                !(is_jump && first < pc)
            })
            .collect()
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

    #[test]
    fn steps_to_a_stop_follow_jumps_branches_and_indirect_jumps_within_a_share() {
        use gloc_compiler::{load_script, Language as ScriptLanguage, LoadOptions};
        use gloc_engine::sensors::SensorList;
        let text = "nregs 2\nnblbs 3\nninstr 9\nlabel 0\nloadi 2,r0\njump r0\nlabel 1\n\
                    loadi 1,r1\nyield\nlabel 2\nloadi 3,r1\njumpi 1\n";
        let loaded = load_script(
            text,
            ScriptLanguage::Gloc,
            &SensorList::embedded(),
            &LoadOptions::default(),
        );
        let program = loaded
            .program
            .unwrap_or_else(|| panic!("{:?}", loaded.diagnostics));
        // pcs: 0 loadi, 1 jump r0 (any label: pcs 0, 2, 4), 2 loadi, 3 yield, 4 loadi,
        // 5 jumpi 1 (pc 2), 6 the final halt.
        assert_eq!(program.instrs.len(), 7);
        let info = DebugInfo::new(
            PathBuf::from("a.gloc"),
            Language::Gloc,
            vec![Some(1); 7],
            vec![String::new(); 7],
        )
        .with_program(&program);
        // A stop at pc 2. By hand: from 1 the indirect jump can land on 2 in one
        // instruction; from 0 it takes two (0 → 1 → 2); from 2 and 3 the share ends at the
        // yield first; from 4 two (4 → 5 → 2); from 5 one; the halt never.
        let never = u64::MAX;
        assert_eq!(info.steps_to_stop(&[2]), [2, 1, never, never, 2, 1, never]);
        assert_eq!(info.steps_to_stop(&[]), [never; 7]);
    }
}
