//! The machine's own form of a checked program: every GLOC instruction
//! translated one to one ("plain" code), and a second copy of the same length
//! in which common pairs and triples are fused into one dispatch.
//!
//! A fused op at pc `i` does exactly what the instructions at `i`, `i + 1`
//! (and `i + 2`) do, writes every register they write, and then goes on at the
//! pc they would reach. The instructions it covers keep their plain copies at
//! `i + 1` and `i + 2`, so a jump into the middle of a fused group still runs
//! the right code. Only groups that cannot trap, yield or print are fused, so a
//! trap, a `yield` and every output still happen at a plain instruction with
//! its own pc. The interpreter charges a fused op the number of GLOC
//! instructions it covers and runs plain code when less fuel than that is
//! left, so the budget, `step` and cycle-overrun traps stay exact to the
//! instruction. Nothing here changes GLOC text, the checker or the debugger's
//! view of the program: the machine stays at the same pcs with the same state.

use super::Cmp;
use crate::program::{Instr, Pc, Program, Reg, Value};
use crate::sensors::SensorId;

/// The most GLOC instructions one fused op covers: the interpreter runs
/// fused code only while at least this much fuel is left.
pub(super) const MAX_FUSED: u64 = 6;

/// Declares [`Op`] with one plain variant per [`Instr`] variant (same fields)
/// plus the fused variants, and the one-to-one translation.
macro_rules! ops {
    (
        plain { $($name:ident { $($field:ident : $ty:ty),* } => $kind:ident ( $($how:tt)* )),* $(,)? }
        fused { $($fused:ident { $($ffield:ident : $fty:ty),* }),* $(,)? }
    ) => {
        /// One dispatch of the interpreter. Plain variants mean what the
        /// [`Instr`] variant of the same name means; fused ones are described
        /// where they are built, in [`fuse`].
        ///
        /// `repr(u8)`: the variant is a plain byte at the start, so dispatch is one
        /// load and one indirect jump (without it the tag is folded into a niche of
        /// the constant's `Value` and costs four more instructions to decode).
        #[derive(Clone, Copy, Debug, PartialEq)]
        #[repr(u8)]
        pub(super) enum Op {
            $($name { $($field: $ty),* },)*
            $($fused { $($ffield: $fty),* },)*
        }

        impl Op {
            /// Calls `visit` with every register the op names.
            fn visit_registers(&self, visit: &mut impl FnMut(Reg)) {
                match self {
                    $(Op::$name { $($field),* } => { $($field.visit(visit);)* })*
                    $(Op::$fused { $($ffield),* } => { $($ffield.visit(visit);)* })*
                }
            }

            /// Replaces every branch target at or past `end` by `end`.
            fn clamp_targets(&mut self, end: Pc) {
                match self {
                    $(Op::$name { $($field),* } => { $($field.clamp_target(end);)* })*
                    $(Op::$fused { $($ffield),* } => { $($ffield.clamp_target(end);)* })*
                }
            }
        }

        impl From<Instr> for Op {
            fn from(instr: Instr) -> Op {
                match instr {
                    $(Instr::$name { $($field),* } => Op::$name { $($field),* },)*
                }
            }
        }
    };
}

/// The op table, handed to `$then!`: every op with its fields, and for each plain op
/// the handler the threaded code runs it with (`threaded.rs` builds `Slot::new`'s
/// selection from it): `fixed(h)` one handler; `typed(h; regs)` `h` instantiated for
/// the one type the registers hold (or ANY); `int_fast(general, int; regs)` the float
/// handler when both are floats, else the integer fast path typed; `int_or_any(h; reg)`
/// `h` for an integer register or any. Fused ops all go to `fused_handler`. An op added
/// here is a compile error in every place that matches on ops until it is handled.
macro_rules! op_table {
    ($then:ident) => {
        $then! {
            plain {
                LoadSensor { sensor: SensorId, dst: Reg } => fixed(op_load_sensor),
                StoreSensor { src: Reg, sensor: SensorId } => fixed(op_store_sensor),
                LoadInt { value: i64, dst: Reg } => fixed(op_load_int),
                LoadFloat { value: f64, dst: Reg } => fixed(op_load_float),
                Move { src: Reg, dst: Reg } => typed(op_move; src),
                Add { a: Reg, b: Reg, dst: Reg } => int_fast(op_add, op_add_int; a, b),
                Sub { a: Reg, b: Reg, dst: Reg } => int_fast(op_sub, op_sub_int; a, b),
                Mul { a: Reg, b: Reg, dst: Reg } => int_fast(op_mul, op_mul_int; a, b),
                Div { a: Reg, b: Reg, dst: Reg } => int_fast(op_div, op_div_int; a, b),
                Mod { a: Reg, b: Reg, dst: Reg } => int_fast(op_mod, op_mod_int; a, b),
                Min { a: Reg, b: Reg, dst: Reg } => typed(op_min; a, b),
                Max { a: Reg, b: Reg, dst: Reg } => typed(op_max; a, b),
                And { a: Reg, b: Reg, dst: Reg } => typed(op_and; a, b),
                Or { a: Reg, b: Reg, dst: Reg } => typed(op_or; a, b),
                Xor { a: Reg, b: Reg, dst: Reg } => typed(op_xor; a, b),
                CmpEq { a: Reg, b: Reg, dst: Reg } => typed(op_cmp_eq; a, b),
                CmpNe { a: Reg, b: Reg, dst: Reg } => typed(op_cmp_ne; a, b),
                CmpLt { a: Reg, b: Reg, dst: Reg } => typed(op_cmp_lt; a, b),
                CmpLe { a: Reg, b: Reg, dst: Reg } => typed(op_cmp_le; a, b),
                CmpGt { a: Reg, b: Reg, dst: Reg } => typed(op_cmp_gt; a, b),
                CmpGe { a: Reg, b: Reg, dst: Reg } => typed(op_cmp_ge; a, b),
                Neg { src: Reg, dst: Reg } => typed(op_neg; src),
                Abs { src: Reg, dst: Reg } => typed(op_abs; src),
                Sqrt { src: Reg, dst: Reg } => typed(op_sqrt; src),
                IntToFloat { src: Reg, dst: Reg } => typed(op_int_to_float; src),
                FloatToInt { src: Reg, dst: Reg } => typed(op_float_to_int; src),
                Not { src: Reg, dst: Reg } => typed(op_not; src),
                LoadMem { addr: Reg, dst: Reg } => int_or_any(op_load_mem_int; addr),
                LoadMemAt { addr: u32, dst: Reg } => fixed(op_load_mem_at),
                StoreMem { src: Reg, addr: Reg } => int_or_any(op_store_mem_int; addr),
                StoreMemAt { src: Reg, addr: u32 } => fixed(op_store_mem_at),
                Branch { cond: Reg, if_true: Pc, if_false: Pc } => typed(op_branch; cond),
                Jump { target: Pc } => fixed(op_jump),
                JumpIndirect { register: Reg } => fixed(op_jump_indirect),
                Yield {} => fixed(op_yield),
                Halt {} => fixed(op_halt),
                Nop {} => fixed(op_nop),
                Write { src: Reg } => fixed(op_output),
                WriteText { text: u32 } => fixed(op_output),
                Print { src: Reg } => fixed(op_output),
                PrintText { text: u32 } => fixed(op_output),
            }
            fused {
                AddK { a: Reg, k: Value, t: Reg, dst: Reg },
                SubK { a: Reg, k: Value, t: Reg, dst: Reg },
                MulK { a: Reg, k: Value, t: Reg, dst: Reg },
                DivK { a: Reg, k: Value, t: Reg, dst: Reg },
                ModK { a: Reg, k: Value, t: Reg, dst: Reg },
                IntToFloatAdd { src: Reg, t: Reg, a: Reg, dst: Reg },
                CmpBr { cmp: Cmp, a: Reg, b: Reg, c: Reg, if_true: Pc, if_false: Pc },
                CmpKBr { cmp: Cmp, a: Reg, k: Value, t: Reg, c: Reg, if_true: Pc, if_false: Pc },
                JumpCmpBr { cmp: Cmp, a: Reg, b: Reg, c: Reg, if_true: Pc, if_false: Pc },
                JumpCmpKBr { cmp: Cmp, a: Reg, k: Value, t: Reg, c: Reg, if_true: Pc, if_false: Pc },
                AddJumpCmpBr { p: Reg, q: Reg, sum: Reg, cmp: Cmp, a: Reg, b: Reg, c: Reg, if_true: Pc, if_false: Pc },
                JumpAddJumpCmpBr { p: Reg, q: Reg, sum: Reg, cmp: Cmp, a: Reg, b: Reg, c: Reg, if_true: Pc, if_false: Pc },
                AddJumpCmpKBr { p: Reg, q: Reg, sum: Reg, cmp: Cmp, a: Reg, k: Value, t: Reg, c: Reg, if_true: Pc, if_false: Pc },
                RangeBr { x: Reg, lo: Value, t_lo: Reg, c_lo: Reg, hi: Value, t_hi: Reg, c_hi: Reg, d: Reg, if_out: Pc, if_in: Pc },
            }
        }
    };
}
pub(super) use op_table;

op_table!(ops);

/// An operand type: registers report themselves, everything else nothing.
trait Operand {
    fn visit(&self, _visit: &mut impl FnMut(Reg)) {}
    fn clamp_target(&mut self, _end: Pc) {}
}

impl Operand for Reg {
    fn visit(&self, visit: &mut impl FnMut(Reg)) {
        visit(*self);
    }
}

impl Operand for Pc {
    fn clamp_target(&mut self, end: Pc) {
        *self = (*self).min(end);
    }
}

impl Operand for SensorId {}
impl Operand for i64 {}
impl Operand for f64 {}
impl Operand for u32 {}
impl Operand for Value {}
impl Operand for Cmp {}

impl Cmp {
    /// The comparison with its operands swapped: `k < a` is `a > k`.
    fn swapped(self) -> Cmp {
        match self {
            Cmp::Eq => Cmp::Eq,
            Cmp::Ne => Cmp::Ne,
            Cmp::Lt => Cmp::Gt,
            Cmp::Le => Cmp::Ge,
            Cmp::Gt => Cmp::Lt,
            Cmp::Ge => Cmp::Le,
        }
    }
}

/// The two forms of a program the interpreter runs.
#[derive(Debug)]
pub(super) struct Code {
    /// One op per GLOC instruction, the same meaning.
    pub plain: Box<[Op]>,
    /// The same, with fused groups starting at some pcs.
    pub fused: Box<[Op]>,
    /// The fused code as threaded code (`vm/threaded.rs`): one slot per op.
    pub threaded: Box<[super::threaded::Slot]>,
    /// The same, with handlers specialised by the registers' static types
    /// ([`Types`]): they skip the tag tests the analysis makes needless. The
    /// machine runs these while its registers agree with the analysis. None
    /// when the program was too large to analyse.
    pub typed: Option<Box<[super::threaded::Slot]>>,
    /// What each register can hold at each pc.
    pub types: Types,
    /// One more than the highest register any op names (at least `nregs`): the
    /// size of a register file that every op can index without a check.
    pub register_bound: usize,
}

impl Code {
    /// Translates a program. The code always ends with a `halt` and every branch
    /// target lies inside it, so the interpreter can fetch without checks (see
    /// [`Code::fetch`]). A checked program ends with a `halt` already and has no
    /// other targets; for any other, a pc past the end meant "halt" before and
    /// still does.
    pub fn new(program: &Program) -> Code {
        let mut plain: Vec<Op> = program
            .instrs
            .iter()
            .map(|&instr| Op::from(instr))
            .collect();
        let mut fused: Vec<Op> = (0..program.instrs.len())
            .map(|pc| fuse(&program.instrs[pc..]).unwrap_or(plain[pc]))
            .collect();
        thread_jumps(&mut fused);
        if plain.last() != Some(&Op::Halt {}) {
            plain.push(Op::Halt {});
            fused.push(Op::Halt {});
        }
        let end = Pc((plain.len() - 1) as u32);
        for op in plain.iter_mut().chain(fused.iter_mut()) {
            op.clamp_targets(end);
        }
        let mut register_bound = program.register_count as usize;
        for op in plain.iter() {
            op.visit_registers(&mut |register| {
                register_bound = register_bound.max(register.index() + 1);
            });
        }
        let types = Types::new(&plain, program, register_bound);
        let unknown = |_: usize, _: Reg| ANY;
        let known = |pc: usize, register: Reg| types.at(pc, register);
        Code {
            threaded: fused
                .iter()
                .enumerate()
                .map(|(pc, &op)| super::threaded::Slot::new(op, pc, &plain, &unknown))
                .collect(),
            typed: types.sets.is_some().then(|| {
                fused
                    .iter()
                    .enumerate()
                    .map(|(pc, &op)| super::threaded::Slot::new(op, pc, &plain, &known))
                    .collect()
            }),
            types,
            plain: plain.into_boxed_slice(),
            fused: fused.into_boxed_slice(),
            register_bound,
        }
    }

    /// The number of ops in each form (one more than the program's
    /// instructions when a `halt` was appended).
    pub fn len(&self) -> usize {
        self.plain.len()
    }
}

/// A set of register types: [`INT`], [`FLOAT`], both ([`ANY`]), or none
/// (a pc no execution reaches).
pub(super) type TypeSet = u8;
pub(super) const INT: TypeSet = 1;
pub(super) const FLOAT: TypeSet = 2;
pub(super) const ANY: TypeSet = INT | FLOAT;

/// The most (pc, register) pairs the type analysis tracks (one byte each);
/// a larger program gets no analysis: every register may hold anything.
const MAX_TYPED: usize = 1 << 22;

/// The most pcs a program may have to be analysed: the typed slots are a
/// second copy of the threaded code (96 bytes per op), which a script of a
/// million instructions should not pay for; real scripts have a few thousand.
const MAX_TYPED_PCS: usize = 1 << 16;

/// The most register sets the analysis may join, in units of [`MAX_TYPED`]:
/// a pc is visited again each time a set at it grows, which real code does a
/// few times, but a contrived one (many registers, many labels reached by
/// indirect jumps) could do far more often; past this the analysis gives up
/// (a few tens of milliseconds at most).
const MAX_JOINS: usize = 16;

/// What each register can hold at each pc, over every execution from the
/// start (pc 0, every register `Int(0)`): a forward data-flow analysis over
/// the control-flow graph, one [`TypeSet`] per register joined at merges.
/// `-O` gives one register to several variables, so the types are per pc,
/// not per program. Memory is not tracked (a load may give either type).
#[derive(Debug)]
pub(super) struct Types {
    registers: usize,
    /// `registers` sets per pc, or nothing when the program is too large.
    sets: Option<Box<[TypeSet]>>,
}

impl Types {
    fn new(plain: &[Op], program: &Program, registers: usize) -> Types {
        let unanalysed = Types {
            registers,
            sets: None,
        };
        let Some(size) = plain.len().checked_mul(registers) else {
            return unanalysed;
        };
        if size > MAX_TYPED || plain.len() > MAX_TYPED_PCS || registers == 0 {
            return unanalysed;
        }
        let mut sets = vec![0 as TypeSet; size];
        sets[..registers].fill(INT);
        let labels: Vec<usize> = program
            .label_pcs
            .iter()
            .flatten()
            .map(|pc| pc.index().min(plain.len() - 1))
            .collect();
        let mut pending = vec![false; plain.len()];
        let mut work = vec![0usize];
        pending[0] = true;
        let mut out = vec![0 as TypeSet; registers];
        let mut budget = MAX_JOINS * MAX_TYPED;
        while let Some(pc) = work.pop() {
            pending[pc] = false;
            out.copy_from_slice(&sets[pc * registers..(pc + 1) * registers]);
            let op = plain[pc];
            if let Some((dst, set)) = result_type(&op, &out) {
                out[dst.index()] = set;
            }
            let mut flow = |to: usize| {
                budget = budget.saturating_sub(registers);
                let at = &mut sets[to * registers..(to + 1) * registers];
                let mut changed = false;
                for (into, &from) in at.iter_mut().zip(&out) {
                    if *into | from != *into {
                        *into |= from;
                        changed = true;
                    }
                }
                if changed && !pending[to] {
                    pending[to] = true;
                    work.push(to);
                }
            };
            match op {
                Op::Halt {} => {}
                Op::Jump { target } => flow(target.index()),
                Op::Branch {
                    if_true, if_false, ..
                } => {
                    flow(if_true.index());
                    flow(if_false.index());
                }
                Op::JumpIndirect { .. } => labels.iter().for_each(|&to| flow(to)),
                _ => {
                    if pc + 1 < plain.len() {
                        flow(pc + 1);
                    }
                }
            }
            if budget == 0 {
                return unanalysed;
            }
        }
        Types {
            registers,
            sets: Some(sets.into_boxed_slice()),
        }
    }

    /// What `register` can hold when the machine is at `pc`.
    pub fn at(&self, pc: usize, register: Reg) -> TypeSet {
        match &self.sets {
            Some(sets) if register.index() < self.registers => sets
                .get(pc * self.registers + register.index())
                .copied()
                .unwrap_or(ANY),
            _ => ANY,
        }
    }

    /// Whether `value` in `register` at `pc` is a state the analysis covers
    /// (the analysis is per register, so each register is checked alone).
    pub fn admits(&self, pc: usize, register: Reg, value: Value) -> bool {
        let set = match value {
            Value::Int(_) => INT,
            Value::Float(_) => FLOAT,
        };
        self.at(pc, register) & set != 0
    }
}

/// The register a plain op writes and what it can hold afterwards, given
/// what the registers can hold before it (`before`).
fn result_type(op: &Op, before: &[TypeSet]) -> Option<(Reg, TypeSet)> {
    let of = |register: Reg| before[register.index()];
    // Integer op integer is an integer, any float makes a float (`arithmetic`).
    let arithmetic = |a: Reg, b: Reg| {
        let (x, y) = (of(a), of(b));
        let int = if x & INT != 0 && y & INT != 0 { INT } else { 0 };
        let float = if (x | y) & FLOAT != 0 { FLOAT } else { 0 };
        int | float
    };
    Some(match *op {
        Op::LoadSensor { dst, .. }
        | Op::LoadFloat { dst, .. }
        | Op::Sqrt { dst, .. }
        | Op::IntToFloat { dst, .. } => (dst, FLOAT),
        Op::LoadInt { dst, .. }
        | Op::And { dst, .. }
        | Op::Or { dst, .. }
        | Op::Xor { dst, .. }
        | Op::CmpEq { dst, .. }
        | Op::CmpNe { dst, .. }
        | Op::CmpLt { dst, .. }
        | Op::CmpLe { dst, .. }
        | Op::CmpGt { dst, .. }
        | Op::CmpGe { dst, .. }
        | Op::FloatToInt { dst, .. }
        | Op::Not { dst, .. } => (dst, INT),
        Op::Move { src, dst } | Op::Neg { src, dst } | Op::Abs { src, dst } => (dst, of(src)),
        Op::Add { a, b, dst }
        | Op::Sub { a, b, dst }
        | Op::Mul { a, b, dst }
        | Op::Div { a, b, dst }
        | Op::Mod { a, b, dst }
        | Op::Min { a, b, dst }
        | Op::Max { a, b, dst } => (dst, arithmetic(a, b)),
        Op::LoadMem { dst, .. } | Op::LoadMemAt { dst, .. } => (dst, ANY),
        Op::StoreSensor { .. }
        | Op::StoreMem { .. }
        | Op::StoreMemAt { .. }
        | Op::Branch { .. }
        | Op::Jump { .. }
        | Op::JumpIndirect { .. }
        | Op::Yield {}
        | Op::Halt {}
        | Op::Nop {}
        | Op::Write { .. }
        | Op::WriteText { .. }
        | Op::Print { .. }
        | Op::PrintText { .. } => return None,
        // Only plain code is analysed.
        Op::AddK { .. }
        | Op::SubK { .. }
        | Op::MulK { .. }
        | Op::DivK { .. }
        | Op::ModK { .. }
        | Op::IntToFloatAdd { .. }
        | Op::CmpBr { .. }
        | Op::CmpKBr { .. }
        | Op::JumpCmpBr { .. }
        | Op::JumpCmpKBr { .. }
        | Op::AddJumpCmpBr { .. }
        | Op::JumpAddJumpCmpBr { .. }
        | Op::AddJumpCmpKBr { .. }
        | Op::RangeBr { .. } => return None,
    })
}

/// How many GLOC instructions an op covers (what it costs in fuel).
#[cfg(test)]
pub(super) fn width(op: &Op) -> u64 {
    match op {
        Op::AddK { .. }
        | Op::SubK { .. }
        | Op::MulK { .. }
        | Op::DivK { .. }
        | Op::ModK { .. }
        | Op::IntToFloatAdd { .. }
        | Op::CmpBr { .. } => 2,
        Op::CmpKBr { .. } | Op::JumpCmpBr { .. } => 3,
        Op::JumpCmpKBr { .. } | Op::AddJumpCmpBr { .. } => 4,
        Op::AddJumpCmpKBr { .. } | Op::JumpAddJumpCmpBr { .. } => 5,
        Op::RangeBr { .. } => 6,
        _ => 1,
    }
}

/// The constant a `loadi`/`loadd` loads, and the register it loads it into.
fn constant(instr: &Instr) -> Option<(Value, Reg)> {
    match *instr {
        Instr::LoadInt { value, dst } => Some((Value::Int(value), dst)),
        Instr::LoadFloat { value, dst } => Some((Value::Float(value), dst)),
        _ => None,
    }
}

/// A comparison instruction as (comparison, a, b, dst).
fn comparison(instr: &Instr) -> Option<(Cmp, Reg, Reg, Reg)> {
    match *instr {
        Instr::CmpEq { a, b, dst } => Some((Cmp::Eq, a, b, dst)),
        Instr::CmpNe { a, b, dst } => Some((Cmp::Ne, a, b, dst)),
        Instr::CmpLt { a, b, dst } => Some((Cmp::Lt, a, b, dst)),
        Instr::CmpLe { a, b, dst } => Some((Cmp::Le, a, b, dst)),
        Instr::CmpGt { a, b, dst } => Some((Cmp::Gt, a, b, dst)),
        Instr::CmpGe { a, b, dst } => Some((Cmp::Ge, a, b, dst)),
        _ => None,
    }
}

/// The fused op for the group of instructions that starts `window`, if any.
fn fuse(window: &[Instr]) -> Option<Op> {
    if let Some(op) = range_check(window) {
        return Some(op);
    }
    let first = window.first()?;
    let second = window.get(1)?;
    // `loadi K,t; cmpXX a,t,c; cbr c,T,F` (or `cmpXX t,a,c`): compare with a constant
    // and branch. Whether `c` is `t` or not, both are written as the three would.
    if let (
        Some((k, t)),
        Some((cmp, x, y, c)),
        Some(&Instr::Branch {
            cond,
            if_true,
            if_false,
        }),
    ) = (constant(first), comparison(second), window.get(2))
    {
        let operands = if y == t && x != t {
            Some((cmp, x))
        } else if x == t && y != t {
            Some((cmp.swapped(), y))
        } else {
            None
        };
        if let (Some((cmp, a)), true) = (operands, cond == c) {
            return Some(Op::CmpKBr {
                cmp,
                a,
                k,
                t,
                c,
                if_true,
                if_false,
            });
        }
    }
    // `cmpXX a,b,c; cbr c,T,F`: compare and branch.
    if let (
        Some((cmp, a, b, c)),
        &Instr::Branch {
            cond,
            if_true,
            if_false,
        },
    ) = (comparison(first), second)
    {
        if cond == c {
            return Some(Op::CmpBr {
                cmp,
                a,
                b,
                c,
                if_true,
                if_false,
            });
        }
    }
    // `i2d src,t; add a,t,dst` (or `add t,a,dst`): the mixed-type add of GBASIC's
    // implicit widening.
    if let (&Instr::IntToFloat { src, dst: t }, &Instr::Add { a: x, b: y, dst }) = (first, second) {
        let a = if y == t && x != t {
            Some(x)
        } else if x == t && y != t {
            Some(y)
        } else {
            None
        };
        if let Some(a) = a {
            return Some(Op::IntToFloatAdd { src, t, a, dst });
        }
    }
    // `loadi K,t; op a,t,dst` (or `op t,a,dst` for `add` and `mul`): arithmetic
    // with a constant operand. Division and `mod` by an integer zero trap, so
    // they stay plain, and so do `K op a` of the other ops and `K op K`.
    let (k, t) = constant(first)?;
    let (x, y, dst, commutes, make): (Reg, Reg, Reg, bool, MakeArithK) = match *second {
        Instr::Add { a, b, dst } => (a, b, dst, true, |a, k, t, dst| Op::AddK { a, k, t, dst }),
        Instr::Mul { a, b, dst } => (a, b, dst, true, |a, k, t, dst| Op::MulK { a, k, t, dst }),
        Instr::Sub { a, b, dst } => (a, b, dst, false, |a, k, t, dst| Op::SubK { a, k, t, dst }),
        Instr::Div { a, b, dst } if k != Value::Int(0) => {
            (a, b, dst, false, |a, k, t, dst| Op::DivK { a, k, t, dst })
        }
        Instr::Mod { a, b, dst } if k != Value::Int(0) => {
            (a, b, dst, false, |a, k, t, dst| Op::ModK { a, k, t, dst })
        }
        _ => return None,
    };
    if y == t && x != t {
        Some(make(x, k, t, dst))
    } else if commutes && x == t && y != t {
        Some(make(y, k, t, dst))
    } else {
        None
    }
}

/// The index check GBASIC puts before every array access whose index it
/// cannot prove in range: `loadi LO,t_lo; cmplt x,t_lo,c_lo; loadi HI,t_hi;
/// cmpge x,t_hi,c_hi; or c_lo,c_hi,d; cbr d,OUT,IN`. The registers must not
/// overlap in a way that would make one write change what a later
/// instruction reads (`c_hi` may be `t_hi`, `c_lo` may be `t_lo`).
fn range_check(window: &[Instr]) -> Option<Op> {
    let [first, second, third, fourth, fifth, sixth, ..] = window else {
        return None;
    };
    let (lo, t_lo) = constant(first)?;
    let (hi, t_hi) = constant(third)?;
    let &Instr::CmpLt { a: x, b, dst: c_lo } = second else {
        return None;
    };
    let &Instr::CmpGe {
        a: x2,
        b: b2,
        dst: c_hi,
    } = fourth
    else {
        return None;
    };
    let &Instr::Or { a: p, b: q, dst: d } = fifth else {
        return None;
    };
    let &Instr::Branch {
        cond,
        if_true,
        if_false,
    } = sixth
    else {
        return None;
    };
    let fits = b == t_lo
        && b2 == t_hi
        && x2 == x
        && x != t_lo
        && x != c_lo
        && x != t_hi
        && c_lo != t_hi
        && c_lo != c_hi
        && ((p == c_lo && q == c_hi) || (p == c_hi && q == c_lo))
        && cond == d;
    fits.then_some(Op::RangeBr {
        x,
        lo,
        t_lo,
        c_lo,
        hi,
        t_hi,
        c_hi,
        d,
        if_out: if_true,
        if_in: if_false,
    })
}

/// Jump threading: a `jumpi` whose target starts a fused compare-and-branch
/// does the compare itself (the loop's back edge and its test in one dispatch),
/// and an `add` just before such a `jumpi` joins it (a `for` loop's step, back
/// edge and test in one dispatch, as Lua's `FORLOOP`). Then a `jumpi` to such
/// a step does it too (the end of an `if` branch inside the loop body).
fn thread_jumps(fused: &mut [Op]) {
    thread_jumps_to_tests(fused);
    for index in 0..fused.len() {
        let Op::Jump { target } = fused[index] else {
            continue;
        };
        if let Some(&Op::AddJumpCmpBr {
            p,
            q,
            sum,
            cmp,
            a,
            b,
            c,
            if_true,
            if_false,
        }) = fused.get(target.index())
        {
            fused[index] = Op::JumpAddJumpCmpBr {
                p,
                q,
                sum,
                cmp,
                a,
                b,
                c,
                if_true,
                if_false,
            };
        }
    }
}

/// The first two steps of [`thread_jumps`].
fn thread_jumps_to_tests(fused: &mut [Op]) {
    for index in 0..fused.len() {
        let Op::Jump { target } = fused[index] else {
            continue;
        };
        fused[index] = match fused.get(target.index()) {
            Some(&Op::CmpBr {
                cmp,
                a,
                b,
                c,
                if_true,
                if_false,
            }) => Op::JumpCmpBr {
                cmp,
                a,
                b,
                c,
                if_true,
                if_false,
            },
            Some(&Op::CmpKBr {
                cmp,
                a,
                k,
                t,
                c,
                if_true,
                if_false,
            }) => Op::JumpCmpKBr {
                cmp,
                a,
                k,
                t,
                c,
                if_true,
                if_false,
            },
            _ => continue,
        };
        let Some(&Op::Add {
            a: p,
            b: q,
            dst: sum,
        }) = index.checked_sub(1).map(|at| &fused[at])
        else {
            continue;
        };
        fused[index - 1] = match fused[index] {
            Op::JumpCmpBr {
                cmp,
                a,
                b,
                c,
                if_true,
                if_false,
            } => Op::AddJumpCmpBr {
                p,
                q,
                sum,
                cmp,
                a,
                b,
                c,
                if_true,
                if_false,
            },
            Op::JumpCmpKBr {
                cmp,
                a,
                k,
                t,
                c,
                if_true,
                if_false,
            } => Op::AddJumpCmpKBr {
                p,
                q,
                sum,
                cmp,
                a,
                k,
                t,
                c,
                if_true,
                if_false,
            },
            _ => continue,
        };
    }
}

/// Builds an arithmetic-with-constant op from (a, k, t, dst).
type MakeArithK = fn(Reg, Value, Reg, Reg) -> Op;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gloc::{self, CheckOptions};
    use crate::sensors::SensorList;

    fn code(body: &str) -> Code {
        let lines = body.lines().count();
        let text = format!("nregs 8\nnblbs 8\nninstr {lines}\n{body}");
        let checked = gloc::check(
            &gloc::parse(&text),
            &SensorList::embedded(),
            &CheckOptions::default(),
        );
        let program = checked.program.expect("the test script checks");
        Code::new(&program)
    }

    #[test]
    fn the_shapes_of_compiled_loops_fuse() {
        // The body of `for i = 1 to n: acc = (acc + i * 7) mod 1000003` as `-O` emits it.
        let code = code(
            "label 0\ncmple r1,r2,r4\ncbr r4,1,2\nlabel 1\nloadi 7,r4\nmul r1,r4,r4\n\
             add r5,r4,r4\nloadi 1000003,r5\nmod r4,r5,r5\nloadi 10,r4\ni2d r4,r4\n\
             add r0,r4,r0\nloadi 0,r6\ncmpeq r1,r6,r6\ncbr r6,2,0\nlabel 2\nyield\njumpi 2",
        );
        let widths: Vec<u64> = code.fused.iter().map(width).collect();
        // pc: 0 cmple+cbr, 2 loadi+mul, 4 add, 5 loadi+mod, 7 loadi (then i2d+add),
        // 8 i2d+add, 10 loadi+cmpeq+cbr, 13 yield, 14 jumpi, 15 the final halt.
        assert_eq!(
            widths,
            [2, 1, 2, 1, 1, 2, 1, 1, 2, 1, 3, 2, 1, 1, 1, 1],
            "{:#?}",
            code.fused
        );
        assert!(matches!(code.fused[0], Op::CmpBr { cmp: Cmp::Le, .. }));
        assert!(matches!(
            code.fused[10],
            Op::CmpKBr {
                cmp: Cmp::Eq,
                k: Value::Int(0),
                ..
            }
        ));
        // The plain code stays one to one.
        assert!(code.plain.iter().all(|op| width(op) == 1));
    }

    #[test]
    fn a_loop_step_joins_its_back_edge_and_test() {
        // `for i = 1 to n` as `-O` emits it: the step `add`, the `jumpi`, and the
        // test (`cmple` + `cbr`, or against a constant) it lands on: one op.
        let code = code(
            "label 0\ncmple r0,r1,r3\ncbr r3,1,2\nlabel 1\nadd r5,r0,r5\nadd r0,r2,r0\njumpi 0\n\
             label 2\nlabel 3\nloadi 9,r1\ncmplt r0,r1,r4\ncbr r4,4,5\nlabel 4\nadd r0,r2,r0\n\
             jumpi 3\nlabel 5\nyield",
        );
        let widths: Vec<u64> = code.fused.iter().map(width).collect();
        // pc: 0 cmple+cbr, 2 add, 3 add+jumpi+cmple+cbr, 4 jumpi+cmple+cbr, 5 loadi+cmplt+cbr,
        // 6 cmplt+cbr, 8 add+jumpi+loadi+cmplt+cbr, 9 jumpi+loadi+cmplt+cbr, 10 yield, 11 halt.
        assert_eq!(
            widths,
            [2, 1, 1, 4, 3, 3, 2, 1, 5, 4, 1, 1],
            "{:#?}",
            code.fused
        );
        assert!(matches!(
            code.fused[8],
            Op::AddJumpCmpKBr {
                cmp: Cmp::Lt,
                k: Value::Int(9),
                ..
            }
        ));
    }

    #[test]
    fn register_types_follow_the_code() {
        // r0 is an integer until `i2d` makes it a float; r1 is one on one path and
        // the other on the other, so both after the join; r2 comes from memory;
        // pc 9 is never reached. Worked by hand, pc by pc.
        let code = code(
            "loadi 1,r0\ncbr r0,1,2\nlabel 1\nloadi 2,r1\njumpi 3\nlabel 2\nloadd 2.0,r1\n\
             label 3\ni2d r0,r0\nloadm r0,r2\nhalt\nadd r0,r0,r0",
        );
        let at = |pc: usize, register: u32| code.types.at(pc, Reg(register));
        // pc: 0 loadi, 1 cbr, 2 loadi r1, 3 jumpi, 4 loadd r1, 5 i2d, 6 loadm, 7 halt, 8 add.
        assert_eq!(
            (at(0, 0), at(1, 0), at(5, 0), at(6, 0)),
            (INT, INT, INT, FLOAT)
        );
        assert_eq!(
            (at(2, 1), at(3, 1), at(4, 1), at(5, 1)),
            (INT, INT, INT, ANY)
        );
        assert_eq!((at(6, 2), at(7, 2)), (INT, ANY));
        assert_eq!(at(8, 0), 0, "an unreached pc has no types");
        assert!(code.types.admits(5, Reg(1), Value::Float(0.5)));
        assert!(!code.types.admits(5, Reg(0), Value::Float(0.5)));
    }

    #[test]
    fn a_program_too_large_to_analyse_runs_untyped() {
        // 65,536 registers × 66 pcs is over MAX_TYPED: no analysis, no typed slots.
        let body: String = (0..64).map(|i| format!("loadi {i},r65535\n")).collect();
        let text = format!("nregs 65536\nnblbs 1\nninstr 65\n{body}yield");
        let checked = gloc::check(
            &gloc::parse(&text),
            &SensorList::embedded(),
            &CheckOptions::default(),
        );
        let code = Code::new(&checked.program.expect("the test script checks"));
        assert!(code.typed.is_none());
        assert_eq!(code.types.at(3, Reg(65535)), ANY);
        // 70,000 instructions on one register: over MAX_TYPED_PCS.
        let body = "loadi 1,r0\n".repeat(70_000);
        let text = format!("nregs 1\nnblbs 1\nninstr 70001\n{body}yield");
        let checked = gloc::check(
            &gloc::parse(&text),
            &SensorList::embedded(),
            &CheckOptions::default(),
        );
        let code = Code::new(&checked.program.expect("the test script checks"));
        assert!(code.typed.is_none());
        assert_eq!(code.types.at(3, Reg(0)), ANY);
    }

    #[test]
    fn an_indirect_jump_reaches_every_label() {
        // `jump r1` may land on label 1, where r0 then holds either type.
        let code = code("loadi 1,r1\nloadd 0.5,r0\njump r1\nlabel 1\nloadi 0,r0\nyield\njump r1");
        assert_eq!(code.types.at(3, Reg(0)), ANY);
        assert_eq!(code.types.at(4, Reg(0)), INT);
    }

    #[test]
    fn a_jump_to_a_loop_step_joins_it() {
        // The end of an `if` branch in a loop body: `jumpi` to the step `add`,
        // whose back edge and test are already one op.
        let code = code(
            "label 0\ncmple r0,r1,r3\ncbr r3,1,3\nlabel 1\nloadi 5,r4\njumpi 2\nlabel 2\n\
             add r0,r2,r0\njumpi 0\nlabel 3\nyield",
        );
        let widths: Vec<u64> = code.fused.iter().map(width).collect();
        // pc: 0 cmple+cbr, 1 cbr, 2 loadi, 3 jumpi+add+jumpi+cmple+cbr, 4 add+jumpi+cmple+cbr,
        // 5 jumpi+cmple+cbr, 6 yield, 7 halt.
        assert_eq!(widths, [2, 1, 1, 5, 4, 3, 1, 1], "{:#?}", code.fused);
        assert!(matches!(
            code.fused[3],
            Op::JumpAddJumpCmpBr {
                cmp: Cmp::Le,
                sum: Reg(0),
                if_true: Pc(2),
                if_false: Pc(6),
                ..
            }
        ));
    }

    #[test]
    fn groups_that_could_trap_or_mean_something_else_stay_plain() {
        // `mod` by the constant 0 traps; `K - a` is not `a - K`; `add t,t,d` adds K to K;
        // a branch on another register than the compare wrote is not a compare-and-branch.
        let code = code(
            "loadi 0,r1\nmod r0,r1,r2\nloadi 3,r1\nsub r1,r0,r2\nloadi 3,r1\nadd r1,r1,r2\n\
             cmplt r0,r1,r3\ncbr r4,1,1\nlabel 1\nyield",
        );
        let widths: Vec<u64> = code.fused.iter().map(width).collect();
        assert_eq!(widths, [1; 10], "{:#?}", code.fused);
    }
}
