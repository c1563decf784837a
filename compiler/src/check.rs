//! The GBASIC type checker: resolves names (declarations are global and hoisted, as
//! the program is one flat scope with `goto`), checks types, and builds the typed tree
//! and the symbol table. Every error is reported once; an expression already wrong
//! has type `Error`, which matches anything.

use std::collections::HashMap;

use gloc_engine::sensors::{Access, SensorId, SensorList};
use gloc_engine::{suggest, Diagnostic, Span};

use crate::ast::{self, BinaryOp, Literal, LoopKind, TypeName, UnaryOp};
use crate::builtins::{self, Param, Returns, BUILTINS};
use crate::codes;
use crate::parser::KEYWORDS;
use crate::typed::{self, Builtin, ExprKind, LabelId, Place, Symbols, Ty, VarId};

/// A type-checked program.
#[derive(Clone, Debug, Default)]
pub struct Checked {
    pub program: typed::Program,
    pub symbols: Symbols,
    pub diagnostics: Vec<Diagnostic>,
}

pub fn check(program: &ast::Program, sensors: &SensorList) -> Checked {
    let mut checker = Checker {
        sensors,
        symbols: Symbols::default(),
        diagnostics: Vec::new(),
        suppressed: crate::Suppressed::default(),
        names: HashMap::new(),
        labels: HashMap::new(),
        sensor_uses: HashMap::new(),
        loops: Vec::new(),
        constant_values: Vec::new(),
    };
    checker.declare_constants(&program.body);
    checker.declare_rest(&program.body);
    let body = checker.check_block(&program.body);
    checker.warn_unused();
    checker.suppressed.finish(&mut checker.diagnostics);
    Checked {
        program: typed::Program { body },
        symbols: checker.symbols,
        diagnostics: checker.diagnostics,
    }
}

/// The names a lone expression may use (a debugger's condition or watch): the script's
/// variables and constants, and the sensor list. Built from a compiled script's symbol
/// table ([`crate::SourceMap`]); the debugger may add names of its own (registers).
#[derive(Clone, Debug)]
pub struct ExpressionScope {
    sensors: std::sync::Arc<SensorList>,
    symbols: Symbols,
    constant_values: Vec<Literal>,
    names: HashMap<String, Symbol>,
}

/// A lone expression checked against an [`ExpressionScope`].
#[derive(Clone, Debug)]
pub struct CheckedExpression {
    pub expr: typed::Expr,
    pub diagnostics: Vec<Diagnostic>,
}

impl ExpressionScope {
    pub fn new(sensors: std::sync::Arc<SensorList>) -> ExpressionScope {
        ExpressionScope {
            sensors,
            symbols: Symbols::default(),
            constant_values: Vec::new(),
            names: HashMap::new(),
        }
    }

    /// Declares a variable (`size`: `Some(n)` for an array); `None` when the name is
    /// already taken in the scope, which keeps the first.
    pub fn declare_variable(&mut self, name: &str, ty: Ty, size: Option<usize>) -> Option<VarId> {
        let key = name.to_ascii_lowercase();
        if self.names.contains_key(&key) {
            return None;
        }
        let id = VarId(self.symbols.variables.len());
        self.symbols.variables.push(typed::Variable {
            name: name.to_string(),
            ty,
            size,
            definition: Span::default(),
            references: Vec::new(),
        });
        self.names.insert(key, Symbol::Variable(id));
        Some(id)
    }

    /// Declares a constant; false when the name is already taken.
    pub fn declare_constant(&mut self, name: &str, value: Literal) -> bool {
        let key = name.to_ascii_lowercase();
        if self.names.contains_key(&key) {
            return false;
        }
        self.symbols.constants.push(typed::Constant {
            name: name.to_string(),
            ty: literal_ty(&value),
            value: match value {
                Literal::Int(value) => value.to_string(),
                Literal::Float(value) => format_float(value),
            },
            definition: Span::default(),
            references: Vec::new(),
        });
        self.names
            .insert(key, Symbol::Constant(self.constant_values.len()));
        self.constant_values.push(value);
        true
    }

    pub fn variables(&self) -> &[typed::Variable] {
        &self.symbols.variables
    }

    pub fn constants(&self) -> &[typed::Constant] {
        &self.symbols.constants
    }

    pub fn sensors(&self) -> &SensorList {
        &self.sensors
    }

    /// The variable `name` (any case), if it is one.
    pub fn variable(&self, name: &str) -> Option<VarId> {
        match self.names.get(&name.to_ascii_lowercase()) {
            Some(Symbol::Variable(id)) => Some(*id),
            _ => None,
        }
    }
}

/// Type-checks one expression by the rules of a script: the same names, conversions
/// and errors as `check` gives the same text inside a program.
pub fn check_expression(expr: &ast::Expr, scope: &ExpressionScope) -> CheckedExpression {
    let mut checker = Checker {
        sensors: &scope.sensors,
        symbols: scope.symbols.clone(),
        diagnostics: Vec::new(),
        suppressed: crate::Suppressed::default(),
        names: scope.names.clone(),
        labels: HashMap::new(),
        sensor_uses: HashMap::new(),
        loops: Vec::new(),
        constant_values: scope.constant_values.clone(),
    };
    let expr = checker.check_expr(expr);
    CheckedExpression {
        expr,
        diagnostics: checker.diagnostics,
    }
}

#[derive(Clone, Copy, Debug)]
enum Symbol {
    Variable(VarId),
    Constant(usize),
}

struct Checker<'a> {
    sensors: &'a SensorList,
    symbols: Symbols,
    diagnostics: Vec<Diagnostic>,
    /// Diagnostics past [`crate::MAX_DIAGNOSTICS`], counted and summed up at the end.
    suppressed: crate::Suppressed,
    /// Lower-cased name → variable or constant.
    names: HashMap<String, Symbol>,
    labels: HashMap<String, LabelId>,
    /// Sensor index → position in `symbols.sensors`.
    sensor_uses: HashMap<u32, usize>,
    /// Loops open around the statement being checked.
    loops: Vec<LoopKind>,
    /// Values of `symbols.constants`, by the same index.
    constant_values: Vec<Literal>,
}

fn literal_ty(value: &Literal) -> Ty {
    match value {
        Literal::Int(_) => Ty::Integer,
        Literal::Float(_) => Ty::Float,
    }
}

/// GBASIC prints floats as Rust's `{:?}` does: always with a point or an exponent.
pub fn format_float(value: f64) -> String {
    format!("{value:?}")
}

impl<'a> Checker<'a> {
    fn error(&mut self, diagnostic: Diagnostic) {
        self.suppressed.push(&mut self.diagnostics, diagnostic);
    }

    /// Reports an error with a hint at what to do.
    fn error_with_help(
        &mut self,
        code: &'static str,
        span: Span,
        message: impl Into<String>,
        help: impl Into<String>,
    ) {
        self.error(Diagnostic::error(code, span, message).with_help(help));
    }

    /// Reports a declaration whose name is taken; returns true when it is free.
    fn name_is_free(&mut self, name: &ast::Name) -> bool {
        let key = name.key();
        let (taken_by, first, help) = if let Some(existing) = self.names.get(&*key).copied() {
            let first = match existing {
                Symbol::Variable(id) => self.symbols.variables[id.0].definition,
                Symbol::Constant(index) => self.symbols.constants[index].definition,
            };
            (
                "is declared twice".to_string(),
                Some(first),
                "rename one of them",
            )
        } else if Builtin::of_name(&key).is_some() || KEYWORDS.contains(&&*key) {
            (
                "is the name of a built-in function".to_string(),
                None,
                "choose another name",
            )
        } else if let Some(sensor) = self.sensors.lookup(&key) {
            let sensor_name = self.sensors.name(sensor).unwrap_or("");
            (
                format!("is the name of the sensor `{sensor_name}`"),
                None,
                "sensors are used by name without a declaration; choose another name",
            )
        } else {
            return true;
        };
        let mut diagnostic = Diagnostic::error(
            codes::DUPLICATE,
            name.span,
            format!("`{}` {taken_by}", name.text),
        )
        .with_help(help);
        if let Some(first) = first {
            diagnostic = diagnostic.with_label(first, "first declared here");
        }
        self.error(diagnostic);
        false
    }

    fn declare_constants(&mut self, body: &[ast::Stmt]) {
        for stmt in body {
            if let ast::StmtKind::Const { name, value } = &stmt.kind {
                if self.name_is_free(name) {
                    let index = self.symbols.constants.len();
                    self.symbols.constants.push(typed::Constant {
                        name: name.text.clone(),
                        ty: literal_ty(value),
                        value: match value {
                            Literal::Int(value) => value.to_string(),
                            Literal::Float(value) => format_float(*value),
                        },
                        definition: name.span,
                        references: Vec::new(),
                    });
                    self.names
                        .insert(name.key().into_owned(), Symbol::Constant(index));
                    self.constant_values.push(value.clone());
                }
            }
            for_each_child_block(stmt, |block| self.declare_constants(block));
        }
    }

    fn declare_rest(&mut self, body: &[ast::Stmt]) {
        for stmt in body {
            match &stmt.kind {
                ast::StmtKind::Dim { name, size, ty } => {
                    let size = match size {
                        None => None,
                        Some(size) => match self.array_size(size) {
                            Some(size) => Some(size),
                            None => continue,
                        },
                    };
                    if self.name_is_free(name) {
                        let id = VarId(self.symbols.variables.len());
                        self.symbols.variables.push(typed::Variable {
                            name: name.text.clone(),
                            ty: match ty {
                                TypeName::Integer => Ty::Integer,
                                TypeName::Float => Ty::Float,
                            },
                            size,
                            definition: name.span,
                            references: Vec::new(),
                        });
                        self.names
                            .insert(name.key().into_owned(), Symbol::Variable(id));
                    }
                }
                ast::StmtKind::Label(name) => match self.labels.get(&*name.key()).copied() {
                    Some(id) => {
                        let first = self.symbols.labels[id.0].definition;
                        self.error(
                            Diagnostic::error(
                                codes::DUPLICATE_LABEL,
                                name.span,
                                format!("the label `{}` is defined twice", name.text),
                            )
                            .with_label(first, "first defined here")
                            .with_help("rename one of the labels"),
                        );
                    }
                    None => {
                        let id = LabelId(self.symbols.labels.len());
                        self.symbols.labels.push(typed::Label {
                            name: name.text.clone(),
                            definition: name.span,
                            references: Vec::new(),
                        });
                        self.labels.insert(name.key().into_owned(), id);
                    }
                },
                _ => {}
            }
            for_each_child_block(stmt, |block| self.declare_rest(block));
        }
    }

    fn array_size(&mut self, size: &ast::ArraySize) -> Option<usize> {
        let (value, span) = match size {
            ast::ArraySize::Literal { value, span } => (*value, *span),
            ast::ArraySize::Const(name) => match self.names.get(&*name.key()).copied() {
                Some(Symbol::Constant(index)) => {
                    self.symbols.constants[index].references.push(name.span);
                    match self.constant_values[index] {
                        Literal::Int(value) => (value, name.span),
                        Literal::Float(_) => {
                            self.error(Diagnostic::error(
                                codes::BAD_ARRAY_SIZE,
                                name.span,
                                format!("the array size `{}` is a float constant", name.text),
                            ));
                            return None;
                        }
                    }
                }
                _ => {
                    self.error(
                        Diagnostic::error(
                            codes::BAD_ARRAY_SIZE,
                            name.span,
                            format!("`{}` is not a constant declared with `const`", name.text),
                        )
                        .with_help("an array size is an integer literal or a `const`"),
                    );
                    return None;
                }
            },
        };
        if !(1..=MAX_ARRAY_SIZE).contains(&value) {
            self.error(Diagnostic::error(
                codes::BAD_ARRAY_SIZE,
                span,
                format!("an array size must be between 1 and {MAX_ARRAY_SIZE}, not {value}"),
            ));
            return None;
        }
        usize::try_from(value).ok()
    }

    fn warn_unused(&mut self) {
        let mut warnings = Vec::new();
        for variable in &self.symbols.variables {
            if variable.references.is_empty() {
                warnings.push(
                    Diagnostic::warning(
                        codes::UNUSED,
                        variable.definition,
                        format!("the variable `{}` is never used", variable.name),
                    )
                    .with_help("remove the declaration"),
                );
            }
        }
        for warning in warnings {
            self.error(warning);
        }
    }

    fn use_sensor(&mut self, sensor: SensorId, span: Span, write: bool) {
        let position = match self.sensor_uses.get(&sensor.0) {
            Some(position) => *position,
            None => {
                let position = self.symbols.sensors.len();
                self.symbols.sensors.push(typed::SensorUse {
                    sensor: sensor.0,
                    name: self.sensors.name(sensor).unwrap_or("").to_string(),
                    reads: Vec::new(),
                    writes: Vec::new(),
                });
                self.sensor_uses.insert(sensor.0, position);
                position
            }
        };
        let entry = &mut self.symbols.sensors[position];
        if write {
            entry.writes.push(span);
        } else {
            entry.reads.push(span);
        }
    }

    /// The closest declared name or sensor to `key`, for "did you mean".
    fn suggest(&self, key: &str) -> Option<String> {
        let variables = self
            .symbols
            .variables
            .iter()
            .map(|variable| variable.name.as_str());
        let constants = self
            .symbols
            .constants
            .iter()
            .map(|constant| constant.name.as_str());
        let sensors = self.sensors.iter().map(|(_, sensor)| sensor.name.as_str());
        suggest::closest(key, variables.chain(constants).chain(sensors)).map(str::to_string)
    }

    fn undeclared(&mut self, name: &ast::Name) {
        if self.diagnostics.len() >= crate::MAX_DIAGNOSTICS {
            // Not kept: counted without the search for a suggestion, the costly part
            // (half a million undeclared names took 6.8 s with it).
            self.error(Diagnostic::error(
                codes::UNDECLARED,
                name.span,
                String::new(),
            ));
            return;
        }
        let mut diagnostic = Diagnostic::error(
            codes::UNDECLARED,
            name.span,
            format!("`{}` is not declared and is not a sensor", name.text),
        );
        match self.suggest(&name.key()) {
            Some(suggestion) => {
                diagnostic = diagnostic
                    .with_help(format!("did you mean `{suggestion}`?"))
                    .with_fix(
                        format!("replace with `{suggestion}`"),
                        name.span,
                        suggestion,
                    );
            }
            None => {
                diagnostic = diagnostic.with_help(format!(
                    "declare it with `dim {} as integer` (or `as float`)",
                    name.text
                ));
            }
        }
        self.error(diagnostic);
    }

    fn check_block(&mut self, body: &[ast::Stmt]) -> Vec<typed::Stmt> {
        body.iter()
            .filter_map(|stmt| self.check_stmt(stmt))
            .collect()
    }

    fn check_stmt(&mut self, stmt: &ast::Stmt) -> Option<typed::Stmt> {
        let kind = match &stmt.kind {
            ast::StmtKind::Dim { .. } | ast::StmtKind::Const { .. } => return None,
            ast::StmtKind::Assign { target, value } => {
                let place = self.check_place(target);
                let value = self.check_expr(value);
                let value = self.coerce_for_place(&place, value);
                typed::StmtKind::Assign { place, value }
            }
            ast::StmtKind::If {
                arms, else_body, ..
            } => {
                let arms = arms
                    .iter()
                    .map(|arm| typed::IfArm {
                        condition: self.check_condition(&arm.condition),
                        body: self.check_block(&arm.body),
                        span: arm.span,
                    })
                    .collect();
                let else_body = else_body.as_ref().map(|body| self.check_block(body));
                typed::StmtKind::If { arms, else_body }
            }
            ast::StmtKind::Label(name) => {
                let id = self.labels.get(&*name.key()).copied()?;
                // A duplicate label was reported; only the first definition counts.
                if self.symbols.labels[id.0].definition != name.span {
                    return None;
                }
                typed::StmtKind::Label(id)
            }
            ast::StmtKind::Goto(name) => match self.labels.get(&*name.key()).copied() {
                Some(id) => {
                    self.symbols.labels[id.0].references.push(name.span);
                    typed::StmtKind::Goto(id)
                }
                None => {
                    let mut diagnostic = Diagnostic::error(
                        codes::UNDEFINED_LABEL,
                        name.span,
                        format!("there is no label `{}`", name.text),
                    );
                    let closest = suggest::closest(
                        &name.key(),
                        self.symbols.labels.iter().map(|label| label.name.as_str()),
                    )
                    .map(str::to_string);
                    diagnostic = match closest {
                        Some(label) => diagnostic
                            .with_help(format!("did you mean `{label}`?"))
                            .with_fix(format!("replace with `{label}`"), name.span, label),
                        None => {
                            diagnostic.with_help(format!("define it with `label: {}`", name.text))
                        }
                    };
                    self.error(diagnostic);
                    return None;
                }
            },
            ast::StmtKind::While {
                condition, body, ..
            } => {
                let condition = self.check_condition(condition);
                self.loops.push(LoopKind::While);
                let body = self.check_block(body);
                self.loops.pop();
                typed::StmtKind::While { condition, body }
            }
            ast::StmtKind::Do {
                pre, body, post, ..
            } => {
                let pre = pre.as_ref().map(|condition| {
                    Box::new((condition.until, self.check_condition(&condition.expr)))
                });
                self.loops.push(LoopKind::Do);
                let body = self.check_block(body);
                self.loops.pop();
                let post = post.as_ref().map(|condition| {
                    Box::new((condition.until, self.check_condition(&condition.expr)))
                });
                typed::StmtKind::Do { pre, body, post }
            }
            ast::StmtKind::For {
                variable,
                from,
                to,
                step,
                body,
                end_span,
            } => return self.check_for(stmt, variable, from, to, step.as_deref(), body, *end_span),
            ast::StmtKind::Exit(kind) => {
                if !self.loops.contains(kind) {
                    let word = kind.keyword();
                    self.error_with_help(
                        codes::EXIT_OUTSIDE_LOOP,
                        stmt.span,
                        format!("`exit {word}` is not inside a `{word}` loop"),
                        "use `goto` to leave other blocks",
                    );
                    return None;
                }
                typed::StmtKind::Exit(*kind)
            }
            ast::StmtKind::Yield => typed::StmtKind::Yield,
            ast::StmtKind::End => typed::StmtKind::End,
            ast::StmtKind::Print(items) => typed::StmtKind::Print(
                items
                    .iter()
                    .map(|item| match item {
                        ast::PrintItem::Text { text, .. } => typed::PrintItem::Text(text.clone()),
                        ast::PrintItem::Expr(expr) => typed::PrintItem::Expr(self.check_expr(expr)),
                    })
                    .collect(),
            ),
        };
        Some(typed::Stmt {
            kind,
            span: stmt.span,
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn check_for(
        &mut self,
        stmt: &ast::Stmt,
        variable: &ast::Name,
        from: &ast::Expr,
        to: &ast::Expr,
        step: Option<&ast::Expr>,
        body: &[ast::Stmt],
        end_span: Option<Span>,
    ) -> Option<typed::Stmt> {
        let var_id = match self.names.get(&*variable.key()).copied() {
            Some(Symbol::Variable(id)) if self.symbols.variables[id.0].size.is_none() => {
                self.symbols.variables[id.0].references.push(variable.span);
                Some(id)
            }
            Some(_) => {
                self.error_with_help(
                    codes::WRONG_KIND,
                    variable.span,
                    format!(
                        "the loop variable `{}` must be a scalar variable",
                        variable.text
                    ),
                    "declare a variable with `dim NAME as integer`",
                );
                None
            }
            None => {
                if self.sensors.lookup(&variable.key()).is_some() {
                    self.error_with_help(
                        codes::WRONG_KIND,
                        variable.span,
                        format!("the sensor `{}` cannot count a `for` loop", variable.text),
                        "count with a variable and assign the sensor in the body",
                    );
                } else {
                    self.undeclared(variable);
                }
                None
            }
        };
        let var_ty = var_id.map_or(Ty::Error, |id| self.symbols.variables[id.0].ty);
        let coerce_bound = |checker: &mut Self, expr: &ast::Expr| {
            let value = checker.check_expr(expr);
            checker.coerce(value, var_ty, "this `for` bound")
        };
        let from = coerce_bound(self, from);
        let to = coerce_bound(self, to);
        let step = step.map(|step| coerce_bound(self, step));
        self.loops.push(LoopKind::For);
        let body_typed = self.check_block(body);
        self.loops.pop();
        let var_id = var_id?;
        let step_value = match &step {
            None => Some(Literal::Int(1)),
            Some(step) => constant_of(step),
        };
        if let Some(step_value) = &step_value {
            let is_zero = match step_value {
                Literal::Int(value) => *value == 0,
                Literal::Float(value) => *value == 0.0,
            };
            if is_zero {
                let span = step.as_ref().map_or(stmt.span, |step| step.span);
                self.error(
                    Diagnostic::warning(
                        codes::ZERO_STEP,
                        span,
                        "a `for` loop with step 0 never ends",
                    )
                    .with_help("use a non-zero step"),
                );
            }
        }
        let trip_count = match (constant_of(&from), constant_of(&to), step_value) {
            (Some(from), Some(to), Some(step))
                if !assigns_variable(&body_typed, var_id) && !holds_label(&body_typed) =>
            {
                trip_count(&from, &to, &step)
            }
            _ => None,
        };
        Some(typed::Stmt {
            kind: typed::StmtKind::For {
                variable: var_id,
                from: Box::new(from),
                to: Box::new(to),
                step: step.map(Box::new),
                body: body_typed,
                trip_count,
                next_span: end_span.unwrap_or(stmt.span),
            },
            span: stmt.span,
        })
    }

    fn check_place(&mut self, target: &ast::Target) -> Place {
        let name = target.name();
        match self.names.get(&*name.key()).copied() {
            Some(Symbol::Constant(index)) => {
                self.symbols.constants[index].references.push(name.span);
                self.error(
                    Diagnostic::error(
                        codes::WRONG_KIND,
                        name.span,
                        format!("`{}` is a constant and cannot be assigned", name.text),
                    )
                    .with_label(
                        self.symbols.constants[index].definition,
                        "declared with `const` here",
                    )
                    .with_help("declare it with `dim` to change it"),
                );
                Place::Error
            }
            Some(Symbol::Variable(id)) => {
                self.symbols.variables[id.0].references.push(name.span);
                let size = self.symbols.variables[id.0].size;
                match (target, size) {
                    (ast::Target::Name(_), None) => Place::Variable(id),
                    (ast::Target::Element { index, .. }, Some(size)) => {
                        let index = self.check_index(index, size);
                        Place::Element {
                            array: id,
                            index: Box::new(index),
                        }
                    }
                    (ast::Target::Name(_), Some(_)) => {
                        self.error_with_help(
                            codes::WRONG_KIND,
                            name.span,
                            format!("`{}` is an array; assign one element", name.text),
                            format!("write `{}(INDEX) = …`", name.text),
                        );
                        Place::Error
                    }
                    (ast::Target::Element { .. }, None) => {
                        self.error(Diagnostic::error(
                            codes::WRONG_KIND,
                            name.span,
                            format!("`{}` is not an array", name.text),
                        ));
                        Place::Error
                    }
                }
            }
            None => match self.sensors.lookup(&name.key()) {
                Some(sensor) => {
                    self.use_sensor(sensor, name.span, true);
                    if let ast::Target::Element { .. } = target {
                        self.error(Diagnostic::error(
                            codes::WRONG_KIND,
                            name.span,
                            format!("the sensor `{}` is not an array", name.text),
                        ));
                        return Place::Error;
                    }
                    let sensor_name = self.sensors.name(sensor).unwrap_or("").to_string();
                    match Access::of_name(&sensor_name) {
                        Access::ReadOnly => {
                            self.error_with_help(codes::READ_ONLY_SENSOR, name.span, format!("the sensor `{sensor_name}` is read-only"), "`m_` (measured) and `x_` (computed) sensors are written by the glider; write a `c_`, `u_` or `sci_` sensor instead");
                            Place::Error
                        }
                        Access::Factory => {
                            self.error(
                                Diagnostic::warning(
                                    codes::FACTORY_SENSOR,
                                    name.span,
                                    format!("`{sensor_name}` is a factory setting"),
                                )
                                .with_help("change `f_` sensors only if you know the consequence"),
                            );
                            Place::Sensor(sensor)
                        }
                        Access::Writable => Place::Sensor(sensor),
                    }
                }
                None => {
                    self.undeclared(name);
                    if let ast::Target::Element { index, .. } = target {
                        self.check_expr(index);
                    }
                    Place::Error
                }
            },
        }
    }

    fn place_ty(&self, place: &Place) -> Ty {
        match place {
            Place::Variable(id) | Place::Element { array: id, .. } => {
                self.symbols.variables[id.0].ty
            }
            Place::Sensor(_) => Ty::Float,
            Place::Error => Ty::Error,
        }
    }

    fn coerce_for_place(&mut self, place: &Place, value: typed::Expr) -> typed::Expr {
        match place {
            // A sensor takes integers as they are (the paper's Fig. 2 stores `loadi 128`).
            Place::Sensor(_) => value,
            _ => {
                let ty = self.place_ty(place);
                self.coerce(value, ty, "this assignment")
            }
        }
    }

    /// Converts `value` to `ty`: integer widens to float; float to integer is an error.
    fn coerce(&mut self, value: typed::Expr, ty: Ty, context: &str) -> typed::Expr {
        match (value.ty, ty) {
            (Ty::Integer, Ty::Float) => to_float(value),
            (Ty::Float, Ty::Integer) => {
                self.error_with_help(
                    codes::TYPE_MISMATCH,
                    value.span,
                    format!("{context} needs an integer, but this is a float"),
                    "convert with `int(…)`, which truncates toward zero",
                );
                typed::Expr {
                    kind: ExprKind::Error,
                    ty: Ty::Error,
                    span: value.span,
                }
            }
            _ => value,
        }
    }

    fn check_condition(&mut self, expr: &ast::Expr) -> typed::Expr {
        let value = self.check_expr(expr);
        if value.ty == Ty::Float {
            self.error_with_help(
                codes::TYPE_MISMATCH,
                value.span,
                "a condition must be an integer, but this is a float",
                "compare it, e.g. `… <> 0.0`",
            );
            return typed::Expr {
                kind: ExprKind::Error,
                ty: Ty::Error,
                span: value.span,
            };
        }
        value
    }

    fn check_index(&mut self, index: &ast::Expr, size: usize) -> typed::Expr {
        let index = self.check_expr(index);
        let index = self.coerce(index, Ty::Integer, "an array index");
        if let Some(Literal::Int(value)) = constant_of(&index) {
            if value < 0 || value as u64 >= size as u64 {
                self.error_with_help(
                    codes::INDEX_OUT_OF_BOUNDS,
                    index.span,
                    format!(
                        "index {value} is out of bounds: the array has {size} elements (0 to {})",
                        size - 1
                    ),
                    format!("use an index from 0 to {}", size - 1),
                );
            }
        }
        index
    }

    fn check_expr(&mut self, expr: &ast::Expr) -> typed::Expr {
        let error = |span| typed::Expr {
            kind: ExprKind::Error,
            ty: Ty::Error,
            span,
        };
        let span = expr.span;
        match &expr.kind {
            ast::ExprKind::Error => error(span),
            ast::ExprKind::Literal(Literal::Int(value)) => typed::Expr {
                kind: ExprKind::Int(*value),
                ty: Ty::Integer,
                span,
            },
            ast::ExprKind::Literal(Literal::Float(value)) => typed::Expr {
                kind: ExprKind::Float(*value),
                ty: Ty::Float,
                span,
            },
            ast::ExprKind::Name(name) => match self.names.get(&*name.key()).copied() {
                Some(Symbol::Constant(index)) => {
                    self.symbols.constants[index].references.push(name.span);
                    match self.constant_values[index] {
                        Literal::Int(value) => typed::Expr {
                            kind: ExprKind::Int(value),
                            ty: Ty::Integer,
                            span,
                        },
                        Literal::Float(value) => typed::Expr {
                            kind: ExprKind::Float(value),
                            ty: Ty::Float,
                            span,
                        },
                    }
                }
                Some(Symbol::Variable(id)) => {
                    self.symbols.variables[id.0].references.push(name.span);
                    let variable = &self.symbols.variables[id.0];
                    if variable.size.is_some() {
                        let text = format!("`{}` is an array; read one element", name.text);
                        let help = format!("write `{}(INDEX)`", name.text);
                        self.error(
                            Diagnostic::error(codes::WRONG_KIND, span, text).with_help(help),
                        );
                        return error(span);
                    }
                    typed::Expr {
                        kind: ExprKind::Variable(id),
                        ty: variable.ty,
                        span,
                    }
                }
                None => match self.sensors.lookup(&name.key()) {
                    Some(sensor) => {
                        self.use_sensor(sensor, span, false);
                        typed::Expr {
                            kind: ExprKind::Sensor(sensor),
                            ty: Ty::Float,
                            span,
                        }
                    }
                    None => {
                        if Builtin::of_name(&name.key()).is_some() {
                            self.error_with_help(
                                codes::WRONG_KIND,
                                span,
                                format!("`{}` is a built-in function", name.text),
                                format!("call it: `{}(…)`", name.text),
                            );
                        } else {
                            self.undeclared(name);
                        }
                        error(span)
                    }
                },
            },
            ast::ExprKind::Call { name, args } => self.check_call(expr, name, args),
            ast::ExprKind::Unary { op, operand } => {
                let operand = self.check_expr(operand);
                match op {
                    UnaryOp::Neg => typed::Expr {
                        ty: operand.ty,
                        kind: ExprKind::Neg(Box::new(operand)),
                        span,
                    },
                    UnaryOp::Not => {
                        let operand = self.require_integer(operand, "`not`");
                        typed::Expr {
                            kind: ExprKind::Not(Box::new(operand)),
                            ty: Ty::Integer,
                            span,
                        }
                    }
                }
            }
            ast::ExprKind::Binary { op, left, right } => {
                let left = self.check_expr(left);
                let right = self.check_expr(right);
                self.check_binary(*op, left, right, span)
            }
        }
    }

    fn require_integer(&mut self, value: typed::Expr, what: &str) -> typed::Expr {
        if value.ty == Ty::Float {
            self.error_with_help(
                codes::TYPE_MISMATCH,
                value.span,
                format!("{what} needs an integer, but this is a float"),
                "convert with `int(…)` or compare the float",
            );
            return typed::Expr {
                kind: ExprKind::Error,
                ty: Ty::Error,
                span: value.span,
            };
        }
        value
    }

    fn check_binary(
        &mut self,
        op: BinaryOp,
        left: typed::Expr,
        right: typed::Expr,
        span: Span,
    ) -> typed::Expr {
        let either_error = left.ty == Ty::Error || right.ty == Ty::Error;
        let operand_ty = if left.ty == Ty::Float || right.ty == Ty::Float {
            Ty::Float
        } else {
            Ty::Integer
        };
        let (left, right, result_ty) = match op {
            BinaryOp::Add | BinaryOp::Sub | BinaryOp::Mul | BinaryOp::Mod => (
                widen(left, operand_ty),
                widen(right, operand_ty),
                operand_ty,
            ),
            BinaryOp::Div => (widen(left, Ty::Float), widen(right, Ty::Float), Ty::Float),
            BinaryOp::IntDiv => {
                let what = "`\\` (integer division)";
                let left = self.require_integer(left, what);
                let right = self.require_integer(right, what);
                (left, right, Ty::Integer)
            }
            BinaryOp::Compare(_) => (
                widen(left, operand_ty),
                widen(right, operand_ty),
                Ty::Integer,
            ),
            BinaryOp::And | BinaryOp::Or => {
                let what = format!("`{}`", op.symbol());
                let left = self.require_integer(left, &what);
                let right = self.require_integer(right, &what);
                (left, right, Ty::Integer)
            }
        };
        if matches!(op, BinaryOp::IntDiv | BinaryOp::Mod) && operand_ty == Ty::Integer {
            if let Some(Literal::Int(0)) = constant_of(&right) {
                self.error(Diagnostic::error(
                    codes::DIVISION_BY_ZERO,
                    right.span,
                    "integer division by zero",
                ));
            }
        }
        let ty = if either_error && !op.is_comparison() {
            Ty::Error
        } else {
            result_ty
        };
        typed::Expr {
            kind: ExprKind::Binary {
                op,
                left: Box::new(left),
                right: Box::new(right),
            },
            ty,
            span,
        }
    }

    fn check_call(
        &mut self,
        expr: &ast::Expr,
        name: &ast::Name,
        args: &[ast::Expr],
    ) -> typed::Expr {
        let span = expr.span;
        let error = typed::Expr {
            kind: ExprKind::Error,
            ty: Ty::Error,
            span,
        };
        match self.names.get(&*name.key()).copied() {
            Some(Symbol::Variable(id)) => {
                self.symbols.variables[id.0].references.push(name.span);
                let size = self.symbols.variables[id.0].size;
                let ty = self.symbols.variables[id.0].ty;
                let Some(size) = size else {
                    self.error(Diagnostic::error(
                        codes::WRONG_KIND,
                        name.span,
                        format!("`{}` is not an array", name.text),
                    ));
                    return error;
                };
                if args.len() != 1 {
                    self.error(Diagnostic::error(
                        codes::BAD_ARGUMENTS,
                        span,
                        format!("an array takes one index, not {}", args.len()),
                    ));
                    return error;
                }
                let index = self.check_index(&args[0], size);
                return typed::Expr {
                    kind: ExprKind::Element {
                        array: id,
                        index: Box::new(index),
                    },
                    ty,
                    span,
                };
            }
            Some(Symbol::Constant(index)) => {
                self.symbols.constants[index].references.push(name.span);
                self.error(Diagnostic::error(
                    codes::WRONG_KIND,
                    name.span,
                    format!("`{}` is a constant, not an array or a function", name.text),
                ));
                return error;
            }
            None => {}
        }
        let Some(builtin) = Builtin::of_name(&name.key()) else {
            if self.sensors.lookup(&name.key()).is_some() {
                self.error(Diagnostic::error(
                    codes::WRONG_KIND,
                    name.span,
                    format!("the sensor `{}` is not an array or a function", name.text),
                ));
            } else {
                let mut diagnostic = Diagnostic::error(
                    codes::UNDECLARED,
                    name.span,
                    format!("`{}` is not an array or a built-in function", name.text),
                );
                let arrays = self
                    .symbols
                    .variables
                    .iter()
                    .filter(|variable| variable.size.is_some())
                    .map(|variable| variable.name.as_str());
                let closest = suggest::closest(
                    &name.key(),
                    BUILTINS.iter().map(|info| info.name).chain(arrays),
                )
                .map(str::to_string);
                diagnostic = match closest {
                    Some(suggestion) => diagnostic
                        .with_help(format!("did you mean `{suggestion}`?"))
                        .with_fix(
                            format!("replace with `{suggestion}`"),
                            name.span,
                            suggestion,
                        ),
                    None => diagnostic
                        .with_help(format!("the built-ins are {}", builtins::names_in_prose())),
                };
                self.error(diagnostic);
            }
            for arg in args {
                self.check_expr(arg);
            }
            return error;
        };
        let args: Vec<typed::Expr> = args.iter().map(|arg| self.check_expr(arg)).collect();
        if args.len() != builtin.arity() {
            self.error(Diagnostic::error(
                codes::BAD_ARGUMENTS,
                span,
                format!(
                    "`{}` takes {} argument{}, not {}",
                    name.key(),
                    builtin.arity(),
                    if builtin.arity() == 1 { "" } else { "s" },
                    args.len()
                ),
            ));
            return error;
        }
        let any_error = args.iter().any(|arg| arg.ty == Ty::Error);
        let any_float = args.iter().any(|arg| arg.ty == Ty::Float);
        let info = builtin.info();
        let ty = match info.returns {
            Returns::Integer => Ty::Integer,
            Returns::Float => Ty::Float,
            Returns::Widest if any_float => Ty::Float,
            Returns::Widest => Ty::Integer,
        };
        let mut args: Vec<typed::Expr> = args
            .into_iter()
            .zip(info.params)
            .map(|(arg, (_, param))| match (param, info.returns) {
                (Param::Float, _) => widen(arg, Ty::Float),
                (Param::Number, Returns::Widest) => widen(arg, ty),
                (Param::Number, _) => arg,
            })
            .collect();
        // `int(x)` of an integer and `float(x)` of a float (or of a widened integer)
        // is the value itself.
        if builtin.is_conversion() && (args[0].ty == ty || any_error) {
            let arg = args.remove(0);
            return typed::Expr {
                kind: arg.kind,
                ty: if any_error { Ty::Error } else { ty },
                span,
            };
        }
        typed::Expr {
            kind: ExprKind::Call { builtin, args },
            ty: if any_error { Ty::Error } else { ty },
            span,
        }
    }
}

/// The largest array GBASIC accepts (memory cells are allocated at load).
pub const MAX_ARRAY_SIZE: i64 = 1 << 20;

fn to_float(value: typed::Expr) -> typed::Expr {
    let span = value.span;
    match value.kind {
        // A literal converts at compile time: `15` in a float context is `15.0`.
        ExprKind::Int(number) => typed::Expr {
            kind: ExprKind::Float(number as f64),
            ty: Ty::Float,
            span,
        },
        _ => typed::Expr {
            kind: ExprKind::ToFloat(Box::new(value)),
            ty: Ty::Float,
            span,
        },
    }
}

fn widen(value: typed::Expr, ty: Ty) -> typed::Expr {
    if value.ty == Ty::Integer && ty == Ty::Float {
        to_float(value)
    } else {
        value
    }
}

/// The value of a constant expression (literals, constants, `-` and `+ - *` on them).
pub fn constant_of(expr: &typed::Expr) -> Option<Literal> {
    match &expr.kind {
        ExprKind::Int(value) => Some(Literal::Int(*value)),
        ExprKind::Float(value) => Some(Literal::Float(*value)),
        ExprKind::Neg(operand) => match constant_of(operand)? {
            Literal::Int(value) => value.checked_neg().map(Literal::Int),
            Literal::Float(value) => Some(Literal::Float(-value)),
        },
        ExprKind::ToFloat(operand) => match constant_of(operand)? {
            Literal::Int(value) => Some(Literal::Float(value as f64)),
            Literal::Float(value) => Some(Literal::Float(value)),
        },
        ExprKind::Binary { op, left, right } => match (constant_of(left)?, constant_of(right)?) {
            (Literal::Int(a), Literal::Int(b)) => match op {
                BinaryOp::Add => a.checked_add(b).map(Literal::Int),
                BinaryOp::Sub => a.checked_sub(b).map(Literal::Int),
                BinaryOp::Mul => a.checked_mul(b).map(Literal::Int),
                _ => None,
            },
            (Literal::Float(a), Literal::Float(b)) => match op {
                BinaryOp::Add => Some(Literal::Float(a + b)),
                BinaryOp::Sub => Some(Literal::Float(a - b)),
                BinaryOp::Mul => Some(Literal::Float(a * b)),
                _ => None,
            },
            _ => None,
        },
        _ => None,
    }
}

/// How often `for v = from to to step step` runs its body, computed with the same
/// arithmetic the machine uses; `None` past a million iterations or on overflow.
fn trip_count(from: &Literal, to: &Literal, step: &Literal) -> Option<u64> {
    match (from, to, step) {
        (Literal::Int(from), Literal::Int(to), Literal::Int(step)) if *step != 0 => {
            count_trips(*from, *to, *step, i64::checked_add)
        }
        (Literal::Float(from), Literal::Float(to), Literal::Float(step))
            if *step != 0.0 && step.is_finite() =>
        {
            count_trips(*from, *to, *step, |value, step| Some(value + step))
        }
        _ => None,
    }
}

/// [`trip_count`] for one type: `step` is not zero, `add` is the machine's `add`
/// (`None` on overflow).
fn count_trips<T: Copy + Default + PartialOrd>(
    from: T,
    to: T,
    step: T,
    add: impl Fn(T, T) -> Option<T>,
) -> Option<u64> {
    const LIMIT: u64 = 1_000_000;
    let zero = T::default();
    let mut count = 0u64;
    let mut value = from;
    while (step > zero && value <= to) || (step < zero && value >= to) {
        count += 1;
        if count > LIMIT {
            return None;
        }
        value = add(value, step)?;
    }
    Some(count)
}

fn assigns_variable(body: &[typed::Stmt], variable: VarId) -> bool {
    body.iter().any(|stmt| match &stmt.kind {
        typed::StmtKind::Assign {
            place: Place::Variable(id),
            ..
        } => *id == variable,
        typed::StmtKind::For {
            variable: inner,
            body,
            ..
        } => *inner == variable || assigns_variable(body, variable),
        typed::StmtKind::If { arms, else_body } => {
            arms.iter().any(|arm| assigns_variable(&arm.body, variable))
                || else_body
                    .as_ref()
                    .is_some_and(|body| assigns_variable(body, variable))
        }
        typed::StmtKind::While { body, .. } | typed::StmtKind::Do { body, .. } => {
            assigns_variable(body, variable)
        }
        _ => false,
    })
}

fn holds_label(body: &[typed::Stmt]) -> bool {
    body.iter().any(|stmt| match &stmt.kind {
        typed::StmtKind::Label(_) => true,
        typed::StmtKind::For { body, .. }
        | typed::StmtKind::While { body, .. }
        | typed::StmtKind::Do { body, .. } => holds_label(body),
        typed::StmtKind::If { arms, else_body } => {
            arms.iter().any(|arm| holds_label(&arm.body))
                || else_body.as_ref().is_some_and(|body| holds_label(body))
        }
        _ => false,
    })
}

fn for_each_child_block(stmt: &ast::Stmt, mut visit: impl FnMut(&[ast::Stmt])) {
    match &stmt.kind {
        ast::StmtKind::If {
            arms, else_body, ..
        } => {
            for arm in arms {
                visit(&arm.body);
            }
            if let Some(body) = else_body {
                visit(body);
            }
        }
        ast::StmtKind::While { body, .. }
        | ast::StmtKind::Do { body, .. }
        | ast::StmtKind::For { body, .. } => visit(body),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Counted by hand: the values the loop variable takes before it passes `to`.
    #[test]
    fn trip_counts_of_constant_for_loops() {
        let int = Literal::Int;
        let float = Literal::Float;
        assert_eq!(trip_count(&int(1), &int(10), &int(1)), Some(10));
        // 10, 7, 4, 1.
        assert_eq!(trip_count(&int(10), &int(1), &int(-3)), Some(4));
        assert_eq!(trip_count(&int(5), &int(1), &int(1)), Some(0));
        // 0, 0.25, 0.5, 0.75, 1 (exact in binary).
        assert_eq!(trip_count(&float(0.0), &float(1.0), &float(0.25)), Some(5));
        assert_eq!(trip_count(&int(1), &int(10), &int(0)), None);
        assert_eq!(trip_count(&float(0.0), &float(1.0), &float(0.0)), None);
        assert_eq!(trip_count(&int(1), &int(2_000_000), &int(1)), None);
        // MAX - 1, MAX, then the next add overflows.
        assert_eq!(
            trip_count(&int(i64::MAX - 1), &int(i64::MAX), &int(1)),
            None
        );
        assert_eq!(trip_count(&int(0), &float(1.0), &int(1)), None);
    }
}
