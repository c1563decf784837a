//! What the Watch panel and the debug console do to a paused script, protocol free:
//! assigning to an expression (`setExpression`: `grad(3)`, a sensor, a variable, `r2`),
//! jumping (`goto`), finding the array an evaluated expression names (so a watched
//! `tsum` expands), and the names the console completes. Every change goes through
//! `Debugger::edit`, so it is journaled like `setVariable`: reverse stepping and replays
//! reproduce it at the clock it was made.

use crate::completion::{Kind, Vocabulary};
use crate::debugger::{Debugger, Edit};
use crate::error::{DebugError, DebugResult};
use crate::expr::Number;
use crate::target::{Named, Phase, Target};

/// Where an assignable expression lives.
#[derive(Clone, Debug, PartialEq)]
pub enum Place {
    Variable(String),
    Element(String, i64),
    Register(usize),
    Sensor(usize),
}

/// The value the user typed: hex as the hex format shows it (`0xc0`), else a GBASIC
/// expression over the paused state (`12`, `m_depth + 1`), as the right side of an
/// assignment in the script.
pub fn value_of<T: Target>(debugger: &Debugger<T>, text: &str) -> DebugResult<Number> {
    match crate::format::parse_hex(text) {
        Some(value) => Ok(value),
        None => debugger.evaluate(text).map_err(|message| {
            DebugError::edit(format!("`{}` is not a value: {message}", text.trim()))
        }),
    }
}

/// What `expression` assigns to, read by GBASIC's own expression parser: a name (a
/// scalar variable, then a register `rN`, then a sensor: the order expressions look
/// names up in) or `name(index)` (an element of an array; the index is an expression,
/// evaluated now).
pub fn place<T: Target>(debugger: &Debugger<T>, expression: &str) -> DebugResult<Place> {
    use gloc_compiler::ast::ExprKind;
    let text = expression.trim();
    let parsed = gloc_compiler::parser::parse_expression(text);
    if let Some(error) = parsed
        .diagnostics
        .iter()
        .find(|diagnostic| diagnostic.is_error())
    {
        return Err(DebugError::edit(format!(
            "`{text}` is not an expression: {}",
            error.message
        )));
    }
    let cannot = || {
        DebugError::edit(format!(
            "`{text}` cannot be assigned: write a variable, an array element like `a(3)`, a register like `r2` or a sensor"
        ))
    };
    let target = &debugger.target;
    let kind = parsed.expr.map(|expr| expr.kind).ok_or_else(cannot)?;
    match kind {
        ExprKind::Call { name, args } => {
            let is_array = target
                .variables()
                .iter()
                .any(|named| named.length.is_some() && named.name.eq_ignore_ascii_case(&name.text));
            if !is_array {
                return Err(DebugError::edit(format!(
                    "`{}` is not an array of the script",
                    name.text
                )));
            }
            let [index] = args.as_slice() else {
                return Err(DebugError::edit(format!(
                    "an element of `{}` takes one index",
                    name.text
                )));
            };
            let span = index.span;
            let index_text = text
                .get(span.start as usize..span.end as usize)
                .ok_or_else(cannot)?;
            match debugger.evaluate(index_text)? {
                Number::Int(index) => Ok(Place::Element(name.text, index)),
                Number::Float(value) => Err(DebugError::edit(format!(
                    "the index of `{}` must be an integer, not {value:?}",
                    name.text
                ))),
            }
        }
        ExprKind::Name(name) => {
            let name = name.text;
            if let Some(named) = target
                .variables()
                .into_iter()
                .find(|named| named.name.eq_ignore_ascii_case(&name))
            {
                return match named.length {
                    Some(_) => Err(DebugError::edit(format!(
                        "`{}` is an array: assign to one element, like `{}(0)`",
                        named.name, named.name
                    ))),
                    None => Ok(Place::Variable(named.name)),
                };
            }
            if debugger
                .info
                .scope
                .constants()
                .iter()
                .any(|constant| constant.name.eq_ignore_ascii_case(&name))
            {
                return Err(DebugError::edit(format!(
                    "`{name}` is a constant; change its `const` line and restart"
                )));
            }
            if let Some(index) = name
                .strip_prefix(['r', 'R'])
                .and_then(|digits| digits.parse::<usize>().ok())
                .filter(|index| *index < target.registers().len())
            {
                return Ok(Place::Register(index));
            }
            target
                .sensor_index(&name)
                .map(Place::Sensor)
                .ok_or_else(cannot)
        }
        _ => Err(cannot()),
    }
}

/// `setExpression`: stores `value` (see `value_of`) at the place `expression` names,
/// journaled, and returns what the place now holds (the variable's type may have
/// converted it: an integer variable keeps whole numbers only).
pub fn assign<T: Target>(
    debugger: &mut Debugger<T>,
    expression: &str,
    value: &str,
) -> DebugResult<Number> {
    let place = place(debugger, expression)?;
    let value = value_of(debugger, value)?;
    let edit = match &place {
        Place::Variable(name) => Edit::Variable(name.clone(), value),
        Place::Element(name, index) => Edit::Element(name.clone(), *index, value),
        Place::Register(index) => Edit::Register(*index, value),
        Place::Sensor(index) => Edit::Sensor(*index, value.as_f64()),
    };
    debugger.edit(edit)?;
    let target = &debugger.target;
    let now = match &place {
        Place::Variable(name) => target.variable(name),
        Place::Element(name, index) => target.element(name, *index),
        Place::Register(index) => target.registers().get(*index).copied(),
        Place::Sensor(index) => Some(Number::Float(target.sensor(*index))),
    };
    now.ok_or_else(|| {
        DebugError::edit(format!(
            "`{}` has no value after the assignment",
            expression.trim()
        ))
    })
}

/// The script's array that `expression` names on its own (`tsum`), with its position
/// among the variables (the session's children reference).
pub fn array<T: Target>(debugger: &Debugger<T>, expression: &str) -> Option<(usize, Named)> {
    let name = expression.trim();
    debugger
        .target
        .variables()
        .into_iter()
        .enumerate()
        .find(|(_, named)| named.length.is_some() && named.name.eq_ignore_ascii_case(name))
}

/// `goto`: the script's next instruction becomes `pc`, journaled. Decision: a jump stays
/// within the current cycle's share of the script. Before the share (at a cycle
/// boundary) the share starts at `pc`; part way through it goes on from `pc`; once the
/// script yielded, the share is over and a jump would land in the next cycle, so it is
/// refused with what to do instead. A halted or trapped script cannot go on.
pub fn goto<T: Target>(debugger: &mut Debugger<T>, pc: usize) -> DebugResult<()> {
    if pc >= debugger.info.instruction_count() {
        return Err(DebugError::edit(format!(
            "pc {pc} is not an instruction of the program"
        )));
    }
    if !debugger.target.script_alive() {
        return Err(DebugError::edit(
            "the script has halted or trapped: it cannot go on; restart to run it again",
        ));
    }
    match debugger.target.phase() {
        Phase::Boundary | Phase::InScript => debugger.edit(Edit::Pc(pc)),
        Phase::ScriptDone => Err(DebugError::edit(format!(
            "the script already yielded in cycle {}: a jump now would leave the cycle; step to the next cycle (`next` stops at its boundary) and jump there",
            debugger.clock().cycle
        ))),
        Phase::Ended => Err(DebugError::edit("the mission has ended")),
    }
}

/// Every name the console can complete in this session: variables and arrays, GBASIC
/// constants, the built-in functions, the sensors (those the script uses first).
pub fn vocabulary<T: Target>(debugger: &Debugger<T>) -> Vocabulary {
    let target = &debugger.target;
    let mut vocabulary = Vocabulary::default();
    for named in target.variables() {
        let kind = match named.length {
            Some(_) => Kind::Array,
            None => Kind::Variable,
        };
        let detail = match named.length {
            Some(length) => format!("{}({length})", named.ty),
            None => named.ty.to_string(),
        };
        vocabulary.push(named.name, kind, detail);
    }
    for constant in debugger.info.scope.constants() {
        let declaration = format!("const {} = {}", constant.name, constant.value);
        vocabulary.push(constant.name.clone(), Kind::Constant, declaration);
    }
    let touched = target.touched_sensors();
    for index in 0..target.sensor_count() {
        let Some(name) = target.sensor_name(index) else {
            continue;
        };
        let kind = if touched.contains(&index) {
            Kind::UsedSensor
        } else {
            Kind::Sensor
        };
        vocabulary.push(name, kind, format!("sensor {index}"));
    }
    vocabulary.with_language_words()
}
