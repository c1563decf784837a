//! The GBASIC parser: recursive descent over lines. It never fails: a syntax error is
//! reported once and parsing resumes at the next line; an unclosed block is reported at
//! its opening line.

use gloc_engine::{Diagnostic, Span};

use crate::ast::*;
use crate::codes;
use crate::lexer::{lex, Token, TokenKind};

/// The result of parsing: always a tree, plus the syntax errors found.
#[derive(Clone, Debug, Default)]
pub struct Parsed {
    pub program: Program,
    pub diagnostics: Vec<Diagnostic>,
}

/// Words that cannot name a variable, constant or label.
pub const KEYWORDS: &[&str] = &[
    "and", "as", "const", "dim", "do", "else", "elseif", "end", "endif", "exit", "float", "for",
    "goto", "if", "integer", "label", "let", "loop", "mod", "next", "not", "or", "print", "rem",
    "step", "then", "to", "until", "wend", "while", "yield",
];

pub fn parse(text: &str) -> Parsed {
    if let Some(diagnostic) = crate::loader::source_too_large(text, crate::Language::Gbasic) {
        return Parsed {
            diagnostics: vec![diagnostic],
            ..Parsed::default()
        };
    }
    let mut parser = Parser {
        text,
        // Comments are tokens for the editor; the grammar never sees them.
        tokens: code_tokens(text),
        pos: 0,
        diagnostics: Vec::new(),
        suppressed: crate::Suppressed::default(),
        open: Vec::new(),
        expression_depth: 0,
        end_name: "the end of the file",
    };
    let mut body = Vec::new();
    loop {
        match parser.parse_block(&mut body) {
            BlockEnd::Eof => break,
            BlockEnd::Closer(closer) => {
                // No block is open here, so the closer is stray.
                parser.stray_closer(closer);
            }
        }
    }
    Parsed {
        program: Program { body },
        diagnostics: parser.into_diagnostics(),
    }
}

/// The tokens the grammar reads: comments (tokens for the editor) removed in place,
/// so the text's tokens are held once, not twice.
fn code_tokens(text: &str) -> Vec<Token> {
    let mut tokens = lex(text);
    tokens.retain(|token| token.kind != TokenKind::Comment);
    tokens
}

/// One expression alone (a debugger's condition, watch or hover), parsed by the same
/// rules as in a script; `expr` is `None` when it has a syntax error.
#[derive(Clone, Debug, Default)]
pub struct ParsedExpression {
    pub expr: Option<Expr>,
    pub diagnostics: Vec<Diagnostic>,
}

/// The longest expression [`parse_expression`] reads: a condition or a watch is a
/// line, and the limit bounds the memory a hostile one can take.
pub const MAX_EXPRESSION_BYTES: usize = 1 << 16;

/// Parses `text` as one GBASIC expression: anything after it is an error.
pub fn parse_expression(text: &str) -> ParsedExpression {
    if text.len() > MAX_EXPRESSION_BYTES {
        return ParsedExpression {
            expr: None,
            diagnostics: vec![Diagnostic::error(
                codes::EXPRESSION_TOO_LONG,
                Span::default(),
                format!(
                    "the expression is {} bytes; an expression is at most {MAX_EXPRESSION_BYTES}",
                    text.len()
                ),
            )],
        };
    }
    let mut parser = Parser {
        text,
        tokens: lex(text),
        pos: 0,
        diagnostics: Vec::new(),
        suppressed: crate::Suppressed::default(),
        open: Vec::new(),
        expression_depth: 0,
        end_name: "the end of the expression",
    };
    if parser.peek().kind == TokenKind::Eof {
        parser.report(Diagnostic::error(
            codes::SYNTAX,
            Span::default(),
            "the expression is empty",
        ));
        return ParsedExpression {
            expr: None,
            diagnostics: parser.diagnostics,
        };
    }
    let expr = parser.parse_expr();
    if expr.is_some() && parser.peek().kind != TokenKind::Eof {
        let diagnostic = parser.syntax_error_here(true, |found| {
            format!("unexpected {found} after the expression")
        });
        parser.report(diagnostic);
    }
    let has_errors = parser.diagnostics.iter().any(Diagnostic::is_error);
    ParsedExpression {
        expr: expr.filter(|_| !has_errors),
        diagnostics: parser.diagnostics,
    }
}

/// GBASIC's spelling of an operator written as in C (`&&`, `!=`, `%`), for a hint.
fn operator_hint(found: &str) -> Option<&'static str> {
    Some(match found {
        "&" | "&&" => "GBASIC writes `and`",
        "|" | "||" => "GBASIC writes `or`",
        "!" => "GBASIC writes `not`, and `<>` for `!=`",
        "%" => "GBASIC writes `mod`",
        "=" | "==" => "GBASIC compares with a single `=`",
        _ => return None,
    })
}

/// A word that ends (or continues) a block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Closer {
    EndIf,
    Else,
    ElseIf,
    Wend,
    Loop,
    Next,
}

impl Closer {
    fn owner(self) -> BlockKind {
        match self {
            Closer::EndIf | Closer::Else | Closer::ElseIf => BlockKind::If,
            Closer::Wend => BlockKind::While,
            Closer::Loop => BlockKind::Do,
            Closer::Next => BlockKind::For,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum BlockKind {
    If,
    While,
    Do,
    For,
}

impl BlockKind {
    fn closer_word(self) -> &'static str {
        match self {
            BlockKind::If => "endif",
            BlockKind::While => "wend",
            BlockKind::Do => "loop",
            BlockKind::For => "next",
        }
    }

    fn opener_word(self) -> &'static str {
        match self {
            BlockKind::If => "if",
            BlockKind::While => "while",
            BlockKind::Do => "do",
            BlockKind::For => "for",
        }
    }
}

enum BlockEnd {
    Eof,
    /// The current line starts with this closer; nothing of it is consumed.
    Closer(Closer),
}

struct Parser<'a> {
    text: &'a str,
    tokens: Vec<Token>,
    pos: usize,
    diagnostics: Vec<Diagnostic>,
    /// Diagnostics past [`crate::MAX_DIAGNOSTICS`], counted and summed up at the end.
    suppressed: crate::Suppressed,
    /// Blocks open around the current position, innermost last.
    open: Vec<BlockKind>,
    /// Expression nesting (parentheses, unary operators, call arguments) under way.
    expression_depth: usize,
    /// What the end of the text is called in messages (a file, or a lone expression).
    end_name: &'static str,
}

/// Deeper nesting is refused with a diagnostic, so no input can exhaust the stack
/// of the parser or of the later passes, which follow the tree.
const MAX_NESTING: usize = 100;

/// The precedence of the comparisons: the prefix `not` binds just looser.
const COMPARISONS: usize = BinaryOp::Compare(Cmp::Eq).precedence();

/// The deepest expression tree accepted (an operator, call or unary minus is a level;
/// parentheses are not). 256 levels keep every recursive pass far inside a 2 MB thread
/// stack, even in a debug build; real expressions are a few levels deep.
const MAX_EXPRESSION_DEPTH: usize = 256;

/// An expression and the depth of its tree in operators (a leaf is 0).
struct Node {
    expr: Expr,
    depth: usize,
}

fn stray_closer_message(closer: Closer) -> (String, String) {
    let word = match closer {
        Closer::EndIf => "endif",
        Closer::Else => "else",
        Closer::ElseIf => "elseif",
        Closer::Wend => "wend",
        Closer::Loop => "loop",
        Closer::Next => "next",
    };
    let opener = closer.owner().opener_word();
    (
        format!("`{word}` without a matching `{opener}`"),
        format!("remove this line, or open the block with `{opener}` above it"),
    )
}

impl<'a> Parser<'a> {
    fn report(&mut self, diagnostic: Diagnostic) {
        self.suppressed.push(&mut self.diagnostics, diagnostic);
    }

    /// The diagnostics, with one summing up those not kept.
    fn into_diagnostics(mut self) -> Vec<Diagnostic> {
        self.suppressed.finish(&mut self.diagnostics);
        self.diagnostics
    }

    fn peek(&self) -> &Token {
        &self.tokens[self.pos.min(self.tokens.len() - 1)]
    }

    fn peek_at(&self, ahead: usize) -> &Token {
        &self.tokens[(self.pos + ahead).min(self.tokens.len() - 1)]
    }

    fn bump(&mut self) -> Token {
        let token = self.peek().clone();
        if self.pos < self.tokens.len() - 1 {
            self.pos += 1;
        }
        token
    }

    fn slice(&self, span: Span) -> &'a str {
        self.text.get(span.range()).unwrap_or("")
    }

    fn word_at(&self, ahead: usize) -> Option<String> {
        let token = self.peek_at(ahead);
        (token.kind == TokenKind::Ident).then(|| self.slice(token.span).to_ascii_lowercase())
    }

    fn at_word(&self, word: &str) -> bool {
        self.word_at(0).as_deref() == Some(word)
    }

    fn eat_word(&mut self, word: &str) -> bool {
        if self.at_word(word) {
            self.bump();
            true
        } else {
            false
        }
    }

    fn at_line_end(&self) -> bool {
        matches!(self.peek().kind, TokenKind::Newline | TokenKind::Eof)
    }

    fn skip_line(&mut self) {
        while !self.at_line_end() {
            self.bump();
        }
        if self.peek().kind == TokenKind::Newline {
            self.bump();
        }
    }

    /// From `span` to the end of its line's last token, for messages about a whole line.
    fn line_span_from(&self, span: Span) -> Span {
        let mut end = span.end;
        let mut index = self.pos;
        while let Some(token) = self.tokens.get(index) {
            if matches!(token.kind, TokenKind::Newline | TokenKind::Eof) {
                break;
            }
            end = end.max(token.span.end);
            index += 1;
        }
        Span {
            start: span.start,
            end,
        }
    }

    fn describe(&self, token: &Token) -> String {
        match token.kind {
            TokenKind::Newline => "the end of the line".to_string(),
            TokenKind::Eof => self.end_name.to_string(),
            TokenKind::Str { .. } => "a string".to_string(),
            _ => format!("`{}`", self.slice(token.span)),
        }
    }

    fn error_here(&mut self, expected: &str) {
        // Where an operand was due, a C operator (`==`'s second `=`, `!`) gets GBASIC's.
        let diagnostic = self.syntax_error_here(expected == "an expression", |found| {
            format!("expected {expected}, found {found}")
        });
        self.report(diagnostic);
    }

    /// A syntax error at the next token, its message made from how that token reads
    /// (see [`Parser::describe`]); with `hint`, a C operator there gets GBASIC's
    /// spelling as the help.
    fn syntax_error_here(&self, hint: bool, message: impl FnOnce(&str) -> String) -> Diagnostic {
        let token = self.peek();
        let diagnostic =
            Diagnostic::error(codes::SYNTAX, token.span, message(&self.describe(token)));
        match operator_hint(self.slice(token.span)).filter(|_| hint) {
            Some(help) => diagnostic.with_help(help),
            None => diagnostic,
        }
    }

    /// Ends a statement: anything left on the line is an error (reported once).
    fn finish_line(&mut self) {
        if !self.at_line_end() {
            let token = self.peek().clone();
            let found = self.describe(&token);
            let span = self.line_span_from(token.span);
            self.report(
                Diagnostic::error(
                    codes::SYNTAX,
                    span,
                    format!("unexpected {found} after the end of the statement"),
                )
                .with_help(
                    operator_hint(self.slice(token.span))
                        .unwrap_or("put each statement on its own line"),
                ),
            );
        }
        self.skip_line();
    }

    /// Reports the closer that starts the current line as closing no open block, and
    /// skips the line.
    fn stray_closer(&mut self, closer: Closer) {
        let span = self.line_span_from(self.peek().span);
        let (message, help) = stray_closer_message(closer);
        self.report(Diagnostic::error(codes::STRAY_CLOSER, span, message).with_help(help));
        self.skip_line();
    }

    /// The closer that starts the current line, if any.
    fn closer_here(&self) -> Option<Closer> {
        match self.word_at(0)?.as_str() {
            "endif" => Some(Closer::EndIf),
            "end" if self.word_at(1).as_deref() == Some("if") => Some(Closer::EndIf),
            "else" => Some(Closer::Else),
            "elseif" => Some(Closer::ElseIf),
            "wend" => Some(Closer::Wend),
            "loop" => Some(Closer::Loop),
            "next" => Some(Closer::Next),
            _ => None,
        }
    }

    /// Parses statements into `body` until end of file or a closer. A closer that
    /// belongs to an enclosing block stops the block; one that belongs to no open block
    /// is reported and skipped.
    fn parse_block(&mut self, body: &mut Vec<Stmt>) -> BlockEnd {
        loop {
            while self.peek().kind == TokenKind::Newline {
                self.bump();
            }
            if self.peek().kind == TokenKind::Eof {
                return BlockEnd::Eof;
            }
            if let Some(closer) = self.closer_here() {
                if self.open.contains(&closer.owner()) || self.open.is_empty() {
                    return BlockEnd::Closer(closer);
                }
                self.stray_closer(closer);
                continue;
            }
            if let Some(stmt) = self.parse_statement() {
                body.push(stmt);
            }
        }
    }

    /// Parses a nested block of `kind` opened at `open_span`; returns the closer found
    /// (not consumed) or `None` after reporting the missing closer.
    fn parse_nested(
        &mut self,
        kind: BlockKind,
        open_span: Span,
        body: &mut Vec<Stmt>,
    ) -> Option<Closer> {
        if self.open.len() >= MAX_NESTING {
            self.report(Diagnostic::error(
                codes::TOO_DEEP,
                open_span,
                format!("blocks are nested more than {MAX_NESTING} levels deep here"),
            ));
            // Skip the rest of the file: its structure cannot be followed.
            while self.peek().kind != TokenKind::Eof {
                self.bump();
            }
            return None;
        }
        self.open.push(kind);
        let end = self.parse_block(body);
        self.open.pop();
        match end {
            BlockEnd::Closer(closer) if closer.owner() == kind => Some(closer),
            _ => {
                let word = kind.closer_word();
                let opener = kind.opener_word();
                let found = match end {
                    BlockEnd::Eof => "the end of the file".to_string(),
                    BlockEnd::Closer(_) => {
                        let token = self.peek().clone();
                        format!("{} first", self.describe(&token))
                    }
                };
                self.report(
                    Diagnostic::error(
                        codes::MISSING_CLOSER,
                        open_span,
                        format!("this `{opener}` has no `{word}`: found {found}"),
                    )
                    .with_help(format!("add `{word}` where the `{opener}` block ends")),
                );
                None
            }
        }
    }

    fn parse_statement(&mut self) -> Option<Stmt> {
        let start = self.peek().span;
        let word = self.word_at(0);
        let result = match word.as_deref() {
            Some("if") => return self.parse_if(),
            Some("while") => return self.parse_while(),
            Some("do") => return self.parse_do(),
            Some("for") => return self.parse_for(),
            _ => self.parse_simple(),
        };
        let span = self.end_line(start, result.is_some());
        Some(Stmt {
            kind: result?,
            span,
        })
    }

    /// Ends the line of a statement that starts at `start` and returns its span: the
    /// rest of the line must be empty when the statement `parsed`, and is skipped
    /// when it did not (its error is already reported).
    fn end_line(&mut self, start: Span, parsed: bool) -> Span {
        let span = self.statement_span(start);
        if parsed {
            self.finish_line();
        } else {
            self.skip_line();
        }
        span
    }

    /// From `start` to the end of the last consumed token.
    fn statement_span(&self, start: Span) -> Span {
        let end = self
            .pos
            .checked_sub(1)
            .and_then(|index| self.tokens.get(index))
            .map_or(start.end, |token| token.span.end);
        Span::new(start.start as usize, (end as usize).max(start.end as usize))
    }

    /// A statement that fits on one line (everything but block statements).
    fn parse_simple(&mut self) -> Option<StmtKind> {
        let token = self.peek().clone();
        if token.kind != TokenKind::Ident {
            self.error_here("a statement");
            return None;
        }
        let word = self.slice(token.span).to_ascii_lowercase();
        match word.as_str() {
            "dim" => self.parse_dim(),
            "const" => self.parse_const(),
            "let" => {
                self.bump();
                self.parse_assignment()
            }
            "label" => {
                self.bump();
                if self.peek().kind == TokenKind::Colon {
                    self.bump();
                } else {
                    self.error_here("`:` after `label`");
                    return None;
                }
                let name = self.parse_name("a label name")?;
                Some(StmtKind::Label(name))
            }
            "goto" => {
                self.bump();
                let name = self.parse_name("a label name after `goto`")?;
                Some(StmtKind::Goto(name))
            }
            "exit" => {
                self.bump();
                let kind = match self.word_at(0).as_deref() {
                    Some("for") => LoopKind::For,
                    Some("do") => LoopKind::Do,
                    Some("while") => LoopKind::While,
                    _ => {
                        self.error_here("`for`, `do` or `while` after `exit`");
                        return None;
                    }
                };
                self.bump();
                Some(StmtKind::Exit(kind))
            }
            "yield" => {
                self.bump();
                Some(StmtKind::Yield)
            }
            "end" => {
                self.bump();
                Some(StmtKind::End)
            }
            "print" => {
                self.bump();
                self.parse_print()
            }
            "if" | "while" | "do" | "for" => {
                self.report(
                    Diagnostic::error(
                        codes::SYNTAX,
                        token.span,
                        format!("a `{word}` block cannot follow `then` on the same line"),
                    )
                    .with_help("start the block on its own line after `then`"),
                );
                None
            }
            _ if KEYWORDS.contains(&word.as_str()) => {
                self.report(Diagnostic::error(
                    codes::SYNTAX,
                    token.span,
                    format!("`{word}` cannot start a statement"),
                ));
                None
            }
            _ => self.parse_assignment(),
        }
    }

    fn parse_name(&mut self, expected: &str) -> Option<Name> {
        let token = self.peek().clone();
        if token.kind != TokenKind::Ident {
            self.error_here(expected);
            return None;
        }
        let text = self.slice(token.span);
        let key = text.to_ascii_lowercase();
        if KEYWORDS.contains(&key.as_str()) {
            self.report(
                Diagnostic::error(
                    codes::KEYWORD_AS_NAME,
                    token.span,
                    format!("`{text}` is a keyword and cannot be used as a name"),
                )
                .with_help("choose another name"),
            );
            return None;
        }
        self.bump();
        Some(Name::new(text, token.span))
    }

    fn parse_type(&mut self) -> Option<TypeName> {
        if self.eat_word("integer") {
            Some(TypeName::Integer)
        } else if self.eat_word("float") {
            Some(TypeName::Float)
        } else {
            self.error_here("`integer` or `float`");
            None
        }
    }

    fn parse_dim(&mut self) -> Option<StmtKind> {
        self.bump();
        let name = self.parse_name("a variable name after `dim`")?;
        let mut size = None;
        if self.peek().kind == TokenKind::LParen {
            self.bump();
            let token = self.peek().clone();
            size = Some(match token.kind {
                TokenKind::Int => {
                    self.bump();
                    let value = self.int_value(&token)?;
                    ArraySize::Literal {
                        value,
                        span: token.span,
                    }
                }
                TokenKind::Ident => ArraySize::Const(self.parse_name("an array size")?),
                _ => {
                    self.error_here("an array size (an integer or a constant)");
                    return None;
                }
            });
            if self.peek().kind != TokenKind::RParen {
                self.error_here("`)` after the array size");
                return None;
            }
            self.bump();
        }
        if !self.eat_word("as") {
            self.error_here("`as integer` or `as float`");
            return None;
        }
        let ty = self.parse_type()?;
        Some(StmtKind::Dim { name, size, ty })
    }

    fn parse_const(&mut self) -> Option<StmtKind> {
        self.bump();
        let name = self.parse_name("a constant name after `const`")?;
        if self.peek().kind != TokenKind::EQUALS {
            self.error_here("`=` after the constant's name");
            return None;
        }
        self.bump();
        let negative = if self.peek().kind == TokenKind::Minus {
            self.bump();
            true
        } else {
            false
        };
        let token = self.peek().clone();
        if !matches!(token.kind, TokenKind::Int | TokenKind::Float) {
            self.error_here("a number (a constant's value is a literal)");
            return None;
        }
        self.bump();
        let value = match (self.number_value(&token)?, negative) {
            (Literal::Int(value), true) => Literal::Int(-value),
            (Literal::Float(value), true) => Literal::Float(-value),
            (value, false) => value,
        };
        Some(StmtKind::Const { name, value })
    }

    fn int_value(&mut self, token: &Token) -> Option<i64> {
        match self.slice(token.span).parse::<i64>() {
            Ok(value) => Some(value),
            Err(_) => {
                self.report(
                    Diagnostic::error(
                        codes::BAD_NUMBER,
                        token.span,
                        "this integer does not fit in 64 bits",
                    )
                    .with_help("write it as a float, e.g. `1e20`"),
                );
                None
            }
        }
    }

    /// The value of an `Int` or `Float` token (reported when it does not fit).
    fn number_value(&mut self, token: &Token) -> Option<Literal> {
        if token.kind == TokenKind::Int {
            self.int_value(token).map(Literal::Int)
        } else {
            self.float_value(token).map(Literal::Float)
        }
    }

    fn float_value(&mut self, token: &Token) -> Option<f64> {
        match self.slice(token.span).parse::<f64>() {
            Ok(value) if value.is_finite() => Some(value),
            _ => {
                self.report(Diagnostic::error(
                    codes::BAD_NUMBER,
                    token.span,
                    "this number is not a finite float",
                ));
                None
            }
        }
    }

    fn parse_assignment(&mut self) -> Option<StmtKind> {
        let name = self.parse_name("a statement")?;
        let target = if self.peek().kind == TokenKind::LParen {
            self.bump();
            let index = self.parse_expr()?;
            if self.peek().kind != TokenKind::RParen {
                self.error_here("`)` after the index");
                return None;
            }
            self.bump();
            Target::Element {
                name,
                index: Box::new(index),
            }
        } else {
            Target::Name(name)
        };
        if self.peek().kind != TokenKind::EQUALS {
            let token = self.peek().clone();
            if token.kind == TokenKind::Colon {
                let name = target.name().text.clone();
                self.report(
                    Diagnostic::error(codes::SYNTAX, token.span, "expected `=`, found `:`")
                        .with_help(format!("a label is written `label: {name}`")),
                );
                return None;
            }
            self.error_here("`=` (an assignment)");
            // A lone word that is no statement: most likely a misspelt keyword (`yeild`).
            if let Target::Name(name) = &target {
                let keyword = gloc_engine::suggest::closest(&name.key(), KEYWORDS.iter().copied());
                // Popped only when there is a keyword to suggest: the error stays.
                if let Some(keyword) = keyword {
                    if let Some(last) = self.diagnostics.pop() {
                        self.report(
                            last.with_help(format!(
                                "`{}` is not a keyword: did you mean `{keyword}`?",
                                name.text
                            ))
                            .with_fix(
                                format!("replace with `{keyword}`"),
                                name.span,
                                keyword,
                            ),
                        );
                    }
                }
            }
            return None;
        }
        self.bump();
        let value = self.parse_expr()?;
        Some(StmtKind::Assign { target, value })
    }

    fn parse_print(&mut self) -> Option<StmtKind> {
        let mut items = Vec::new();
        if self.at_line_end() || self.at_word("else") {
            return Some(StmtKind::Print(items));
        }
        loop {
            let token = self.peek().clone();
            if let TokenKind::Str { terminated } = token.kind {
                if !terminated {
                    self.report(
                        Diagnostic::error(
                            codes::SYNTAX,
                            token.span,
                            "this string has no closing `\"`",
                        )
                        .with_help("close the string on the same line"),
                    );
                    return None;
                }
                self.bump();
                let raw = self.slice(token.span);
                let inner = raw.get(1..raw.len().saturating_sub(1)).unwrap_or("");
                items.push(PrintItem::Text {
                    text: inner.replace("\"\"", "\""),
                    span: token.span,
                });
            } else {
                items.push(PrintItem::Expr(self.parse_expr()?));
            }
            if self.peek().kind == TokenKind::Comma {
                self.bump();
            } else {
                break;
            }
        }
        Some(StmtKind::Print(items))
    }

    fn parse_if(&mut self) -> Option<Stmt> {
        let if_token = self.bump();
        let condition = self.parse_condition_then(if_token.span);
        let header_span = self.statement_span(if_token.span);
        let Some(condition) = condition else {
            // Keep the block structure so a later `endif` is not reported as stray.
            self.skip_line();
            let mut ignored = Vec::new();
            self.parse_if_rest(header_span, &mut ignored);
            return None;
        };
        if !self.at_line_end() {
            // One-line form: `if c then statement [else statement]`.
            let body_start = self.peek().span;
            let kind = self.parse_simple();
            let mut body = Vec::new();
            if let Some(kind) = kind {
                body.push(Stmt {
                    kind,
                    span: self.statement_span(body_start),
                });
            } else {
                self.skip_line();
                return None;
            }
            let mut else_body = None;
            if self.eat_word("else") {
                let else_start = self.peek().span;
                let kind = self.parse_simple();
                match kind {
                    Some(kind) => {
                        else_body = Some(vec![Stmt {
                            kind,
                            span: self.statement_span(else_start),
                        }])
                    }
                    None => {
                        self.skip_line();
                        return None;
                    }
                }
            }
            let span = self.statement_span(if_token.span);
            self.finish_line();
            return Some(Stmt {
                kind: StmtKind::If {
                    arms: vec![IfArm {
                        condition,
                        body,
                        span: header_span,
                    }],
                    else_body,
                    end_span: None,
                },
                span,
            });
        }
        self.skip_line();
        let mut arms = vec![IfArm {
            condition,
            body: Vec::new(),
            span: header_span,
        }];
        let (else_body, end_span) = self.parse_if_rest(header_span, &mut arms);
        Some(Stmt {
            kind: StmtKind::If {
                arms,
                else_body,
                end_span,
            },
            span: header_span,
        })
    }

    /// Parses an `if` block's bodies after its header line: `elseif` arms, `else` and
    /// `endif`. The first arm's body is filled in `arms[0]` when there is one.
    fn parse_if_rest(
        &mut self,
        open_span: Span,
        arms: &mut Vec<IfArm>,
    ) -> (Option<Vec<Stmt>>, Option<Span>) {
        let mut body = Vec::new();
        let mut else_body: Option<Vec<Stmt>> = None;
        loop {
            let closer = self.parse_nested(BlockKind::If, open_span, &mut body);
            let target = if let Some(else_body) = else_body.as_mut() {
                else_body
            } else if let Some(arm) = arms.last_mut() {
                &mut arm.body
            } else {
                &mut Vec::new()
            };
            target.append(&mut body);
            let Some(closer) = closer else {
                return (else_body, None);
            };
            let token = self.peek().clone();
            match closer {
                Closer::EndIf => {
                    let first = self.bump();
                    let mut span = first.span;
                    if self.at_word("if") {
                        span = span.cover(self.bump().span);
                    }
                    self.finish_line();
                    return (else_body, Some(span));
                }
                Closer::Else => {
                    self.bump();
                    if else_body.is_some() {
                        self.report(Diagnostic::error(
                            codes::SYNTAX,
                            token.span,
                            "a second `else` in the same `if`",
                        ));
                    }
                    self.finish_line();
                    else_body = Some(Vec::new());
                }
                Closer::ElseIf => {
                    self.bump();
                    if else_body.is_some() {
                        self.report(
                            Diagnostic::error(codes::SYNTAX, token.span, "`elseif` after `else`")
                                .with_help("move this arm above the `else`"),
                        );
                    }
                    let condition = self.parse_condition_then(token.span);
                    let span = self.statement_span(token.span);
                    self.finish_line();
                    if let (Some(condition), None) = (condition, else_body.as_ref()) {
                        arms.push(IfArm {
                            condition,
                            body: Vec::new(),
                            span,
                        });
                    }
                }
                _ => return (else_body, None),
            }
        }
    }

    /// `COND then` after `if`/`elseif`.
    fn parse_condition_then(&mut self, keyword: Span) -> Option<Expr> {
        if self.at_line_end() {
            self.report(Diagnostic::error(
                codes::SYNTAX,
                keyword,
                "expected a condition after this keyword",
            ));
            return None;
        }
        let condition = self.parse_expr()?;
        if !self.eat_word("then") {
            let token = self.peek().clone();
            let found = self.describe(&token);
            self.report(
                Diagnostic::error(
                    codes::SYNTAX,
                    token.span,
                    format!("expected `then`, found {found}"),
                )
                .with_help("end the condition with `then`"),
            );
            return None;
        }
        Some(condition)
    }

    fn parse_while(&mut self) -> Option<Stmt> {
        let keyword = self.bump();
        let condition = if self.at_line_end() {
            self.error_here("a condition after `while`");
            None
        } else {
            self.parse_expr()
        };
        let (header_span, body, closer) =
            self.parse_loop_body(BlockKind::While, keyword.span, condition.is_some());
        let end_span = match closer {
            Some(_) => {
                let token = self.bump();
                self.finish_line();
                Some(token.span)
            }
            None => None,
        };
        Some(Stmt {
            kind: StmtKind::While {
                condition: condition?,
                body,
                end_span,
            },
            span: header_span,
        })
    }

    /// A loop's body after its header line (from `keyword`; `parsed`: the header
    /// parsed): the header's span, the body, and the closer found (not consumed;
    /// `None` after reporting it missing).
    fn parse_loop_body(
        &mut self,
        kind: BlockKind,
        keyword: Span,
        parsed: bool,
    ) -> (Span, Vec<Stmt>, Option<Closer>) {
        let header_span = self.end_line(keyword, parsed);
        let mut body = Vec::new();
        let closer = self.parse_nested(kind, header_span, &mut body);
        (header_span, body, closer)
    }

    fn parse_do_condition(&mut self) -> Result<Option<DoCondition>, ()> {
        let until = if self.eat_word("while") {
            false
        } else if self.eat_word("until") {
            true
        } else {
            return Ok(None);
        };
        match self.parse_expr() {
            Some(expr) => Ok(Some(DoCondition { until, expr })),
            None => Err(()),
        }
    }

    fn parse_do(&mut self) -> Option<Stmt> {
        let keyword = self.bump();
        let pre = self.parse_do_condition();
        let (header_span, body, closer) =
            self.parse_loop_body(BlockKind::Do, keyword.span, pre.is_ok());
        let mut post = Ok(None);
        let end_span = match closer {
            Some(_) => {
                let token = self.bump();
                post = self.parse_do_condition();
                Some(self.end_line(token.span, post.is_ok()))
            }
            None => None,
        };
        let (Ok(pre), Ok(post)) = (pre, post) else {
            return None;
        };
        if let (Some(_), Some(post)) = (&pre, &post) {
            self.report(
                Diagnostic::error(
                    codes::SYNTAX,
                    post.expr.span,
                    "a `do` loop has a condition at both ends",
                )
                .with_help("keep the condition either after `do` or after `loop`"),
            );
            return None;
        }
        Some(Stmt {
            kind: StmtKind::Do {
                pre: pre.map(Box::new),
                body,
                post: post.map(Box::new),
                end_span,
            },
            span: header_span,
        })
    }

    fn parse_for(&mut self) -> Option<Stmt> {
        let keyword = self.bump();
        let header = self.parse_for_header();
        let (header_span, body, closer) =
            self.parse_loop_body(BlockKind::For, keyword.span, header.is_some());
        let mut end_span = None;
        if closer.is_some() {
            let token = self.bump();
            let mut span = token.span;
            if !self.at_line_end() {
                if let Some(name) = self.parse_name("the loop variable after `next`") {
                    span = span.cover(name.span);
                    if let Some((variable, ..)) = &header {
                        if name.key() != variable.key() {
                            self.report(
                                Diagnostic::error(
                                    codes::BAD_NEXT,
                                    name.span,
                                    format!(
                                        "`next {}` does not match the loop variable `{}`",
                                        name.text, variable.text
                                    ),
                                )
                                .with_label(
                                    variable.span,
                                    "the innermost `for` counts this variable",
                                )
                                .with_help(format!("write `next {}` or just `next`", variable.text))
                                .with_fix(
                                    format!("replace with `{}`", variable.text),
                                    name.span,
                                    variable.text.clone(),
                                ),
                            );
                        }
                    }
                } else {
                    self.skip_line();
                    end_span = Some(span);
                }
            }
            if end_span.is_none() {
                self.finish_line();
                end_span = Some(span);
            }
        }
        let (variable, from, to, step) = header?;
        Some(Stmt {
            kind: StmtKind::For {
                variable,
                from: Box::new(from),
                to: Box::new(to),
                step: step.map(Box::new),
                body,
                end_span,
            },
            span: header_span,
        })
    }

    fn parse_for_header(&mut self) -> Option<(Name, Expr, Expr, Option<Expr>)> {
        let variable = self.parse_name("the loop variable after `for`")?;
        if self.peek().kind != TokenKind::EQUALS {
            self.error_here("`=` after the loop variable");
            return None;
        }
        self.bump();
        let from = self.parse_expr()?;
        if !self.eat_word("to") {
            self.error_here("`to`");
            return None;
        }
        let to = self.parse_expr()?;
        let step = if self.eat_word("step") {
            Some(self.parse_expr()?)
        } else {
            None
        };
        Some((variable, from, to, step))
    }

    // Expressions, loosest first: or, and, not, comparison, + -, mod, \, * /, unary -.
    // Each level returns the tree's depth beside it (`Node`), so a chain such as
    // `1 + 1 + …`, which a loop builds into a left-deep tree, is refused at the operator
    // that would make it deeper than `MAX_EXPRESSION_DEPTH`: every later pass follows the
    // tree recursively, and so does dropping it.

    fn parse_expr(&mut self) -> Option<Expr> {
        self.parse_expr_node().map(|node| node.expr)
    }

    fn parse_expr_node(&mut self) -> Option<Node> {
        if !self.enter_expression() {
            return None;
        }
        let expr = self.parse_binary(0);
        self.expression_depth -= 1;
        expr
    }

    /// Counts one level of expression nesting; false (reported) when too deep.
    fn enter_expression(&mut self) -> bool {
        if self.expression_depth >= MAX_NESTING {
            let span = self.peek().span;
            self.report(Diagnostic::error(
                codes::TOO_DEEP,
                span,
                format!("this expression is nested more than {MAX_NESTING} levels deep"),
            ));
            return false;
        }
        self.expression_depth += 1;
        true
    }

    /// A node over `children`, refused (reported at `operator`) when it would make the
    /// tree deeper than `MAX_EXPRESSION_DEPTH`.
    fn node(&mut self, expr: Expr, children: &[usize], operator: Span) -> Option<Node> {
        let depth = children.iter().copied().max().unwrap_or(0) + 1;
        if depth > MAX_EXPRESSION_DEPTH {
            self.report(
                Diagnostic::error(
                    codes::EXPRESSION_TOO_DEEP,
                    operator,
                    format!(
                        "this expression is more than {MAX_EXPRESSION_DEPTH} operators deep \
                         (each term of a chain such as `1 + 1 + …` adds a level)"
                    ),
                )
                .with_help("split it into several assignments to intermediate variables"),
            );
            return None;
        }
        Some(Node { expr, depth })
    }

    fn binary(&mut self, op: BinaryOp, operator: Span, left: Node, right: Node) -> Option<Node> {
        let children = [left.depth, right.depth];
        let expr = Expr {
            span: left.expr.span.cover(right.expr.span),
            kind: ExprKind::Binary {
                op,
                left: Box::new(left.expr),
                right: Box::new(right.expr),
            },
        };
        self.node(expr, &children, operator)
    }

    fn unary(&mut self, op: UnaryOp, operator: Span, operand: Node) -> Option<Node> {
        let children = [operand.depth];
        let expr = Expr {
            span: operator.cover(operand.expr.span),
            kind: ExprKind::Unary {
                op,
                operand: Box::new(operand.expr),
            },
        };
        self.node(expr, &children, operator)
    }

    /// The operators of precedence level `level` and tighter (see
    /// [`BinaryOp::precedence`]), each level's chain from the left.
    fn parse_binary(&mut self, level: usize) -> Option<Node> {
        let mut left = self.parse_operand(level)?;
        while let Some(op) = self.operator_at(level) {
            let operator = self.bump().span;
            let right = self.parse_operand(level)?;
            left = self.binary(op, operator, left, right)?;
        }
        Some(left)
    }

    /// An operand of the operators of `level`: the next tighter level, with the
    /// prefix `not` above the comparisons and the prefix minus below all.
    fn parse_operand(&mut self, level: usize) -> Option<Node> {
        let tighter = level + 1;
        if tighter == COMPARISONS {
            self.parse_not()
        } else if tighter < BinaryOp::LEVELS {
            self.parse_binary(tighter)
        } else {
            self.parse_unary()
        }
    }

    /// The binary operator of precedence level `level` the next token is, if any.
    fn operator_at(&self, level: usize) -> Option<BinaryOp> {
        let op = match self.peek().kind {
            TokenKind::Compare(cmp) => BinaryOp::Compare(cmp),
            TokenKind::Plus => BinaryOp::Add,
            TokenKind::Minus => BinaryOp::Sub,
            TokenKind::Backslash => BinaryOp::IntDiv,
            TokenKind::Star => BinaryOp::Mul,
            TokenKind::Slash => BinaryOp::Div,
            TokenKind::Ident => match self.word_at(0)?.as_str() {
                "or" => BinaryOp::Or,
                "and" => BinaryOp::And,
                "mod" => BinaryOp::Mod,
                _ => return None,
            },
            _ => return None,
        };
        (op.precedence() == level).then_some(op)
    }

    fn parse_not(&mut self) -> Option<Node> {
        if self.at_word("not") {
            let keyword = self.bump();
            if !self.enter_expression() {
                return None;
            }
            let operand = self.parse_not();
            self.expression_depth -= 1;
            return self.unary(UnaryOp::Not, keyword.span, operand?);
        }
        self.parse_binary(COMPARISONS)
    }

    fn parse_unary(&mut self) -> Option<Node> {
        match self.peek().kind {
            TokenKind::Minus => {
                let minus = self.bump();
                if !self.enter_expression() {
                    return None;
                }
                let operand = self.parse_unary();
                self.expression_depth -= 1;
                self.unary(UnaryOp::Neg, minus.span, operand?)
            }
            TokenKind::Plus => {
                self.bump();
                if !self.enter_expression() {
                    return None;
                }
                let operand = self.parse_unary();
                self.expression_depth -= 1;
                operand
            }
            _ => self.parse_primary(),
        }
    }

    fn parse_primary(&mut self) -> Option<Node> {
        let token = self.peek().clone();
        let leaf = |expr| Some(Node { expr, depth: 0 });
        match token.kind {
            TokenKind::Int | TokenKind::Float => {
                self.bump();
                leaf(Expr {
                    kind: ExprKind::Literal(self.number_value(&token)?),
                    span: token.span,
                })
            }
            TokenKind::LParen => {
                self.bump();
                let inner = self.parse_expr_node()?;
                if self.peek().kind != TokenKind::RParen {
                    self.error_here("`)`");
                    return None;
                }
                let close = self.bump();
                Some(Node {
                    expr: Expr {
                        kind: inner.expr.kind,
                        span: token.span.cover(close.span),
                    },
                    depth: inner.depth,
                })
            }
            TokenKind::Ident => {
                let text = self.slice(token.span);
                let key = text.to_ascii_lowercase();
                let is_call = self.peek_at(1).kind == TokenKind::LParen;
                // `int(` and `float(` are calls; other keywords are not names.
                if KEYWORDS.contains(&key.as_str()) && !(is_call && key == "float") {
                    self.error_here("an expression");
                    return None;
                }
                self.bump();
                let name = Name::new(text, token.span);
                if !is_call {
                    return leaf(Expr {
                        span: name.span,
                        kind: ExprKind::Name(name),
                    });
                }
                self.bump();
                let mut args = Vec::new();
                let mut depths = Vec::new();
                if self.peek().kind != TokenKind::RParen {
                    loop {
                        let arg = self.parse_expr_node()?;
                        args.push(arg.expr);
                        depths.push(arg.depth);
                        if self.peek().kind == TokenKind::Comma {
                            self.bump();
                        } else {
                            break;
                        }
                    }
                }
                if self.peek().kind != TokenKind::RParen {
                    self.error_here("`,` or `)`");
                    return None;
                }
                let close = self.bump();
                let call = Expr {
                    span: token.span.cover(close.span),
                    kind: ExprKind::Call {
                        name: Box::new(name),
                        args,
                    },
                };
                self.node(call, &depths, token.span)
            }
            TokenKind::Str { .. } => {
                self.report(
                    Diagnostic::error(
                        codes::SYNTAX,
                        token.span,
                        "a string cannot be used in an expression",
                    )
                    .with_help("strings are only allowed as `print` items"),
                );
                None
            }
            TokenKind::Unknown => {
                let text = self.slice(token.span).to_string();
                let mut diagnostic = Diagnostic::error(
                    codes::BAD_CHARACTER,
                    token.span,
                    format!("unexpected character `{text}`"),
                );
                if let Some(help) = operator_hint(&text) {
                    diagnostic = diagnostic.with_help(help);
                }
                self.report(diagnostic);
                None
            }
            _ => {
                self.error_here("an expression");
                None
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn errors(text: &str) -> Vec<(String, String, Option<String>)> {
        parse(text)
            .diagnostics
            .into_iter()
            .filter(|diagnostic| diagnostic.is_error())
            .map(|diagnostic| {
                (
                    diagnostic.code.to_string(),
                    diagnostic.message,
                    diagnostic.help,
                )
            })
            .collect()
    }

    #[test]
    fn a_misspelt_keyword_alone_is_an_error_with_did_you_mean() {
        let found = errors("yeild\n");
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].0, codes::SYNTAX);
        assert_eq!(
            found[0].2.as_deref(),
            Some("`yeild` is not a keyword: did you mean `yield`?")
        );
    }

    #[test]
    fn a_word_near_no_keyword_keeps_its_error_without_a_suggestion() {
        // `nregs 1` (GLOC's header) is no GBASIC statement: still an error.
        let found = errors("nregs 1\n");
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].0, codes::SYNTAX);
        assert_eq!(found[0].2, None);
    }

    /// `text` parsed as an expression, fully parenthesized.
    fn grouped(text: &str) -> String {
        fn show(expr: &Expr) -> String {
            match &expr.kind {
                ExprKind::Literal(Literal::Int(value)) => value.to_string(),
                ExprKind::Name(name) => name.text.clone(),
                ExprKind::Unary { op, operand } => {
                    let symbol = if *op == UnaryOp::Not { "not " } else { "-" };
                    format!("({symbol}{})", show(operand))
                }
                ExprKind::Binary { op, left, right } => {
                    format!("({} {} {})", show(left), op.symbol(), show(right))
                }
                other => panic!("not in these tests: {other:?}"),
            }
        }
        let parsed = parse_expression(text);
        assert!(parsed.diagnostics.is_empty(), "{:?}", parsed.diagnostics);
        show(&parsed.expr.expect(text))
    }

    // Grouped by hand from the precedence in docs/gbasic.md, loosest first: `or`,
    // `and`, `not`, comparisons, `+ -`, `mod`, `\`, `* /`, prefix minus.
    #[test]
    fn operators_group_by_precedence_and_from_the_left() {
        assert_eq!(
            grouped("a or b and not c = 1 + 2 mod 3 \\ 4 * -5"),
            "(a or (b and (not (c = (1 + (2 mod (3 \\ (4 * (-5)))))))))"
        );
        assert_eq!(grouped("a - b - c"), "((a - b) - c)");
        assert_eq!(grouped("a * b / c mod d"), "(((a * b) / c) mod d)");
        assert_eq!(grouped("a < b <> c"), "((a < b) <> c)");
        assert_eq!(grouped("not not a and b"), "((not (not a)) and b)");
        assert_eq!(grouped("a \\ b * c - d"), "((a \\ (b * c)) - d)");
    }
}
