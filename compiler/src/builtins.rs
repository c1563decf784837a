//! GBASIC's built-in functions, one table: name, parameters and their types, the
//! result type, the GLOC instruction, and the one-line doc. The checker types calls
//! from it, code generation picks the instruction from it, the editor's hover,
//! completion and signature help show its text, and names are reserved by it.

use crate::ir::{Op1, Op2};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Builtin {
    Abs,
    Sqrt,
    Min,
    Max,
    /// `int(x)`: float to integer (truncates toward zero).
    Int,
    /// `float(x)`: integer to float.
    Float,
}

/// What a parameter accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    /// An integer or a float. When the result is [`Returns::Widest`], every argument
    /// is brought to the result's type; otherwise it is kept as it is.
    Number,
    /// A float; an integer argument is converted to float.
    Float,
}

/// The type of a call's value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Returns {
    Integer,
    Float,
    /// Float when any argument is a float, else integer.
    Widest,
}

/// The GLOC instruction a call compiles to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Instruction {
    Unary(Op1),
    Binary(Op2),
}

/// One built-in function.
#[derive(Clone, Copy, Debug)]
pub struct BuiltinInfo {
    pub builtin: Builtin,
    /// Lower case, as GBASIC's case-insensitive names are keyed.
    pub name: &'static str,
    /// Each parameter's name (as the signature shows it) and what it accepts.
    pub params: &'static [(&'static str, Param)],
    pub returns: Returns,
    pub instruction: Instruction,
    /// One line: what the value is.
    pub doc: &'static str,
}

/// Every built-in, in the order the editor lists them.
pub const BUILTINS: &[BuiltinInfo] = &[
    BuiltinInfo {
        builtin: Builtin::Abs,
        name: "abs",
        params: &[("x", Param::Number)],
        returns: Returns::Widest,
        instruction: Instruction::Unary(Op1::Abs),
        doc: "|x|, same type as x",
    },
    BuiltinInfo {
        builtin: Builtin::Sqrt,
        name: "sqrt",
        params: &[("x", Param::Float)],
        returns: Returns::Float,
        instruction: Instruction::Unary(Op1::Sqrt),
        doc: "square root, a float",
    },
    BuiltinInfo {
        builtin: Builtin::Min,
        name: "min",
        params: &[("a", Param::Number), ("b", Param::Number)],
        returns: Returns::Widest,
        instruction: Instruction::Binary(Op2::Min),
        doc: "the smaller; float if either is",
    },
    BuiltinInfo {
        builtin: Builtin::Max,
        name: "max",
        params: &[("a", Param::Number), ("b", Param::Number)],
        returns: Returns::Widest,
        instruction: Instruction::Binary(Op2::Max),
        doc: "the larger; float if either is",
    },
    BuiltinInfo {
        builtin: Builtin::Int,
        name: "int",
        params: &[("x", Param::Number)],
        returns: Returns::Integer,
        instruction: Instruction::Unary(Op1::D2i),
        doc: "float to integer, truncating toward zero",
    },
    BuiltinInfo {
        builtin: Builtin::Float,
        name: "float",
        params: &[("x", Param::Float)],
        returns: Returns::Float,
        instruction: Instruction::Unary(Op1::I2d),
        doc: "integer to float",
    },
];

impl Builtin {
    /// The built-in called `name` (lower case).
    pub fn of_name(name: &str) -> Option<Builtin> {
        BuiltinInfo::of_name(name).map(|info| info.builtin)
    }

    pub fn info(self) -> &'static BuiltinInfo {
        // The table has one row per variant, in declaration order (a test checks).
        &BUILTINS[self as usize]
    }

    pub fn name(self) -> &'static str {
        self.info().name
    }

    pub fn arity(self) -> usize {
        self.info().params.len()
    }

    /// `int(x)` and `float(x)`: a call of one on a value already of its type is
    /// that value.
    pub fn is_conversion(self) -> bool {
        matches!(self, Builtin::Int | Builtin::Float)
    }
}

impl BuiltinInfo {
    /// The row for `name` (lower case).
    pub fn of_name(name: &str) -> Option<&'static BuiltinInfo> {
        BUILTINS.iter().find(|info| info.name == name)
    }

    /// `max(a, b)`.
    pub fn signature(&self) -> String {
        self.signature_and_params().0
    }

    /// [`signature`](Self::signature) and the byte range of each parameter's name in it.
    pub fn signature_and_params(&self) -> (String, Vec<(usize, usize)>) {
        let mut signature = format!("{}(", self.name);
        let mut ranges = Vec::with_capacity(self.params.len());
        for (position, (param, _)) in self.params.iter().enumerate() {
            if position > 0 {
                signature.push_str(", ");
            }
            ranges.push((signature.len(), signature.len() + param.len()));
            signature.push_str(param);
        }
        signature.push(')');
        (signature, ranges)
    }

    /// `max(a, b): the larger; float if either is`: signature and doc on one line.
    pub fn summary(&self) -> String {
        format!("{}: {}", self.signature(), self.doc)
    }
}

/// "abs, sqrt, min, max, int and float".
pub fn names_in_prose() -> String {
    let names: Vec<&str> = BUILTINS.iter().map(|info| info.name).collect();
    match names.split_last() {
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn info_finds_each_variants_own_row() {
        for (position, info) in BUILTINS.iter().enumerate() {
            assert_eq!(info.builtin as usize, position, "{}", info.name);
            assert_eq!(info.builtin.info().name, info.name);
            assert_eq!(Builtin::of_name(info.name), Some(info.builtin));
        }
        assert_eq!(Builtin::of_name("sqr"), None);
        assert_eq!(names_in_prose(), "abs, sqrt, min, max, int and float");
        assert_eq!(
            Builtin::Max.info().signature_and_params(),
            ("max(a, b)".to_string(), vec![(4, 5), (7, 8)])
        );
    }
}
