//! The GLOC interpreter: runs a checked [`Program`] one control cycle at a
//! time against a [`Host`] that owns the sensor array.
//!
//! All state is allocated in [`Machine::new`], sized from the header; running
//! allocates nothing (the output line buffer is reused). One `match` loop over
//! resolved instructions, with the per-cycle budget as fuel.

use std::fmt::{self, Write as _};
use std::sync::Arc;

use crate::diagnostic::Span;
use crate::program::{Instr, Pc, Program, Reg, Value};
use crate::sensors::SensorId;

/// The default per-cycle instruction budget. The paper's engine added at most
/// 30 ms to the 4 s cycle on a 16 MHz Persistor, where an interpreted
/// instruction costs a few microseconds: 10,000 instructions is that order of
/// time, and far more than any script in the paper needs (Fig. 2 runs at most 16).
pub const DEFAULT_CYCLE_BUDGET: u64 = 10_000;

/// How a script sees the world: the glider's sensor array and its output.
pub trait Host {
    fn load_sensor(&mut self, sensor: SensorId) -> f64;
    fn store_sensor(&mut self, sensor: SensorId, value: f64);
    /// One finished output line (from `print` or `prints`), without a newline.
    fn print_line(&mut self, line: &str);
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MachineConfig {
    /// Instructions one cycle may execute before it traps with a cycle overrun.
    pub cycle_budget: u64,
}

impl Default for MachineConfig {
    fn default() -> MachineConfig {
        MachineConfig {
            cycle_budget: DEFAULT_CYCLE_BUDGET,
        }
    }
}

/// A run-time failure. After a trap the script stops; the host carries on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TrapKind {
    /// Integer `div` or `mod` with a zero divisor.
    DivisionByZero,
    /// `loadm`/`storem` outside `0..nmem`.
    MemoryOutOfBounds { address: i64, size: u32 },
    /// `loadm`/`storem` with a float address that is not a whole number.
    NonIntegerAddress { value: f64 },
    /// `jump rN` where rN holds no defined label number.
    BadIndirectJump { value: Value },
    /// The cycle executed its whole budget without reaching a `yield`.
    CycleOverrun { budget: u64 },
}

/// A trap with the pc of the instruction that caused it and its source place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trap {
    pub kind: TrapKind,
    pub pc: Pc,
    /// 1-based source line of the instruction.
    pub line: u32,
    pub span: Span,
}

/// Why [`Machine::run_cycle`] returned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CycleEnd {
    Yielded,
    /// The script executed `halt` (or fell off its end); it stays halted.
    Halted,
    Trapped(Trap),
}

/// Whether the machine can still run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Status {
    Running,
    Halted,
    Trapped(Trap),
}

/// An error from the debugging setters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AccessError {
    #[error("register r{0} does not exist")]
    NoSuchRegister(u32),
    #[error("memory address {0} does not exist")]
    NoSuchAddress(u32),
}

/// A running script. Cheap to clone (the program is shared), so a debugger
/// can snapshot it.
#[derive(Clone, Debug)]
pub struct Machine {
    program: Arc<Program>,
    config: MachineConfig,
    pc: u32,
    registers: Vec<Value>,
    memory: Vec<Value>,
    /// The output line being built by `write`/`writes`.
    output: String,
    executed_this_cycle: u64,
    /// False between cycles: the next instruction starts a new cycle.
    in_cycle: bool,
    cycles_completed: u64,
    status: Status,
}

/// How the inner loop stopped.
enum Exit {
    Yield,
    Halt,
    Trap(TrapKind),
    OutOfFuel,
}

impl Machine {
    pub fn new(program: Arc<Program>, config: MachineConfig) -> Machine {
        let registers = vec![Value::default(); program.register_count as usize];
        let memory = vec![Value::default(); program.memory_size as usize];
        Machine {
            program,
            config,
            pc: 0,
            registers,
            memory,
            output: String::with_capacity(256),
            executed_this_cycle: 0,
            in_cycle: false,
            cycles_completed: 0,
            status: Status::Running,
        }
    }

    /// Runs until `yield`, `halt`, a trap or the cycle budget runs out (a
    /// [`TrapKind::CycleOverrun`]). A halted or trapped machine returns the
    /// same end again without running.
    pub fn run_cycle(&mut self, host: &mut impl Host) -> CycleEnd {
        self.execute(host, u64::MAX).unwrap_or(CycleEnd::Yielded)
    }

    /// Executes one instruction. `None`: the cycle goes on; `Some(end)`: the
    /// instruction ended the cycle (or the machine is halted or trapped).
    pub fn step(&mut self, host: &mut impl Host) -> Option<CycleEnd> {
        self.execute(host, 1)
    }

    /// Starts the script again from pc 0 with cleared registers and memory.
    pub fn reset(&mut self) {
        self.pc = 0;
        self.registers.fill(Value::default());
        self.memory.fill(Value::default());
        self.output.clear();
        self.executed_this_cycle = 0;
        self.in_cycle = false;
        self.cycles_completed = 0;
        self.status = Status::Running;
    }

    pub fn program(&self) -> &Arc<Program> {
        &self.program
    }

    pub fn config(&self) -> MachineConfig {
        self.config
    }

    /// The next instruction to execute (for a trapped machine: the one that trapped).
    pub fn pc(&self) -> Pc {
        Pc(self.pc)
    }

    pub fn status(&self) -> Status {
        self.status
    }

    pub fn registers(&self) -> &[Value] {
        &self.registers
    }

    pub fn memory(&self) -> &[Value] {
        &self.memory
    }

    /// Instructions executed in the current cycle (or in the last one, between cycles).
    pub fn instructions_this_cycle(&self) -> u64 {
        self.executed_this_cycle
    }

    /// Cycles ended by a `yield` so far.
    pub fn cycles_completed(&self) -> u64 {
        self.cycles_completed
    }

    /// True between cycles: the next instruction starts a new cycle.
    pub fn at_cycle_boundary(&self) -> bool {
        !self.in_cycle
    }

    /// The output line written so far by `write`/`writes` and not yet printed.
    pub fn pending_output(&self) -> &str {
        &self.output
    }

    pub fn set_register(&mut self, register: Reg, value: Value) -> Result<(), AccessError> {
        let slot = self
            .registers
            .get_mut(register.index())
            .ok_or(AccessError::NoSuchRegister(register.0))?;
        *slot = value;
        Ok(())
    }

    pub fn set_memory(&mut self, address: u32, value: Value) -> Result<(), AccessError> {
        let slot = self
            .memory
            .get_mut(address as usize)
            .ok_or(AccessError::NoSuchAddress(address))?;
        *slot = value;
        Ok(())
    }

    fn trap(&mut self, kind: TrapKind) -> CycleEnd {
        let pc = Pc(self.pc);
        let trap = Trap {
            kind,
            pc,
            line: self.program.line(pc),
            span: self.program.span(pc),
        };
        self.status = Status::Trapped(trap);
        self.in_cycle = false;
        CycleEnd::Trapped(trap)
    }

    /// The interpreter loop: at most `max_instructions`, within the budget.
    fn execute(&mut self, host: &mut impl Host, max_instructions: u64) -> Option<CycleEnd> {
        match self.status {
            Status::Running => {}
            Status::Halted => return Some(CycleEnd::Halted),
            Status::Trapped(trap) => return Some(CycleEnd::Trapped(trap)),
        }
        if !self.in_cycle {
            self.in_cycle = true;
            self.executed_this_cycle = 0;
        }
        let allowed = max_instructions.min(
            self.config
                .cycle_budget
                .saturating_sub(self.executed_this_cycle),
        );
        let mut fuel = allowed;
        let program: &Program = &self.program;
        let instrs = program.instrs.as_slice();
        let registers = self.registers.as_mut_slice();
        let memory = self.memory.as_mut_slice();
        let output = &mut self.output;
        let mut pc = self.pc as usize;

        macro_rules! reg {
            ($register:expr) => {
                registers[$register.0 as usize]
            };
        }
        macro_rules! arithmetic {
            ($a:expr, $b:expr, $dst:expr, |$x:ident, $y:ident| $int:expr, |$fx:ident, $fy:ident| $float:expr) => {{
                reg!($dst) = match (reg!($a), reg!($b)) {
                    (Value::Int($x), Value::Int($y)) => Value::Int($int),
                    (left, right) => {
                        let ($fx, $fy) = (left.as_f64(), right.as_f64());
                        Value::Float($float)
                    }
                };
            }};
        }
        macro_rules! compare {
            ($a:expr, $b:expr, $dst:expr, $op:tt) => {{
                let result = match (reg!($a), reg!($b)) {
                    (Value::Int(x), Value::Int(y)) => x $op y,
                    (left, right) => left.as_f64() $op right.as_f64(),
                };
                reg!($dst) = Value::Int(i64::from(result));
            }};
        }
        macro_rules! bitwise {
            ($a:expr, $b:expr, $dst:expr, $op:tt) => {{
                reg!($dst) = Value::Int(reg!($a).as_i64() $op reg!($b).as_i64());
            }};
        }
        macro_rules! address {
            ($value:expr) => {
                match memory_index($value, memory.len()) {
                    Ok(index) => index,
                    Err(kind) => break Exit::Trap(kind),
                }
            };
        }

        let exit = loop {
            if fuel == 0 {
                break Exit::OutOfFuel;
            }
            fuel -= 1;
            let Some(instr) = instrs.get(pc) else {
                // Unreachable for a checked program (it ends with `Halt`).
                break Exit::Halt;
            };
            match *instr {
                Instr::LoadSensor { sensor, dst } => {
                    reg!(dst) = Value::Float(host.load_sensor(sensor));
                }
                Instr::StoreSensor { src, sensor } => {
                    host.store_sensor(sensor, reg!(src).as_f64());
                }
                Instr::LoadInt { value, dst } => reg!(dst) = Value::Int(value),
                Instr::LoadFloat { value, dst } => reg!(dst) = Value::Float(value),
                Instr::Move { src, dst } => reg!(dst) = reg!(src),
                Instr::Add { a, b, dst } => {
                    arithmetic!(a, b, dst, |x, y| x.wrapping_add(y), |x, y| x + y)
                }
                Instr::Sub { a, b, dst } => {
                    arithmetic!(a, b, dst, |x, y| x.wrapping_sub(y), |x, y| x - y)
                }
                Instr::Mul { a, b, dst } => {
                    arithmetic!(a, b, dst, |x, y| x.wrapping_mul(y), |x, y| x * y)
                }
                Instr::Div { a, b, dst } => {
                    if let (Value::Int(_), Value::Int(0)) = (reg!(a), reg!(b)) {
                        break Exit::Trap(TrapKind::DivisionByZero);
                    }
                    arithmetic!(a, b, dst, |x, y| x.wrapping_div(y), |x, y| x / y)
                }
                Instr::Mod { a, b, dst } => {
                    if let (Value::Int(_), Value::Int(0)) = (reg!(a), reg!(b)) {
                        break Exit::Trap(TrapKind::DivisionByZero);
                    }
                    arithmetic!(a, b, dst, |x, y| x.wrapping_rem(y), |x, y| x % y)
                }
                Instr::Min { a, b, dst } => {
                    arithmetic!(a, b, dst, |x, y| x.min(y), |x, y| x.min(y))
                }
                Instr::Max { a, b, dst } => {
                    arithmetic!(a, b, dst, |x, y| x.max(y), |x, y| x.max(y))
                }
                Instr::And { a, b, dst } => bitwise!(a, b, dst, &),
                Instr::Or { a, b, dst } => bitwise!(a, b, dst, |),
                Instr::Xor { a, b, dst } => bitwise!(a, b, dst, ^),
                Instr::CmpEq { a, b, dst } => compare!(a, b, dst, ==),
                Instr::CmpNe { a, b, dst } => compare!(a, b, dst, !=),
                Instr::CmpLt { a, b, dst } => compare!(a, b, dst, <),
                Instr::CmpLe { a, b, dst } => compare!(a, b, dst, <=),
                Instr::CmpGt { a, b, dst } => compare!(a, b, dst, >),
                Instr::CmpGe { a, b, dst } => compare!(a, b, dst, >=),
                Instr::Neg { src, dst } => {
                    reg!(dst) = match reg!(src) {
                        Value::Int(x) => Value::Int(x.wrapping_neg()),
                        Value::Float(x) => Value::Float(-x),
                    }
                }
                Instr::Abs { src, dst } => {
                    reg!(dst) = match reg!(src) {
                        Value::Int(x) => Value::Int(x.wrapping_abs()),
                        Value::Float(x) => Value::Float(x.abs()),
                    }
                }
                Instr::Sqrt { src, dst } => reg!(dst) = Value::Float(reg!(src).as_f64().sqrt()),
                Instr::IntToFloat { src, dst } => reg!(dst) = Value::Float(reg!(src).as_f64()),
                Instr::FloatToInt { src, dst } => reg!(dst) = Value::Int(reg!(src).as_i64()),
                Instr::Not { src, dst } => reg!(dst) = Value::Int(i64::from(!reg!(src).is_true())),
                Instr::LoadMem { addr, dst } => {
                    let index = address!(reg!(addr));
                    reg!(dst) = memory[index];
                }
                Instr::LoadMemAt { addr, dst } => reg!(dst) = memory[addr as usize],
                Instr::StoreMem { src, addr } => {
                    let index = address!(reg!(addr));
                    memory[index] = reg!(src);
                }
                Instr::StoreMemAt { src, addr } => memory[addr as usize] = reg!(src),
                Instr::Branch {
                    cond,
                    if_true,
                    if_false,
                } => {
                    pc = if reg!(cond).is_true() {
                        if_true.index()
                    } else {
                        if_false.index()
                    };
                    continue;
                }
                Instr::Jump { target } => {
                    pc = target.index();
                    continue;
                }
                Instr::JumpIndirect { register } => {
                    let value = reg!(register);
                    let target = match value {
                        Value::Int(label) => usize::try_from(label)
                            .ok()
                            .and_then(|label| program.label_pcs.get(label).copied().flatten()),
                        Value::Float(_) => None,
                    };
                    match target {
                        Some(target) => {
                            pc = target.index();
                            continue;
                        }
                        None => break Exit::Trap(TrapKind::BadIndirectJump { value }),
                    }
                }
                Instr::Yield => break Exit::Yield,
                Instr::Halt => break Exit::Halt,
                Instr::Nop => {}
                Instr::Write { src } => append_item(output, |out| write_value(out, reg!(src))),
                Instr::WriteText { text } => {
                    let text = program.texts.get(text as usize).map_or("", |text| text);
                    append_item(output, |out| out.push_str(text));
                }
                Instr::Print { src } => {
                    append_item(output, |out| write_value(out, reg!(src)));
                    host.print_line(output);
                    output.clear();
                }
                Instr::PrintText { text } => {
                    let text = program.texts.get(text as usize).map_or("", |text| text);
                    append_item(output, |out| out.push_str(text));
                    host.print_line(output);
                    output.clear();
                }
            }
            pc += 1;
        };

        self.executed_this_cycle += allowed - fuel;
        self.pc = pc as u32;
        match exit {
            Exit::Yield => {
                self.pc += 1;
                self.in_cycle = false;
                self.cycles_completed += 1;
                Some(CycleEnd::Yielded)
            }
            Exit::Halt => {
                self.status = Status::Halted;
                self.in_cycle = false;
                Some(CycleEnd::Halted)
            }
            Exit::Trap(kind) => Some(self.trap(kind)),
            Exit::OutOfFuel => {
                if self.executed_this_cycle >= self.config.cycle_budget {
                    Some(self.trap(TrapKind::CycleOverrun {
                        budget: self.config.cycle_budget,
                    }))
                } else {
                    None
                }
            }
        }
    }
}

/// Converts a register value to a memory index, or the trap it causes.
fn memory_index(value: Value, size: usize) -> Result<usize, TrapKind> {
    let address = match value {
        Value::Int(address) => address,
        Value::Float(address) => {
            if address.fract() != 0.0 || !address.is_finite() {
                return Err(TrapKind::NonIntegerAddress { value: address });
            }
            address as i64
        }
    };
    match usize::try_from(address) {
        Ok(index) if index < size => Ok(index),
        _ => Err(TrapKind::MemoryOutOfBounds {
            address,
            size: size as u32,
        }),
    }
}

/// Appends one output item, separated from the previous one by a space.
fn append_item(output: &mut String, write: impl FnOnce(&mut String)) {
    if !output.is_empty() {
        output.push(' ');
    }
    write(output);
}

fn write_value(output: &mut String, value: Value) {
    // Writing to a String cannot fail.
    let _ = write!(output, "{value}");
}

impl fmt::Display for TrapKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TrapKind::DivisionByZero => f.write_str("integer division by zero"),
            TrapKind::MemoryOutOfBounds { address, size } => write!(
                f,
                "memory address {address} is out of bounds (nmem {size}: 0 to {})",
                i64::from(*size) - 1
            ),
            TrapKind::NonIntegerAddress { value } => {
                write!(f, "memory address {value:?} is not a whole number")
            }
            TrapKind::BadIndirectJump { value } => {
                write!(f, "indirect jump to {value}, which is not a defined label")
            }
            TrapKind::CycleOverrun { budget } => write!(
                f,
                "cycle overrun: {budget} instructions ran without a `yield`"
            ),
        }
    }
}

impl fmt::Display for Trap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} (pc {}, line {})", self.kind, self.pc.0, self.line)
    }
}
