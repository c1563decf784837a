//! The script as both debugged worlds see it: the launch attributes and their settings,
//! the loaded script with its variables, and the reads and writes of registers,
//! variables and array elements that the live world and the replay share (so neither
//! world imports the other).

use std::path::PathBuf;
use std::sync::Arc;

use gloc_compiler::{LoadedScript, Storage};
use gloc_engine::program::{Pc, Program, Reg, Value};
use gloc_engine::sensors::SensorList;
use gloc_engine::vm::{Machine, TrapKind as VmTrapKind};
use gloc_project::settings::Settings;
use gloc_project::{Overrides, Surface};

use crate::expr::Number;
use crate::program::SourceLines;
use crate::target::{Named, StepEvent, TrapKind};

/// What the `launch` request gave, checked for types by the session. The project
/// layer (`gloc_project`) resolves it over the nearest gloc.toml and the defaults and
/// checks every value ([`resolve`]); nothing here decides a setting.
#[derive(Clone, Debug, Default)]
pub struct LaunchConfig {
    pub program: PathBuf,
    pub mission: Option<PathBuf>,
    pub masterdata: Option<PathBuf>,
    pub profile: Option<PathBuf>,
    pub seed: Option<u64>,
    /// As given: a budget out of range is refused by the project layer.
    pub cycle_budget: Option<u64>,
    pub max_cycles: Option<u64>,
    /// Recorded data to replay instead of simulating (one CSV file or glider logs).
    pub replay: Vec<PathBuf>,
    /// The folder searched first for the glider logs' sensor lists.
    pub sensor_cache: Option<PathBuf>,
}

/// The project settings of a launch: its attributes over gloc.toml over the defaults.
/// An error names where the value came from (`launch attribute cycleBudget: …`,
/// `gloc.toml:1:16: …`), in the words the CLI and the language server use.
pub fn resolve(config: &LaunchConfig) -> Result<Settings, String> {
    Settings::resolve(
        Some(&config.program),
        Overrides {
            masterdata: config.masterdata.clone(),
            cycle_budget: config.cycle_budget,
            mission: config.mission.clone(),
            sensor_cache: config.sensor_cache.clone(),
            ..Overrides::new(Surface::Launch)
        },
    )
    .map_err(|error| error.to_string())
}

/// A GBASIC variable and where it lives.
#[derive(Clone, Debug)]
pub(crate) struct VariableSlot {
    pub(crate) name: String,
    pub(crate) float: bool,
    pub(crate) storage: Storage,
}

/// The script loaded for debugging: what both worlds start from.
pub(crate) struct DebugScript {
    pub path: PathBuf,
    pub text: String,
    pub program: Arc<Program>,
    pub loaded: LoadedScript,
    /// The source line of each pc.
    pub lines: SourceLines,
    pub variables: Vec<VariableSlot>,
    /// The sensors the script loads or stores, in first-use order.
    pub touched: Vec<usize>,
    pub sensor_list: Arc<SensorList>,
    /// The script's warnings (W2302 over the budget, …), one line each, shown at
    /// launch as `gloc check` shows them.
    pub warnings: Vec<String>,
}

pub(crate) fn registers_of(machine: Option<&Machine>) -> Vec<Number> {
    machine
        .map(|machine| machine.registers().to_vec())
        .unwrap_or_default()
}

pub(crate) fn set_pc_in(machine: Option<&mut Machine>, pc: usize) -> Result<(), String> {
    let pc = u32::try_from(pc).map_err(|_| format!("pc {pc} is not an instruction"))?;
    machine
        .ok_or("no script is running")?
        .set_pc(Pc(pc))
        .map_err(|error| error.to_string())
}

pub(crate) fn set_register_in(
    machine: Option<&mut Machine>,
    index: usize,
    value: Number,
) -> Result<(), String> {
    machine
        .ok_or("no script is running")?
        .set_register(Reg(index as u32), value)
        .map_err(|error| error.to_string())
}

pub(crate) fn variables_of(machine: Option<&Machine>, slots: &[VariableSlot]) -> Vec<Named> {
    let Some(machine) = machine else {
        return Vec::new();
    };
    slots
        .iter()
        .map(|variable| match variable.storage {
            Storage::Register { register } => {
                let value = machine
                    .registers()
                    .get(register as usize)
                    .copied()
                    .unwrap_or_default();
                Named {
                    name: variable.name.clone(),
                    value: value.to_string(),
                    ty: if variable.float { "float" } else { "integer" },
                    length: None,
                    element: None,
                    evaluate_name: Some(variable.name.clone()),
                }
            }
            Storage::Memory { base, size } => {
                let cells: Vec<String> = machine
                    .memory()
                    .iter()
                    .skip(base as usize)
                    .take(size as usize)
                    .map(|cell| typed_cell(variable, *cell).to_string())
                    .collect();
                Named {
                    name: variable.name.clone(),
                    value: format!("[{}]", cells.join(", ")),
                    ty: if variable.float {
                        "float array"
                    } else {
                        "integer array"
                    },
                    length: Some(size as usize),
                    element: Some(if variable.float {
                        gloc_compiler::typed::Ty::Float
                    } else {
                        gloc_compiler::typed::Ty::Integer
                    }),
                    evaluate_name: Some(variable.name.clone()),
                }
            }
        })
        .collect()
}

pub(crate) fn variable_of(
    machine: Option<&Machine>,
    slots: &[VariableSlot],
    name: &str,
) -> Option<Number> {
    let variable = slots
        .iter()
        .find(|variable| variable.name.eq_ignore_ascii_case(name))?;
    match variable.storage {
        Storage::Register { register } => machine?.registers().get(register as usize).copied(),
        // An array has no single value in an expression.
        Storage::Memory { .. } => None,
    }
}

pub(crate) fn set_variable_in(
    machine: Option<&mut Machine>,
    slots: &[VariableSlot],
    name: &str,
    value: Number,
) -> Result<(), String> {
    let variable = slots
        .iter()
        .find(|variable| variable.name.eq_ignore_ascii_case(name))
        .ok_or_else(|| format!("no variable `{name}`"))?;
    let value = typed_value(variable, value)?;
    let machine = machine.ok_or("no script is running")?;
    match variable.storage {
        Storage::Register { register } => machine.set_register(Reg(register), value),
        Storage::Memory { base, .. } => machine.set_memory(base, value),
    }
    .map_err(|error| error.to_string())
}

fn array<'a>(slots: &'a [VariableSlot], name: &str) -> Option<&'a VariableSlot> {
    slots
        .iter()
        .find(|variable| variable.name.eq_ignore_ascii_case(name))
        .filter(|variable| matches!(variable.storage, Storage::Memory { .. }))
}

pub(crate) fn element_of(
    machine: Option<&Machine>,
    slots: &[VariableSlot],
    name: &str,
    index: i64,
) -> Option<Number> {
    let variable = array(slots, name)?;
    let Storage::Memory { base, size } = variable.storage else {
        return None;
    };
    let index = u32::try_from(index).ok().filter(|index| *index < size)?;
    machine?
        .memory()
        .get((base + index) as usize)
        .map(|cell| typed_cell(variable, *cell))
}

/// A memory cell as the script reads it: cells never written hold integer 0, and a
/// float array's read converts (`0.0`), as the compiled `loadm; i2d` does.
fn typed_cell(variable: &VariableSlot, cell: Value) -> Number {
    if variable.float {
        Value::Float(cell.as_f64())
    } else {
        cell
    }
}

pub(crate) fn set_element_in(
    machine: Option<&mut Machine>,
    slots: &[VariableSlot],
    name: &str,
    index: i64,
    value: Number,
) -> Result<(), String> {
    let variable = array(slots, name).ok_or_else(|| format!("no array `{name}`"))?;
    let Storage::Memory { base, size } = variable.storage else {
        return Err(format!("`{name}` is not an array"));
    };
    let index = u32::try_from(index)
        .ok()
        .filter(|index| *index < size)
        .ok_or_else(|| format!("{name}({index}) is outside 0..{}", size.saturating_sub(1)))?;
    let value = typed_value(variable, value)?;
    machine
        .ok_or("no script is running")?
        .set_memory(base + index, value)
        .map_err(|error| error.to_string())
}

/// Keeps a variable's declared type by GBASIC's assignment rule: an integer widens
/// into a float variable; a float is refused by an integer one (as the checker
/// refuses `i = 2.0`).
fn typed_value(variable: &VariableSlot, value: Number) -> Result<Value, String> {
    if variable.float {
        return Ok(Value::Float(value.as_f64()));
    }
    match value {
        Number::Int(value) => Ok(Value::Int(value)),
        Number::Float(value) => Err(format!(
            "`{}` is an integer variable, and {value:?} is a float (convert with `int(…)`, \
             which truncates toward zero)",
            variable.name
        )),
    }
}

/// A float as the script's `print` writes it (the shortest text that reads back exactly).
pub(crate) fn float_text(value: f64) -> String {
    Value::Float(value).to_string()
}

/// A trap as an end-of-run summary words it: what and where, its line from the one
/// pc → line map (as the stop at the trap said it).
pub(crate) fn trap_words(
    trap: &gloc_engine::vm::Trap,
    lines: &SourceLines,
    loaded: &LoadedScript,
) -> String {
    let message = loaded.trap_message(&trap.kind);
    match lines.line(trap.pc.index()) {
        Some(line) => format!("{message} at line {line} (pc {})", trap.pc.0),
        None => format!("{message} (pc {})", trap.pc.0),
    }
}

/// A machine trap as the debugger's exception kind and message (the message the
/// loader words for the script's author, as `gloc run` shows it).
pub(crate) fn trap_event(trap: &gloc_engine::vm::Trap, loaded: &LoadedScript) -> StepEvent {
    StepEvent::Trapped {
        kind: match trap.kind {
            VmTrapKind::CycleOverrun { .. } => TrapKind::CycleOverrun,
            _ => TrapKind::Runtime,
        },
        message: loaded.trap_message(&trap.kind),
    }
}
