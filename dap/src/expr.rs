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
pub fn evaluate<T: Target>(
    text: &str,
    scope: &ExpressionScope,
    target: &T,
) -> Result<Number, String> {
    let (scope, registers) = with_registers(scope, target);
    let expr = expression::compile_expression(text, &scope)?;
    let state = State {
        target,
        scope: &scope,
        registers,
    };
    expression::evaluate(&expr, &scope, &state).map_err(|error| error.to_string())
}

/// As [`evaluate`], and a whole array named alone (`tsum`) is shown.
pub fn watch<T: Target>(
    text: &str,
    scope: &ExpressionScope,
    target: &T,
) -> Result<Watched, String> {
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
pub fn check<T: Target>(text: &str, scope: &ExpressionScope, target: &T) -> Result<(), String> {
    let (scope, _) = with_registers(scope, target);
    expression::compile_expression(text, &scope).map(|_| ())
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

/// The scope with the registers added (after the script's names, which win), and the
/// id of the first register.
fn with_registers<T: Target>(scope: &ExpressionScope, target: &T) -> (ExpressionScope, Registers) {
    let mut scope = scope.clone();
    let mut ids = Vec::new();
    for (index, value) in target.registers().iter().enumerate() {
        let ty = match value {
            Number::Int(_) => Ty::Integer,
            Number::Float(_) => Ty::Float,
        };
        if let Some(id) = scope.declare_variable(&format!("r{index}"), ty, None) {
            ids.push((id, index));
        }
    }
    (scope, Registers(ids))
}

/// Register variables of a scope: (id, register index).
struct Registers(Vec<(VarId, usize)>);

struct State<'a, T: Target> {
    target: &'a T,
    scope: &'a ExpressionScope,
    registers: Registers,
}

impl<T: Target> ExpressionState for State<'_, T> {
    fn variable(&self, id: VarId) -> Option<Number> {
        if let Some((_, index)) = self.registers.0.iter().find(|(known, _)| *known == id) {
            return self.target.registers().get(*index).copied();
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
