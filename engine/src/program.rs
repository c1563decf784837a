//! The validated, resolved form of a GLOC script that the interpreter runs.
//!
//! Every operand is resolved: registers, program counters, sensor indices and
//! memory addresses are known to be in range (the checker establishes this),
//! so the interpreter never looks anything up by name. Debug information
//! (spans and lines) lives in side tables indexed by pc.

use std::fmt;

use crate::diagnostic::Span;
use crate::sensors::SensorId;

/// A register index (`rN`), below the program's `nregs`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Reg(pub u32);

/// An instruction index into [`Program::instrs`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Pc(pub u32);

impl Reg {
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl Pc {
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// What a register or memory cell holds. Registers start as `Int(0)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    Int(i64),
    Float(f64),
}

impl Default for Value {
    fn default() -> Value {
        Value::Int(0)
    }
}

impl Value {
    /// The value as a float (integers convert exactly up to 2^53).
    pub fn as_f64(self) -> f64 {
        match self {
            Value::Int(value) => value as f64,
            Value::Float(value) => value,
        }
    }

    /// The value as an integer: floats truncate toward zero and saturate; NaN gives 0.
    pub fn as_i64(self) -> i64 {
        match self {
            Value::Int(value) => value,
            Value::Float(value) => value as i64,
        }
    }

    /// Zero (and NaN) are false; everything else is true.
    pub fn is_true(self) -> bool {
        match self {
            Value::Int(value) => value != 0,
            Value::Float(value) => value != 0.0 && !value.is_nan(),
        }
    }
}

/// Integers print without a point, floats as Rust's `{:?}` (`15.0`, `0.1`, `1e-7`).
impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Int(value) => write!(f, "{value}"),
            Value::Float(value) => write!(f, "{value:?}"),
        }
    }
}

/// A resolved instruction. Operands are sources first, destination last, as
/// in GLOC text. See `docs/gloc.md` for the type rules.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Instr {
    /// dst := sensor[sensor] (a float)
    LoadSensor { sensor: SensorId, dst: Reg },
    /// sensor[sensor] := float(src)
    StoreSensor { src: Reg, sensor: SensorId },
    /// dst := Int(value)
    LoadInt { value: i64, dst: Reg },
    /// dst := Float(value)
    LoadFloat { value: f64, dst: Reg },
    /// dst := a
    Move { src: Reg, dst: Reg },
    /// dst := a + b
    Add { a: Reg, b: Reg, dst: Reg },
    /// dst := a - b
    Sub { a: Reg, b: Reg, dst: Reg },
    /// dst := a * b
    Mul { a: Reg, b: Reg, dst: Reg },
    /// dst := a / b (integer division truncates; integer b = 0 traps)
    Div { a: Reg, b: Reg, dst: Reg },
    /// dst := a mod b (sign of a; integer b = 0 traps)
    Mod { a: Reg, b: Reg, dst: Reg },
    /// dst := min(a, b)
    Min { a: Reg, b: Reg, dst: Reg },
    /// dst := max(a, b)
    Max { a: Reg, b: Reg, dst: Reg },
    /// dst := int(a) & int(b)
    And { a: Reg, b: Reg, dst: Reg },
    /// dst := int(a) | int(b)
    Or { a: Reg, b: Reg, dst: Reg },
    /// dst := int(a) ^ int(b)
    Xor { a: Reg, b: Reg, dst: Reg },
    /// dst := a == b
    CmpEq { a: Reg, b: Reg, dst: Reg },
    /// dst := a != b
    CmpNe { a: Reg, b: Reg, dst: Reg },
    /// dst := a < b
    CmpLt { a: Reg, b: Reg, dst: Reg },
    /// dst := a <= b
    CmpLe { a: Reg, b: Reg, dst: Reg },
    /// dst := a > b
    CmpGt { a: Reg, b: Reg, dst: Reg },
    /// dst := a >= b
    CmpGe { a: Reg, b: Reg, dst: Reg },
    /// dst := -a
    Neg { src: Reg, dst: Reg },
    /// dst := |a|
    Abs { src: Reg, dst: Reg },
    /// dst := sqrt(float(a))
    Sqrt { src: Reg, dst: Reg },
    /// dst := float(a)
    IntToFloat { src: Reg, dst: Reg },
    /// dst := int(a)
    FloatToInt { src: Reg, dst: Reg },
    /// dst := a == 0 ? 1 : 0
    Not { src: Reg, dst: Reg },
    /// dst := memory[a] (bounds-checked at run time)
    LoadMem { addr: Reg, dst: Reg },
    /// dst := memory[addr] (address checked statically)
    LoadMemAt { addr: u32, dst: Reg },
    /// memory[a] := src (bounds-checked at run time)
    StoreMem { src: Reg, addr: Reg },
    /// memory[addr] := src (address checked statically)
    StoreMemAt { src: Reg, addr: u32 },
    /// pc := c is true ? if_true : if_false
    Branch {
        cond: Reg,
        if_true: Pc,
        if_false: Pc,
    },
    /// pc := target
    Jump { target: Pc },
    /// pc := label_pcs[int(r)] (traps when r holds no defined label)
    JumpIndirect { register: Reg },
    /// end the cycle; the next cycle starts at the following instruction
    Yield,
    /// stop the script for the rest of the mission
    Halt,
    /// nothing
    Nop,
    /// append the value of r to the output line
    Write { src: Reg },
    /// append texts[text] to the output line
    WriteText { text: u32 },
    /// append the value of r and end the output line
    Print { src: Reg },
    /// append texts[text] and end the output line
    PrintText { text: u32 },
}

/// Where control can go after an instruction, within one control cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// The next instruction.
    Next,
    /// Always to this pc.
    Jump(Pc),
    /// To one of two pcs (the same one twice when both targets agree).
    Branch(Pc, Pc),
    /// To any defined label (`jump rN`).
    Indirect,
    /// Nowhere in this cycle: `yield` or `halt`.
    End,
}

impl Instr {
    /// Where control goes next: the one statement of control flow the checker's cycle
    /// analysis and the debugger's reachability both use.
    pub fn flow(&self) -> Flow {
        match *self {
            Instr::Yield | Instr::Halt => Flow::End,
            Instr::Jump { target } => Flow::Jump(target),
            Instr::Branch {
                if_true, if_false, ..
            } => Flow::Branch(if_true, if_false),
            Instr::JumpIndirect { .. } => Flow::Indirect,
            _ => Flow::Next,
        }
    }
}

/// A checked GLOC script, ready to run. Built by [`crate::gloc::check`].
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    /// The instructions, labels removed. The last one is always a `Halt`
    /// that execution reaches by falling off the end of the script.
    pub instrs: Vec<Instr>,
    /// pc → span of the source line's statement.
    pub spans: Vec<Span>,
    /// pc → 1-based source line.
    pub lines: Vec<u32>,
    /// Label number → pc of the instruction it names (`None`: not defined).
    pub label_pcs: Vec<Option<Pc>>,
    /// The texts of `writes` / `prints`.
    pub texts: Vec<Box<str>>,
    /// `nregs`.
    pub register_count: u32,
    /// `nmem`.
    pub memory_size: u32,
    /// Sensors the script stores to, in order of first appearance in the code.
    pub stored_sensors: Vec<SensorId>,
    /// Sensors the script loads, in order of first appearance in the code.
    pub loaded_sensors: Vec<SensorId>,
}

impl Program {
    pub fn span(&self, pc: Pc) -> Span {
        self.spans.get(pc.index()).copied().unwrap_or_default()
    }

    pub fn line(&self, pc: Pc) -> u32 {
        self.lines.get(pc.index()).copied().unwrap_or(0)
    }

    /// The pc a label number names, if defined.
    pub fn label_pc(&self, label: u32) -> Option<Pc> {
        self.label_pcs.get(label as usize).copied().flatten()
    }

    /// The first pc whose source line is `line` or later (for breakpoints).
    pub fn pc_at_or_after_line(&self, line: u32) -> Option<Pc> {
        self.lines
            .iter()
            .position(|&at| at >= line)
            .map(|pc| Pc(pc as u32))
    }
}
