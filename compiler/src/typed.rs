//! The typed GBASIC tree: names resolved to symbols, implicit conversions made
//! explicit, constants replaced by their values. Code generation reads only this.

use gloc_engine::sensors::SensorId;
use gloc_engine::Span;

use crate::ast::{BinaryOp, LoopKind};
pub use crate::builtins::Builtin;

/// A GBASIC type. `Error` stands for an expression already reported as wrong; it
/// matches every type so one mistake gives one diagnostic.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Ty {
    Integer,
    Float,
    Error,
}

impl Ty {
    /// The types a `dim` or `const` can give, in the order the editor offers them.
    pub const DECLARABLE: [Ty; 2] = [Ty::Integer, Ty::Float];

    /// As GBASIC spells it (`dim x as float`).
    pub fn name(self) -> &'static str {
        match self {
            Ty::Integer => "integer",
            Ty::Float => "float",
            Ty::Error => "{error}",
        }
    }
}

/// Index into `Symbols::variables`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct VarId(pub usize);

/// Index into `Symbols::labels`; equal to the user label's GLOC number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LabelId(pub usize);

#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    Int(i64),
    Float(f64),
    Variable(VarId),
    Sensor(SensorId),
    Element {
        array: VarId,
        index: Box<Expr>,
    },
    Neg(Box<Expr>),
    /// Logical not: 1 when the operand is 0, else 0.
    Not(Box<Expr>),
    /// Both operands have the operation's operand type (already converted).
    Binary {
        op: BinaryOp,
        left: Box<Expr>,
        right: Box<Expr>,
    },
    Call {
        builtin: Builtin,
        args: Vec<Expr>,
    },
    /// Integer to float (implicit widening or `float()`).
    ToFloat(Box<Expr>),
    Error,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub ty: Ty,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Place {
    Variable(VarId),
    Sensor(SensorId),
    Element { array: VarId, index: Box<Expr> },
    Error,
}

#[derive(Clone, Debug, PartialEq)]
pub enum PrintItem {
    Expr(Expr),
    Text(String),
}

pub type IfArm = crate::ast::Arm<Expr, Stmt>;

#[derive(Clone, Debug, PartialEq)]
pub enum StmtKind {
    Assign {
        place: Place,
        value: Expr,
    },
    If {
        arms: Vec<IfArm>,
        else_body: Option<Vec<Stmt>>,
    },
    Label(LabelId),
    Goto(LabelId),
    While {
        condition: Expr,
        body: Vec<Stmt>,
    },
    Do {
        /// `(until, condition)` after `do`; boxed, as the rare large fields below
        /// are: a statement is as large as its largest variant.
        pre: Option<Box<(bool, Expr)>>,
        body: Vec<Stmt>,
        /// `(until, condition)` after `loop`.
        post: Option<Box<(bool, Expr)>>,
    },
    For {
        variable: VarId,
        from: Box<Expr>,
        to: Box<Expr>,
        step: Option<Box<Expr>>,
        body: Vec<Stmt>,
        /// How many times the body runs, when the limits are constants and the body
        /// neither assigns the variable nor holds a label (so it can only be entered
        /// from the top). Passed to the GLOC checker as a loop bound.
        trip_count: Option<u64>,
        /// Span of `next`.
        next_span: Span,
    },
    Exit(LoopKind),
    Yield,
    End,
    Print(Vec<PrintItem>),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Stmt {
    pub kind: StmtKind,
    pub span: Span,
}

/// What a name in the program stands for.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    /// As first declared.
    pub name: String,
    pub ty: Ty,
    /// `Some(n)` for an array of n elements.
    pub size: Option<usize>,
    pub definition: Span,
    pub references: Vec<Span>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Constant {
    pub name: String,
    pub ty: Ty,
    /// The value as GBASIC prints it.
    pub value: String,
    pub definition: Span,
    pub references: Vec<Span>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    pub name: String,
    /// A `goto` to a label the program does not define is an error, not a label.
    pub definition: Span,
    pub references: Vec<Span>,
}

/// A sensor named in the program.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorUse {
    pub sensor: u32,
    pub name: String,
    pub reads: Vec<Span>,
    pub writes: Vec<Span>,
}

/// Every name of a program, with its definition and references.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Symbols {
    pub variables: Vec<Variable>,
    pub constants: Vec<Constant>,
    pub labels: Vec<Label>,
    /// Sensors in order of first use.
    pub sensors: Vec<SensorUse>,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Program {
    pub body: Vec<Stmt>,
}
