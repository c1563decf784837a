//! GBASIC tokens: a line-oriented lexer that never fails (bad characters become
//! `Unknown` tokens the parser reports once).

use gloc_engine::vm::Cmp;
use gloc_engine::Span;

#[derive(Clone, Debug, PartialEq)]
pub enum TokenKind {
    /// A name or keyword; keywords are recognised by the parser, case-insensitively.
    Ident,
    Int,
    Float,
    /// A string literal; `terminated` is false when the line ended first.
    Str {
        terminated: bool,
    },
    LParen,
    RParen,
    Comma,
    Colon,
    Plus,
    Minus,
    Star,
    Slash,
    Backslash,
    /// `= <> < <= > >=`; `=` also assigns (see [`TokenKind::EQUALS`]).
    Compare(Cmp),
    Newline,
    /// A comment, to the end of its line (without the line end): from a `'` outside
    /// a string, or from `rem` as the first word of a line (where a statement
    /// starts). The parser skips these.
    Comment,
    /// A character that starts no token.
    Unknown,
    Eof,
}

impl TokenKind {
    /// `=`: the comparison, and the sign of an assignment, a `const` and a `for`.
    pub const EQUALS: TokenKind = TokenKind::Compare(Cmp::Eq);
}

#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    pub kind: TokenKind,
    pub span: Span,
}

/// Splits `text` into tokens. A `'` outside a string, and `rem` as a line's first
/// word, start a `Comment` token to the end of the line.
pub fn lex(text: &str) -> Vec<Token> {
    let bytes = text.as_bytes();
    let mut tokens = Vec::new();
    let mut at = 0;
    while at < bytes.len() {
        let start = at;
        let byte = bytes[at];
        let kind = match byte {
            b'\n' => {
                at += 1;
                TokenKind::Newline
            }
            b' ' | b'\t' | b'\r' | 0x0c => {
                at += 1;
                continue;
            }
            b'\'' => {
                tokens.push(comment_to_line_end(bytes, start, &mut at));
                continue;
            }
            b'"' => {
                at += 1;
                let mut terminated = false;
                while at < bytes.len() && bytes[at] != b'\n' {
                    if bytes[at] == b'"' {
                        // `""` inside a string is one quote, as in other BASICs.
                        if bytes.get(at + 1) == Some(&b'"') {
                            at += 2;
                            continue;
                        }
                        at += 1;
                        terminated = true;
                        break;
                    }
                    at += 1;
                }
                TokenKind::Str { terminated }
            }
            b'0'..=b'9' | b'.' if is_number_start(bytes, at) => lex_number(bytes, &mut at),
            b'a'..=b'z' | b'A'..=b'Z' | b'_' => {
                while at < bytes.len() && (bytes[at].is_ascii_alphanumeric() || bytes[at] == b'_') {
                    at += 1;
                }
                let first_on_line = tokens
                    .last()
                    .is_none_or(|token: &Token| token.kind == TokenKind::Newline);
                if first_on_line && text[start..at].eq_ignore_ascii_case("rem") {
                    tokens.push(comment_to_line_end(bytes, start, &mut at));
                    continue;
                }
                TokenKind::Ident
            }
            b'(' => single(&mut at, TokenKind::LParen),
            b')' => single(&mut at, TokenKind::RParen),
            b',' => single(&mut at, TokenKind::Comma),
            b':' => single(&mut at, TokenKind::Colon),
            b'+' => single(&mut at, TokenKind::Plus),
            b'-' => single(&mut at, TokenKind::Minus),
            b'*' => single(&mut at, TokenKind::Star),
            b'/' => single(&mut at, TokenKind::Slash),
            b'\\' => single(&mut at, TokenKind::Backslash),
            b'=' => single(&mut at, TokenKind::EQUALS),
            b'<' => match bytes.get(at + 1) {
                Some(b'>') => double(&mut at, TokenKind::Compare(Cmp::Ne)),
                Some(b'=') => double(&mut at, TokenKind::Compare(Cmp::Le)),
                _ => single(&mut at, TokenKind::Compare(Cmp::Lt)),
            },
            b'>' => match bytes.get(at + 1) {
                Some(b'=') => double(&mut at, TokenKind::Compare(Cmp::Ge)),
                _ => single(&mut at, TokenKind::Compare(Cmp::Gt)),
            },
            _ => {
                // Skip one whole character so spans stay on char boundaries.
                let width = text[at..].chars().next().map_or(1, char::len_utf8);
                at += width;
                TokenKind::Unknown
            }
        };
        tokens.push(Token {
            kind,
            span: Span::new(start, at),
        });
    }
    tokens.push(Token {
        kind: TokenKind::Eof,
        span: Span::new(bytes.len(), bytes.len()),
    });
    tokens
}

/// The comment from `start` to the end of its line; a CRLF line's `\r` ends the
/// line, not the comment.
fn comment_to_line_end(bytes: &[u8], start: usize, at: &mut usize) -> Token {
    while *at < bytes.len() && bytes[*at] != b'\n' {
        *at += 1;
    }
    let end = if *at > start && bytes[*at - 1] == b'\r' {
        *at - 1
    } else {
        *at
    };
    Token {
        kind: TokenKind::Comment,
        span: Span::new(start, end),
    }
}

fn single(at: &mut usize, kind: TokenKind) -> TokenKind {
    *at += 1;
    kind
}

fn double(at: &mut usize, kind: TokenKind) -> TokenKind {
    *at += 2;
    kind
}

fn is_number_start(bytes: &[u8], at: usize) -> bool {
    bytes[at].is_ascii_digit() || bytes.get(at + 1).is_some_and(u8::is_ascii_digit)
}

/// `123`, `15.0`, `.5`, `1.5e-3`, `1e7`. The digits are checked again when the value is
/// parsed, so this only has to find the end.
fn lex_number(bytes: &[u8], at: &mut usize) -> TokenKind {
    let mut is_float = false;
    while *at < bytes.len() && bytes[*at].is_ascii_digit() {
        *at += 1;
    }
    if *at < bytes.len() && bytes[*at] == b'.' {
        is_float = true;
        *at += 1;
        while *at < bytes.len() && bytes[*at].is_ascii_digit() {
            *at += 1;
        }
    }
    if *at < bytes.len() && (bytes[*at] == b'e' || bytes[*at] == b'E') {
        let mut look = *at + 1;
        if look < bytes.len() && (bytes[look] == b'+' || bytes[look] == b'-') {
            look += 1;
        }
        if look < bytes.len() && bytes[look].is_ascii_digit() {
            is_float = true;
            *at = look;
            while *at < bytes.len() && bytes[*at].is_ascii_digit() {
                *at += 1;
            }
        }
    }
    if is_float {
        TokenKind::Float
    } else {
        TokenKind::Int
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<TokenKind> {
        lex(text).into_iter().map(|token| token.kind).collect()
    }

    #[test]
    fn numbers_operators_and_comments() {
        use TokenKind::*;
        assert_eq!(
            kinds("x = 1.5e-3 <> .5 ' note\n"),
            vec![
                Ident,
                Compare(Cmp::Eq),
                Float,
                Compare(Cmp::Ne),
                Float,
                Comment,
                Newline,
                Eof
            ]
        );
        assert_eq!(
            kinds("a(1) \\ 2"),
            vec![Ident, LParen, Int, RParen, Backslash, Int, Eof]
        );
    }

    #[test]
    fn comments_are_tokens_to_the_line_end_and_a_quote_in_a_string_is_none() {
        let text =
            "print \"it's\" ' done\r\n' whole line\nx = 1 '\n  REM old, 'quoted'\r\nremark = 1\nx = rem\n";
        let comments: Vec<&str> = lex(text)
            .into_iter()
            .filter(|token| token.kind == TokenKind::Comment)
            .map(|token| &text[token.span.range()])
            .collect();
        // `rem` is a comment as a line's first word only (`remark` is another word;
        // after `=` it is a misplaced keyword the parser reports).
        assert_eq!(
            comments,
            ["' done", "' whole line", "'", "REM old, 'quoted'"]
        );
    }

    #[test]
    fn strings_with_doubled_quotes_and_unterminated() {
        let tokens = lex("\"a\"\"b\" \"open\n");
        assert_eq!(tokens[0].kind, TokenKind::Str { terminated: true });
        assert_eq!(tokens[0].span, Span::new(0, 6));
        assert_eq!(tokens[1].kind, TokenKind::Str { terminated: false });
    }

    #[test]
    fn unknown_characters_keep_char_boundaries() {
        let tokens = lex("é$");
        assert_eq!(tokens[0].span, Span::new(0, 2));
        assert_eq!(tokens[1].span, Span::new(2, 3));
    }
}
