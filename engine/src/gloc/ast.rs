//! GLOC as written: one [`Line`] per source line, with byte spans, before any
//! validation. The printer turns it back into canonical text.

use crate::diagnostic::Span;

/// A whole GLOC file: every source line, in order (blank and comment lines too).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct File {
    pub lines: Vec<Line>,
}

/// One source line.
#[derive(Clone, Debug, PartialEq)]
pub struct Line {
    /// 1-based line number.
    pub number: u32,
    /// The line's text without its line end (`\n` or `\r\n`).
    pub span: Span,
    pub kind: LineKind,
    /// A `#` comment to the end of the line, as written (starting with `#`).
    pub comment: Option<String>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum LineKind {
    /// Nothing but spaces (and maybe a comment).
    Blank,
    /// A header line such as `nregs 8`.
    Directive(Directive),
    /// `label N`.
    Label(LabelDef),
    Instruction(Instruction),
    /// A line that could not be parsed; kept verbatim so printing loses nothing.
    Invalid {
        text: String,
    },
}

impl LineKind {
    /// True for the lines that `ninstr` counts: labels, instructions and
    /// lines that failed to parse.
    pub fn is_statement(&self) -> bool {
        matches!(
            self,
            LineKind::Label(_) | LineKind::Instruction(_) | LineKind::Invalid { .. }
        )
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectiveKind {
    Nregs,
    /// The paper's spelling of the label count.
    Nblbs,
    /// Accepted alias of `nblbs`.
    Nlbls,
    Ninstr,
    /// Words of array memory (our extension; default 0).
    Nmem,
}

impl DirectiveKind {
    pub fn keyword(self) -> &'static str {
        match self {
            DirectiveKind::Nregs => "nregs",
            DirectiveKind::Nblbs => "nblbs",
            DirectiveKind::Nlbls => "nlbls",
            DirectiveKind::Ninstr => "ninstr",
            DirectiveKind::Nmem => "nmem",
        }
    }

    pub fn from_keyword(word: &str) -> Option<DirectiveKind> {
        Some(match word {
            "nregs" => DirectiveKind::Nregs,
            "nblbs" => DirectiveKind::Nblbs,
            "nlbls" => DirectiveKind::Nlbls,
            "ninstr" => DirectiveKind::Ninstr,
            "nmem" => DirectiveKind::Nmem,
            _ => return None,
        })
    }

    /// `nlbls` and `nblbs` declare the same thing.
    pub fn is_label_count(self) -> bool {
        matches!(self, DirectiveKind::Nblbs | DirectiveKind::Nlbls)
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Directive {
    pub kind: DirectiveKind,
    pub keyword_span: Span,
    pub value: u64,
    pub value_span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub struct LabelDef {
    pub number: u32,
    pub number_span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Instruction {
    pub opcode: Opcode,
    pub opcode_span: Span,
    /// Operands in source order (sources first, destination last). The parser
    /// guarantees they match `opcode.signature()`.
    pub operands: Vec<Operand>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Operand {
    pub kind: OperandKind,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub enum OperandKind {
    /// `rN`.
    Register(u32),
    /// A literal without a point or exponent: an integer, a sensor index or a label number.
    Integer(i64),
    /// A literal with a point or an exponent.
    Float(f64),
    /// `"text"`, unescaped.
    Text(String),
    /// A word that is no register and no number: a sensor named by name
    /// (`loads m_depth,r0`), resolved against the active list by the checker.
    Name(String),
}

/// What an operand position accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OperandShape {
    /// `rN`.
    Register,
    /// A sensor: its index (a non-negative integer literal) or its name.
    Sensor,
    /// A label number (a non-negative integer literal).
    Label,
    /// An integer literal.
    Integer,
    /// An integer or float literal (read as a float).
    Number,
    /// A memory address: a register or a non-negative integer literal.
    Address,
    /// A string literal.
    Text,
}

impl OperandShape {
    pub fn describe(self) -> &'static str {
        match self {
            OperandShape::Register => "a register such as `r0`",
            OperandShape::Sensor => "a sensor name or index such as `m_depth` or `444`",
            OperandShape::Label => "a label number such as `3`",
            OperandShape::Integer => "an integer such as `128`",
            OperandShape::Number => "a number such as `15.0`",
            OperandShape::Address => "a memory address (a register or an integer)",
            OperandShape::Text => "a string such as \"depth\"",
        }
    }

    /// How the shape is written in a usage line (`cbr rC,Ltrue,Lfalse`).
    fn placeholder(self) -> &'static str {
        match self {
            OperandShape::Register => "r",
            OperandShape::Sensor => "SENSOR",
            OperandShape::Label => "LABEL",
            OperandShape::Integer => "INT",
            OperandShape::Number => "NUM",
            OperandShape::Address => "ADDR",
            OperandShape::Text => "\"TEXT\"",
        }
    }
}

/// Where an instruction comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// Used in the paper's Fig. 2.
    Paper,
    /// Added by this project.
    Ours,
}

macro_rules! opcodes {
    ($( $variant:ident $name:literal $origin:ident [$($shape:ident),*] $semantics:literal; )*) => {
        /// Every GLOC instruction except `label` (which is a [`LineKind::Label`]).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum Opcode {
            $( #[doc = $semantics] $variant, )*
        }

        impl Opcode {
            pub const ALL: &'static [Opcode] = &[$(Opcode::$variant),*];

            pub fn name(self) -> &'static str {
                match self { $(Opcode::$variant => $name,)* }
            }

            pub fn signature(self) -> &'static [OperandShape] {
                match self { $(Opcode::$variant => &[$(OperandShape::$shape),*],)* }
            }

            pub fn origin(self) -> Origin {
                match self { $(Opcode::$variant => Origin::$origin,)* }
            }

            /// The opcode for a lower-case mnemonic.
            pub fn from_name(name: &str) -> Option<Opcode> {
                match name { $($name => Some(Opcode::$variant),)* _ => None }
            }

            /// One line of semantics, e.g. `dst := a + b`.
            pub fn semantics(self) -> &'static str {
                match self { $(Opcode::$variant => $semantics,)* }
            }
        }
    };
}

opcodes! {
    Loads "loads" Paper [Sensor, Register] "dst := sensor[S] (always a float)";
    Stores "stores" Paper [Register, Sensor] "sensor[S] := float(src)";
    Loadi "loadi" Paper [Integer, Register] "dst := integer literal";
    Loadd "loadd" Paper [Number, Register] "dst := float literal";
    Cmpgt "cmpgt" Paper [Register, Register, Register] "dst := a > b ? 1 : 0";
    Cmplt "cmplt" Paper [Register, Register, Register] "dst := a < b ? 1 : 0";
    Cbr "cbr" Paper [Register, Label, Label] "goto (c != 0 ? Ltrue : Lfalse)";
    Jumpi "jumpi" Paper [Label] "goto L";
    Yield "yield" Paper [] "end this control cycle; the next cycle continues after the yield";
    Jump "jump" Ours [Register] "goto label number held in r (any label may be the target)";
    Mov "mov" Ours [Register, Register] "dst := a (register copy)";
    Add "add" Ours [Register, Register, Register] "dst := a + b";
    Sub "sub" Ours [Register, Register, Register] "dst := a - b";
    Mul "mul" Ours [Register, Register, Register] "dst := a * b";
    Div "div" Ours [Register, Register, Register] "dst := a / b (integer division truncates; integer b = 0 traps)";
    Mod "mod" Ours [Register, Register, Register] "dst := a mod b (sign of a; integer b = 0 traps)";
    Neg "neg" Ours [Register, Register] "dst := -a";
    Abs "abs" Ours [Register, Register] "dst := |a|";
    Sqrt "sqrt" Ours [Register, Register] "dst := sqrt(float(a)) (a float; NaN for a < 0)";
    Min "min" Ours [Register, Register, Register] "dst := min(a, b)";
    Max "max" Ours [Register, Register, Register] "dst := max(a, b)";
    I2d "i2d" Ours [Register, Register] "dst := float(a)";
    D2i "d2i" Ours [Register, Register] "dst := int(a) (truncates toward zero, saturates; NaN gives 0)";
    And "and" Ours [Register, Register, Register] "dst := int(a) & int(b) (bitwise)";
    Or "or" Ours [Register, Register, Register] "dst := int(a) | int(b) (bitwise)";
    Xor "xor" Ours [Register, Register, Register] "dst := int(a) ^ int(b) (bitwise)";
    Not "not" Ours [Register, Register] "dst := a == 0 ? 1 : 0 (logical)";
    Cmpeq "cmpeq" Ours [Register, Register, Register] "dst := a == b ? 1 : 0";
    Cmpne "cmpne" Ours [Register, Register, Register] "dst := a != b ? 1 : 0";
    Cmple "cmple" Ours [Register, Register, Register] "dst := a <= b ? 1 : 0";
    Cmpge "cmpge" Ours [Register, Register, Register] "dst := a >= b ? 1 : 0";
    Loadm "loadm" Ours [Address, Register] "dst := memory[addr] (bounds-checked)";
    Storem "storem" Ours [Register, Address] "memory[addr] := src (bounds-checked)";
    Write "write" Ours [Register] "append the value of r to the output line";
    Writes "writes" Ours [Text] "append the text to the output line";
    Print "print" Ours [Register] "append the value of r and end the output line";
    Prints "prints" Ours [Text] "append the text and end the output line";
    Halt "halt" Ours [] "stop the script for the rest of the mission";
    Nop "nop" Ours [] "do nothing";
}

impl Opcode {
    /// The usage line, e.g. `cbr r,LABEL,LABEL`.
    pub fn usage(self) -> String {
        let operands: Vec<&str> = self
            .signature()
            .iter()
            .map(|shape| shape.placeholder())
            .collect();
        if operands.is_empty() {
            self.name().to_string()
        } else {
            format!("{} {}", self.name(), operands.join(","))
        }
    }
}

impl File {
    /// The statement lines (labels, instructions and invalid lines).
    pub fn statements(&self) -> impl Iterator<Item = &Line> {
        self.lines.iter().filter(|line| line.kind.is_statement())
    }

    /// The first directive of a kind (`nblbs` and `nlbls` count as one kind).
    pub fn directive(&self, kind: DirectiveKind) -> Option<&Directive> {
        self.lines.iter().find_map(|line| match &line.kind {
            LineKind::Directive(directive)
                if directive.kind == kind
                    || (kind.is_label_count() && directive.kind.is_label_count()) =>
            {
                Some(directive)
            }
            _ => None,
        })
    }
}
