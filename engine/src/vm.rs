//! The GLOC interpreter: runs a checked [`Program`] one control cycle at a
//! time against a [`Host`] that owns the sensor array.
//!
//! All state is allocated in [`Machine::new`], sized from the header; running
//! allocates nothing (the output line buffer is reused). One `match` loop over
//! resolved instructions, with the per-cycle budget as fuel, and in optimised
//! builds threaded dispatch over the same code (`vm/threaded.rs`), with the
//! `match` loop as its reference.
//!
//! ## How it runs (moved here from ARCHITECTURE.md)
//!
//! `vm::Machine` runs it: a `match` loop (and, in optimised builds, threaded code; below)
//! with the cycle budget as fuel, state allocated in `new`, output line buffer reused
//! (and handed to the host at 64 KiB, `MAX_OUTPUT_LINE`, so a script that never prints
//! cannot grow it). The loop does not run `Instr` itself but the machine's own
//! form, `vm::code` (built once in `Machine::new`, shared by clones): a one-to-one
//! "plain" copy and a "fused" copy of the same length in which common groups are one
//! dispatch (a constant operand and its arithmetic, compare and branch, a constant
//! compare and branch, `i2d` and `add`, GBASIC's six-instruction array index check, a
//! back-edge `jumpi` threaded into the loop test). A fused op at pc `i` writes every
//! register its instructions write and leaves the covered pcs their plain copies, so
//! jumps into a group stay right; groups that could trap, yield or print are never fused,
//! so traps and output keep their pc. The fused loop runs while the fuel covers the
//! widest group and the plain loop finishes the budget, so the cycle budget, `step` (one
//! unit of fuel: always plain) and overrun traps stay exact to the instruction. In
//! optimised builds the fused code runs as threaded code (`vm/threaded.rs`,
//! `Dispatch::Threaded`): one slot per op holding the handler function chosen for its
//! variant (and its comparison and its constant's type; integer fast paths that go on in
//! the general handler by a tail call), its branch targets as offsets and its operands;
//! every handler has one signature and ends by calling the next slot's handler in tail
//! position, which LLVM compiles to an indirect `jmp` (one per handler, and a conditional
//! branch before it in branching ops, so the predictor learns each). Rust does not
//! guarantee the tail call, so `engine/tests/tail_calls.rs` builds the release library
//! and reads its disassembly (`objdump`) and fails when a handler calls through a
//! register; at `opt-level` 0 there are no tail calls, so `engine/build.rs` sets
//! `cfg(gloc_threaded)` only at `opt-level` 2, 3, `s` or `z`, and the `match` loop stays
//! the default elsewhere and the reference: `fused.rs` runs the loop, the threaded code
//! and single steps on the same scripts and budgets (1–80) and compares everything after
//! every cycle. Handlers are also specialised by the registers' static types: `Code::new`
//! runs a forward data-flow analysis over the plain code (`code::Types`: per pc and
//! register, the set {integer, float} it can hold, joined at merges; per pc because `-O`
//! gives one register to variables of different types; memory untracked; given up past
//! 65,536 pcs, 4 M (pc, register) cells or 64 M joins), and a second slot array
//! (`Code::typed`) takes, for each op whose operands have one known type, a handler
//! instantiated for it (a const parameter) that reads the register without testing its
//! tag. The machine runs it while its registers agree with the analysis:
//! `Machine::set_register` (the debugger's `setVariable`) switches to the untyped slots
//! when the stored value's type is not one the analysis allows there, until `reset`. A
//! typed read loads the payload from either variant, so a wrong analysis would give a
//! wrong number, never undefined behaviour. The plain instruction list is written twice,
//! as `program::Instr` and as the plain variants of `vm::code::Op` (the interpreter's
//! `repr(u8)` enum, which adds the fused variants); `Op`'s `From<Instr>` is one
//! exhaustive mapping generated from `code.rs`'s table, so an op or a field added to one
//! and not the other does not compile. Output ops are left to the `match` loop (one
//! implementation of printing); a handler gets at most 4,096 units of fuel per entry,
//! which bounds the stack should a tail call ever be missing. Decision: register reads
//! and op fetches are unchecked (`unsafe`) after `Code::new` established the invariants
//! (the register file covers every register an op names; the code ends with `halt` and
//! every target lies inside it): measured with callgrind, they were 15% of the loop's
//! instructions. The engine is the one crate allowed `unsafe` (every other crate has
//! `#![forbid(unsafe_code)]`), and only at those accesses: in the threaded handlers the
//! bodies are safe code, registers are reached through `threaded::Registers` whose
//! accessors carry the one SAFETY argument, and each slot dereference and tail call has
//! its own SAFETY line (`clippy::undocumented_unsafe_blocks` is denied workspace-wide).

use std::fmt::{self, Write as _};
use std::sync::Arc;

use crate::diagnostic::Span;
use crate::program::{Pc, Program, Reg, Value};
use crate::sensors::SensorId;

mod code;
mod match_loop;
mod threaded;

use code::{Code, MAX_FUSED};

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
    /// [`Host::print_line`] with the pc of the instruction that ended the line (a
    /// `print`/`prints`, or a `write` that made it too long); the machine calls this
    /// one. A host that shows where output comes from overrides it.
    fn print_line_at(&mut self, line: &str, pc: Pc) {
        let _ = pc;
        self.print_line(line);
    }
}

/// A sensor's value in a host's sensor array (indexed by the active list): a sensor
/// past its end reads 0, the rule every host keeps.
#[inline]
pub fn sensor_value(values: &[f64], sensor: SensorId) -> f64 {
    values.get(sensor.index()).copied().unwrap_or(0.0)
}

/// Stores `value` to `sensor` in a host's sensor array; a store past its end is
/// dropped (`false`), the rule every host keeps.
#[inline]
pub fn set_sensor(values: &mut [f64], sensor: SensorId, value: f64) -> bool {
    match values.get_mut(sensor.index()) {
        Some(slot) => {
            *slot = value;
            true
        }
        None => false,
    }
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
    #[error("pc {0} is not an instruction of the program")]
    NoSuchInstruction(u32),
    #[error("the script has stopped (halted or trapped); it cannot go on")]
    Stopped,
}

/// How the interpreter dispatches ops. Both run the same code with the same
/// results, pcs and instruction counts (`engine/tests/fused.rs` compares them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dispatch {
    /// One `match` over the op, in a loop: the reference, and the default of
    /// unoptimised builds.
    Loop,
    /// Each op's handler jumps to the next op's handler (`vm/threaded.rs`): the
    /// default where the build script enabled it (optimised builds, where
    /// LLVM turns the handlers' tail calls into jumps).
    Threaded,
}

impl Default for Dispatch {
    fn default() -> Dispatch {
        if cfg!(gloc_threaded) {
            Dispatch::Threaded
        } else {
            Dispatch::Loop
        }
    }
}

/// A running script. Cheap to clone (the program is shared), so a debugger
/// can snapshot it.
#[derive(Clone, Debug)]
pub struct Machine {
    program: Arc<Program>,
    /// The program in the interpreter's own form, plain and fused (see `code`).
    code: Arc<Code>,
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
    dispatch: Dispatch,
    /// Whether the registers agree with the loader's type analysis
    /// (`code::Types`), so that threaded dispatch may run the handlers
    /// specialised by it. Only [`Machine::set_register`] can break that (a
    /// debugger storing a float where the code only ever puts integers); the
    /// machine then runs the untyped handlers until [`Machine::reset`].
    typed: bool,
}

/// How the inner loop stopped.
#[derive(Clone, Copy)]
enum Exit {
    Yield,
    Halt,
    Trap(TrapKind),
    OutOfFuel,
}

impl Machine {
    pub fn new(program: Arc<Program>, config: MachineConfig) -> Machine {
        let code = Arc::new(Code::new(&program));
        // Every register an op names has a slot: the loop indexes without checks.
        let registers = vec![Value::default(); code.register_bound];
        let memory = vec![Value::default(); program.memory_size as usize];
        Machine {
            program,
            code,
            config,
            pc: 0,
            registers,
            memory,
            output: String::with_capacity(256),
            executed_this_cycle: 0,
            in_cycle: false,
            cycles_completed: 0,
            status: Status::Running,
            dispatch: Dispatch::default(),
            typed: true,
        }
    }

    /// Chooses the dispatch (the default is [`Dispatch::default`]); the results
    /// are the same, only the speed differs.
    pub fn set_dispatch(&mut self, dispatch: Dispatch) {
        self.dispatch = dispatch;
    }

    pub fn dispatch(&self) -> Dispatch {
        self.dispatch
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

    /// Executes at most `max_instructions` on the fused code, stopping exactly where as
    /// many `step`s would (a debugger runs to the next place a breakpoint could stop).
    pub fn run_for(&mut self, host: &mut impl Host, max_instructions: u64) -> Option<CycleEnd> {
        self.execute(host, max_instructions)
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
        self.typed = true;
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
        if !self.code.types.admits(self.pc as usize, register, value) {
            self.typed = false;
        }
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

    /// Moves the next instruction to `pc` (a debugger's "jump"), in or between cycles:
    /// the instructions run this cycle still count against the budget.
    pub fn set_pc(&mut self, pc: Pc) -> Result<(), AccessError> {
        if pc.index() >= self.program.instrs.len() {
            return Err(AccessError::NoSuchInstruction(pc.0));
        }
        if self.status != Status::Running {
            return Err(AccessError::Stopped);
        }
        self.pc = pc.0;
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
        let code: &Code = &self.code;
        let mut pc = self.pc as usize;
        debug_assert!(pc < code.len());
        debug_assert!(self.registers.len() >= code.register_bound);
        let mut parts = match_loop::Parts {
            program: &self.program,
            code_len: code.plain.len(),
            registers: self.registers.as_mut_slice(),
            memory: self.memory.as_mut_slice(),
            output: &mut self.output,
        };
        // Fused ops only while the fuel covers the widest of them; the last one or
        // two instructions of a budget run plain, so that the budget runs out at
        // exactly the same instruction as in plain code.
        let mut exit = match self.dispatch {
            Dispatch::Loop => {
                match_loop::run(&code.fused, MAX_FUSED, &mut parts, host, &mut pc, &mut fuel)
            }
            Dispatch::Threaded => loop {
                let mut context = threaded::Context::new(
                    &mut *host,
                    &mut *parts.memory,
                    parts.program,
                    code.len(),
                );
                let slots = match &code.typed {
                    Some(typed) if self.typed => typed,
                    _ => &code.threaded,
                };
                match threaded::run(slots, parts.registers, &mut pc, &mut fuel, &mut context) {
                    threaded::Stop::Exit(exit) => break exit,
                    // An output op: the match loop runs it, with one unit of fuel.
                    threaded::Stop::RunInLoop => {
                        let rest = fuel - 1;
                        fuel = 1;
                        let exit =
                            match_loop::run(&code.plain, 1, &mut parts, host, &mut pc, &mut fuel);
                        fuel += rest;
                        if !matches!(exit, Exit::OutOfFuel) {
                            break exit;
                        }
                    }
                }
            },
        };
        if matches!(exit, Exit::OutOfFuel) {
            exit = match_loop::run(&code.plain, 1, &mut parts, host, &mut pc, &mut fuel);
        }
        self.conclude(exit, allowed - fuel, pc)
    }

    /// Ends a run of the interpreter: counts what it spent, keeps its pc, and turns how
    /// it stopped into the cycle's end (`None`: out of this call's instructions, the
    /// cycle goes on).
    fn conclude(&mut self, exit: Exit, spent: u64, pc: usize) -> Option<CycleEnd> {
        self.executed_this_cycle += spent;
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

/// Where `jump rN` goes with `value` in rN: the target's pc, or how the
/// machine stops (a trap, or a halt for a label past the end of a hand-built
/// program, as running off the end does).
fn indirect_target(program: &Program, value: Value, code_len: usize) -> Result<usize, Exit> {
    let target = match value {
        Value::Int(label) => usize::try_from(label)
            .ok()
            .and_then(|label| program.label_pcs.get(label).copied().flatten()),
        Value::Float(_) => None,
    };
    match target {
        Some(target) if target.index() < code_len => Ok(target.index()),
        Some(_) => Err(Exit::Halt),
        None => Err(Exit::Trap(TrapKind::BadIndirectJump { value })),
    }
}

/// A two-operand machine operation, for code that computes on values outside a run:
/// the debugger evaluates GBASIC expressions with [`apply_binary`], so a watch
/// computes exactly what the script computes. The GBASIC compiler's IR names its
/// operations with these too (`gloc_compiler::ir::Op2`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinaryOperation {
    Add,
    Sub,
    Mul,
    Div,
    Mod,
    Min,
    Max,
    And,
    Or,
    CmpEq,
    CmpNe,
    CmpLt,
    CmpLe,
    CmpGt,
    CmpGe,
}

/// A comparison: what `cmpeq` … `cmpge` compute (and the fused compare-and-branch
/// ops), and GBASIC's `= <> < <= > >=`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Cmp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

impl BinaryOperation {
    /// The `cmpXX` operation that computes `cmp`.
    pub fn compare(cmp: Cmp) -> BinaryOperation {
        match cmp {
            Cmp::Eq => BinaryOperation::CmpEq,
            Cmp::Ne => BinaryOperation::CmpNe,
            Cmp::Lt => BinaryOperation::CmpLt,
            Cmp::Le => BinaryOperation::CmpLe,
            Cmp::Gt => BinaryOperation::CmpGt,
            Cmp::Ge => BinaryOperation::CmpGe,
        }
    }

    /// The GLOC instruction that performs it.
    pub fn mnemonic(self) -> &'static str {
        match self {
            BinaryOperation::Add => "add",
            BinaryOperation::Sub => "sub",
            BinaryOperation::Mul => "mul",
            BinaryOperation::Div => "div",
            BinaryOperation::Mod => "mod",
            BinaryOperation::Min => "min",
            BinaryOperation::Max => "max",
            BinaryOperation::And => "and",
            BinaryOperation::Or => "or",
            BinaryOperation::CmpEq => "cmpeq",
            BinaryOperation::CmpNe => "cmpne",
            BinaryOperation::CmpLt => "cmplt",
            BinaryOperation::CmpLe => "cmple",
            BinaryOperation::CmpGt => "cmpgt",
            BinaryOperation::CmpGe => "cmpge",
        }
    }
}

/// A one-operand machine operation (see [`BinaryOperation`]; `gloc_compiler::ir::Op1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnaryOperation {
    Neg,
    Abs,
    Sqrt,
    /// Integer to float (`i2d`).
    I2d,
    /// Float to integer, truncating (`d2i`).
    D2i,
    Not,
}

impl UnaryOperation {
    /// The GLOC instruction that performs it.
    pub fn mnemonic(self) -> &'static str {
        match self {
            UnaryOperation::Neg => "neg",
            UnaryOperation::Abs => "abs",
            UnaryOperation::Sqrt => "sqrt",
            UnaryOperation::I2d => "i2d",
            UnaryOperation::D2i => "d2i",
            UnaryOperation::Not => "not",
        }
    }
}

/// `left op right` as the machine computes it, or the trap it raises (an integer
/// `div` or `mod` by zero).
pub fn apply_binary(op: BinaryOperation, left: Value, right: Value) -> Result<Value, TrapKind> {
    use BinaryOperation as B;
    if matches!(op, B::Div | B::Mod) && integer_division_by_zero(left, right) {
        return Err(TrapKind::DivisionByZero);
    }
    Ok(match op {
        B::Add => add(left, right),
        B::Sub => sub(left, right),
        B::Mul => mul(left, right),
        B::Div => div(left, right),
        B::Mod => rem(left, right),
        B::Min => minimum(left, right),
        B::Max => maximum(left, right),
        B::And => bit_and(left, right),
        B::Or => bit_or(left, right),
        B::CmpEq => truth(compare(Cmp::Eq, left, right)),
        B::CmpNe => truth(compare(Cmp::Ne, left, right)),
        B::CmpLt => truth(compare(Cmp::Lt, left, right)),
        B::CmpLe => truth(compare(Cmp::Le, left, right)),
        B::CmpGt => truth(compare(Cmp::Gt, left, right)),
        B::CmpGe => truth(compare(Cmp::Ge, left, right)),
    })
}

/// `op value` as the machine computes it.
pub fn apply_unary(op: UnaryOperation, value: Value) -> Value {
    match op {
        UnaryOperation::Neg => negate(value),
        UnaryOperation::Abs => absolute(value),
        UnaryOperation::Sqrt => square_root(value),
        UnaryOperation::I2d => to_float(value),
        UnaryOperation::D2i => to_int(value),
        UnaryOperation::Not => logical_not(value),
    }
}

// The value functions of the operations that are one line each: the `match` loop, the
// threaded handlers and `apply_binary`/`apply_unary` all call these, so there is one
// definition of what each operation computes.

#[inline(always)]
fn minimum(left: Value, right: Value) -> Value {
    arithmetic(left, right, i64::min, f64::min)
}

#[inline(always)]
fn maximum(left: Value, right: Value) -> Value {
    arithmetic(left, right, i64::max, f64::max)
}

#[inline(always)]
fn bit_and(left: Value, right: Value) -> Value {
    Value::Int(left.as_i64() & right.as_i64())
}

#[inline(always)]
fn bit_or(left: Value, right: Value) -> Value {
    Value::Int(left.as_i64() | right.as_i64())
}

#[inline(always)]
fn bit_xor(left: Value, right: Value) -> Value {
    Value::Int(left.as_i64() ^ right.as_i64())
}

#[inline(always)]
fn square_root(value: Value) -> Value {
    Value::Float(value.as_f64().sqrt())
}

#[inline(always)]
fn to_float(value: Value) -> Value {
    Value::Float(value.as_f64())
}

#[inline(always)]
fn to_int(value: Value) -> Value {
    Value::Int(value.as_i64())
}

#[inline(always)]
fn logical_not(value: Value) -> Value {
    truth(!value.is_true())
}

/// An integer `div` or `mod` by zero, which traps (float division does not).
#[inline(always)]
fn integer_division_by_zero(left: Value, right: Value) -> bool {
    matches!((left, right), (Value::Int(_), Value::Int(0)))
}

#[inline(always)]
fn negate(value: Value) -> Value {
    match value {
        Value::Int(x) => Value::Int(x.wrapping_neg()),
        Value::Float(x) => Value::Float(-x),
    }
}

#[inline(always)]
fn absolute(value: Value) -> Value {
    match value {
        Value::Int(x) => Value::Int(x.wrapping_abs()),
        Value::Float(x) => Value::Float(x.abs()),
    }
}

/// Integer op integer is an integer; any float makes both floats (docs/gloc.md).
#[inline(always)]
fn arithmetic(
    left: Value,
    right: Value,
    int: impl FnOnce(i64, i64) -> i64,
    float: impl FnOnce(f64, f64) -> f64,
) -> Value {
    match (left, right) {
        (Value::Int(x), Value::Int(y)) => Value::Int(int(x, y)),
        (left, right) => Value::Float(float(left.as_f64(), right.as_f64())),
    }
}

#[inline(always)]
fn add(left: Value, right: Value) -> Value {
    arithmetic(left, right, i64::wrapping_add, |x, y| x + y)
}

#[inline(always)]
fn sub(left: Value, right: Value) -> Value {
    arithmetic(left, right, i64::wrapping_sub, |x, y| x - y)
}

#[inline(always)]
fn mul(left: Value, right: Value) -> Value {
    arithmetic(left, right, i64::wrapping_mul, |x, y| x * y)
}

/// Division; the caller has trapped an integer zero divisor.
#[inline(always)]
fn div(left: Value, right: Value) -> Value {
    arithmetic(left, right, i64::wrapping_div, |x, y| x / y)
}

/// Remainder with the sign of the dividend; the caller has trapped an integer zero divisor.
#[inline(always)]
fn rem(left: Value, right: Value) -> Value {
    arithmetic(left, right, i64::wrapping_rem, |x, y| x % y)
}

/// Integers compare as integers; any float makes both floats (NaN compares false
/// except with `cmpne`).
#[inline(always)]
fn compare(cmp: Cmp, left: Value, right: Value) -> bool {
    match (left, right) {
        (Value::Int(x), Value::Int(y)) => holds(cmp, x, y),
        (left, right) => holds(cmp, left.as_f64(), right.as_f64()),
    }
}

/// Whether `x cmp y` holds, for integers and floats alike (through `PartialOrd`, so a
/// NaN makes every comparison but `Ne` false).
#[inline(always)]
fn holds<T: PartialOrd>(cmp: Cmp, x: T, y: T) -> bool {
    match cmp {
        Cmp::Eq => x == y,
        Cmp::Ne => x != y,
        Cmp::Lt => x < y,
        Cmp::Le => x <= y,
        Cmp::Gt => x > y,
        Cmp::Ge => x >= y,
    }
}

/// A truth value as GLOC stores it: the integer 1 or 0.
#[inline(always)]
fn truth(value: bool) -> Value {
    Value::Int(i64::from(value))
}

/// An output line that `write`/`writes` make longer than this many bytes is handed to
/// the host at once, ending with [`OUTPUT_LINE_CONTINUED`], and the next item starts a
/// new line: a script that never `print`s cannot make the machine hold more than this
/// (plus one item). Real lines are a few dozen bytes.
pub const MAX_OUTPUT_LINE: usize = 65_536;

/// Ends an output line that was cut at [`MAX_OUTPUT_LINE`].
pub const OUTPUT_LINE_CONTINUED: &str = " [continued]";

/// Hands an unfinished line to the host once it is over [`MAX_OUTPUT_LINE`].
fn cap_output_line(output: &mut String, host: &mut impl Host, pc: usize) {
    if output.len() > MAX_OUTPUT_LINE {
        output.push_str(OUTPUT_LINE_CONTINUED);
        host.print_line_at(output, Pc(pc as u32));
        output.clear();
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
