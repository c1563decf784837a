//! The script as both debugged worlds see it: what a launch gives (`LaunchConfig`, its
//! settings resolved by the project layer), the loaded script, and [`ScriptState`], the
//! one implementation of the reads and writes of registers, variables, array elements
//! and the pc that the live world and the replay share (so neither world imports the
//! other, and the debugger's `Target` is implemented once, by `world::World`).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gloc_compiler::{LoadedScript, Storage};
use gloc_engine::program::{Pc, Program, Reg, Value};
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{CycleEnd, Machine, TrapKind as VmTrapKind};
use gloc_engine::Diagnostic;
use gloc_project::settings::Settings;
use gloc_project::{Overrides, Surface};

use crate::error::{DebugError, DebugResult};
use crate::expr::Number;
use crate::program::SourceLines;
use crate::target::{Named, StepEvent, TrapKind};

/// What a launch gives besides the script's path: the settings it overrides (the
/// attributes `mission`, `masterdata`, `cycleBudget`, `sensorCache`, mapped onto the
/// project layer's one `Overrides` by `launch`), and what is no setting (the profile,
/// the seed, the run's length, the recording to replay). The project layer
/// (`gloc_project`) resolves the overrides over the nearest gloc.toml and the defaults
/// and checks every value ([`resolve`]); nothing here decides a setting.
#[derive(Clone, Debug)]
pub struct LaunchConfig {
    pub program: PathBuf,
    pub overrides: Overrides,
    pub profile: Option<PathBuf>,
    pub seed: Option<u64>,
    pub max_cycles: Option<u64>,
    /// Recorded data to replay instead of simulating (one CSV file or glider logs).
    pub replay: Vec<PathBuf>,
}

impl Default for LaunchConfig {
    fn default() -> Self {
        LaunchConfig {
            program: PathBuf::new(),
            overrides: Overrides::new(Surface::Launch),
            profile: None,
            seed: None,
            max_cycles: None,
            replay: Vec::new(),
        }
    }
}

impl LaunchConfig {
    /// The script at `program` flown in `mission` (the embedded Fig. 2 mission when
    /// `None`), everything else as gloc.toml or the defaults say.
    pub fn new(program: impl Into<PathBuf>, mission: Option<PathBuf>) -> LaunchConfig {
        let mut config = LaunchConfig {
            program: program.into(),
            ..LaunchConfig::default()
        };
        config.overrides.mission = mission;
        config
    }
}

/// The project settings of a launch: its attributes over gloc.toml over the defaults.
/// An error names where the value came from (`launch attribute cycleBudget: …`,
/// `gloc.toml:1:16: …`), in the words the CLI and the language server use.
pub fn resolve(config: &LaunchConfig) -> DebugResult<Settings> {
    Settings::resolve(Some(&config.program), config.overrides.clone())
        .map_err(|error| DebugError::launch(error.to_string()))
}

/// A GBASIC variable and where it lives.
#[derive(Clone, Debug)]
pub(crate) struct VariableSlot {
    pub(crate) name: String,
    pub(crate) float: bool,
    pub(crate) storage: Storage,
}

/// The script loaded for debugging: what both worlds start from, its source and
/// the state the world it launches keeps (its `touched` are the script's own sensors,
/// in first-use order, until a replay adds the recorded ones).
pub(crate) struct DebugScript {
    pub path: PathBuf,
    pub text: String,
    /// The loaded script's program (`state.loaded.program`, which a launch requires).
    pub program: Arc<Program>,
    pub state: ScriptState,
}

impl DebugScript {
    /// The script's warnings (W2302 over the budget, …), one line each, shown at
    /// launch as `gloc check` shows them.
    pub fn warnings(&self) -> impl Iterator<Item = String> + '_ {
        self.state
            .loaded
            .diagnostics
            .iter()
            .filter(|diagnostic| !diagnostic.is_error())
            .map(|diagnostic| self.render(diagnostic))
    }

    /// `file:line:column: severity[CODE]: message` for a diagnostic of the script.
    pub fn render(&self, diagnostic: &Diagnostic) -> String {
        render(&self.path, &self.text, diagnostic)
    }
}

/// `file:line:column: severity[CODE]: message`: the headline of the one renderer
/// (`gloc_engine::render`), as the CLI prints it.
pub(crate) fn render(path: &Path, text: &str, diagnostic: &Diagnostic) -> String {
    let display = path.display().to_string();
    gloc_engine::render::SourceFile::new(&display, text).headline(diagnostic)
}

/// The script as both worlds run it, fixed for the run and shared by every snapshot:
/// its variables, its lines, the loaded script (which words traps), the sensors it
/// touches, the sensor list and the run's length. The reads and writes of the script's
/// state (registers, variables, array elements, the pc) are its methods, over the
/// machine of whichever world holds it (`None`: no script is running), so the live
/// and the replay world share one implementation of them.
#[derive(Debug)]
pub struct ScriptState {
    pub(crate) variables: Vec<VariableSlot>,
    /// The source line of each pc.
    pub(crate) lines: SourceLines,
    /// The loaded script, which names traps for the script's author.
    pub(crate) loaded: LoadedScript,
    /// The sensors the Sensors scope lists first: the script's, in first-use order
    /// (and, in a replay, the recorded ones the list has).
    pub(crate) touched: Vec<usize>,
    pub(crate) sensor_list: Arc<SensorList>,
    /// The run stops after this many cycles (`maxCycles`).
    pub(crate) max_cycles: Option<u64>,
}

impl ScriptState {
    pub fn sensor_count(&self) -> usize {
        self.sensor_list.len()
    }

    pub fn sensor_name(&self, index: usize) -> Option<&str> {
        self.sensor_list.name(SensorId(index as u32))
    }

    pub fn sensor_index(&self, name: &str) -> Option<usize> {
        self.sensor_list.lookup(name).map(SensorId::index)
    }

    pub(crate) fn registers(&self, machine: Option<&Machine>) -> Vec<Number> {
        machine
            .map(|machine| machine.registers().to_vec())
            .unwrap_or_default()
    }

    pub(crate) fn set_pc(&self, machine: Option<&mut Machine>, pc: usize) -> DebugResult<()> {
        let pc = u32::try_from(pc)
            .map_err(|_| DebugError::edit(format!("pc {pc} is not an instruction")))?;
        running(machine)?
            .set_pc(Pc(pc))
            .map_err(|error| DebugError::edit(error.to_string()))
    }

    pub(crate) fn set_register(
        &self,
        machine: Option<&mut Machine>,
        index: usize,
        value: Number,
    ) -> DebugResult<()> {
        running(machine)?
            .set_register(Reg(index as u32), value)
            .map_err(|error| DebugError::edit(error.to_string()))
    }

    pub(crate) fn variables(&self, machine: Option<&Machine>) -> Vec<Named> {
        let Some(machine) = machine else {
            return Vec::new();
        };
        self.variables
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

    pub(crate) fn variable(&self, machine: Option<&Machine>, name: &str) -> Option<Number> {
        let variable = self.slot(name)?;
        match variable.storage {
            Storage::Register { register } => machine?.registers().get(register as usize).copied(),
            // An array has no single value in an expression.
            Storage::Memory { .. } => None,
        }
    }

    pub(crate) fn set_variable(
        &self,
        machine: Option<&mut Machine>,
        name: &str,
        value: Number,
    ) -> DebugResult<()> {
        let variable = self
            .slot(name)
            .ok_or_else(|| DebugError::edit(format!("no variable `{name}`")))?;
        let value = typed_value(variable, value)?;
        let machine = running(machine)?;
        match variable.storage {
            Storage::Register { register } => machine.set_register(Reg(register), value),
            Storage::Memory { base, .. } => machine.set_memory(base, value),
        }
        .map_err(|error| DebugError::edit(error.to_string()))
    }

    pub(crate) fn element(
        &self,
        machine: Option<&Machine>,
        name: &str,
        index: i64,
    ) -> Option<Number> {
        let variable = self.array(name)?;
        let Storage::Memory { base, size } = variable.storage else {
            return None;
        };
        let index = u32::try_from(index).ok().filter(|index| *index < size)?;
        machine?
            .memory()
            .get((base + index) as usize)
            .map(|cell| typed_cell(variable, *cell))
    }

    pub(crate) fn set_element(
        &self,
        machine: Option<&mut Machine>,
        name: &str,
        index: i64,
        value: Number,
    ) -> DebugResult<()> {
        let variable = self
            .array(name)
            .ok_or_else(|| DebugError::edit(format!("no array `{name}`")))?;
        let Storage::Memory { base, size } = variable.storage else {
            return Err(DebugError::edit(format!("`{name}` is not an array")));
        };
        let index = u32::try_from(index)
            .ok()
            .filter(|index| *index < size)
            .ok_or_else(|| {
                DebugError::edit(format!(
                    "{name}({index}) is outside 0..{}",
                    size.saturating_sub(1)
                ))
            })?;
        let value = typed_value(variable, value)?;
        running(machine)?
            .set_memory(base + index, value)
            .map_err(|error| DebugError::edit(error.to_string()))
    }

    /// A trap as an end-of-run summary words it: what and where, its line from the one
    /// pc → line map (as the stop at the trap said it).
    pub(crate) fn trap_words(&self, trap: &gloc_engine::vm::Trap) -> String {
        let message = self.loaded.trap_message(&trap.kind);
        match self.lines.line(trap.pc.index()) {
            Some(line) => format!("{message} at line {line} (pc {})", trap.pc.0),
            None => format!("{message} (pc {})", trap.pc.0),
        }
    }

    /// How a share of the script ended as the debugger's step event (a trap with the
    /// message the loader words for the script's author, as `gloc run` shows it).
    pub(crate) fn step_event(&self, end: Option<CycleEnd>) -> StepEvent {
        match end {
            None => StepEvent::Executed,
            Some(CycleEnd::Yielded) => StepEvent::Yielded,
            Some(CycleEnd::Halted) => StepEvent::Halted,
            Some(CycleEnd::Trapped(trap)) => StepEvent::Trapped {
                kind: match trap.kind {
                    VmTrapKind::CycleOverrun { .. } => TrapKind::CycleOverrun,
                    _ => TrapKind::Runtime,
                },
                message: self.loaded.trap_message(&trap.kind),
            },
        }
    }

    fn slot(&self, name: &str) -> Option<&VariableSlot> {
        self.variables
            .iter()
            .find(|variable| variable.name.eq_ignore_ascii_case(name))
    }

    fn array(&self, name: &str) -> Option<&VariableSlot> {
        self.slot(name)
            .filter(|variable| matches!(variable.storage, Storage::Memory { .. }))
    }
}

/// The machine an edit needs, or why there is none.
fn running(machine: Option<&mut Machine>) -> DebugResult<&mut Machine> {
    machine.ok_or_else(|| DebugError::edit("no script is running"))
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

/// Keeps a variable's declared type by GBASIC's assignment rule: an integer widens
/// into a float variable; a float is refused by an integer one (as the checker
/// refuses `i = 2.0`).
fn typed_value(variable: &VariableSlot, value: Number) -> DebugResult<Value> {
    if variable.float {
        return Ok(Value::Float(value.as_f64()));
    }
    match value {
        Number::Int(value) => Ok(Value::Int(value)),
        Number::Float(value) => Err(DebugError::edit(format!(
            "`{}` is an integer variable, and {value:?} is a float (convert with `int(…)`, \
             which truncates toward zero)",
            variable.name
        ))),
    }
}

/// A float as the script's `print` writes it (the shortest text that reads back exactly).
pub(crate) fn float_text(value: f64) -> String {
    Value::Float(value).to_string()
}
