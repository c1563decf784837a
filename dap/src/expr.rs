//! The debugger's expressions (conditions, watches, hovers, logpoint interpolations,
//! `setVariable` values) in the one GBASIC expression language: parsed and checked by
//! the compiler ([`gloc_compiler::expression`]) against the script's symbols, and
//! evaluated over the paused world with the machine's operations. Only the names are
//! the debugger's: a script's variables, constants and sensors as in the script, and
//! the registers `r0`, `r1`, … (typed by what they hold now), where no variable or
//! constant of the script has that name.

use gloc_compiler::ast;
use gloc_compiler::expression::{self, ExpressionScope, ExpressionState};
use gloc_compiler::typed::{Ty, VarId};
use gloc_engine::sensors::SensorId;

use crate::error::{DebugError, DebugResult};
use crate::target::Target;

/// A value as the script sees it: the machine's own value (integer or float).
pub use gloc_engine::program::Value as Number;

/// The GBASIC type name of a value (`integer`, `float`).
pub fn type_name(value: Number) -> &'static str {
    expression::type_name(value)
}

/// What a watch or hover shows.
#[derive(Clone, Debug, PartialEq)]
pub enum Watched {
    Value(Number),
    /// A whole array, named alone (`tsum`): shown as the Variables view shows it, with
    /// its elements as children. GBASIC has no array values, so nothing else can use it.
    Array {
        name: String,
        shown: String,
    },
}

/// The value of `text` in the paused `target` (`scope`: the script's symbols).
pub fn evaluate<T: Target>(text: &str, scope: &ExpressionScope, target: &T) -> DebugResult<Number> {
    let (scope, registers) = with_registers(text, scope, target);
    let expr = expression::compile_expression(text, &scope).map_err(DebugError::Expression)?;
    let state = State {
        target,
        scope: &scope,
        registers,
    };
    expression::evaluate(&expr, &scope, &state)
        .map_err(|error| DebugError::Expression(error.to_string()))
}

/// As [`evaluate`], and a whole array named alone (`tsum`) is shown.
pub fn watch<T: Target>(text: &str, scope: &ExpressionScope, target: &T) -> DebugResult<Watched> {
    if let Some(array) = array_named(text, scope) {
        if let Some(named) = target
            .variables()
            .into_iter()
            .find(|named| named.name.eq_ignore_ascii_case(&array))
        {
            return Ok(Watched::Array {
                name: named.name,
                shown: named.value,
            });
        }
    }
    evaluate(text, scope, target).map(Watched::Value)
}

/// Why `text` can never be evaluated here (a syntax, name or type error); a value
/// that only fails on the current state (a division by zero) is not such a reason.
pub fn check<T: Target>(text: &str, scope: &ExpressionScope, target: &T) -> DebugResult<()> {
    let (scope, _) = with_registers(text, scope, target);
    expression::compile_expression(text, &scope)
        .map(|_| ())
        .map_err(DebugError::Expression)
}

/// The array `text` names alone, if it is one of the script's arrays.
fn array_named(text: &str, scope: &ExpressionScope) -> Option<String> {
    let parsed = expression::parse_expression(text);
    let ast::ExprKind::Name(name) = parsed.expr?.kind else {
        return None;
    };
    let id = scope.variable(&name.text)?;
    let variable = scope.variables().get(id.0)?;
    variable.size.map(|_| variable.name.clone())
}

/// The scope with the registers the expression names added (after the script's
/// names, which win), typed by what they hold now, and their values.
fn with_registers<T: Target>(
    text: &str,
    scope: &ExpressionScope,
    target: &T,
) -> (ExpressionScope, Registers) {
    let mut scope = scope.clone();
    let mut named = Vec::new();
    if let Some(expr) = expression::parse_expression(text).expr {
        register_names(&expr, &mut named);
    }
    if named.is_empty() {
        return (scope, Registers::default());
    }
    let values = target.registers();
    let mut ids = Vec::new();
    for (name, index) in named {
        let Some(value) = values.get(index) else {
            continue;
        };
        let ty = match value {
            Number::Int(_) => Ty::Integer,
            Number::Float(_) => Ty::Float,
        };
        if let Some(id) = scope.declare_variable(&name, ty, None) {
            ids.push((id, *value));
        }
    }
    (scope, Registers(ids))
}

/// The names of the form `rN` in `expr` (with N), which may be registers.
fn register_names(expr: &ast::Expr, out: &mut Vec<(String, usize)>) {
    let mut add = |name: &ast::Name| {
        let index = name
            .key()
            .strip_prefix('r')
            .filter(|digits| digits.bytes().all(|byte| byte.is_ascii_digit()))
            .and_then(|digits| digits.parse::<usize>().ok());
        if let Some(index) = index {
            if !out
                .iter()
                .any(|(known, _)| known.eq_ignore_ascii_case(&name.text))
            {
                out.push((name.text.clone(), index));
            }
        }
    };
    match &expr.kind {
        ast::ExprKind::Name(name) => add(name),
        ast::ExprKind::Call { name, args } => {
            add(name);
            for arg in args {
                register_names(arg, out);
            }
        }
        ast::ExprKind::Unary { operand, .. } => register_names(operand, out),
        ast::ExprKind::Binary { left, right, .. } => {
            register_names(left, out);
            register_names(right, out);
        }
        ast::ExprKind::Literal(_) | ast::ExprKind::Error => {}
    }
}

/// The registers an expression names: (id in its scope, value now).
#[derive(Default)]
struct Registers(Vec<(VarId, Number)>);

struct State<'a, T: Target> {
    target: &'a T,
    scope: &'a ExpressionScope,
    registers: Registers,
}

impl<T: Target> ExpressionState for State<'_, T> {
    fn variable(&self, id: VarId) -> Option<Number> {
        if let Some((_, value)) = self.registers.0.iter().find(|(known, _)| *known == id) {
            return Some(*value);
        }
        let variable = self.scope.variables().get(id.0)?;
        self.target.variable(&variable.name)
    }

    fn element(&self, id: VarId, index: usize) -> Option<Number> {
        let variable = self.scope.variables().get(id.0)?;
        self.target
            .element(&variable.name, i64::try_from(index).ok()?)
    }

    fn sensor(&self, sensor: SensorId) -> Option<f64> {
        let index = sensor.index();
        (index < self.target.sensor_count()).then(|| self.target.sensor(index))
    }
}
