//! GBASIC: analysis, completion, hover text, signatures and formatting, read
//! off `gloc-compiler` (its analysis API, lexer, keyword and built-in tables,
//! and the loader that also checks the compiled GLOC).

use gloc_compiler::builtins::{Builtin, BuiltinInfo, BUILTINS};
use gloc_compiler::lexer::{self, TokenKind as Lexed};
use gloc_compiler::loader::LoadOptions;
use gloc_compiler::typed::Ty;
use gloc_compiler::{Optimization, SymbolKind as CompilerKind};
use gloc_engine::diagnostic::Fix;
use gloc_engine::gloc::Bound;
use gloc_engine::sensors::SensorId;
use gloc_engine::{Diagnostic, Span};

use crate::analysis::{
    Analysis, Completion, CompletionKind, Context, CycleStart, Hint, Insert, Signature, Symbol,
    SymbolKind, Token, TokenKind,
};
use crate::lang;

/// Code of "`x` is not declared and is not a sensor" (gloc-compiler's `UNDECLARED`).
const UNDECLARED: &str = gloc_compiler::codes::UNDECLARED;

pub fn analyze(text: &str, context: &Context) -> Analysis {
    // One compile gives both the symbols and what `gloc check` reports (the
    // loader adds what the compiled GLOC would have: loops without `yield`, the
    // cycle budget, moved back onto GBASIC lines).
    let (compiler, loaded) = gloc_compiler::analysis::analyze_and_load(
        text,
        &context.sensors,
        &LoadOptions {
            optimization: Optimization::Plain,
            cycle_budget: context.cycle_budget,
        },
    );
    let mut analysis = Analysis {
        compiled: loaded.gloc_text.clone(),
        diagnostics: loaded.diagnostics,
        ..Analysis::default()
    };
    add_fixes(text, &compiler.blocks, &mut analysis.diagnostics);
    for info in &compiler.symbols {
        let kind = match info.kind {
            CompilerKind::Variable => SymbolKind::Variable,
            CompilerKind::Array => SymbolKind::Array,
            CompilerKind::Constant => SymbolKind::Constant,
            CompilerKind::Label => SymbolKind::Label,
            CompilerKind::Sensor => SymbolKind::Sensor,
        };
        let definition_line = info
            .occurrences
            .definition
            .map(|span| line_span(text, span));
        analysis.symbols.push(Symbol {
            name: info.name.clone(),
            kind,
            occurrences: info.occurrences.clone(),
            extent: definition_line.unwrap_or_default(),
            detail: info.detail.clone(),
            renamable: kind != SymbolKind::Sensor,
        });
    }
    label_sections(text, &mut analysis);
    for block in &compiler.blocks {
        analysis.folds.push(block.span);
    }
    collect_tokens(text, &compiler, context, &mut analysis);
    if let (Some(stats), Some(map)) = (
        &loaded.stats,
        loaded.gbasic.as_ref().map(|build| &build.source_map),
    ) {
        if let Some(worst_case) = &stats.worst_case {
            // pc → GBASIC span: the source map lists GLOC lines, labels included.
            let origins: Vec<Span> = map
                .lines
                .iter()
                .filter(|origin| !origin.is_label)
                .map(|origin| origin.span())
                .collect();
            if let Some(first) = origins.first() {
                let end = line_span(text, *first).end as usize;
                analysis
                    .hints
                    .push(cycle_hint(end, "first cycle", worst_case.from_start));
                analysis.cycles.push(CycleStart {
                    offset: end,
                    worst: worst_case.from_start,
                });
            }
            for (pc, bound) in &worst_case.from_yields {
                if let Some(span) = origins.get(pc.0 as usize) {
                    analysis.cycles.push(CycleStart {
                        offset: span.end as usize,
                        worst: *bound,
                    });
                    analysis
                        .hints
                        .push(cycle_hint(span.end as usize, "next cycle", *bound));
                }
            }
        }
    }
    analysis.hints.sort_by_key(|hint| hint.offset);
    analysis.hints.dedup_by_key(|hint| hint.offset);
    analysis
}

fn cycle_hint(offset: usize, which: &str, bound: Bound) -> Hint {
    let label = match bound {
        Bound::Finite(count) => format!("{which} ≤ {count} instr"),
        Bound::Unbounded => format!("{which}: unbounded"),
    };
    Hint {
        offset,
        label,
        tooltip: Some(
            "Worst-case number of GLOC instructions executed in the control cycle that starts here, the ending `yield` included."
                .to_string(),
        ),
        padding_left: true,
    }
}

/// The whole line (without its line end) holding `span`'s start.
fn line_span(text: &str, span: Span) -> Span {
    let at = (span.start as usize).min(text.len());
    let start = text[..at].rfind('\n').map_or(0, |index| index + 1);
    let end = text[at..].find('\n').map_or(text.len(), |index| at + index);
    let end = if text[..end].ends_with('\r') {
        end - 1
    } else {
        end
    };
    Span::new(start, end.max(start))
}

/// A label's section runs from its line to the line before the next label.
fn label_sections(text: &str, analysis: &mut Analysis) {
    let mut starts: Vec<(usize, usize)> = analysis
        .symbols
        .iter()
        .enumerate()
        .filter(|(_, symbol)| symbol.kind == SymbolKind::Label)
        .filter_map(|(index, symbol)| Some((symbol.occurrences.definition?.start as usize, index)))
        .collect();
    starts.sort();
    for (position, (start, index)) in starts.iter().enumerate() {
        let line_start = text[..*start].rfind('\n').map_or(0, |at| at + 1);
        let next = starts.get(position + 1).map_or(text.len(), |(next, _)| {
            text[..*next].rfind('\n').map_or(0, |at| at + 1)
        });
        let end = text[..next].trim_end().len().max(line_start);
        let section = Span::new(line_start, end);
        analysis.symbols[*index].extent = section;
        analysis.folds.push(section);
    }
}

/// "declare `x` with dim" for undeclared names; "insert `yield` in this loop"
/// for loops the GLOC checker flags on the compiled code.
fn add_fixes(text: &str, blocks: &[gloc_compiler::Block], diagnostics: &mut [Diagnostic]) {
    for diagnostic in diagnostics.iter_mut() {
        if diagnostic.code == UNDECLARED && diagnostic.fixes.is_empty() {
            let Some(name) = text
                .get(diagnostic.span.range())
                .filter(|name| is_identifier(name))
            else {
                continue;
            };
            let line_start = text[..diagnostic.span.start as usize]
                .rfind('\n')
                .map_or(0, |at| at + 1);
            let indent = indentation(&text[line_start..]);
            for ty in Ty::DECLARABLE.map(Ty::name) {
                diagnostic.fixes.push(Fix {
                    title: format!("declare `{name}` with `dim {name} as {ty}`"),
                    span: Span::new(line_start, line_start),
                    replacement: format!("{indent}dim {name} as {ty}\n"),
                });
            }
        }
        if (diagnostic.code == gloc_engine::codes::gloc::LOOP_MAY_OVERRUN
            || diagnostic.code == gloc_engine::codes::gloc::LOOP_WITHOUT_YIELD)
            && diagnostic.fixes.is_empty()
        {
            // A structured loop: before its closing line (`wend`, `loop`, `next`),
            // one level deeper. A `goto` loop: before the jump back.
            let innermost_loop = blocks
                .iter()
                .filter(|block| matches!(block.kind, "while" | "do" | "for"))
                .filter(|block| {
                    block.span.start <= diagnostic.span.start
                        && diagnostic.span.start <= block.span.end
                })
                .min_by_key(|block| block.span.len());
            let (line_start, indent) = match innermost_loop {
                Some(block) => {
                    let closing_end = (block.span.end as usize).min(text.len());
                    let line_start = text[..closing_end.saturating_sub(1)]
                        .rfind('\n')
                        .map_or(0, |at| at + 1);
                    let mut indent = indentation(&text[line_start..]);
                    indent.push_str(INDENT);
                    (line_start, indent)
                }
                None => {
                    let closing = diagnostic
                        .labels
                        .first()
                        .map_or(diagnostic.span, |label| label.span);
                    if closing.is_empty() && closing.start == 0 {
                        continue;
                    }
                    let line_start = text[..closing.start as usize]
                        .rfind('\n')
                        .map_or(0, |at| at + 1);
                    (line_start, indentation(&text[line_start..]))
                }
            };
            diagnostic.fixes.push(Fix {
                title: "insert `yield` in this loop".to_string(),
                span: Span::new(line_start, line_start),
                replacement: format!("{indent}yield\n"),
            });
        }
    }
}

fn indentation(line: &str) -> String {
    line.chars()
        .take_while(|character| *character == ' ' || *character == '\t')
        .collect()
}

fn is_identifier(word: &str) -> bool {
    let mut characters = word.chars();
    characters
        .next()
        .is_some_and(|first| first.is_ascii_alphabetic() || first == '_')
        && characters.all(|character| character.is_ascii_alphanumeric() || character == '_')
}

fn is_keyword(word: &str) -> bool {
    gloc_compiler::analysis::keywords().contains(&word.to_ascii_lowercase().as_str())
}

fn builtin(word: &str) -> Option<&'static BuiltinInfo> {
    BuiltinInfo::of_name(&word.to_ascii_lowercase())
}

fn collect_tokens(
    text: &str,
    compiler: &gloc_compiler::Analysis,
    context: &Context,
    analysis: &mut Analysis,
) {
    // Classify names by the compiler's symbol table (by span).
    let mut by_span: std::collections::HashMap<u32, (TokenKind, Option<SensorId>)> =
        std::collections::HashMap::new();
    for info in &compiler.symbols {
        for span in info.occurrences.iter() {
            let entry = match (info.kind, &info.sensor) {
                (_, Some(sensor)) => {
                    let kind = if sensor.writes.contains(&span) {
                        TokenKind::SensorWrite
                    } else {
                        TokenKind::SensorRead
                    };
                    (kind, Some(SensorId(sensor.index)))
                }
                (CompilerKind::Variable | CompilerKind::Array, None) => (TokenKind::Variable, None),
                (CompilerKind::Constant, None) => (TokenKind::Constant, None),
                (CompilerKind::Label, None) => (TokenKind::Label, None),
                (CompilerKind::Sensor, None) => (TokenKind::SensorRead, None),
            };
            by_span.insert(span.start, entry);
        }
    }
    let tokens = lexer::lex(text);
    for token in &tokens {
        if token.kind == Lexed::Comment {
            push(analysis, token.span, TokenKind::Comment, None);
            continue;
        }
        let word = &text[token.span.range()];
        let kind = match &token.kind {
            Lexed::Ident => match by_span.get(&token.span.start) {
                Some((kind, sensor)) => {
                    push(analysis, token.span, *kind, *sensor);
                    continue;
                }
                // `float` is a type keyword as well as a built-in.
                None if builtin(word).is_some_and(|info| info.builtin != Builtin::Float) => {
                    TokenKind::Function
                }
                None if is_keyword(word) => TokenKind::Keyword,
                None => match context.sensors.lookup(word) {
                    Some(id) => {
                        push(analysis, token.span, TokenKind::SensorRead, Some(id));
                        continue;
                    }
                    None => TokenKind::Variable,
                },
            },
            Lexed::Int | Lexed::Float => TokenKind::Number,
            Lexed::Str { .. } => TokenKind::String,
            Lexed::Unknown
            | Lexed::Eof
            | Lexed::Newline
            | Lexed::LParen
            | Lexed::RParen
            | Lexed::Comma
            | Lexed::Colon => continue,
            _ => TokenKind::Operator,
        };
        push(analysis, token.span, kind, None);
    }
    analysis.tokens.sort_by_key(|token| token.span.start);
}

fn push(analysis: &mut Analysis, span: Span, kind: TokenKind, sensor: Option<SensorId>) {
    if !span.is_empty() {
        analysis.tokens.push(Token { span, kind, sensor });
    }
}

/// GBASIC names are identifiers that are not keywords, built-ins, sensors or
/// another declared name (all case-insensitive).
pub fn check_new_name(
    symbol: &Symbol,
    new_name: &str,
    analysis: &Analysis,
    context: &Context,
) -> Result<(), String> {
    if !is_identifier(new_name) {
        return Err(format!(
            "`{new_name}` is not a valid name: use letters, digits and `_`, starting with a letter"
        ));
    }
    if is_keyword(new_name) || builtin(new_name).is_some() {
        return Err(format!("`{new_name}` is a GBASIC keyword"));
    }
    if context.sensors.lookup(new_name).is_some() {
        return Err(format!("`{new_name}` is a sensor name"));
    }
    if new_name.eq_ignore_ascii_case(&symbol.name) {
        return Ok(());
    }
    let same_namespace =
        |kind: SymbolKind| (kind == SymbolKind::Label) == (symbol.kind == SymbolKind::Label);
    if analysis
        .symbols
        .iter()
        .any(|other| same_namespace(other.kind) && other.name.eq_ignore_ascii_case(new_name))
    {
        return Err(format!("`{new_name}` is already declared"));
    }
    Ok(())
}

/// Where the cursor is, as completion sees it.
enum Position {
    /// After `goto`.
    Label,
    /// After `as` in a declaration.
    Type,
    /// The first word of a statement: an assignment target or a keyword.
    Statement,
    /// Inside an expression.
    Expression,
    /// Nothing to offer (a comment, a string, a declaration's name).
    Nothing,
}

fn position(text: &str, offset: usize) -> Position {
    let offset = offset.min(text.len());
    let line_start = text[..offset].rfind('\n').map_or(0, |at| at + 1);
    let Some(before) = text.get(line_start..offset) else {
        return Position::Nothing;
    };
    // In a comment or an unterminated string: nothing (the lexer knows a `'` or a
    // `""` inside a string).
    let tokens = lexer::lex(before);
    let in_comment_or_string = tokens.iter().any(|token| {
        matches!(
            token.kind,
            Lexed::Comment | Lexed::Str { terminated: false }
        )
    });
    if in_comment_or_string {
        return Position::Nothing;
    }
    // The words before the one being typed.
    let complete = before
        .trim_end_matches(|character: char| character.is_ascii_alphanumeric() || character == '_');
    let words: Vec<String> = complete
        .split(|character: char| !character.is_ascii_alphanumeric() && character != '_')
        .filter(|word| !word.is_empty())
        .map(str::to_ascii_lowercase)
        .collect();
    let last_symbol = complete.trim_end().chars().last();
    match words.last().map(String::as_str) {
        Some("goto") => Position::Label,
        Some("as") => Position::Type,
        Some("dim" | "const" | "label") => Position::Nothing,
        Some("then" | "else")
            if last_symbol.is_some_and(|character| character.is_ascii_alphanumeric()) =>
        {
            Position::Statement
        }
        None => Position::Statement,
        Some("let" | "for") if words.len() == 1 => Position::Statement,
        _ => Position::Expression,
    }
}

pub fn completions(
    text: &str,
    offset: usize,
    analysis: &Analysis,
    context: &Context,
) -> Vec<Completion> {
    let symbols = |wanted: &[SymbolKind]| -> Vec<Completion> {
        analysis
            .symbols
            .iter()
            .filter(|symbol| {
                wanted.contains(&symbol.kind) && symbol.occurrences.definition.is_some()
            })
            .map(|symbol| Completion {
                label: symbol.name.clone(),
                kind: match symbol.kind {
                    SymbolKind::Label => CompletionKind::Label,
                    SymbolKind::Constant => CompletionKind::Constant,
                    _ => CompletionKind::Variable,
                },
                detail: Some(symbol.detail.clone()),
                documentation: None,
                insert: None,
                filter_text: None,
                // Declared names before the long sensor list.
                sort_text: Some(format!("0{}", symbol.name.to_ascii_lowercase())),
            })
            .collect()
    };
    match position(text, offset) {
        Position::Nothing => Vec::new(),
        Position::Label => symbols(&[SymbolKind::Label]),
        Position::Type => Ty::DECLARABLE
            .iter()
            .map(|ty| keyword_item(ty.name()))
            .collect(),
        Position::Statement => {
            let mut items = symbols(&[SymbolKind::Variable, SymbolKind::Array]);
            items.extend(
                STATEMENT_KEYWORDS
                    .iter()
                    .map(|(keyword, _)| keyword_item(keyword)),
            );
            items.extend(lang::sensor_completions(&context.sensors, true));
            items
        }
        Position::Expression => {
            let mut items = symbols(&[
                SymbolKind::Variable,
                SymbolKind::Array,
                SymbolKind::Constant,
            ]);
            items.extend(BUILTINS.iter().map(|info| Completion {
                label: info.name.to_string(),
                kind: CompletionKind::Function,
                detail: Some(info.summary()),
                documentation: None,
                insert: Some(Insert::Snippet(format!("{}($1)", info.name))),
                filter_text: None,
                sort_text: Some(format!("1{}", info.name)),
            }));
            items.extend(
                ["and", "or", "not", "mod", "then", "to", "step"]
                    .iter()
                    .map(|keyword| keyword_item(keyword)),
            );
            items.extend(lang::sensor_completions(&context.sensors, false));
            items
        }
    }
}

fn keyword_item(keyword: &str) -> Completion {
    Completion {
        label: keyword.to_string(),
        kind: CompletionKind::Keyword,
        detail: None,
        documentation: keyword_doc(keyword).map(str::to_string),
        insert: None,
        filter_text: None,
        sort_text: Some(format!("2{keyword}")),
    }
}

/// The words that can start a statement, with one line of documentation each.
const STATEMENT_KEYWORDS: [(&str, &str); 17] = [
    ("dim", "`dim NAME as integer|float`, `dim NAME(SIZE) as …`: declares a variable or an array (indices 0 to SIZE−1); it starts at 0."),
    ("const", "`const NAME = literal`: a named constant."),
    ("let", "`[let] TARGET = EXPR`: assigns a variable, an array element or a writable sensor."),
    ("if", "`if COND then … [elseif COND then …] [else …] endif`, or one line: `if COND then STATEMENT`."),
    ("label", "`label: NAME`: a place `goto` can jump to."),
    ("goto", "`goto NAME`: continues at `label: NAME`."),
    ("while", "`while COND … wend`: repeats while COND is true (non-zero)."),
    ("do", "`do … loop`, `do while|until COND … loop`, `do … loop while|until COND`."),
    ("for", "`for V = A to B [step S] … next [V]`."),
    ("exit", "`exit for`, `exit do`, `exit while`: leaves the innermost such loop."),
    ("yield", "Ends the script's share of this 4-second control cycle; the script continues here next cycle."),
    ("end", "Stops the script for the rest of the mission (`end if` closes an `if`)."),
    ("print", "`print ITEM, ITEM, …`: one output line, items joined by one space."),
    ("rem", "`rem …`: a comment to the end of the line (so is `'`)."),
    ("next", "Closes a `for` loop."),
    ("wend", "Closes a `while` loop."),
    ("loop", "Closes a `do` loop (`loop while|until COND` tests at the end)."),
];

fn keyword_doc(keyword: &str) -> Option<&'static str> {
    let lower = keyword.to_ascii_lowercase();
    STATEMENT_KEYWORDS
        .iter()
        .find(|(name, _)| *name == lower)
        .map(|(_, doc)| *doc)
        .or(match lower.as_str() {
            "then" => Some("Ends the condition of an `if` or `elseif`."),
            "else" => Some("The branch of an `if` taken when no condition held."),
            "elseif" => Some("`elseif COND then`: another condition of an `if`."),
            "endif" => Some("Closes an `if` block (also `end if`)."),
            "integer" => Some("64-bit integer type. Integers widen to float implicitly."),
            "float" => Some(
                "64-bit float type (sensors are floats). Float to integer only through `int()`.",
            ),
            "as" => Some("Gives the type in a `dim`."),
            "to" | "step" => Some("`for V = A to B [step S]`."),
            "until" => Some("`do until COND` / `loop until COND`: repeat until COND is true."),
            "and" | "or" => Some(
                "Logical operators: integer 0 is false, anything else true; the result is 0 or 1.",
            ),
            "not" => Some("Logical not: 1 when the operand is 0, else 0."),
            "mod" => Some("Remainder, with the sign of the left operand."),
            _ => None,
        })
}

pub fn word_markdown(word: &str, kind: TokenKind) -> Option<String> {
    match kind {
        TokenKind::Function => {
            builtin(word).map(|info| format!("```gbasic\n{}\n```", info.summary()))
        }
        TokenKind::Keyword => keyword_doc(word).map(str::to_string),
        _ => None,
    }
}

/// Signature help inside a built-in's parentheses.
pub fn signature(text: &str, offset: usize) -> Option<Signature> {
    let offset = offset.min(text.len());
    let line_start = text[..offset].rfind('\n').map_or(0, |at| at + 1);
    let before = text.get(line_start..offset)?;
    // Find the innermost unclosed `(` and count the commas at its depth.
    let mut depth = 0usize;
    let mut commas = 0usize;
    let mut open = None;
    for (index, character) in before.char_indices().rev() {
        match character {
            ')' => depth += 1,
            '(' if depth == 0 => {
                open = Some(index);
                break;
            }
            '(' => depth -= 1,
            ',' if depth == 0 => commas += 1,
            _ => {}
        }
    }
    let open = open?;
    let name_start = before[..open]
        .trim_end()
        .rfind(|character: char| !character.is_ascii_alphanumeric() && character != '_')
        .map_or(0, |at| at + 1);
    let name = before[name_start..open].trim();
    let info = builtin(name)?;
    let (label, parameters) = info.signature_and_params();
    Some(Signature {
        label,
        documentation: info.doc.to_string(),
        active_parameter: commas.min(parameters.len().saturating_sub(1)),
        parameters,
    })
}

const INDENT: &str = "  ";

/// Re-indents every line by block depth (two spaces a level, as in the
/// paper's Fig. 3) and trims trailing spaces; nothing else changes.
pub fn format(text: &str) -> Option<String> {
    let mut depth = 0usize;
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    for line in text.split_inclusive('\n') {
        let (content, ending) = match line.strip_suffix("\r\n") {
            Some(content) => (content, "\r\n"),
            None => match line.strip_suffix('\n') {
                Some(content) => (content, "\n"),
                None => (line, ""),
            },
        };
        let content = content.trim();
        let words: Vec<String> = lexer::lex(content)
            .iter()
            .filter(|token| token.kind == Lexed::Ident)
            .map(|token| content[token.span.range()].to_ascii_lowercase())
            .collect();
        let first = words.first().map(String::as_str).unwrap_or("");
        let second = words.get(1).map(String::as_str).unwrap_or("");
        let last_token_is_then = lexer::lex(content)
            .iter()
            .rfind(|token| !matches!(token.kind, Lexed::Newline | Lexed::Comment | Lexed::Eof))
            .is_some_and(|token| content[token.span.range()].eq_ignore_ascii_case("then"));
        let closes = matches!(first, "endif" | "wend" | "loop" | "next")
            || (first == "end" && second == "if");
        let reopens = matches!(first, "else" | "elseif");
        if closes || reopens {
            depth = depth.saturating_sub(1);
        }
        if !content.is_empty() {
            for _ in 0..depth {
                out.push_str(INDENT);
            }
            out.push_str(content);
        }
        out.push_str(ending);
        let opens = (first == "if" && last_token_is_then)
            || matches!(first, "while" | "for")
            || (first == "do")
            || reopens;
        if opens {
            depth += 1;
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_indents_by_block_and_keeps_everything_else() {
        let text = "label: a\nif m_depth > 15.0 then\nSCI_RUHP_BEHS = 128   \nwhile x < 3\n  x = x + 1 ' count\n      wend\nelse\ndo\nyield\nloop until x > 9\n   end if\nif x then y = 1\nfor i = 1 to 3\nnext i\r\n";
        let expected = "label: a\nif m_depth > 15.0 then\n  SCI_RUHP_BEHS = 128\n  while x < 3\n    x = x + 1 ' count\n  wend\nelse\n  do\n    yield\n  loop until x > 9\nend if\nif x then y = 1\nfor i = 1 to 3\nnext i\r\n";
        assert_eq!(format(text).as_deref(), Some(expected));
    }

    #[test]
    fn completion_positions() {
        assert!(matches!(position("goto st", 7), Position::Label));
        assert!(matches!(position("dim x as fl", 11), Position::Type));
        assert!(matches!(position("  SCI_R", 7), Position::Statement));
        assert!(matches!(
            position("if m_depth > 1 then SCI", 23),
            Position::Statement
        ));
        assert!(matches!(position("if m_de", 7), Position::Expression));
        assert!(matches!(position("x = abs(m_", 10), Position::Expression));
        assert!(matches!(position("print \"m_", 9), Position::Nothing));
        assert!(matches!(position("x = 1 ' m_", 10), Position::Nothing));
    }

    #[test]
    fn every_builtin_has_hover_text_and_a_signature() {
        for info in BUILTINS {
            let hover = word_markdown(&info.name.to_ascii_uppercase(), TokenKind::Function)
                .unwrap_or_default();
            assert!(hover.contains(info.doc), "{}: {hover}", info.name);
            let text = format!("x = {}(", info.name);
            let help = signature(&text, text.len()).expect(info.name);
            assert_eq!(help.documentation, info.doc);
            assert_eq!(help.parameters.len(), info.params.len(), "{}", info.name);
            for ((start, end), (param, _)) in help.parameters.iter().zip(info.params) {
                assert_eq!(&help.label[*start..*end], *param, "{}", help.label);
            }
        }
    }

    #[test]
    fn signature_of_builtins() {
        let max = signature("x = max(a, abs(b), ", 19).expect("max");
        assert_eq!(max.label, "max(a, b)");
        assert_eq!(max.active_parameter, 1);
        assert_eq!(max.parameters, vec![(4, 5), (7, 8)]);
        assert!(signature("x = foo(", 8).is_none());
    }
}
