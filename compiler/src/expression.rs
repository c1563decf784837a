//! One GBASIC expression outside a program: the debugger's conditions, watches, hovers,
//! logpoint interpolations and `setVariable` values. It is parsed by the script's parser
//! ([`parse_expression`]), checked by the script's checker ([`check_expression`]) against
//! an [`ExpressionScope`], and evaluated here over live values with the machine's own
//! operations ([`gloc_engine::vm::apply_binary`]), so that it computes exactly what the
//! compiled script computes: integer and float kept apart, `/` float division, `\`
//! integer division, `and`/`or`/`not` logical, the same built-ins.

use std::fmt;
use std::sync::Arc;

use gloc_engine::program::Value;
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{apply_binary, apply_unary, BinaryOperation, UnaryOperation};
use gloc_engine::Diagnostic;

use crate::ast::BinaryOp;
use crate::builtins::Instruction;
pub use crate::check::{check_expression, CheckedExpression, ExpressionScope};
pub use crate::parser::{parse_expression, ParsedExpression};
use crate::typed::{Expr, ExprKind, Ty, VarId};
use crate::SourceMap;

/// The live values an expression reads, by the ids of its scope.
pub trait ExpressionState {
    /// The value of the scalar variable `id`; `None` when it has none here.
    fn variable(&self, id: VarId) -> Option<Value>;
    /// Cell `index` of the array `id`, the index already checked against its size.
    fn element(&self, id: VarId, index: usize) -> Option<Value>;
    fn sensor(&self, sensor: SensorId) -> Option<f64>;
}

/// Why an expression that type-checked has no value on the current state.
#[derive(Clone, Debug, PartialEq)]
pub enum EvaluationError {
    /// An integer `\`, `/`-free `mod` or `div` by zero: the script would trap here.
    DivisionByZero,
    /// An index outside its array: the script would trap here.
    IndexOutOfBounds {
        array: String,
        index: i64,
        size: usize,
    },
    /// A name whose value the state does not hold (no script running).
    Unavailable(String),
}

impl fmt::Display for EvaluationError {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EvaluationError::DivisionByZero => formatter.write_str("integer division by zero"),
            EvaluationError::IndexOutOfBounds { array, index, size } => write!(
                formatter,
                "index {index} is outside `{array}` (0 to {})",
                size.saturating_sub(1)
            ),
            EvaluationError::Unavailable(name) => write!(formatter, "`{name}` has no value here"),
        }
    }
}

/// The scope of a compiled GBASIC script: its variables (as the source map keeps them),
/// its constants and the sensor list it was compiled against.
pub fn scope_of_source_map(map: &SourceMap, sensors: Arc<SensorList>) -> ExpressionScope {
    let mut scope = ExpressionScope::new(sensors);
    for variable in &map.variables {
        let size = match variable.storage {
            crate::Storage::Memory { size, .. } => Some(size as usize),
            crate::Storage::Register { .. } => None,
        };
        scope.declare_variable(&variable.name, variable.ty, size);
    }
    for constant in &map.constants {
        if let Some(value) = constant.literal() {
            scope.declare_constant(&constant.name, value);
        }
    }
    scope
}

/// Parses and checks `text` in `scope`: the typed expression, or the first error as
/// `column N: what is wrong (what to do)`.
pub fn compile_expression(text: &str, scope: &ExpressionScope) -> Result<Expr, String> {
    let parsed = parse_expression(text);
    let describe = |diagnostics: &[Diagnostic]| {
        diagnostics
            .iter()
            .find(|diagnostic| diagnostic.is_error())
            .map(|diagnostic| describe(text, diagnostic))
    };
    if let Some(message) = describe(&parsed.diagnostics) {
        return Err(message);
    }
    let Some(expr) = parsed.expr else {
        return Err("the expression is empty".into());
    };
    let checked = check_expression(&expr, scope);
    match describe(&checked.diagnostics) {
        Some(message) => Err(message),
        None => Ok(checked.expr),
    }
}

/// A diagnostic on a one-line expression: its 1-based column (in characters), message
/// and help.
fn describe(text: &str, diagnostic: &Diagnostic) -> String {
    let start = (diagnostic.span.start as usize).min(text.len());
    let column = text
        .get(..start)
        .map_or(start, |before| before.chars().count())
        + 1;
    let mut message = format!("column {column}: {}", diagnostic.message);
    if let Some(help) = &diagnostic.help {
        message.push_str(&format!(" ({help})"));
    }
    message
}

/// The value of a checked expression on `state`, computed as the compiled script does.
pub fn evaluate(
    expr: &Expr,
    scope: &ExpressionScope,
    state: &dyn ExpressionState,
) -> Result<Value, EvaluationError> {
    let value = |expr: &Expr| evaluate(expr, scope, state);
    let name_of = |id: VarId| {
        scope
            .variables()
            .get(id.0)
            .map_or_else(String::new, |variable| variable.name.clone())
    };
    Ok(match &expr.kind {
        ExprKind::Int(number) => Value::Int(*number),
        ExprKind::Float(number) => Value::Float(*number),
        ExprKind::Variable(id) => state
            .variable(*id)
            .ok_or_else(|| EvaluationError::Unavailable(name_of(*id)))?,
        ExprKind::Sensor(sensor) => Value::Float(state.sensor(*sensor).ok_or_else(|| {
            EvaluationError::Unavailable(scope.sensors().name(*sensor).unwrap_or("?").into())
        })?),
        ExprKind::Element { array, index } => {
            let size = scope
                .variables()
                .get(array.0)
                .and_then(|variable| variable.size)
                .unwrap_or(0);
            let index = value(index)?.as_i64();
            let cell = usize::try_from(index)
                .ok()
                .filter(|cell| *cell < size)
                .ok_or_else(|| EvaluationError::IndexOutOfBounds {
                    array: name_of(*array),
                    index,
                    size,
                })?;
            let cell = state
                .element(*array, cell)
                .ok_or_else(|| EvaluationError::Unavailable(name_of(*array)))?;
            // Cells never written hold integer 0; the compiled read of a float array
            // converts (codegen's `I2d` after `loadm`).
            if expr.ty == Ty::Float {
                apply_unary(UnaryOperation::I2d, cell)
            } else {
                cell
            }
        }
        ExprKind::Neg(operand) => apply_unary(UnaryOperation::Neg, value(operand)?),
        ExprKind::Not(operand) => apply_unary(UnaryOperation::Not, value(operand)?),
        ExprKind::ToFloat(operand) => apply_unary(UnaryOperation::I2d, value(operand)?),
        ExprKind::Binary { op, left, right } => {
            // Both sides are computed, as in the compiled code (no short circuit).
            let (a, b) = (value(left)?, value(right)?);
            let (a, b) = if matches!(op, BinaryOp::And | BinaryOp::Or) {
                // Logical: each side made 0 or 1 first (codegen's `truth`).
                let truth = |value| binary(BinaryOperation::CmpNe, value, Value::Int(0));
                (truth(a)?, truth(b)?)
            } else {
                (a, b)
            };
            let operation = op.machine_operation();
            binary(operation, a, b)?
        }
        ExprKind::Call { builtin, args } => {
            let args = args.iter().map(value).collect::<Result<Vec<_>, _>>()?;
            let first = args.first().copied().unwrap_or_default();
            let second = args.get(1).copied().unwrap_or(first);
            // The built-in's own GLOC instruction, from the compiler's one table.
            match builtin.info().instruction {
                Instruction::Unary(operation) => apply_unary(operation, first),
                Instruction::Binary(operation) => binary(operation, first, second)?,
            }
        }
        // The checker reported it; `compile_expression` never returns one.
        ExprKind::Error => return Err(EvaluationError::Unavailable("{error}".into())),
    })
}

fn binary(operation: BinaryOperation, a: Value, b: Value) -> Result<Value, EvaluationError> {
    apply_binary(operation, a, b).map_err(|_| EvaluationError::DivisionByZero)
}

/// The GBASIC type name of a value (`integer`, `float`).
pub fn type_name(value: Value) -> &'static str {
    match value {
        Value::Int(_) => Ty::Integer.name(),
        Value::Float(_) => Ty::Float.name(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ast::Literal;

    struct Fixed;

    impl ExpressionState for Fixed {
        fn variable(&self, id: VarId) -> Option<Value> {
            // `state` (integer 2), `x` (float 12.5)
            [Value::Int(2), Value::Float(12.5)].get(id.0).copied()
        }
        fn element(&self, _: VarId, index: usize) -> Option<Value> {
            Some(Value::Int(index as i64 * 10))
        }
        fn sensor(&self, _: SensorId) -> Option<f64> {
            Some(20.25)
        }
    }

    fn scope() -> ExpressionScope {
        let mut scope = ExpressionScope::new(Arc::new(SensorList::embedded()));
        scope.declare_variable("state", Ty::Integer, None);
        scope.declare_variable("x", Ty::Float, None);
        scope.declare_variable("a", Ty::Integer, Some(3));
        scope.declare_variable("f", Ty::Float, Some(3));
        scope.declare_constant("NBINS", Literal::Int(45));
        scope.declare_constant("MARGIN", Literal::Float(4.0));
        scope
    }

    /// The printed form of `text`'s value (or its error), as GBASIC prints.
    fn run(text: &str) -> Result<String, String> {
        let scope = scope();
        let expr = compile_expression(text, &scope)?;
        evaluate(&expr, &scope, &Fixed)
            .map(|value| value.to_string())
            .map_err(|error| error.to_string())
    }

    fn check(text: &str, expected: &str) {
        assert_eq!(run(text).as_deref(), Ok(expected), "{text}");
    }

    fn error(text: &str) -> String {
        run(text).expect_err(text)
    }

    // Expected values worked by hand from docs/gbasic.md's rules.
    #[test]
    fn the_cases_the_old_evaluator_got_wrong() {
        // `/` is always float division in GBASIC (the old evaluator gave 3).
        check("7 / 2", "3.5");
        check("6 / 3", "2.0");
        // `\` is integer division (the old evaluator refused it).
        check("7 \\ 2", "3");
        check("-7 \\ 2", "-3");
        // `mod` binds looser than `*` and `\`: 7 mod 2 * 3 is 7 mod (2 * 3) = 1 in
        // GBASIC, (7 mod 2) * 3 = 3 with C's precedence; 9 mod 7 \ 2 is 9 mod 3 = 0,
        // not (9 mod 7) \ 2 = 1.
        check("7 mod 2 * 3", "1");
        check("9 mod 7 \\ 2", "0");
        check("1 + 7 mod 4", "4");
        // C operators are refused, with GBASIC's spelling as the help.
        let message = error("state = 2 && x > 1.0");
        assert!(message.contains("column 11"), "{message}");
        assert!(message.contains("`and`"), "{message}");
        assert!(error("7 % 2").contains("`mod`"));
        assert!(error("!state").contains("`not`"));
        assert!(error("state == 2").contains("single `=`"));
        assert!(error("state || 1").contains("`or`"));
    }

    #[test]
    fn integer_and_float_are_kept() {
        check("state + 1", "3");
        check("state + 1.0", "3.0");
        check("x * 2", "25.0");
        check("NBINS - 1", "44");
        check("MARGIN + 10.0", "14.0");
        check("int(x)", "12");
        check("float(state)", "2.0");
        check("min(state, 1)", "1");
        check("max(state, 1.5)", "2.0");
        check("sqrt(16)", "4.0");
        check("abs(-state)", "2");
        check("m_depth", "20.25");
        check("a(state) + a(0)", "20");
        // A float array's cell that holds integer 0 reads as 0.0, as compiled code does.
        check("f(0)", "0.0");
        check("x > 10 and state = 2", "1");
        check("not state <> 2", "1");
        check("state or 0", "1");
        check("3 and 5", "1");
    }

    #[test]
    fn errors_are_messages_with_the_column() {
        assert!(error("").contains("empty"));
        let message = error("x > nope");
        assert!(message.starts_with("column 5:"), "{message}");
        assert!(error("m_dpth > 1").contains("did you mean `m_depth`"));
        assert!(error("x \\ 2").contains("integer"));
        assert!(error("if x > 1.0 then").starts_with("column 1:"));
        assert!(error("(1 + 2").contains("`)`"));
        assert!(error("1 2").contains("after the expression"));
        assert!(error("a(5)").contains("out of bounds"));
        assert_eq!(error("a(state + 2)"), "index 4 is outside `a` (0 to 2)");
        assert_eq!(error("1 \\ (state - 2)"), "integer division by zero");
        assert!(error(&"(".repeat(60_000)).contains("nested"));
        assert!(error(&"-".repeat(60_000)).contains("nested"));
        assert!(error(&"not ".repeat(16_000)).contains("nested"));
        assert!(error(&vec!["1"; 1000].join(" + ")).contains("deep"));
        assert!(error(&"1+".repeat(40_000)).contains("at most 65536"));
        assert!(error("a").contains("array"));
        assert!(error("NBINS(1)").contains("constant"));
    }
}
