//! The untyped GBASIC syntax tree, as written (names keep their spelling and span).

/// GBASIC's comparisons are the machine's, one type for the lexer, the tree and the
/// code.
pub use gloc_engine::vm::Cmp;
use gloc_engine::Span;

/// A name as written. Its lookup key, the lower-cased spelling, is made when asked
/// ([`Name::key`]) rather than stored: a tree holds millions of names at most, and a
/// second string each doubled their cost.
#[derive(Clone, Debug, PartialEq)]
pub struct Name {
    pub text: String,
    pub span: Span,
}

impl Name {
    pub fn new(text: &str, span: Span) -> Name {
        Name {
            text: text.to_string(),
            span,
        }
    }

    /// The lower-cased spelling, used for every lookup (GBASIC ignores case):
    /// borrowed when the name is already lower case, as most are (an allocation per
    /// lookup showed in the compile bench).
    pub fn key(&self) -> std::borrow::Cow<'_, str> {
        if self.text.bytes().any(|byte| byte.is_ascii_uppercase()) {
            std::borrow::Cow::Owned(self.text.to_ascii_lowercase())
        } else {
            std::borrow::Cow::Borrowed(&self.text)
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TypeName {
    Integer,
    Float,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Literal {
    Int(i64),
    Float(f64),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinaryOp {
    Add,
    Sub,
    Mul,
    /// `/`: always float division.
    Div,
    /// `\`: integer division.
    IntDiv,
    Mod,
    /// `= <> < <= > >=`.
    Compare(Cmp),
    And,
    Or,
}

impl BinaryOp {
    pub fn symbol(self) -> &'static str {
        match self {
            BinaryOp::Add => "+",
            BinaryOp::Sub => "-",
            BinaryOp::Mul => "*",
            BinaryOp::Div => "/",
            BinaryOp::IntDiv => "\\",
            BinaryOp::Mod => "mod",
            BinaryOp::Compare(cmp) => match cmp {
                Cmp::Eq => "=",
                Cmp::Ne => "<>",
                Cmp::Lt => "<",
                Cmp::Le => "<=",
                Cmp::Gt => ">",
                Cmp::Ge => ">=",
            },
            BinaryOp::And => "and",
            BinaryOp::Or => "or",
        }
    }

    /// The machine operation that computes it, once the operands have the types
    /// the checker made explicit. `and`/`or` are logical: each operand is made 0 or
    /// 1 first (`cmpne x, 0`), then the bitwise operation is applied to those.
    /// Code generation and the debugger's evaluator both take it from here.
    pub fn machine_operation(self) -> gloc_engine::vm::BinaryOperation {
        use gloc_engine::vm::BinaryOperation as M;
        match self {
            BinaryOp::Add => M::Add,
            BinaryOp::Sub => M::Sub,
            BinaryOp::Mul => M::Mul,
            // `/` has float operands by then, `\` integer ones: one `div` for both.
            BinaryOp::Div | BinaryOp::IntDiv => M::Div,
            BinaryOp::Mod => M::Mod,
            BinaryOp::Compare(cmp) => M::compare(cmp),
            BinaryOp::And => M::And,
            BinaryOp::Or => M::Or,
        }
    }

    /// How tightly it binds: 0 for `or`, the loosest, up to [`BinaryOp::LEVELS`]` - 1`
    /// for `*` and `/`. The prefix `not` binds between `and` and the comparisons, the
    /// prefix minus tighter than all; operators of one level group from the left.
    pub const fn precedence(self) -> usize {
        match self {
            BinaryOp::Or => 0,
            BinaryOp::And => 1,
            BinaryOp::Compare(_) => 2,
            BinaryOp::Add | BinaryOp::Sub => 3,
            BinaryOp::Mod => 4,
            BinaryOp::IntDiv => 5,
            BinaryOp::Mul | BinaryOp::Div => 6,
        }
    }

    /// The number of precedence levels.
    pub const LEVELS: usize = 7;

    pub fn is_comparison(self) -> bool {
        matches!(self, BinaryOp::Compare(_))
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnaryOp {
    Neg,
    Not,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    Literal(Literal),
    Name(Name),
    /// `name(args)`: an array element or a built-in call; the checker decides.
    Call {
        /// Boxed, as the rare large fields below are: an expression or a statement
        /// is as large as its largest variant, and a tree holds millions.
        name: Box<Name>,
        args: Vec<Expr>,
    },
    Unary {
        op: UnaryOp,
        operand: Box<Expr>,
    },
    Binary {
        op: BinaryOp,
        left: Box<Expr>,
        right: Box<Expr>,
    },
    /// A syntax error stood here; already reported.
    Error,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

/// The left side of an assignment.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    Name(Name),
    Element { name: Name, index: Box<Expr> },
}

impl Target {
    pub fn name(&self) -> &Name {
        match self {
            Target::Name(name) | Target::Element { name, .. } => name,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub enum PrintItem {
    Expr(Expr),
    Text { text: String, span: Span },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoopKind {
    For,
    Do,
    While,
}

impl LoopKind {
    pub fn keyword(self) -> &'static str {
        match self {
            LoopKind::For => "for",
            LoopKind::Do => "do",
            LoopKind::While => "while",
        }
    }
}

/// `while`/`until` on a `do` loop.
#[derive(Clone, Debug, PartialEq)]
pub struct DoCondition {
    pub until: bool,
    pub expr: Expr,
}

/// One `if`/`elseif` arm: of the parsed tree ([`IfArm`]) or of the checked one
/// ([`crate::typed::IfArm`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Arm<E, S> {
    pub condition: E,
    pub body: Vec<S>,
    /// The span of the `if`/`elseif` keyword through `then`.
    pub span: Span,
}

pub type IfArm = Arm<Expr, Stmt>;

#[derive(Clone, Debug, PartialEq)]
pub enum StmtKind {
    Dim {
        name: Name,
        size: Option<ArraySize>,
        ty: TypeName,
    },
    Const {
        name: Name,
        value: Literal,
    },
    Assign {
        target: Target,
        value: Expr,
    },
    If {
        arms: Vec<IfArm>,
        else_body: Option<Vec<Stmt>>,
        /// Span of the closing `endif`, if any.
        end_span: Option<Span>,
    },
    Label(Name),
    Goto(Name),
    While {
        condition: Expr,
        body: Vec<Stmt>,
        end_span: Option<Span>,
    },
    Do {
        pre: Option<Box<DoCondition>>,
        body: Vec<Stmt>,
        post: Option<Box<DoCondition>>,
        end_span: Option<Span>,
    },
    For {
        variable: Name,
        from: Box<Expr>,
        to: Box<Expr>,
        step: Option<Box<Expr>>,
        body: Vec<Stmt>,
        end_span: Option<Span>,
    },
    Exit(LoopKind),
    Yield,
    End,
    Print(Vec<PrintItem>),
}

/// An array size: an integer literal or the name of an integer constant.
#[derive(Clone, Debug, PartialEq)]
pub enum ArraySize {
    Literal { value: i64, span: Span },
    Const(Name),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Stmt {
    pub kind: StmtKind,
    /// The statement's first line (for a block: its header line).
    pub span: Span,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Program {
    pub body: Vec<Stmt>,
}
