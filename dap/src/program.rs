//! Static debug information about the loaded script: which source line each GLOC
//! instruction comes from, where statements start, and the GLOC text for disassembly.

use std::collections::{BTreeSet, HashMap};
use std::path::PathBuf;
use std::sync::Arc;

use gloc_compiler::expression::ExpressionScope;
use gloc_compiler::LoadedScript;
use gloc_engine::program::{Flow, Program};

/// The source language the user debugs: the compiler's one `Language`.
pub use gloc_compiler::Language;

/// The source line of each pc (`None`: generated code with no line of its own), shared
/// by the debug info and the world: every line the user sees (stops, printed lines, trap
/// texts and summaries) comes from it.
#[derive(Clone, Debug, Default)]
pub struct SourceLines(Arc<[Option<u32>]>);

impl SourceLines {
    pub fn new(lines: Vec<Option<u32>>) -> SourceLines {
        SourceLines(lines.into())
    }

    /// The loaded script's own map (`LoadedScript::line_of_pc`), except that the
    /// implicit final `halt` of a GLOC script (reached by falling off its end) has no
    /// line, and neither has a GLOC line 0.
    pub fn of(loaded: &LoadedScript) -> SourceLines {
        let mut lines = loaded.lines_of_pcs();
        if loaded.gbasic.is_none() {
            for line in &mut lines {
                *line = line.filter(|line| *line > 0);
            }
            if lines.len() > 1 {
                if let Some(last) = lines.last_mut() {
                    *last = None;
                }
            }
        }
        SourceLines::new(lines)
    }

    pub fn line(&self, pc: usize) -> Option<u32> {
        self.0.get(pc).copied().flatten()
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    pub fn iter(&self) -> impl Iterator<Item = Option<u32>> + '_ {
        self.0.iter().copied()
    }
}

#[derive(Clone, Debug)]
pub struct DebugInfo {
    pub path: PathBuf,
    pub language: Language,
    /// The source line of each instruction.
    pub lines: SourceLines,
    /// The GLOC text of each instruction, for `disassemble`.
    pub instruction_text: Vec<String>,
    lines_with_code: BTreeSet<u32>,
    /// `is_line_entry` of each pc, computed once (it is asked after every step).
    line_entry: Vec<bool>,
    /// Control flow of each instruction and the pcs of the labels (for `jump rN`); empty
    /// when unknown, and then nothing is run fused.
    flow: Vec<Flow>,
    label_pcs: Vec<usize>,
    /// Lines of the source as an editor shows them (the empty line after a final
    /// newline included), when known: a breakpoint past them is refused.
    pub source_lines: Option<u32>,
    /// The names the debugger's expressions may use: the script's variables and
    /// constants and the sensor list (empty until [`DebugInfo::with_scope`]).
    pub scope: ExpressionScope,
}

impl DebugInfo {
    pub fn new(
        path: PathBuf,
        language: Language,
        lines: SourceLines,
        instruction_text: Vec<String>,
    ) -> DebugInfo {
        let lines_with_code = lines.iter().flatten().collect();
        let mut info = DebugInfo {
            path,
            language,
            lines,
            instruction_text,
            lines_with_code,
            line_entry: Vec::new(),
            flow: Vec::new(),
            label_pcs: Vec::new(),
            source_lines: None,
            scope: ExpressionScope::new(Arc::default()),
        };
        info.line_entry = info.line_entries();
        info
    }

    /// Adds the control flow of the checked program (the one `lines` describes): what
    /// the fast path and the line entries (which jumps go back) need.
    pub fn with_program(mut self, program: &Program) -> DebugInfo {
        if program.instrs.len() != self.lines.len() {
            return self;
        }
        self.flow = program.instrs.iter().map(|instr| instr.flow()).collect();
        self.label_pcs = program
            .label_pcs
            .iter()
            .flatten()
            .map(|pc| pc.index())
            .collect();
        self.line_entry = self.line_entries();
        self
    }

    /// Sets the names the debugger's expressions may use.
    pub fn with_scope(mut self, scope: ExpressionScope) -> DebugInfo {
        self.scope = scope;
        self
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
        self.lines.len()
    }

    pub fn line(&self, pc: usize) -> Option<u32> {
        self.lines.line(pc)
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
        (0..self.lines.len())
            .map(|pc| {
                let Some(line) = self.line(pc) else {
                    return false;
                };
                let first = *first_pc.entry(line).or_insert(pc);
                if !self.is_statement_start(pc) {
                    return false;
                }
                let is_jump = matches!(self.flow.get(pc), Some(Flow::Jump(_)));
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

    /// Where a `goto` to `line` lands: the pcs that enter the line (`is_line_entry`), in
    /// order, after moving it to the nearest line with code as a breakpoint moves (a
    /// `label:` line has no code of its own: its label's code is on the next line).
    /// Empty when the script has no code.
    pub fn goto_targets(&self, line: u32) -> (Option<u32>, Vec<usize>) {
        let Some(line) = self.resolve_line(line) else {
            return (None, Vec::new());
        };
        let pcs = (0..self.instruction_count())
            .filter(|pc| self.line(*pc) == Some(line) && self.is_line_entry(*pc))
            .collect();
        (Some(line), pcs)
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

    /// `text` loaded against the embedded sensor list with the default options.
    fn embedded_load(text: &str, language: gloc_compiler::Language) -> gloc_compiler::LoadedScript {
        gloc_compiler::load_script(
            text,
            language,
            &gloc_engine::sensors::SensorList::embedded(),
            &gloc_compiler::LoadOptions::default(),
        )
    }

    #[test]
    fn lines_move_to_the_nearest_line_with_code() {
        let info = DebugInfo::new(
            PathBuf::from("a.gbas"),
            Language::Gbasic,
            SourceLines::new(vec![Some(2), Some(2), Some(3), None, Some(6)]),
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
        use gloc_compiler::Language as ScriptLanguage;
        // The jump back from `wend` to the test is attributed to the `while` line (3),
        // after line 4's code: it opens a statement but is not line 3's entry.
        let text =
            "dim i as integer\nlabel: top\nwhile i < 3\n  i = i + 1\nwend\nyield\ngoto top\n";
        let loaded = embedded_load(text, ScriptLanguage::Gbasic);
        let program = loaded
            .program
            .clone()
            .unwrap_or_else(|| panic!("{:?}", loaded.diagnostics));
        let count = program.instrs.len();
        let info = DebugInfo::new(
            PathBuf::from("a.gbas"),
            Language::Gbasic,
            SourceLines::of(&loaded),
            vec![String::new(); count],
        )
        .with_program(&program);
        let info = &info;
        let on_line = |line: u32| (0..count).filter(move |pc| info.line(*pc) == Some(line));
        let entries = |line: u32| on_line(line).filter(|pc| info.is_line_entry(*pc)).count();
        assert_eq!(entries(3), 1);
        assert_eq!(entries(4), 1);
        assert_eq!(entries(6), 1);
        assert_eq!(entries(7), 1);
        let first_of_4 = on_line(4).next().unwrap_or(0);
        let jump_back: Vec<usize> = on_line(3)
            .filter(|pc| *pc > first_of_4 && info.is_statement_start(*pc))
            .collect();
        assert_eq!(jump_back.len(), 1, "{:?}", info.lines);
        assert!(matches!(program.instrs[jump_back[0]].flow(), Flow::Jump(_)));
        assert!(!info.is_line_entry(jump_back[0]));
        // A jump to the `while` line enters it at its test, never at the jump back; a
        // jump to `label: top` (no code of its own) goes to the `while`.
        let (line, targets) = info.goto_targets(3);
        assert_eq!(line, Some(3));
        assert_eq!(targets.len(), 1);
        assert!(targets[0] < first_of_4 && !targets.contains(&jump_back[0]));
        assert_eq!(info.goto_targets(2), (Some(3), targets.clone()));
    }

    #[test]
    fn source_lines_are_the_loaders_line_of_pc_for_both_languages() {
        use gloc_compiler::Language as ScriptLanguage;
        use gloc_engine::program::Pc;
        let examples = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/");
        for (name, language) in [
            ("thermocline.gbas", ScriptLanguage::Gbasic),
            ("fig3.gbas", ScriptLanguage::Gbasic),
            ("fig2.gloc", ScriptLanguage::Gloc),
        ] {
            let text = std::fs::read_to_string(format!("{examples}{name}")).expect("example");
            let loaded = embedded_load(&text, language);
            let count = loaded.program.as_ref().expect("checks").instrs.len();
            let lines = SourceLines::of(&loaded);
            assert_eq!(lines.len(), count, "{name}");
            // Pc by pc through `line_of_pc` (`origin_of_pc` for GBASIC); a GLOC
            // script's final implicit `halt` has no line of its own.
            for pc in 0..count {
                let expected = match language {
                    ScriptLanguage::Gloc if pc + 1 == count => None,
                    _ => loaded.line_of_pc(Pc(pc as u32)).filter(|line| *line > 0),
                };
                assert_eq!(lines.line(pc), expected, "{name} pc {pc}");
            }
        }
    }

    #[test]
    fn steps_to_a_stop_follow_jumps_branches_and_indirect_jumps_within_a_share() {
        use gloc_compiler::Language as ScriptLanguage;
        let text = "nregs 2\nnblbs 3\nninstr 9\nlabel 0\nloadi 2,r0\njump r0\nlabel 1\n\
                    loadi 1,r1\nyield\nlabel 2\nloadi 3,r1\njumpi 1\n";
        let loaded = embedded_load(text, ScriptLanguage::Gloc);
        let program = loaded
            .program
            .unwrap_or_else(|| panic!("{:?}", loaded.diagnostics));
        // pcs: 0 loadi, 1 jump r0 (any label: pcs 0, 2, 4), 2 loadi, 3 yield, 4 loadi,
        // 5 jumpi 1 (pc 2), 6 the final halt.
        assert_eq!(program.instrs.len(), 7);
        let info = DebugInfo::new(
            PathBuf::from("a.gloc"),
            Language::Gloc,
            SourceLines::new(vec![Some(1); 7]),
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
