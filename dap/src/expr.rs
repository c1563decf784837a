//! A small evaluator for GBASIC expressions typed in the debugger: breakpoint
//! conditions, watches, hovers and the debug console (`m_depth > 10 and state = 2`).
//!
//! It lives here rather than in the compiler because the debugger evaluates over live
//! values (variables, registers, sensors) that a compiler never sees, and it must report
//! a bad expression as a message, never fail the session.

use std::fmt;

/// The message of an integer division by zero: a condition that only fails so on
/// the current values is still a well-formed condition.
pub const DIVISION_BY_ZERO: &str = "division by zero";

/// A value as the script sees it: GLOC registers hold integers or floats.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Number {
    Int(i64),
    Float(f64),
}

impl Number {
    pub fn as_f64(self) -> f64 {
        match self {
            Number::Int(value) => value as f64,
            Number::Float(value) => value,
        }
    }

    pub fn is_true(self) -> bool {
        self.as_f64() != 0.0
    }

    pub fn type_name(self) -> &'static str {
        match self {
            Number::Int(_) => "integer",
            Number::Float(_) => "float",
        }
    }

    /// Parses what a user types into the Variables view: `12`, `-3`, `15.5`, `1e-3`, and
    /// the hex the view shows with the hex format (`0xc0`, `-0x10`).
    pub fn parse(text: &str) -> Option<Number> {
        let text = text.trim();
        if let Ok(value) = text.parse::<i64>() {
            return Some(Number::Int(value));
        }
        let (negative, unsigned) = match text.strip_prefix('-') {
            Some(rest) => (true, rest),
            None => (false, text),
        };
        if let Some(digits) = unsigned
            .strip_prefix("0x")
            .or_else(|| unsigned.strip_prefix("0X"))
        {
            // Hex is an integer's 64 bits: `0xffffffffffffffff` is -1, as printed.
            let bits = u64::from_str_radix(digits, 16).ok()?;
            let value = bits as i64;
            return Some(Number::Int(if negative {
                value.wrapping_neg()
            } else {
                value
            }));
        }
        text.parse::<f64>()
            .ok()
            .filter(|value| value.is_finite())
            .map(Number::Float)
    }
}

impl fmt::Display for Number {
    /// The GLOC `print` text, from the engine's one formatter: integers without a point,
    /// floats in the shortest text that reads back to the same double.
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&gloc_engine::program::Value::from(*self), formatter)
    }
}

impl From<Number> for gloc_engine::program::Value {
    fn from(number: Number) -> Self {
        match number {
            Number::Int(value) => gloc_engine::program::Value::Int(value),
            Number::Float(value) => gloc_engine::program::Value::Float(value),
        }
    }
}

/// Looks a name up in the paused program: a GBASIC variable, a register (`r3`) or a
/// sensor, in that order.
pub trait Names {
    fn lookup(&self, name: &str) -> Option<Number>;
    /// Element `index` of the array `name` (`a(3)`).
    fn element(&self, name: &str, index: i64) -> Option<Number> {
        let _ = (name, index);
        None
    }
}

/// Evaluates `text`; the error says what is wrong and where.
pub fn evaluate(text: &str, names: &dyn Names) -> Result<Number, String> {
    let tokens = tokenize(text)?;
    if tokens.is_empty() {
        return Err("the expression is empty".into());
    }
    let mut parser = Parser {
        tokens,
        position: 0,
        names,
        depth: 0,
    };
    let value = parser.or()?;
    if let Some(token) = parser.tokens.get(parser.position) {
        return Err(format!(
            "unexpected `{}` after the expression",
            token.text()
        ));
    }
    Ok(value)
}

#[derive(Clone, Debug, PartialEq)]
enum Token {
    Number(Number),
    Name(String),
    Symbol(&'static str),
}

impl Token {
    fn text(&self) -> String {
        match self {
            Token::Number(number) => number.to_string(),
            Token::Name(name) => name.clone(),
            Token::Symbol(symbol) => (*symbol).to_string(),
        }
    }
}

const SYMBOLS: &[&str] = &[
    "<>", "<=", ">=", "==", "!=", "&&", "||", "<", ">", "=", "+", "-", "*", "/", "%", "(", ")", "!",
];

fn tokenize(text: &str) -> Result<Vec<Token>, String> {
    let bytes = text.as_bytes();
    let mut tokens = Vec::new();
    let mut index = 0;
    while index < bytes.len() {
        let byte = bytes[index];
        if byte.is_ascii_whitespace() {
            index += 1;
        } else if byte.is_ascii_digit()
            || (byte == b'.' && bytes.get(index + 1).is_some_and(u8::is_ascii_digit))
        {
            let start = index;
            while index < bytes.len()
                && (bytes[index].is_ascii_alphanumeric()
                    || bytes[index] == b'.'
                    || ((bytes[index] == b'-' || bytes[index] == b'+')
                        && matches!(bytes[index - 1], b'e' | b'E')))
            {
                index += 1;
            }
            let word = &text[start..index];
            let number = Number::parse(word)
                .ok_or_else(|| format!("`{word}` at column {} is not a number", start + 1))?;
            tokens.push(Token::Number(number));
        } else if byte.is_ascii_alphabetic() || byte == b'_' {
            let start = index;
            while index < bytes.len()
                && (bytes[index].is_ascii_alphanumeric() || bytes[index] == b'_')
            {
                index += 1;
            }
            tokens.push(Token::Name(text[start..index].to_string()));
        } else if let Some(symbol) = SYMBOLS
            .iter()
            .find(|symbol| text[index..].starts_with(**symbol))
        {
            tokens.push(Token::Symbol(symbol));
            index += symbol.len();
        } else {
            let character = text[index..].chars().next().unwrap_or('?');
            return Err(format!("unexpected `{character}` at column {}", index + 1));
        }
    }
    Ok(tokens)
}

struct Parser<'a> {
    tokens: Vec<Token>,
    position: usize,
    names: &'a dyn Names,
    /// Nesting of parentheses and prefix operators, bounded so hostile input cannot
    /// overflow the stack.
    depth: usize,
}

const MAX_DEPTH: usize = 200;

impl Parser<'_> {
    fn peek_is(&self, words: &[&str]) -> Option<String> {
        match self.tokens.get(self.position) {
            Some(Token::Symbol(symbol)) if words.contains(symbol) => Some((*symbol).to_string()),
            Some(Token::Name(name)) if words.iter().any(|word| word.eq_ignore_ascii_case(name)) => {
                Some(name.to_ascii_lowercase())
            }
            _ => None,
        }
    }

    fn or(&mut self) -> Result<Number, String> {
        let mut left = self.and()?;
        while self.peek_is(&["or", "||"]).is_some() {
            self.position += 1;
            let right = self.and()?;
            left = boolean(left.is_true() || right.is_true());
        }
        Ok(left)
    }

    fn and(&mut self) -> Result<Number, String> {
        let mut left = self.not()?;
        while self.peek_is(&["and", "&&"]).is_some() {
            self.position += 1;
            let right = self.not()?;
            left = boolean(left.is_true() && right.is_true());
        }
        Ok(left)
    }

    fn enter(&mut self) -> Result<(), String> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(format!("the expression nests more than {MAX_DEPTH} deep"));
        }
        Ok(())
    }

    fn not(&mut self) -> Result<Number, String> {
        if self.peek_is(&["not", "!"]).is_some() {
            self.position += 1;
            self.enter()?;
            let value = self.not()?;
            self.depth -= 1;
            return Ok(boolean(!value.is_true()));
        }
        self.comparison()
    }

    fn comparison(&mut self) -> Result<Number, String> {
        let left = self.sum()?;
        if let Some(operator) = self.peek_is(&["=", "==", "<>", "!=", "<", "<=", ">", ">="]) {
            self.position += 1;
            let right = self.sum()?;
            let (a, b) = (left.as_f64(), right.as_f64());
            let result = match operator.as_str() {
                "=" | "==" => a == b,
                "<>" | "!=" => a != b,
                "<" => a < b,
                "<=" => a <= b,
                ">" => a > b,
                _ => a >= b,
            };
            return Ok(boolean(result));
        }
        Ok(left)
    }

    fn sum(&mut self) -> Result<Number, String> {
        let mut left = self.product()?;
        while let Some(operator) = self.peek_is(&["+", "-"]) {
            self.position += 1;
            let right = self.product()?;
            left = arithmetic(&operator, left, right)?;
        }
        Ok(left)
    }

    fn product(&mut self) -> Result<Number, String> {
        let mut left = self.unary()?;
        while let Some(operator) = self.peek_is(&["*", "/", "%", "mod"]) {
            self.position += 1;
            let right = self.unary()?;
            left = arithmetic(&operator, left, right)?;
        }
        Ok(left)
    }

    fn unary(&mut self) -> Result<Number, String> {
        if self.peek_is(&["-"]).is_some() {
            self.position += 1;
            self.enter()?;
            let value = match self.unary()? {
                Number::Int(value) => Number::Int(value.wrapping_neg()),
                Number::Float(value) => Number::Float(-value),
            };
            self.depth -= 1;
            return Ok(value);
        }
        if self.peek_is(&["+"]).is_some() {
            self.position += 1;
            self.enter()?;
            let value = self.unary()?;
            self.depth -= 1;
            return Ok(value);
        }
        self.atom()
    }

    fn atom(&mut self) -> Result<Number, String> {
        let token = self.tokens.get(self.position).cloned();
        self.position += 1;
        match token {
            Some(Token::Number(number)) => Ok(number),
            Some(Token::Name(name)) if self.peek_is(&["("]).is_some() => {
                self.position += 1;
                self.enter()?;
                let index = self.or()?;
                self.depth -= 1;
                if self.peek_is(&[")"]).is_none() {
                    return Err(format!("missing `)` after the index of `{name}`"));
                }
                self.position += 1;
                let Number::Int(index) = index else {
                    return Err(format!(
                        "the index of `{name}` must be an integer, not {index}"
                    ));
                };
                self.names
                    .element(&name, index)
                    .ok_or_else(|| format!("`{name}({index})` is not an element of an array"))
            }
            Some(Token::Name(name)) => match name.to_ascii_lowercase().as_str() {
                "true" => Ok(Number::Int(1)),
                "false" => Ok(Number::Int(0)),
                _ => self
                    .names
                    .lookup(&name)
                    .ok_or_else(|| format!("`{name}` is not a variable, register or sensor")),
            },
            Some(Token::Symbol("(")) => {
                self.enter()?;
                let value = self.or()?;
                self.depth -= 1;
                if self.peek_is(&[")"]).is_none() {
                    return Err("missing `)`".into());
                }
                self.position += 1;
                Ok(value)
            }
            Some(token) => Err(format!("expected a value, found `{}`", token.text())),
            None => Err("the expression ends too early".into()),
        }
    }
}

fn boolean(value: bool) -> Number {
    Number::Int(i64::from(value))
}

fn arithmetic(operator: &str, left: Number, right: Number) -> Result<Number, String> {
    if let (Number::Int(a), Number::Int(b)) = (left, right) {
        return match operator {
            "+" => Ok(Number::Int(a.wrapping_add(b))),
            "-" => Ok(Number::Int(a.wrapping_sub(b))),
            "*" => Ok(Number::Int(a.wrapping_mul(b))),
            "/" | "%" | "mod" if b == 0 => Err(DIVISION_BY_ZERO.into()),
            "/" => Ok(Number::Int(a.wrapping_div(b))),
            _ => Ok(Number::Int(a.wrapping_rem(b))),
        };
    }
    let (a, b) = (left.as_f64(), right.as_f64());
    Ok(Number::Float(match operator {
        "+" => a + b,
        "-" => a - b,
        "*" => a * b,
        "/" => a / b,
        _ => a % b,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Fixed;
    impl Names for Fixed {
        fn lookup(&self, name: &str) -> Option<Number> {
            match name.to_ascii_lowercase().as_str() {
                "m_depth" => Some(Number::Float(12.5)),
                "state" => Some(Number::Int(2)),
                _ => None,
            }
        }
        fn element(&self, name: &str, index: i64) -> Option<Number> {
            (name == "a" && (0..3).contains(&index)).then_some(Number::Int(index * 10))
        }
    }

    fn check(text: &str, expected: Number) {
        assert_eq!(evaluate(text, &Fixed), Ok(expected), "{text}");
    }

    #[test]
    fn gbasic_conditions() {
        check("m_depth > 10 and state = 2", Number::Int(1));
        check("m_depth > 15.0", Number::Int(0));
        check("M_DEPTH > 10 AND NOT state <> 2", Number::Int(1));
        check("state = 1 or m_depth < 13", Number::Int(1));
        check("(state + 1) * 2", Number::Int(6));
        check("7 / 2", Number::Int(3));
        check("7.0 / 2", Number::Float(3.5));
        check("-state", Number::Int(-2));
        check("1e-3 * 1000", Number::Float(1.0));
        check("m_depth", Number::Float(12.5));
        check("a(state) + a(0)", Number::Int(20));
    }

    #[test]
    fn a_long_chain_is_a_loop_not_a_recursion() {
        // Chains are folded as they are read (no tree), so only nesting needs a cap.
        // 200,000 terms (20 times what overflowed the compiler's passes) keeps this
        // test near a second in a debug build.
        let chain = |operator: &str| vec!["1"; 200_000].join(operator);
        check(&chain(" + "), Number::Int(200_000));
        check(&chain(" * "), Number::Int(1));
        check(&chain(" or "), Number::Int(1));
        check(&chain(" and "), Number::Int(1));
    }

    #[test]
    fn bad_expressions_are_messages() {
        assert!(evaluate("", &Fixed).is_err());
        let error = |text: &str| evaluate(text, &Fixed).err().unwrap_or_default();
        assert!(error(&"(".repeat(100_000)).contains("nests"));
        assert!(error(&"-".repeat(100_000)).contains("nests"));
        assert!(error(&"not ".repeat(100_000)).contains("nests"));
        assert_eq!(
            evaluate(&format!("{}1{}", "(".repeat(150), ")".repeat(150)), &Fixed),
            Ok(Number::Int(1))
        );
        assert!(error("nope > 1").contains("`nope`"));
        assert!(error("(1 + 2").contains(")"));
        assert!(error("1 / 0").contains("division"));
        assert!(error("1 $ 2").contains("column 3"));
        assert!(error("1 2").contains("unexpected"));
        assert!(error("a(3)").contains("a(3)"));
        assert!(error("a(1.5)").contains("integer"));
    }
}
