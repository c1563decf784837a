//! The compiler's GLOC code before printing: one `Instr` per GLOC line, each with the
//! GBASIC span it came from. The optimizer rewrites this; the printer turns it into
//! GLOC text in the paper's format (header, then `op a,b,c` lines).

use std::fmt::Write as _;

use gloc_engine::{gloc, Span};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Reg(pub u32);

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Lbl(pub u32);

/// A memory address operand: a register, or a constant address.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Addr {
    Reg(Reg),
    At(u32),
}

/// The IR's operations are the machine's own (one list, with their GLOC mnemonics).
pub use gloc_engine::vm::{BinaryOperation as Op2, UnaryOperation as Op1};

#[derive(Clone, Debug, PartialEq)]
pub enum Instr {
    Label(Lbl),
    /// dst := sensor
    LoadS {
        sensor: u32,
        dst: Reg,
    },
    /// sensor := src
    StoreS {
        src: Reg,
        sensor: u32,
    },
    LoadI {
        value: i64,
        dst: Reg,
    },
    LoadD {
        value: f64,
        dst: Reg,
    },
    Mov {
        src: Reg,
        dst: Reg,
    },
    Binary {
        op: Op2,
        a: Reg,
        b: Reg,
        dst: Reg,
    },
    Unary {
        op: Op1,
        src: Reg,
        dst: Reg,
    },
    Cbr {
        cond: Reg,
        on_true: Lbl,
        on_false: Lbl,
    },
    Jumpi(Lbl),
    Yield,
    Halt,
    LoadM {
        addr: Addr,
        dst: Reg,
    },
    StoreM {
        src: Reg,
        addr: Addr,
    },
    Write(Reg),
    Writes(String),
    Print(Reg),
    Prints(String),
}

/// The `dst` field of an instruction that writes a register, borrowed as the
/// instruction is (shared or mutable), for [`Instr::def`] and [`Instr::map_def`].
macro_rules! destination {
    ($instr:expr) => {
        match $instr {
            Instr::LoadS { dst, .. }
            | Instr::LoadI { dst, .. }
            | Instr::LoadD { dst, .. }
            | Instr::Mov { dst, .. }
            | Instr::Binary { dst, .. }
            | Instr::Unary { dst, .. }
            | Instr::LoadM { dst, .. } => Some(dst),
            _ => None,
        }
    };
}

/// The registers an instruction reads (at most two), borrowed as the instruction is,
/// for [`Instr::uses`] and [`Instr::map_uses`].
macro_rules! sources {
    ($instr:expr) => {
        match $instr {
            Instr::StoreS { src, .. } | Instr::Mov { src, .. } | Instr::Unary { src, .. } => {
                [Some(src), None]
            }
            Instr::Binary { a, b, .. } => [Some(a), Some(b)],
            Instr::Cbr { cond, .. } => [Some(cond), None],
            Instr::LoadM {
                addr: Addr::Reg(reg),
                ..
            } => [Some(reg), None],
            Instr::StoreM { src, addr } => match addr {
                Addr::Reg(reg) => [Some(src), Some(reg)],
                Addr::At(_) => [Some(src), None],
            },
            Instr::Write(reg) | Instr::Print(reg) => [Some(reg), None],
            _ => [None, None],
        }
    };
}

impl Instr {
    /// The register this instruction writes.
    pub fn def(&self) -> Option<Reg> {
        destination!(self).copied()
    }

    /// The registers this instruction reads.
    pub fn uses(&self) -> Vec<Reg> {
        sources!(self).into_iter().flatten().copied().collect()
    }

    /// Rewrites every register the instruction reads.
    pub fn map_uses(&mut self, mut map: impl FnMut(Reg) -> Reg) {
        for src in sources!(self).into_iter().flatten() {
            *src = map(*src);
        }
    }

    /// Rewrites the register the instruction writes.
    pub fn map_def(&mut self, map: impl FnOnce(Reg) -> Reg) {
        if let Some(dst) = destination!(self) {
            *dst = map(*dst);
        }
    }

    /// Labels this instruction may jump to.
    pub fn targets(&self) -> Vec<Lbl> {
        match self {
            Instr::Cbr {
                on_true, on_false, ..
            } => vec![*on_true, *on_false],
            Instr::Jumpi(label) => vec![*label],
            _ => Vec::new(),
        }
    }

    /// True when execution never continues to the next line.
    pub fn ends_flow(&self) -> bool {
        matches!(self, Instr::Jumpi(_) | Instr::Cbr { .. } | Instr::Halt)
    }

    /// True when removing the instruction (its result unused) cannot change behavior:
    /// no sensor, memory or output effect, no control flow, and no trap. Integer
    /// `div`/`mod` may trap on zero, and `loadm` on a bad address, so they stay.
    pub fn is_pure(&self) -> bool {
        match self {
            Instr::LoadS { .. }
            | Instr::LoadI { .. }
            | Instr::LoadD { .. }
            | Instr::Mov { .. }
            | Instr::Unary { .. } => true,
            Instr::Binary { op, .. } => !matches!(op, Op2::Div | Op2::Mod),
            _ => false,
        }
    }
}

/// Compiled code: the instructions with their GBASIC spans, and the header counts.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Code {
    pub instrs: Vec<Instr>,
    /// One per instruction: the GBASIC text it came from.
    pub spans: Vec<Span>,
    pub register_count: u32,
    pub label_count: u32,
    pub memory_size: u32,
    /// The CRC of the sensor list the indices are for, written as the first line
    /// (`# sensors: 1f35be3b`; see `gloc_engine::gloc::identity`).
    pub sensor_list: Option<String>,
}

impl Code {
    pub fn push(&mut self, instr: Instr, span: Span) {
        self.instrs.push(instr);
        self.spans.push(span);
    }

    /// GLOC text in the paper's format. `nmem` is written only when memory is used.
    pub fn to_gloc(&self) -> String {
        let mut text = String::with_capacity(self.instrs.len() * 14 + 60);
        if let Some(crc) = &self.sensor_list {
            let _ = writeln!(text, "# sensors: {crc}");
        }
        let _ = writeln!(text, "nregs {}", self.register_count);
        let _ = writeln!(text, "nblbs {}", self.label_count);
        let _ = writeln!(text, "ninstr {}", self.instrs.len());
        if self.memory_size > 0 {
            let _ = writeln!(text, "nmem {}", self.memory_size);
        }
        for instr in &self.instrs {
            write_instr(&mut text, instr);
            text.push('\n');
        }
        text
    }

    /// The 0-based line of the GLOC text where instruction `index` is printed.
    pub fn line_of_instr(&self, index: usize) -> usize {
        index + if self.memory_size > 0 { 4 } else { 3 } + usize::from(self.sensor_list.is_some())
    }
}

fn addr(addr: &Addr) -> String {
    match addr {
        Addr::Reg(Reg(reg)) => format!("r{reg}"),
        Addr::At(at) => at.to_string(),
    }
}

fn write_instr(text: &mut String, instr: &Instr) {
    let _ = match instr {
        Instr::Label(Lbl(label)) => write!(text, "label {label}"),
        Instr::LoadS { sensor, dst } => write!(text, "loads {sensor},r{}", dst.0),
        Instr::StoreS { src, sensor } => write!(text, "stores r{},{sensor}", src.0),
        Instr::LoadI { value, dst } => write!(text, "loadi {value},r{}", dst.0),
        Instr::LoadD { value, dst } => write!(text, "loadd {value:?},r{}", dst.0),
        Instr::Mov { src, dst } => write!(text, "mov r{},r{}", src.0, dst.0),
        Instr::Binary { op, a, b, dst } => {
            write!(text, "{} r{},r{},r{}", op.mnemonic(), a.0, b.0, dst.0)
        }
        Instr::Unary { op, src, dst } => write!(text, "{} r{},r{}", op.mnemonic(), src.0, dst.0),
        Instr::Cbr {
            cond,
            on_true,
            on_false,
        } => write!(text, "cbr r{},{},{}", cond.0, on_true.0, on_false.0),
        Instr::Jumpi(Lbl(label)) => write!(text, "jumpi {label}"),
        Instr::Yield => write!(text, "yield"),
        Instr::Halt => write!(text, "halt"),
        Instr::LoadM { addr: at, dst } => write!(text, "loadm {},r{}", addr(at), dst.0),
        Instr::StoreM { src, addr: at } => write!(text, "storem r{},{}", src.0, addr(at)),
        Instr::Write(reg) => write!(text, "write r{}", reg.0),
        Instr::Writes(words) => write!(text, "writes {}", gloc::quote(words)),
        Instr::Print(reg) => write!(text, "print r{}", reg.0),
        Instr::Prints(words) => write!(text, "prints {}", gloc::quote(words)),
    };
}
