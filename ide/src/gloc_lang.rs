//! GLOC: analysis, completion, hover text, signatures and formatting, all
//! read off `gloc_engine::gloc` (parser, checker, instruction table).

use std::collections::BTreeMap;

use gloc_compiler::loader::{load_script_written_for, Language, LoadOptions};
use gloc_compiler::Optimization;
use gloc_engine::gloc::ast::{
    DirectiveKind, File, Line, LineKind, Opcode, OperandKind, OperandShape, Origin,
};
use gloc_engine::gloc::{self, Bound};
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::{Diagnostic, Occurrences, Span};

use crate::analysis::{
    Analysis, Completion, CompletionKind, Context, CycleStart, Hint, Insert, Signature, Symbol,
    SymbolKind, Token, TokenKind,
};
use crate::lang;

pub fn analyze(text: &str, context: &Context) -> Analysis {
    let parsed = gloc::parse(text);
    // The shared loader gives exactly what `gloc check` reports (the checker's
    // diagnostics plus the cycle-budget warning) and the checked program.
    let loaded = load_script_written_for(
        text,
        Language::Gloc,
        &context.sensors,
        &LoadOptions {
            optimization: Optimization::Plain,
            cycle_budget: context.cycle_budget,
        },
        written_for(text, context),
    );
    let file = &parsed.file;
    let mut analysis = Analysis {
        diagnostics: loaded.diagnostics,
        ..Analysis::default()
    };
    let statements = loaded.stats.as_ref().map_or(0, |stats| stats.statements);
    add_yield_fixes(text, file, statements, &mut analysis.diagnostics);
    collect_tokens(text, file, context, &mut analysis);
    collect_labels(file, &mut analysis);
    let worst_case = loaded
        .stats
        .as_ref()
        .and_then(|stats| stats.worst_case.as_ref());
    if let (Some(worst_case), Some(program)) = (worst_case, &loaded.program) {
        if let Some(first) = file
            .statements()
            .find(|line| matches!(line.kind, LineKind::Instruction(_)))
        {
            analysis.hints.push(cycle_hint(
                first.span.end as usize,
                "first cycle",
                worst_case.from_start,
                context,
            ));
            analysis.cycles.push(CycleStart {
                offset: first.span.end as usize,
                worst: worst_case.from_start,
            });
        }
        for (pc, bound) in &worst_case.from_yields {
            let span = program.span(*pc);
            analysis.cycles.push(CycleStart {
                offset: span.end as usize,
                worst: *bound,
            });
            analysis
                .hints
                .push(cycle_hint(span.end as usize, "next cycle", *bound, context));
        }
    }
    analysis
}

/// The list a `# sensors: CRC` line names when it is a third list (neither the
/// active nor the embedded one): `<crc>.cac` in the context's folders. Read only
/// for such a line, so typing costs nothing otherwise.
fn written_for(text: &str, context: &Context) -> Option<std::sync::Arc<SensorList>> {
    gloc::identity::find_written_for(text, &context.sensors, &context.list_folders)
}

fn cycle_hint(offset: usize, which: &str, bound: Bound, context: &Context) -> Hint {
    let label = match bound {
        Bound::Finite(count) => format!("{which} ≤ {count} instr"),
        Bound::Unbounded => format!("{which}: unbounded"),
    };
    let budget = match (context.cycle_budget, context.cycle_budget_from.as_deref()) {
        (None, _) => format!(
            "(the budget is {} by default)",
            gloc_engine::vm::DEFAULT_CYCLE_BUDGET
        ),
        (Some(budget), Some("the default")) => format!("(the budget is {budget} by default)"),
        (Some(budget), Some(from)) => format!("(the budget is {budget}, from {from})"),
        (Some(budget), None) => format!("(the budget is {budget}, from the project settings)"),
    };
    Hint {
        offset,
        label,
        tooltip: Some(format!(
            "Worst-case number of instructions executed in the control cycle that starts here, the ending `yield` included {budget}."
        )),
        padding_left: true,
    }
}

/// "Insert `yield` in this loop" for the loops the checker flags.
fn add_yield_fixes(text: &str, file: &File, statements: u32, diagnostics: &mut [Diagnostic]) {
    let ninstr = file.directive(DirectiveKind::Ninstr);
    for diagnostic in diagnostics.iter_mut() {
        if diagnostic.code != gloc_engine::codes::gloc::LOOP_MAY_OVERRUN
            && diagnostic.code != gloc_engine::codes::gloc::LOOP_WITHOUT_YIELD
        {
            continue;
        }
        // Before the jump back when the checker names it, else before the loop's first line.
        let anchor = diagnostic
            .labels
            .first()
            .map_or(diagnostic.span, |label| label.span);
        let line_start = text[..anchor.start as usize]
            .rfind('\n')
            .map_or(0, |at| at + 1);
        let indent: String = text[line_start..]
            .chars()
            .take_while(|character| *character == ' ' || *character == '\t')
            .collect();
        diagnostic.fixes.push(gloc_engine::diagnostic::Fix {
            title: "insert `yield` in this loop".to_string(),
            span: Span::new(line_start, line_start),
            replacement: format!("{indent}yield\n"),
        });
        // Keep the header true: one more statement.
        if let Some(ninstr) = ninstr.filter(|directive| directive.value == u64::from(statements)) {
            diagnostic.fixes.push(gloc_engine::diagnostic::Fix {
                title: "update `ninstr`".to_string(),
                span: ninstr.value_span,
                replacement: (ninstr.value + 1).to_string(),
            });
        }
    }
}

fn collect_tokens(text: &str, file: &File, context: &Context, analysis: &mut Analysis) {
    for line in &file.lines {
        match &line.kind {
            LineKind::Blank | LineKind::Invalid { .. } => {}
            LineKind::Directive(directive) => {
                push(analysis, directive.keyword_span, TokenKind::Directive, None);
                push(analysis, directive.value_span, TokenKind::Number, None);
            }
            LineKind::Label(label) => {
                let keyword_start = line.span.start as usize
                    + (text[line.span.range()].len() - text[line.span.range()].trim_start().len());
                push(
                    analysis,
                    Span::new(keyword_start, keyword_start + 5),
                    TokenKind::Keyword,
                    None,
                );
                push(analysis, label.number_span, TokenKind::Label, None);
            }
            LineKind::Instruction(instruction) => {
                push(analysis, instruction.opcode_span, TokenKind::Keyword, None);
                let shapes = instruction.opcode.signature();
                for (operand, shape) in instruction.operands.iter().zip(shapes) {
                    let (kind, sensor) = match (&operand.kind, shape) {
                        (OperandKind::Register(_), _) => (TokenKind::Register, None),
                        (OperandKind::Integer(index), OperandShape::Sensor) => {
                            let id = u32::try_from(*index).ok().map(SensorId);
                            let known = id.filter(|id| context.sensors.get(*id).is_some());
                            if let Some(id) = known {
                                let name = context.sensors.name(id).unwrap_or_default();
                                analysis.hints.push(Hint {
                                    offset: operand.span.end as usize,
                                    label: format!(":{name}"),
                                    tooltip: None,
                                    padding_left: false,
                                });
                            }
                            let kind = if instruction.opcode == Opcode::Stores {
                                TokenKind::SensorWrite
                            } else {
                                TokenKind::SensorRead
                            };
                            (kind, known)
                        }
                        (OperandKind::Name(name), OperandShape::Sensor) => {
                            let kind = if instruction.opcode == Opcode::Stores {
                                TokenKind::SensorWrite
                            } else {
                                TokenKind::SensorRead
                            };
                            (kind, context.sensors.lookup(name))
                        }
                        (OperandKind::Integer(_), OperandShape::Label) => (TokenKind::Label, None),
                        (OperandKind::Text(_), _) => (TokenKind::String, None),
                        _ => (TokenKind::Number, None),
                    };
                    push(analysis, operand.span, kind, sensor);
                }
            }
        }
        if let Some(comment) = &line.comment {
            let line_text = &text[line.span.range()];
            if let Some(at) = line_text.rfind(comment.trim_end()) {
                let start = line.span.start as usize + at;
                push(
                    analysis,
                    Span::new(start, start + comment.trim_end().len()),
                    TokenKind::Comment,
                    None,
                );
            }
        }
    }
}

fn push(analysis: &mut Analysis, span: Span, kind: TokenKind, sensor: Option<SensorId>) {
    if !span.is_empty() {
        analysis.tokens.push(Token { span, kind, sensor });
    }
}

/// Labels: each number's definition, the jumps to it, and its section.
fn collect_labels(file: &File, analysis: &mut Analysis) {
    let mut labels: BTreeMap<u32, Symbol> = BTreeMap::new();
    let label_lines: Vec<&Line> = file
        .lines
        .iter()
        .filter(|line| matches!(line.kind, LineKind::Label(_)))
        .collect();
    for (index, line) in label_lines.iter().enumerate() {
        let LineKind::Label(label) = &line.kind else {
            continue;
        };
        // The section runs to the last statement before the next label.
        let section_end = file
            .lines
            .iter()
            .filter(|other| other.span.start > line.span.start)
            .take_while(|other| {
                label_lines
                    .get(index + 1)
                    .is_none_or(|next| other.span.start < next.span.start)
            })
            .filter(|other| other.kind.is_statement())
            .last()
            .map_or(line.span.end, |last| last.span.end);
        let section = Span::new(line.span.start as usize, section_end as usize);
        analysis.folds.push(section);
        let symbol = labels
            .entry(label.number)
            .or_insert_with(|| new_label(label.number));
        if symbol.occurrences.definition.is_none() {
            symbol.occurrences.definition = Some(label.number_span);
            symbol.extent = section;
        } else {
            // A duplicate definition (the checker reports it) still renames along.
            symbol.occurrences.references.push(label.number_span);
        }
    }
    for line in &file.lines {
        let LineKind::Instruction(instruction) = &line.kind else {
            continue;
        };
        for (operand, shape) in instruction
            .operands
            .iter()
            .zip(instruction.opcode.signature())
        {
            if let (OperandKind::Integer(number), OperandShape::Label) = (&operand.kind, shape) {
                if let Ok(number) = u32::try_from(*number) {
                    labels
                        .entry(number)
                        .or_insert_with(|| new_label(number))
                        .occurrences
                        .references
                        .push(operand.span);
                }
            }
        }
    }
    analysis.symbols.extend(labels.into_values());
    analysis.tokens.sort_by_key(|token| token.span.start);
}

fn new_label(number: u32) -> Symbol {
    Symbol {
        name: number.to_string(),
        kind: SymbolKind::Label,
        occurrences: Occurrences::default(),
        extent: Span::default(),
        detail: format!("label {number}"),
        renamable: true,
    }
}

/// Renaming a GLOC label renumbers it: the new name must be a free label number
/// below the `nblbs` header's count.
pub fn check_new_name(
    symbol: &Symbol,
    new_name: &str,
    analysis: &Analysis,
    text: &str,
) -> Result<(), String> {
    let Ok(number) = new_name.parse::<u32>() else {
        return Err(format!(
            "GLOC labels are numbers; `{new_name}` is not a label number"
        ));
    };
    if symbol.name == number.to_string() {
        return Ok(());
    }
    if let Some(count) = gloc::parse(text)
        .file
        .directive(DirectiveKind::Nblbs)
        .map(|directive| directive.value)
    {
        if u64::from(number) >= count {
            return Err(format!(
                "label {number} is out of range: `nblbs {count}` allows labels 0 to {}; raise nblbs first",
                count.saturating_sub(1)
            ));
        }
    }
    let taken = analysis.symbols.iter().any(|other| {
        other.kind == SymbolKind::Label
            && other.name == number.to_string()
            && other.occurrences.definition.is_some()
    });
    if taken {
        return Err(format!("label {number} already exists"));
    }
    Ok(())
}

pub fn completions(
    text: &str,
    offset: usize,
    analysis: &Analysis,
    context: &Context,
) -> Vec<Completion> {
    let line_start = text[..offset.min(text.len())]
        .rfind('\n')
        .map_or(0, |at| at + 1);
    let Some(before) = text.get(line_start..offset) else {
        return Vec::new();
    };
    if before.contains('#') {
        return Vec::new();
    }
    let trimmed = before.trim_start();
    let Some((word, operands)) = trimmed.split_once(char::is_whitespace) else {
        return first_word_completions();
    };
    let word = word.to_ascii_lowercase();
    if word == "label" {
        return Vec::new();
    }
    let Some(opcode) = Opcode::from_name(&word) else {
        return Vec::new();
    };
    let operand_index = operands.matches(',').count();
    let Some(shape) = opcode.signature().get(operand_index) else {
        return Vec::new();
    };
    match shape {
        OperandShape::Register | OperandShape::Address => register_completions(text),
        OperandShape::Sensor => gloc_sensor_completions(&context.sensors, opcode == Opcode::Stores),
        OperandShape::Label => analysis
            .symbols
            .iter()
            .filter(|symbol| {
                symbol.kind == SymbolKind::Label && symbol.occurrences.definition.is_some()
            })
            .map(|symbol| Completion {
                label: symbol.name.clone(),
                kind: CompletionKind::Label,
                detail: Some(format!(
                    "label {} ({} jumps)",
                    symbol.name,
                    symbol.occurrences.references.len()
                )),
                documentation: None,
                insert: None,
                filter_text: None,
                sort_text: None,
            })
            .collect(),
        OperandShape::Integer | OperandShape::Number | OperandShape::Text => Vec::new(),
    }
}

fn first_word_completions() -> Vec<Completion> {
    let mut items: Vec<Completion> = Opcode::ALL
        .iter()
        .map(|opcode| Completion {
            label: opcode.name().to_string(),
            kind: CompletionKind::Instruction,
            detail: Some(opcode.usage()),
            documentation: Some(instruction_markdown(*opcode)),
            insert: Some(Insert::Snippet(snippet(*opcode))),
            filter_text: None,
            sort_text: None,
        })
        .collect();
    items.push(keyword(
        "label",
        "label ${1:0}",
        "`label N`: a jump target (labels are numbers).",
    ));
    for (name, documentation) in DIRECTIVES {
        items.push(keyword(name, &format!("{name} ${{1:0}}"), documentation));
    }
    items
}

fn keyword(label: &str, snippet: &str, documentation: &str) -> Completion {
    Completion {
        label: label.to_string(),
        kind: CompletionKind::Keyword,
        detail: None,
        documentation: Some(documentation.to_string()),
        insert: Some(Insert::Snippet(snippet.to_string())),
        filter_text: None,
        sort_text: None,
    }
}

/// `cbr ${1:r0},${2:0},${3:0}`: a snippet with one placeholder per operand.
fn snippet(opcode: Opcode) -> String {
    let operands: Vec<String> = opcode
        .signature()
        .iter()
        .enumerate()
        .map(|(index, shape)| {
            let placeholder = match shape {
                OperandShape::Register | OperandShape::Address => "r0",
                OperandShape::Sensor | OperandShape::Label | OperandShape::Integer => "0",
                OperandShape::Number => "0.0",
                OperandShape::Text => "\\\"text\\\"",
            };
            format!("${{{}:{placeholder}}}", index + 1)
        })
        .collect();
    if operands.is_empty() {
        opcode.name().to_string()
    } else {
        format!("{} {}", opcode.name(), operands.join(","))
    }
}

const DIRECTIVES: [(&str, &str); 5] = [
    (
        "nregs",
        "`nregs N`: the script uses registers `r0` to `r(N-1)`.",
    ),
    (
        "nblbs",
        "`nblbs N`: the script uses labels `0` to `N-1` (the paper's spelling).",
    ),
    ("nlbls", "`nlbls N`: same as `nblbs`."),
    (
        "ninstr",
        "`ninstr N`: the number of lines after the header, labels included.",
    ),
    (
        "nmem",
        "`nmem N`: cells of array memory for `loadm`/`storem` (default 0).",
    ),
];

fn register_completions(text: &str) -> Vec<Completion> {
    let parsed = gloc::parse(text);
    let count = parsed
        .file
        .directive(DirectiveKind::Nregs)
        .map_or(8, |directive| directive.value.min(256));
    (0..count)
        .map(|register| Completion {
            label: format!("r{register}"),
            kind: CompletionKind::Register,
            detail: Some("register".to_string()),
            documentation: None,
            insert: None,
            filter_text: None,
            sort_text: Some(format!("{register:05}")),
        })
        .collect()
}

/// Sensors by name, inserting the name (GLOC takes a sensor's name or its
/// index; the name reads better and holds on any list). The label is the name,
/// what the user types; the filter text adds the index, so typing `444` finds
/// `m_depth` too; the detail names the index.
fn gloc_sensor_completions(list: &SensorList, store: bool) -> Vec<Completion> {
    lang::sensor_completions(list, store)
        .into_iter()
        .filter_map(|mut item| {
            let id = list.lookup(&item.label)?;
            item.filter_text = Some(format!("{} {}", item.label, id.0));
            Some(item)
        })
        .collect()
}

pub fn word_markdown(word: &str, kind: TokenKind) -> Option<String> {
    let lower = word.to_ascii_lowercase();
    match kind {
        TokenKind::Keyword if lower == "label" => Some(
            "`label N`: a jump target. Labels are numbers; `jumpi`, `cbr` and `jump` go to them."
                .to_string(),
        ),
        TokenKind::Keyword => Opcode::from_name(&lower).map(instruction_markdown),
        TokenKind::Directive => DIRECTIVES
            .iter()
            .find(|(name, _)| *name == lower)
            .map(|(_, documentation)| documentation.to_string()),
        TokenKind::Register => Some(format!(
            "register `{lower}`: holds an integer or a float; starts as integer 0."
        )),
        _ => None,
    }
}

fn instruction_markdown(opcode: Opcode) -> String {
    let origin = match opcode.origin() {
        Origin::Paper => "from the paper (Woithe & Kremer, Fig. 2)",
        Origin::Ours => "a gloc extension",
    };
    let operands: Vec<&str> = opcode
        .signature()
        .iter()
        .map(|shape| shape.describe())
        .collect();
    let mut text = format!(
        "```gloc\n{}\n```\n{}\n\n",
        opcode.usage(),
        opcode.semantics()
    );
    if !operands.is_empty() {
        text.push_str(&format!("Operands: {}.\n\n", operands.join("; ")));
    }
    text.push_str(&format!("*{origin}*"));
    text
}

/// The operand shape of the instruction under the cursor.
pub fn signature(text: &str, offset: usize) -> Option<Signature> {
    let line_start = text[..offset.min(text.len())]
        .rfind('\n')
        .map_or(0, |at| at + 1);
    let before = text.get(line_start..offset)?;
    if before.contains('#') {
        return None;
    }
    let (word, operands) = before.trim_start().split_once(char::is_whitespace)?;
    let opcode = Opcode::from_name(&word.to_ascii_lowercase())?;
    let shapes = opcode.signature();
    if shapes.is_empty() {
        return None;
    }
    let usage = opcode.usage();
    let mut parameters = Vec::new();
    let mut position = opcode.name().len() + 1;
    for piece in usage[position..].split(',') {
        parameters.push((position, position + piece.len()));
        position += piece.len() + 1;
    }
    let active_parameter = operands.matches(',').count().min(shapes.len() - 1);
    Some(Signature {
        label: usage,
        documentation: opcode.semantics().to_string(),
        parameters,
        active_parameter,
    })
}

/// Canonical GLOC (the engine's printer); unparseable lines are kept verbatim.
pub fn format(text: &str) -> Option<String> {
    Some(gloc::print(&gloc::parse(text).file))
}
