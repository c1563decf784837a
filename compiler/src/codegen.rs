//! Code generation from the typed tree to GLOC, in the paper's scheme: user labels are
//! numbered first in order of definition, then each `if`'s two labels (and each loop's)
//! as they are met; every value gets a fresh register. Scalar variables live in
//! registers allocated before the temporaries; arrays live in memory cells.

use gloc_engine::Span;

use crate::ast::{BinaryOp, LoopKind};
use crate::builtins::Instruction;
use crate::ir::{Addr, Code, Instr, Lbl, Op1, Op2, Reg};
use crate::typed::{self, ExprKind, Place, Symbols, Ty, VarId};

/// Where a variable lives at run time.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase", tag = "kind")]
pub enum Storage {
    Register { register: u32 },
    Memory { base: u32, size: u32 },
}

/// A `for` loop whose trip count is known, for the GLOC checker's loop bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ForBound {
    /// The label at the loop's test (the loop header in the GLOC control-flow graph).
    pub header: Lbl,
    /// The most times control enters the header from the back edge.
    pub trip_count: u64,
}

pub struct Generated {
    pub code: Code,
    /// Indexed by `VarId`.
    pub storage: Vec<Storage>,
    pub for_bounds: Vec<ForBound>,
}

pub fn generate(program: &typed::Program, symbols: &Symbols) -> Generated {
    let mut generator = Generator {
        code: Code::default(),
        next_register: 0,
        next_label: symbols.labels.len() as u32,
        storage: Vec::new(),
        loops: Vec::new(),
        for_bounds: Vec::new(),
        span: Span::default(),
    };
    let mut memory = 0u32;
    for variable in &symbols.variables {
        let storage = match variable.size {
            None => Storage::Register {
                register: generator.fresh().0,
            },
            Some(size) => {
                let size = size as u32;
                let base = memory;
                memory = memory.saturating_add(size);
                Storage::Memory { base, size }
            }
        };
        generator.storage.push(storage);
    }
    generator.code.memory_size = memory;
    // Registers start as integer 0; float variables start as 0.0.
    for (index, variable) in symbols.variables.iter().enumerate() {
        if let (Storage::Register { register }, Ty::Float) = (generator.storage[index], variable.ty)
        {
            generator.span = variable.definition;
            generator.emit(Instr::LoadD {
                value: 0.0,
                dst: Reg(register),
            });
        }
    }
    // Falling off the end stops the script (the GLOC checker appends a `halt`).
    generator.block(&program.body);
    generator.code.register_count = generator.next_register;
    generator.code.label_count = generator.next_label;
    Generated {
        code: generator.code,
        storage: generator.storage,
        for_bounds: generator.for_bounds,
    }
}

struct OpenLoop {
    kind: LoopKind,
    exit: Lbl,
}

struct Generator {
    code: Code,
    next_register: u32,
    next_label: u32,
    storage: Vec<Storage>,
    loops: Vec<OpenLoop>,
    for_bounds: Vec<ForBound>,
    /// The GBASIC span of the statement or expression being compiled.
    span: Span,
}

impl Generator {
    fn fresh(&mut self) -> Reg {
        let register = Reg(self.next_register);
        self.next_register += 1;
        register
    }

    fn label(&mut self) -> Lbl {
        let label = Lbl(self.next_label);
        self.next_label += 1;
        label
    }

    fn emit(&mut self, instr: Instr) {
        self.code.push(instr, self.span);
    }

    /// `a op b` into a fresh register.
    fn binary(&mut self, op: Op2, a: Reg, b: Reg) -> Reg {
        let dst = self.fresh();
        self.emit(Instr::Binary { op, a, b, dst });
        dst
    }

    /// An integer constant in a fresh register.
    fn load_int(&mut self, value: i64) -> Reg {
        let dst = self.fresh();
        self.emit(Instr::LoadI { value, dst });
        dst
    }

    /// A float constant in a fresh register.
    fn load_float(&mut self, value: f64) -> Reg {
        let dst = self.fresh();
        self.emit(Instr::LoadD { value, dst });
        dst
    }

    /// `cbr cond, on_true, on_false`.
    fn branch(&mut self, cond: Reg, on_true: Lbl, on_false: Lbl) {
        self.emit(Instr::Cbr {
            cond,
            on_true,
            on_false,
        });
    }

    fn block(&mut self, body: &[typed::Stmt]) {
        for stmt in body {
            self.stmt(stmt);
        }
    }

    fn stmt(&mut self, stmt: &typed::Stmt) {
        self.span = stmt.span;
        match &stmt.kind {
            typed::StmtKind::Assign { place, value } => self.assign(place, value, stmt.span),
            typed::StmtKind::If { arms, else_body } => {
                self.if_chain(arms, else_body.as_deref(), stmt.span)
            }
            typed::StmtKind::Label(label) => self.emit(Instr::Label(Lbl(label.0 as u32))),
            typed::StmtKind::Goto(label) => self.emit(Instr::Jumpi(Lbl(label.0 as u32))),
            typed::StmtKind::While { condition, body } => {
                let top = self.label();
                let enter = self.label();
                let exit = self.label();
                self.emit(Instr::Label(top));
                let condition = self.expr(condition);
                self.span = stmt.span;
                self.branch(condition, enter, exit);
                self.emit(Instr::Label(enter));
                self.loop_body(LoopKind::While, exit, body);
                self.span = stmt.span;
                self.emit(Instr::Jumpi(top));
                self.emit(Instr::Label(exit));
            }
            typed::StmtKind::Do { pre, body, post } => {
                let top = self.label();
                let exit = self.label();
                self.emit(Instr::Label(top));
                if let Some((until, condition)) = pre.as_deref() {
                    let enter = self.label();
                    let condition = self.expr(condition);
                    self.span = stmt.span;
                    let (on_true, on_false) = if *until { (exit, enter) } else { (enter, exit) };
                    self.branch(condition, on_true, on_false);
                    self.emit(Instr::Label(enter));
                }
                self.loop_body(LoopKind::Do, exit, body);
                match post.as_deref() {
                    Some((until, condition)) => {
                        self.span = condition.span;
                        let condition = self.expr(condition);
                        let (on_true, on_false) = if *until { (exit, top) } else { (top, exit) };
                        self.branch(condition, on_true, on_false);
                    }
                    None => {
                        self.span = stmt.span;
                        self.emit(Instr::Jumpi(top));
                    }
                }
                self.emit(Instr::Label(exit));
            }
            typed::StmtKind::For {
                variable,
                from,
                to,
                step,
                body,
                trip_count,
                next_span,
            } => self.for_loop(
                stmt.span,
                *variable,
                from,
                to,
                step.as_deref(),
                body,
                *trip_count,
                *next_span,
            ),
            typed::StmtKind::Exit(kind) => {
                let exit = self
                    .loops
                    .iter()
                    .rev()
                    .find(|open| open.kind == *kind)
                    .map(|open| open.exit);
                if let Some(exit) = exit {
                    self.emit(Instr::Jumpi(exit));
                }
            }
            typed::StmtKind::Yield => self.emit(Instr::Yield),
            typed::StmtKind::End => self.emit(Instr::Halt),
            typed::StmtKind::Print(items) => self.print(items, stmt.span),
        }
    }

    /// `if … elseif … else … endif`: each arm's test, its body, a jump to the end.
    fn if_chain(&mut self, arms: &[typed::IfArm], else_body: Option<&[typed::Stmt]>, span: Span) {
        let mut end = None;
        let last_arm = arms.len().saturating_sub(1);
        for (index, arm) in arms.iter().enumerate() {
            self.span = arm.span;
            let condition = self.expr(&arm.condition);
            let on_true = self.label();
            let on_false = self.label();
            let has_more = index < last_arm || else_body.is_some();
            if has_more && end.is_none() {
                end = Some(self.label());
            }
            self.span = arm.span;
            self.branch(condition, on_true, on_false);
            self.emit(Instr::Label(on_true));
            self.block(&arm.body);
            self.span = arm.span;
            if let (true, Some(end)) = (has_more, end) {
                self.emit(Instr::Jumpi(end));
            }
            self.emit(Instr::Label(on_false));
        }
        if let Some(body) = else_body {
            self.block(body);
        }
        if let Some(end) = end {
            self.span = span;
            self.emit(Instr::Label(end));
        }
    }

    /// `print`: every item but the last written, the last printed (ending the line).
    fn print(&mut self, items: &[typed::PrintItem], span: Span) {
        if items.is_empty() {
            self.emit(Instr::Prints(String::new()));
        }
        let last = items.len().saturating_sub(1);
        for (index, item) in items.iter().enumerate() {
            let ends_line = index == last;
            match item {
                typed::PrintItem::Text(text) => {
                    self.span = span;
                    self.emit(if ends_line {
                        Instr::Prints(text.clone())
                    } else {
                        Instr::Writes(text.clone())
                    });
                }
                typed::PrintItem::Expr(expr) => {
                    let register = self.expr(expr);
                    self.span = span;
                    self.emit(if ends_line {
                        Instr::Print(register)
                    } else {
                        Instr::Write(register)
                    });
                }
            }
        }
    }

    fn loop_body(&mut self, kind: LoopKind, exit: Lbl, body: &[typed::Stmt]) {
        self.loops.push(OpenLoop { kind, exit });
        self.block(body);
        self.loops.pop();
    }

    #[allow(clippy::too_many_arguments)]
    fn for_loop(
        &mut self,
        span: Span,
        variable: VarId,
        from: &typed::Expr,
        to: &typed::Expr,
        step: Option<&typed::Expr>,
        body: &[typed::Stmt],
        trip_count: Option<u64>,
        next_span: Span,
    ) {
        let Some(Storage::Register { register }) = self.storage.get(variable.0).copied() else {
            return;
        };
        let counter = Reg(register);
        let start = self.expr(from);
        self.span = span;
        self.emit(Instr::Mov {
            src: start,
            dst: counter,
        });
        // The limit and the step are evaluated once, before the first test.
        let limit = self.expr(to);
        let (step_register, step_sign) = match step {
            None => {
                self.span = span;
                let register = self.load_int(1);
                (register, Some(true))
            }
            Some(step) => {
                let sign = match crate::check::constant_of(step) {
                    Some(crate::ast::Literal::Int(value)) => Some(value >= 0),
                    Some(crate::ast::Literal::Float(value)) => Some(value >= 0.0),
                    None => None,
                };
                (self.expr(step), sign)
            }
        };
        let test = self.label();
        let enter = self.label();
        let exit = self.label();
        self.span = span;
        self.emit(Instr::Label(test));
        let condition = match step_sign {
            Some(upward) => {
                let op = if upward { Op2::CmpLe } else { Op2::CmpGe };
                self.binary(op, counter, limit)
            }
            None => {
                // A step of unknown sign: (step >= 0 and v <= limit) or (step < 0 and v >= limit).
                let zero = if step.is_some_and(|step| step.ty == Ty::Float) {
                    self.load_float(0.0)
                } else {
                    self.load_int(0)
                };
                let upward = self.binary(Op2::CmpGe, step_register, zero);
                let below = self.binary(Op2::CmpLe, counter, limit);
                let first = self.binary(Op2::And, upward, below);
                let downward = self.binary(Op2::CmpLt, step_register, zero);
                let above = self.binary(Op2::CmpGe, counter, limit);
                let second = self.binary(Op2::And, downward, above);
                self.binary(Op2::Or, first, second)
            }
        };
        self.branch(condition, enter, exit);
        self.emit(Instr::Label(enter));
        self.loop_body(LoopKind::For, exit, body);
        self.span = next_span;
        self.emit(Instr::Binary {
            op: Op2::Add,
            a: counter,
            b: step_register,
            dst: counter,
        });
        self.emit(Instr::Jumpi(test));
        self.emit(Instr::Label(exit));
        if let Some(trip_count) = trip_count {
            self.for_bounds.push(ForBound {
                header: test,
                trip_count,
            });
        }
    }

    fn assign(&mut self, place: &Place, value: &typed::Expr, span: Span) {
        match place {
            Place::Variable(id) => {
                let value = self.expr(value);
                self.span = span;
                if let Some(Storage::Register { register }) = self.storage.get(id.0).copied() {
                    self.emit(Instr::Mov {
                        src: value,
                        dst: Reg(register),
                    });
                }
            }
            Place::Sensor(sensor) => {
                let value = self.expr(value);
                self.span = span;
                self.emit(Instr::StoreS {
                    src: value,
                    sensor: sensor.0,
                });
            }
            Place::Element { array, index } => {
                let address = self.address(*array, index);
                let value = self.expr(value);
                self.span = span;
                self.emit(Instr::StoreM {
                    src: value,
                    addr: address,
                });
            }
            Place::Error => {}
        }
    }

    /// The address of `array(index)`. A constant index was checked at compile time;
    /// any other index is checked here, and a bad one traps by reading address -1
    /// (the trap's pc maps to the GBASIC line of the access).
    fn address(&mut self, array: VarId, index: &typed::Expr) -> Addr {
        let Some(Storage::Memory { base, size }) = self.storage.get(array.0).copied() else {
            return Addr::At(0);
        };
        if let Some(crate::ast::Literal::Int(value)) = crate::check::constant_of(index) {
            return Addr::At(base.saturating_add(u32::try_from(value).unwrap_or(0)));
        }
        let span = index.span;
        let index = self.expr(index);
        self.span = span;
        let zero = self.load_int(0);
        let below = self.binary(Op2::CmpLt, index, zero);
        let limit = self.load_int(i64::from(size));
        let above = self.binary(Op2::CmpGe, index, limit);
        let outside = self.binary(Op2::Or, below, above);
        let bad = self.label();
        let good = self.label();
        self.branch(outside, bad, good);
        self.emit(Instr::Label(bad));
        let trap = self.load_int(-1);
        self.emit(Instr::LoadM {
            addr: Addr::Reg(trap),
            dst: trap,
        });
        self.emit(Instr::Label(good));
        if base == 0 {
            return Addr::Reg(index);
        }
        let base_register = self.load_int(i64::from(base));
        let address = self.binary(Op2::Add, index, base_register);
        Addr::Reg(address)
    }

    fn expr(&mut self, expr: &typed::Expr) -> Reg {
        self.span = expr.span;
        match &expr.kind {
            ExprKind::Int(value) => self.load_int(*value),
            ExprKind::Float(value) => self.load_float(*value),
            ExprKind::Variable(id) => match self.storage.get(id.0).copied() {
                Some(Storage::Register { register }) => Reg(register),
                _ => self.fresh(),
            },
            ExprKind::Sensor(sensor) => {
                let dst = self.fresh();
                self.emit(Instr::LoadS {
                    sensor: sensor.0,
                    dst,
                });
                dst
            }
            ExprKind::Element { array, index } => {
                let address = self.address(*array, index);
                self.span = expr.span;
                let dst = self.fresh();
                self.emit(Instr::LoadM { addr: address, dst });
                if expr.ty == Ty::Float {
                    // Cells never written hold integer 0; reading a float array gives 0.0.
                    let float = self.fresh();
                    self.emit(Instr::Unary {
                        op: Op1::I2d,
                        src: dst,
                        dst: float,
                    });
                    return float;
                }
                dst
            }
            ExprKind::Neg(operand) => self.unary(Op1::Neg, operand, expr.span),
            ExprKind::Not(operand) => self.unary(Op1::Not, operand, expr.span),
            ExprKind::ToFloat(operand) => self.unary(Op1::I2d, operand, expr.span),
            ExprKind::Binary { op, left, right } => {
                let a = self.expr(left);
                let b = self.expr(right);
                self.span = expr.span;
                let (a, b) = if matches!(op, BinaryOp::And | BinaryOp::Or) {
                    // Logical, not bitwise: make each side 0 or 1 first unless it
                    // already is (a comparison or another logical operator).
                    let a = self.truth(left, a);
                    let b = self.truth(right, b);
                    self.span = expr.span;
                    (a, b)
                } else {
                    (a, b)
                };
                self.binary(op.machine_operation(), a, b)
            }
            ExprKind::Call { builtin, args } => {
                let registers: Vec<Reg> = args.iter().map(|arg| self.expr(arg)).collect();
                self.span = expr.span;
                let dst = self.fresh();
                let first = registers.first().copied().unwrap_or(dst);
                let second = registers.get(1).copied().unwrap_or(first);
                let instr = match builtin.info().instruction {
                    Instruction::Unary(op) => Instr::Unary {
                        op,
                        src: first,
                        dst,
                    },
                    Instruction::Binary(op) => Instr::Binary {
                        op,
                        a: first,
                        b: second,
                        dst,
                    },
                };
                self.emit(instr);
                dst
            }
            ExprKind::Error => self.fresh(),
        }
    }

    fn unary(&mut self, op: Op1, operand: &typed::Expr, span: Span) -> Reg {
        let src = self.expr(operand);
        self.span = span;
        let dst = self.fresh();
        self.emit(Instr::Unary { op, src, dst });
        dst
    }

    /// `value` as 0 or 1: unchanged when `expr` is already a truth value.
    fn truth(&mut self, expr: &typed::Expr, value: Reg) -> Reg {
        let is_truth = match &expr.kind {
            ExprKind::Not(_) => true,
            ExprKind::Binary { op, .. } => {
                op.is_comparison() || matches!(op, BinaryOp::And | BinaryOp::Or)
            }
            ExprKind::Int(value) => *value == 0 || *value == 1,
            _ => false,
        };
        if is_truth {
            return value;
        }
        self.span = expr.span;
        let zero = self.load_int(0);
        self.binary(Op2::CmpNe, value, zero)
    }
}
