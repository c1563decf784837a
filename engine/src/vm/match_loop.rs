//! The interpreter's reference `match` loop: one op at a time over the plain or the
//! fused code, by concern: [`run`] takes the fuel and dispatches, [`value_op`] computes
//! (loads of constants, moves, arithmetic, compares, memory), [`host_op`] talks to the
//! host (sensors, output), [`control_op`] jumps, yields and halts, and [`fused_op`]
//! runs a fused group. `execute` in `vm.rs` runs it as the whole interpreter
//! ([`Dispatch::Loop`](super::Dispatch)) or, under threaded code, for one output op.
//!
//! Each op function returns the next pc, or the [`Exit`] that ends the run with the pc
//! left at the op that ended it (a trap, `yield` or `halt` keeps its own pc).

use super::code::Op;
use super::{
    absolute, add, append_item, bit_and, bit_or, bit_xor, cap_output_line, compare, div,
    indirect_target, integer_division_by_zero, logical_not, maximum, memory_index, minimum, mul,
    negate, rem, square_root, sub, to_float, to_int, truth, write_value, Cmp, Exit, Host, TrapKind,
};
use crate::program::{Pc, Program, Reg, Value};

/// What the loop works on, borrowed apart from the machine.
pub(super) struct Parts<'a> {
    pub program: &'a Program,
    /// Length of the code: an indirect jump's bound.
    pub code_len: usize,
    /// At least `code.register_bound` long (see [`Parts::get`]).
    pub registers: &'a mut [Value],
    pub memory: &'a mut [Value],
    pub output: &'a mut String,
}

impl Parts<'_> {
    #[inline(always)]
    fn get(&self, register: Reg) -> Value {
        // SAFETY: `Machine::new` made the register file `code.register_bound` long, one
        // more than the highest register any op names, and nothing changes its length
        // afterwards; every `Reg` read here comes from an op of that code.
        *unsafe { self.registers.get_unchecked(register.0 as usize) }
    }

    #[inline(always)]
    fn set(&mut self, register: Reg, value: Value) {
        // SAFETY: as in `get`: the register comes from an op of the code the register
        // file was sized for.
        *unsafe { self.registers.get_unchecked_mut(register.0 as usize) } = value;
    }
}

/// The next pc, or the end of the run.
type Next = Result<usize, Exit>;

/// Runs `ops` from `*pc` until an op ends the run, or with [`Exit::OutOfFuel`] when
/// less than `needed` fuel is left (`needed` covers the widest op of `ops`, so the
/// budget runs out at exactly the instruction it would in plain code).
#[inline(always)]
pub(super) fn run(
    ops: &[Op],
    needed: u64,
    parts: &mut Parts<'_>,
    host: &mut impl Host,
    pc: &mut usize,
    fuel: &mut u64,
) -> Exit {
    // The pc and the fuel live in locals while the loop runs (written back at its end),
    // so they stay in registers.
    let (mut at, mut left) = (*pc, *fuel);
    let exit = run_from(ops, needed, parts, host, &mut at, &mut left);
    (*pc, *fuel) = (at, left);
    exit
}

#[inline(always)]
fn run_from(
    ops: &[Op],
    needed: u64,
    parts: &mut Parts<'_>,
    host: &mut impl Host,
    pc: &mut usize,
    fuel: &mut u64,
) -> Exit {
    loop {
        if *fuel < needed {
            return Exit::OutOfFuel;
        }
        // SAFETY: `pc < code.len()` always: execution starts at 0 or where it stopped;
        // the last op is a `halt`, so stepping past any other op stays inside; a fused
        // group never covers the last op; branch targets were clamped into the code by
        // `Code::new`; and an indirect jump checks its target.
        let op = unsafe { ops.get_unchecked(*pc) };
        *fuel -= 1;
        // One arm per op, so that after inlining each function meets an op whose kind
        // is known and its own `match` folds away: one dispatch per op.
        let next = match *op {
            Op::LoadSensor { .. } => host_op(op, parts, host, *pc),
            Op::StoreSensor { .. } => host_op(op, parts, host, *pc),
            Op::Write { .. } => host_op(op, parts, host, *pc),
            Op::WriteText { .. } => host_op(op, parts, host, *pc),
            Op::Print { .. } => host_op(op, parts, host, *pc),
            Op::PrintText { .. } => host_op(op, parts, host, *pc),
            Op::Branch { .. } => control_op(op, parts, *pc),
            Op::Jump { .. } => control_op(op, parts, *pc),
            Op::JumpIndirect { .. } => control_op(op, parts, *pc),
            Op::Yield {} => control_op(op, parts, *pc),
            Op::Halt {} => control_op(op, parts, *pc),
            Op::LoadInt { .. } => value_op(op, parts, *pc),
            Op::LoadFloat { .. } => value_op(op, parts, *pc),
            Op::Move { .. } => value_op(op, parts, *pc),
            Op::Add { .. } => value_op(op, parts, *pc),
            Op::Sub { .. } => value_op(op, parts, *pc),
            Op::Mul { .. } => value_op(op, parts, *pc),
            Op::Div { .. } => value_op(op, parts, *pc),
            Op::Mod { .. } => value_op(op, parts, *pc),
            Op::Min { .. } => value_op(op, parts, *pc),
            Op::Max { .. } => value_op(op, parts, *pc),
            Op::And { .. } => value_op(op, parts, *pc),
            Op::Or { .. } => value_op(op, parts, *pc),
            Op::Xor { .. } => value_op(op, parts, *pc),
            Op::CmpEq { .. } => value_op(op, parts, *pc),
            Op::CmpNe { .. } => value_op(op, parts, *pc),
            Op::CmpLt { .. } => value_op(op, parts, *pc),
            Op::CmpLe { .. } => value_op(op, parts, *pc),
            Op::CmpGt { .. } => value_op(op, parts, *pc),
            Op::CmpGe { .. } => value_op(op, parts, *pc),
            Op::Neg { .. } => value_op(op, parts, *pc),
            Op::Abs { .. } => value_op(op, parts, *pc),
            Op::Sqrt { .. } => value_op(op, parts, *pc),
            Op::IntToFloat { .. } => value_op(op, parts, *pc),
            Op::FloatToInt { .. } => value_op(op, parts, *pc),
            Op::Not { .. } => value_op(op, parts, *pc),
            Op::LoadMem { .. } => value_op(op, parts, *pc),
            Op::LoadMemAt { .. } => value_op(op, parts, *pc),
            Op::StoreMem { .. } => value_op(op, parts, *pc),
            Op::StoreMemAt { .. } => value_op(op, parts, *pc),
            Op::Nop {} => value_op(op, parts, *pc),
            Op::AddK { .. } => constant_op(op, parts, fuel, *pc),
            Op::SubK { .. } => constant_op(op, parts, fuel, *pc),
            Op::MulK { .. } => constant_op(op, parts, fuel, *pc),
            Op::DivK { .. } => constant_op(op, parts, fuel, *pc),
            Op::ModK { .. } => constant_op(op, parts, fuel, *pc),
            Op::IntToFloatAdd { .. } => constant_op(op, parts, fuel, *pc),
            Op::CmpBr { .. } => branch_op(op, parts, fuel, *pc),
            Op::CmpKBr { .. } => branch_op(op, parts, fuel, *pc),
            Op::JumpCmpBr { .. } => branch_op(op, parts, fuel, *pc),
            Op::JumpCmpKBr { .. } => branch_op(op, parts, fuel, *pc),
            Op::AddJumpCmpBr { .. } => branch_op(op, parts, fuel, *pc),
            Op::JumpAddJumpCmpBr { .. } => branch_op(op, parts, fuel, *pc),
            Op::AddJumpCmpKBr { .. } => branch_op(op, parts, fuel, *pc),
            Op::RangeBr { .. } => branch_op(op, parts, fuel, *pc),
        };
        match next {
            Ok(next) => *pc = next,
            Err(exit) => return exit,
        }
    }
}

/// Constants, moves, arithmetic, compares and memory: each writes its register and
/// goes on; a division by zero or an address outside memory traps.
#[inline(always)]
fn value_op(op: &Op, parts: &mut Parts<'_>, pc: usize) -> Next {
    macro_rules! binary {
        ($f:expr, $a:expr, $b:expr, $dst:expr) => {{
            let value = $f(parts.get($a), parts.get($b));
            parts.set($dst, value);
        }};
    }
    macro_rules! unary {
        ($f:expr, $src:expr, $dst:expr) => {{
            let value = $f(parts.get($src));
            parts.set($dst, value);
        }};
    }
    macro_rules! comparison {
        ($cmp:expr, $a:expr, $b:expr, $dst:expr) => {{
            let value = truth(compare($cmp, parts.get($a), parts.get($b)));
            parts.set($dst, value);
        }};
    }
    match *op {
        Op::LoadInt { value, dst } => parts.set(dst, Value::Int(value)),
        Op::LoadFloat { value, dst } => parts.set(dst, Value::Float(value)),
        Op::Move { src, dst } => parts.set(dst, parts.get(src)),
        Op::Add { a, b, dst } => binary!(add, a, b, dst),
        Op::Sub { a, b, dst } => binary!(sub, a, b, dst),
        Op::Mul { a, b, dst } => binary!(mul, a, b, dst),
        Op::Div { a, b, dst } => {
            divisor_not_zero(parts, a, b)?;
            binary!(div, a, b, dst);
        }
        Op::Mod { a, b, dst } => {
            divisor_not_zero(parts, a, b)?;
            binary!(rem, a, b, dst);
        }
        Op::Min { a, b, dst } => binary!(minimum, a, b, dst),
        Op::Max { a, b, dst } => binary!(maximum, a, b, dst),
        Op::And { a, b, dst } => binary!(bit_and, a, b, dst),
        Op::Or { a, b, dst } => binary!(bit_or, a, b, dst),
        Op::Xor { a, b, dst } => binary!(bit_xor, a, b, dst),
        Op::CmpEq { a, b, dst } => comparison!(Cmp::Eq, a, b, dst),
        Op::CmpNe { a, b, dst } => comparison!(Cmp::Ne, a, b, dst),
        Op::CmpLt { a, b, dst } => comparison!(Cmp::Lt, a, b, dst),
        Op::CmpLe { a, b, dst } => comparison!(Cmp::Le, a, b, dst),
        Op::CmpGt { a, b, dst } => comparison!(Cmp::Gt, a, b, dst),
        Op::CmpGe { a, b, dst } => comparison!(Cmp::Ge, a, b, dst),
        Op::Neg { src, dst } => unary!(negate, src, dst),
        Op::Abs { src, dst } => unary!(absolute, src, dst),
        Op::Sqrt { src, dst } => unary!(square_root, src, dst),
        Op::IntToFloat { src, dst } => unary!(to_float, src, dst),
        Op::FloatToInt { src, dst } => unary!(to_int, src, dst),
        Op::Not { src, dst } => unary!(logical_not, src, dst),
        Op::LoadMem { addr, dst } => {
            let index = memory_index(parts.get(addr), parts.memory.len()).map_err(Exit::Trap)?;
            parts.set(dst, parts.memory[index]);
        }
        Op::LoadMemAt { addr, dst } => parts.set(dst, parts.memory[addr as usize]),
        Op::StoreMem { src, addr } => {
            let index = memory_index(parts.get(addr), parts.memory.len()).map_err(Exit::Trap)?;
            parts.memory[index] = parts.get(src);
        }
        Op::StoreMemAt { src, addr } => parts.memory[addr as usize] = parts.get(src),
        // `run` hands the other ops to their own functions.
        _ => {}
    }
    Ok(pc + 1)
}

/// An integer division by zero traps (a float one gives infinity or NaN).
#[inline(always)]
fn divisor_not_zero(parts: &Parts<'_>, a: Reg, b: Reg) -> Result<(), Exit> {
    if integer_division_by_zero(parts.get(a), parts.get(b)) {
        Err(Exit::Trap(TrapKind::DivisionByZero))
    } else {
        Ok(())
    }
}

/// Sensors and output: what the host sees.
#[inline(always)]
fn host_op(op: &Op, parts: &mut Parts<'_>, host: &mut impl Host, pc: usize) -> Next {
    match *op {
        Op::LoadSensor { sensor, dst } => parts.set(dst, Value::Float(host.load_sensor(sensor))),
        Op::StoreSensor { src, sensor } => host.store_sensor(sensor, parts.get(src).as_f64()),
        Op::Write { src } => {
            let value = parts.get(src);
            append_item(parts.output, |out| write_value(out, value));
            cap_output_line(parts.output, host, pc);
        }
        Op::WriteText { text } => {
            let text = parts
                .program
                .texts
                .get(text as usize)
                .map_or("", |text| text);
            append_item(parts.output, |out| out.push_str(text));
            cap_output_line(parts.output, host, pc);
        }
        Op::Print { src } => {
            let value = parts.get(src);
            append_item(parts.output, |out| write_value(out, value));
            host.print_line_at(parts.output, Pc(pc as u32));
            parts.output.clear();
        }
        Op::PrintText { text } => {
            let text = parts
                .program
                .texts
                .get(text as usize)
                .map_or("", |text| text);
            append_item(parts.output, |out| out.push_str(text));
            host.print_line_at(parts.output, Pc(pc as u32));
            parts.output.clear();
        }
        // `run` hands only the ops above here.
        _ => {}
    }
    Ok(pc + 1)
}

/// Branches, jumps, `yield` and `halt`.
#[inline(always)]
fn control_op(op: &Op, parts: &mut Parts<'_>, pc: usize) -> Next {
    match *op {
        Op::Branch {
            cond,
            if_true,
            if_false,
        } => Ok(if parts.get(cond).is_true() {
            if_true.index()
        } else {
            if_false.index()
        }),
        Op::Jump { target } => Ok(target.index()),
        Op::JumpIndirect { register } => {
            indirect_target(parts.program, parts.get(register), parts.code_len)
        }
        Op::Yield {} => Err(Exit::Yield),
        Op::Halt {} => Err(Exit::Halt),
        // `run` hands only the ops above here.
        _ => Ok(pc + 1),
    }
}

/// A fused group of a constant and an operation: writes what its instructions write,
/// in their order, and charges the instruction it covers beyond the one `run` charged.
#[inline(always)]
fn constant_op(op: &Op, parts: &mut Parts<'_>, fuel: &mut u64, pc: usize) -> Next {
    // A fused `loadi/loadd K,t; op a,t,dst`: writes the constant's register, then `dst`.
    macro_rules! with_constant {
        ($f:expr, $a:expr, $k:expr, $t:expr, $dst:expr) => {{
            *fuel -= 1;
            parts.set($t, $k);
            let value = $f(parts.get($a), $k);
            parts.set($dst, value);
            Ok(pc + 2)
        }};
    }
    match *op {
        Op::AddK { a, k, t, dst } => with_constant!(add, a, k, t, dst),
        Op::SubK { a, k, t, dst } => with_constant!(sub, a, k, t, dst),
        Op::MulK { a, k, t, dst } => with_constant!(mul, a, k, t, dst),
        Op::DivK { a, k, t, dst } => with_constant!(div, a, k, t, dst),
        Op::ModK { a, k, t, dst } => with_constant!(rem, a, k, t, dst),
        Op::IntToFloatAdd { src, t, a, dst } => {
            *fuel -= 1;
            let widened = Value::Float(parts.get(src).as_f64());
            parts.set(t, widened);
            let value = add(parts.get(a), widened);
            parts.set(dst, value);
            Ok(pc + 2)
        }
        // `run` hands only the ops above here.
        _ => Ok(pc + 1),
    }
}

/// A fused compare and branch (with the add, the constant or the jump before it):
/// writes what its instructions write, in their order, and charges the instructions it
/// covers beyond the one `run` charged.
#[inline(always)]
fn branch_op(op: &Op, parts: &mut Parts<'_>, fuel: &mut u64, pc: usize) -> Next {
    // A fused compare and branch: writes the compare's result register and branches.
    macro_rules! compare_branch {
        ($extra:expr, $cmp:expr, $a:expr, $b:expr, $c:expr, $if_true:expr, $if_false:expr) => {{
            *fuel -= $extra;
            let result = compare($cmp, parts.get($a), $b);
            parts.set($c, truth(result));
            Ok(if result {
                $if_true.index()
            } else {
                $if_false.index()
            })
        }};
    }
    match *op {
        // The `jump` before a group is one more instruction charged, nothing else.
        Op::CmpBr {
            cmp,
            a,
            b,
            c,
            if_true,
            if_false,
        }
        | Op::JumpCmpBr {
            cmp,
            a,
            b,
            c,
            if_true,
            if_false,
        } => {
            let extra = if matches!(op, Op::CmpBr { .. }) { 1 } else { 2 };
            compare_branch!(extra, cmp, a, parts.get(b), c, if_true, if_false)
        }
        Op::CmpKBr {
            cmp,
            a,
            k,
            t,
            c,
            if_true,
            if_false,
        }
        | Op::JumpCmpKBr {
            cmp,
            a,
            k,
            t,
            c,
            if_true,
            if_false,
        } => {
            parts.set(t, k);
            let extra = if matches!(op, Op::CmpKBr { .. }) {
                2
            } else {
                3
            };
            compare_branch!(extra, cmp, a, k, c, if_true, if_false)
        }
        Op::AddJumpCmpBr {
            p,
            q,
            sum,
            cmp,
            a,
            b,
            c,
            if_true,
            if_false,
        }
        | Op::JumpAddJumpCmpBr {
            p,
            q,
            sum,
            cmp,
            a,
            b,
            c,
            if_true,
            if_false,
        } => {
            let total = add(parts.get(p), parts.get(q));
            parts.set(sum, total);
            let extra = if matches!(op, Op::AddJumpCmpBr { .. }) {
                3
            } else {
                4
            };
            compare_branch!(extra, cmp, a, parts.get(b), c, if_true, if_false)
        }
        Op::AddJumpCmpKBr {
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
        } => {
            let total = add(parts.get(p), parts.get(q));
            parts.set(sum, total);
            parts.set(t, k);
            compare_branch!(4, cmp, a, k, c, if_true, if_false)
        }
        Op::RangeBr {
            x,
            lo,
            t_lo,
            c_lo,
            hi,
            t_hi,
            c_hi,
            d,
            if_out,
            if_in,
        } => {
            *fuel -= 5;
            let index = parts.get(x);
            let below = compare(Cmp::Lt, index, lo);
            let above = compare(Cmp::Ge, index, hi);
            parts.set(t_lo, lo);
            parts.set(c_lo, truth(below));
            parts.set(t_hi, hi);
            parts.set(c_hi, truth(above));
            parts.set(d, truth(below | above));
            Ok(if below | above {
                if_out.index()
            } else {
                if_in.index()
            })
        }
        // `run` hands only the ops above here.
        _ => Ok(pc + 1),
    }
}
