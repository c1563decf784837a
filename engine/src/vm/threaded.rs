//! Threaded dispatch: the fused code as an array of slots, each holding the
//! handler function that runs its op, and handlers that end by calling the
//! next slot's handler.
//!
//! Every handler has the same signature and calls the next one in tail
//! position, so LLVM's sibling-call optimisation compiles that call to an
//! indirect `jmp`: each op ends with its own indirect jump, which the branch
//! predictor learns per op (the `match` loop has one shared jump for all of
//! them), and no `match` decodes the op: a handler reads the fields of the one
//! variant it was chosen for. Rust does not guarantee the tail call (`become`
//! is unstable), so `engine/tests/tail_calls.rs` reads the release build's
//! disassembly and fails when a handler ends in a `call`; at `opt-level` 0 no
//! handler tail-calls, which is why the build script enables this path only
//! for optimised builds (`cfg(gloc_threaded)`) and the `match` loop in
//! `vm.rs` stays the reference. Even where a tail call were missing, [`run`]
//! enters the handlers with at most [`CHUNK`] units of fuel, so the stack
//! depth stays bounded.
//!
//! Semantics are the `match` loop's, op for op (`engine/tests/fused.rs` runs
//! both on the same scripts): a handler charges the fuel of every GLOC
//! instruction its op covers and stops, with the pc of the next op, once
//! less than [`MAX_FUSED`] is left; traps, `yield` and `halt` stop at their
//! own pc. The four output ops are not run here: their handler stops with
//! [`Stop::RunInLoop`] and the `match` loop runs that one op, so output has
//! one implementation.
//!
//! Handlers are specialised where the loader knows an operand's type: a fused
//! op's constant is an integer or a float for good, and each comparison has
//! its own handler, so neither costs a test at run time. The common ops have an
//! integer fast path (`*_int`): with integer operands it computes without the
//! float code (so it saves no registers), and otherwise it goes on in the
//! general handler by a tail call, before writing anything. A branching
//! handler branches on its condition and then jumps (`branch_handler!`): a
//! conditional branch the predictor sees, where a select feeding one indirect
//! jump ran the branchy `states` benchmark at half the speed.
//!
//! Each handler that reads registers also has instances for operands of one
//! known type (a const parameter `T`, read through [`read`]): `Code::typed`
//! uses them where the loader's type analysis (`code::Types`) proves the type
//! at that pc, so the tag tests and the fallback fold away; `Code::threaded`
//! uses the untyped ones, which the machine runs once a debugger has stored a
//! value the analysis does not allow.

use std::hint::unreachable_unchecked;

use super::code::{op_table, Op, TypeSet, ANY, FLOAT, INT, MAX_FUSED};
use super::{
    absolute, add, compare, div, indirect_target, integer_division_by_zero, memory_index, mul,
    negate, rem, sub, truth, Cmp, Exit, Host, TrapKind,
};
use crate::program::{Pc, Program, Reg, Value};
use crate::sensors::SensorId;

/// The most fuel one entry into the handlers gets (see [`run`]): it bounds the
/// stack depth should a handler ever not tail-call.
const CHUNK: u64 = 4096;

/// One op of the threaded code: its handler, its branch targets and its operands.
#[derive(Clone, Copy, Debug)]
pub(super) struct Slot {
    handler: Handler,
    /// The op's branch targets (taken or jump target, then not taken) as byte
    /// offsets from this slot, so that a handler needs no base pointer (one
    /// register fewer: fewer handlers save registers). 0 where unused.
    jumps: [isize; 2],
    op: Op,
}

/// The one signature of every handler: the slot it runs, the register file,
/// the fuel left, and the rest of the machine.
type Handler = unsafe fn(*const Slot, Registers, u64, &mut Context<'_>);

/// The register file as the handlers see it: its first register. Made only by [`run`],
/// from the machine's register file, which `Machine::new` made `code.register_bound`
/// long; every register an op names lies below that bound (`Code::new`), so each access
/// through it is in bounds. (Checking the length again in `run` cost the `match` loop
/// 3% more instructions: the extra argument changed its register allocation.)
/// Its accessors ([`get`], [`set`], [`read`]) are the only `unsafe` register accesses.
#[derive(Clone, Copy)]
#[repr(transparent)]
pub(super) struct Registers(*mut Value);

/// What the handlers reach besides the registers, and where they leave how
/// they stopped.
pub(super) struct Context<'a> {
    pub host: &'a mut dyn Host,
    pub memory: &'a mut [Value],
    pub program: &'a Program,
    /// The number of slots (an indirect jump checks its target against it).
    pub code_len: usize,
    /// The first slot (set by [`run`]): pcs are indices from it.
    base: *const Slot,
    /// Set by the handler that stops: why, at which pc, with how much fuel.
    stop: Stop,
    pc: usize,
    fuel: u64,
}

/// Why the handlers returned.
#[derive(Clone, Copy)]
pub(super) enum Stop {
    Exit(Exit),
    /// The op at the pc is an output op: the `match` loop runs it.
    RunInLoop,
}

impl<'a> Context<'a> {
    pub fn new(
        host: &'a mut dyn Host,
        memory: &'a mut [Value],
        program: &'a Program,
        code_len: usize,
    ) -> Context<'a> {
        Context {
            host,
            memory,
            program,
            code_len,
            base: std::ptr::null(),
            stop: Stop::Exit(Exit::OutOfFuel),
            pc: 0,
            fuel: 0,
        }
    }
}

/// Runs the threaded code from `*pc` while at least [`MAX_FUSED`] fuel is left,
/// as the `match` loop over the fused code does; updates `*pc` and `*fuel`.
pub(super) fn run(
    slots: &[Slot],
    registers: &mut [Value],
    pc: &mut usize,
    fuel: &mut u64,
    context: &mut Context<'_>,
) -> Stop {
    let base = slots.as_ptr();
    context.base = base;
    let regs = Registers(registers.as_mut_ptr());
    loop {
        if *fuel < MAX_FUSED {
            return Stop::Exit(Exit::OutOfFuel);
        }
        assert!(*pc < slots.len(), "the pc stays inside the code");
        let chunk = (*fuel).min(CHUNK);
        // SAFETY: `*pc` is inside the code (checked above); every handler keeps
        // the pc inside it (the code ends with `halt`, targets were clamped by
        // `Code::new`, an indirect jump checks its target), reads only the
        // fields of the variant it was chosen for (`Slot::new`), and indexes
        // registers below `code.register_bound`, which the register file covers.
        unsafe { ((*base.add(*pc)).handler)(base.add(*pc), regs, chunk, context) };
        *fuel -= chunk - context.fuel;
        *pc = context.pc;
        match context.stop {
            Stop::Exit(Exit::OutOfFuel) => continue,
            stop => return stop,
        }
    }
}

/// The comparisons in the order of their handler's const parameter.
const CMPS: [Cmp; 6] = [Cmp::Eq, Cmp::Ne, Cmp::Lt, Cmp::Le, Cmp::Gt, Cmp::Ge];

macro_rules! by_cmp {
    ($cmp:expr, $handler:ident $(, $rest:expr)*) => {
        [
            $handler::<0 $(, $rest)*> as Handler,
            $handler::<1 $(, $rest)*>,
            $handler::<2 $(, $rest)*>,
            $handler::<3 $(, $rest)*>,
            $handler::<4 $(, $rest)*>,
            $handler::<5 $(, $rest)*>,
        ][CMPS.iter().position(|&cmp| cmp == $cmp).unwrap_or(0)]
    };
}
// A handler instantiated for the operand type `$t` (INT, FLOAT or ANY).
macro_rules! by_type {
    ($t:expr, $handler:ident $(, $rest:expr)*) => {
        match $t {
            INT => $handler::<$($rest,)* INT> as Handler,
            FLOAT => $handler::<$($rest,)* FLOAT>,
            _ => $handler::<$($rest,)* ANY>,
        }
    };
}
macro_rules! by_cmp_type {
    ($cmp:expr, $t:expr, $handler:ident $(, $rest:expr)*) => {
        match $t {
            INT => by_cmp!($cmp, $handler $(, $rest)*, INT),
            FLOAT => by_cmp!($cmp, $handler $(, $rest)*, FLOAT),
            _ => by_cmp!($cmp, $handler $(, $rest)*, ANY),
        }
    };
}

// The handler of one plain op, by its kind in the op table (`code.rs`, `op_table!`).
macro_rules! handler_of {
    ($operands:ident, $pc:ident, fixed($handler:ident)) => {
        $handler as Handler
    };
    ($operands:ident, $pc:ident, typed($handler:ident; $($reg:ident),+)) => {
        by_type!($operands.all(&[$(($pc, $reg)),+]), $handler)
    };
    ($operands:ident, $pc:ident, int_fast($general:ident, $int:ident; $($reg:ident),+)) => {
        match $operands.all(&[$(($pc, $reg)),+]) {
            FLOAT => $general::<FLOAT> as Handler,
            t => by_type!(t, $int),
        }
    };
    ($operands:ident, $pc:ident, int_or_any($handler:ident; $reg:ident)) => {
        match $operands.all(&[($pc, $reg)]) {
            INT => $handler::<INT> as Handler,
            _ => $handler::<ANY>,
        }
    };
}

// `select_handler`, generated from the op table: each plain op's handler by its kind,
// every fused op's by `fused_handler` (its operands are read at several pcs).
macro_rules! handler_selection {
    (
        plain { $($name:ident { $($field:ident : $ty:ty),* } => $kind:ident ( $($how:tt)* )),* $(,)? }
        fused { $($fused:ident { $($ffield:ident : $fty:ty),* }),* $(,)? }
    ) => {
        /// The handler made for `op`'s variant (and its comparison, constant type and
        /// operand types) at `pc`.
        fn select_handler(op: Op, pc: usize, operands: &Operands<'_>) -> Handler {
            match op {
                $(
                    #[allow(unused_variables)]
                    Op::$name { $($field),* } => handler_of!(operands, pc, $kind($($how)*)),
                )*
                $(Op::$fused { .. })|* => fused_handler(op, pc, operands),
            }
        }
    };
}

op_table!(handler_selection);

impl Slot {
    /// The slot for `op` at `pc`: the handler made for its variant (and its
    /// comparison, constant type and operand types) and its branch targets.
    /// `types(pc, register)` says what `register` can hold at `pc` of the plain
    /// code (`plain`); [`ANY`] everywhere gives the untyped handlers.
    pub fn new(op: Op, pc: usize, plain: &[Op], types: &dyn Fn(usize, Reg) -> TypeSet) -> Slot {
        let operands = Operands { plain, types };
        let handler = select_handler(op, pc, &operands);
        Slot {
            handler,
            jumps: branch_offsets(op, pc),
            op,
        }
    }
}

/// What the loader's type analysis says of an op's operands.
struct Operands<'a> {
    plain: &'a [Op],
    types: &'a dyn Fn(usize, Reg) -> TypeSet,
}

impl Operands<'_> {
    /// The one type all these (pc, register) reads have, or ANY.
    fn all(&self, reads: &[(usize, Reg)]) -> TypeSet {
        let mut sets = reads
            .iter()
            .map(|&(at, register)| (self.types)(at, register));
        let first = sets.next().unwrap_or(ANY);
        if (first == INT || first == FLOAT) && sets.all(|set| set == first) {
            first
        } else {
            ANY
        }
    }

    /// Where the `jumpi` at `at` of the plain code goes (for the threaded jumps: their
    /// compare runs there).
    fn target(&self, at: usize) -> Option<usize> {
        match self.plain.get(at) {
            Some(&Op::Jump { target }) => Some(target.index()),
            _ => None,
        }
    }
}

fn is_int(value: Value) -> bool {
    matches!(value, Value::Int(_))
}

/// The handler of a fused op (one that covers several GLOC instructions): its operands'
/// types are read at the pcs of the instructions it covers.
fn fused_handler(op: Op, pc: usize, operands: &Operands<'_>) -> Handler {
    let all = |reads: &[(usize, Reg)]| operands.all(reads);
    let target = |at: usize| operands.target(at);
    match op {
        // `loadi/loadd K,t` at pc, the operation at pc + 1.
        Op::AddK { k, a, .. } if is_int(k) => match all(&[(pc + 1, a)]) {
            INT => op_add_k_int::<INT>,
            _ => op_add_k_int::<ANY>,
        },
        Op::AddK { a, .. } => by_type!(all(&[(pc + 1, a)]), op_add_k, false),
        Op::SubK { k, a, .. } if is_int(k) => match all(&[(pc + 1, a)]) {
            INT => op_sub_k_int::<INT>,
            _ => op_sub_k_int::<ANY>,
        },
        Op::SubK { a, .. } => by_type!(all(&[(pc + 1, a)]), op_sub_k, false),
        Op::MulK { k, a, .. } if is_int(k) => match all(&[(pc + 1, a)]) {
            INT => op_mul_k_int::<INT>,
            _ => op_mul_k_int::<ANY>,
        },
        Op::MulK { a, .. } => by_type!(all(&[(pc + 1, a)]), op_mul_k, false),
        Op::DivK { k, a, .. } if is_int(k) => match all(&[(pc + 1, a)]) {
            INT => op_div_k_int::<INT>,
            _ => op_div_k_int::<ANY>,
        },
        Op::DivK { a, .. } => by_type!(all(&[(pc + 1, a)]), op_div_k, false),
        Op::ModK { k, a, .. } if is_int(k) => match all(&[(pc + 1, a)]) {
            INT => op_mod_k_int::<INT>,
            _ => op_mod_k_int::<ANY>,
        },
        Op::ModK { a, .. } => by_type!(all(&[(pc + 1, a)]), op_mod_k, false),
        // `i2d` at pc, the `add` at pc + 1.
        Op::IntToFloatAdd { a, .. } => match all(&[(pc + 1, a)]) {
            FLOAT => op_int_to_float_add::<FLOAT>,
            _ => op_int_to_float_add::<ANY>,
        },
        Op::CmpBr { cmp, a, b, .. } => match all(&[(pc, a), (pc, b)]) {
            FLOAT => by_cmp!(cmp, op_cmp_br, FLOAT),
            t => by_cmp_type!(cmp, t, op_cmp_br_int),
        },
        Op::JumpCmpBr { cmp, a, b, .. } => {
            let t = target(pc).map_or(ANY, |to| all(&[(to, a), (to, b)]));
            match t {
                FLOAT => by_cmp!(cmp, op_jump_cmp_br, FLOAT),
                t => by_cmp_type!(cmp, t, op_jump_cmp_br_int),
            }
        }
        Op::CmpKBr { cmp, k, a, .. } if is_int(k) => match all(&[(pc + 1, a)]) {
            INT => by_cmp!(cmp, op_cmp_k_br_int, INT),
            _ => by_cmp!(cmp, op_cmp_k_br_int, ANY),
        },
        Op::CmpKBr { cmp, a, .. } => by_cmp_type!(cmp, all(&[(pc + 1, a)]), op_cmp_k_br, false),
        Op::JumpCmpKBr { cmp, k, a, .. } => {
            let t = target(pc).map_or(ANY, |to| all(&[(to + 1, a)]));
            if is_int(k) {
                match t {
                    INT => by_cmp!(cmp, op_jump_cmp_k_br_int, INT),
                    _ => by_cmp!(cmp, op_jump_cmp_k_br_int, ANY),
                }
            } else {
                by_cmp_type!(cmp, t, op_jump_cmp_k_br, false)
            }
        }
        // `add p,q,sum` at pc, `jumpi` at pc + 1, the compare at its target.
        Op::AddJumpCmpBr {
            cmp, p, q, a, b, ..
        } => {
            let t = target(pc + 1).map_or(ANY, |to| all(&[(pc, p), (pc, q), (to, a), (to, b)]));
            match t {
                INT => by_cmp!(cmp, op_add_jump_cmp_br_int, INT),
                _ => by_cmp!(cmp, op_add_jump_cmp_br_int, ANY),
            }
        }
        // `jumpi` at pc, then the above at its target.
        Op::JumpAddJumpCmpBr {
            cmp, p, q, a, b, ..
        } => {
            let t = target(pc)
                .and_then(|to| Some((to, target(to + 1)?)))
                .map_or(ANY, |(to, test)| {
                    all(&[(to, p), (to, q), (test, a), (test, b)])
                });
            match t {
                INT => by_cmp!(cmp, op_jump_add_jump_cmp_br_int, INT),
                _ => by_cmp!(cmp, op_jump_add_jump_cmp_br_int, ANY),
            }
        }
        Op::AddJumpCmpKBr {
            cmp, k, p, q, a, ..
        } if is_int(k) => {
            let t = target(pc + 1).map_or(ANY, |to| all(&[(pc, p), (pc, q), (to + 1, a)]));
            match t {
                INT => by_cmp!(cmp, op_add_jump_cmp_k_br_int, INT),
                _ => by_cmp!(cmp, op_add_jump_cmp_k_br_int, ANY),
            }
        }
        Op::AddJumpCmpKBr { cmp, .. } => by_cmp!(cmp, op_add_jump_cmp_k_br, false),
        // The index is compared at pc + 1 (and pc + 3, unchanged).
        Op::RangeBr { lo, hi, x, .. } if is_int(lo) && is_int(hi) => match all(&[(pc + 1, x)]) {
            INT => op_range_br_int::<INT>,
            _ => op_range_br_int::<ANY>,
        },
        Op::RangeBr { .. } => op_range_br::<false>,
        other => unreachable!("{other:?} is routed here only if fused"),
    }
}

/// The op's branch targets as byte offsets from its slot (see [`Slot::jumps`]).
fn branch_offsets(op: Op, pc: usize) -> [isize; 2] {
    let offset =
        |target: Pc| (target.index() as isize - pc as isize) * std::mem::size_of::<Slot>() as isize;
    match op {
        Op::Jump { target } => [offset(target), 0],
        Op::Branch {
            if_true, if_false, ..
        }
        | Op::CmpBr {
            if_true, if_false, ..
        }
        | Op::CmpKBr {
            if_true, if_false, ..
        }
        | Op::JumpCmpBr {
            if_true, if_false, ..
        }
        | Op::JumpCmpKBr {
            if_true, if_false, ..
        }
        | Op::AddJumpCmpBr {
            if_true, if_false, ..
        }
        | Op::JumpAddJumpCmpBr {
            if_true, if_false, ..
        }
        | Op::AddJumpCmpKBr {
            if_true, if_false, ..
        }
        | Op::RangeBr {
            if_out: if_true,
            if_in: if_false,
            ..
        } => [offset(if_true), offset(if_false)],
        _ => [0, 0],
    }
}

/// Reads a register named by an op of the code.
#[inline(always)]
fn get(regs: Registers, register: Reg) -> Value {
    // SAFETY: `register` is named by an op of the code, so it lies below the bound the
    // register file covers ([`Registers`]).
    unsafe { *regs.0.add(register.0 as usize) }
}

/// Writes a register named by an op of the code.
#[inline(always)]
fn set(regs: Registers, register: Reg, value: Value) {
    // SAFETY: as in [`get`].
    unsafe { *regs.0.add(register.0 as usize) = value }
}

/// What GBASIC's index check (`RangeBr`) writes, in the order of the `loadi;
/// cmplt; loadi; cmpge; or` it fuses (`c_lo` may be `t_lo`, `c_hi` may be
/// `t_hi`): each bound, each comparison's truth, and whether the index is
/// outside, which it gives.
#[inline(always)]
fn range_outcome(
    regs: Registers,
    [t_lo, c_lo, t_hi, c_hi, d]: [Reg; 5],
    (lo, hi): (Value, Value),
    (below, above): (bool, bool),
) -> bool {
    set(regs, t_lo, lo);
    set(regs, c_lo, truth(below));
    set(regs, t_hi, hi);
    set(regs, c_hi, truth(above));
    set(regs, d, truth(below | above));
    below | above
}

/// Reads a register whose type the loader proved to be `T` ([`INT`] or
/// [`FLOAT`]; [`ANY`]: not known): the optimiser then sees the variant and
/// drops the tag tests. Both arms read the same 8 bytes, so a wrong `T` could
/// only give a wrong number, never undefined behaviour; `Machine` runs typed
/// handlers only while its registers agree with the analysis.
#[inline(always)]
fn read<const T: TypeSet>(regs: Registers, register: Reg) -> Value {
    let value = get(regs, register);
    match T {
        INT => Value::Int(match value {
            Value::Int(x) => x,
            Value::Float(x) => x.to_bits() as i64,
        }),
        FLOAT => Value::Float(match value {
            Value::Int(x) => f64::from_bits(x as u64),
            Value::Float(x) => x,
        }),
        _ => value,
    }
}

/// A constant whose type the loader knew when it chose the handler: the
/// optimiser sees the type, so no tag is tested at run time.
#[inline(always)]
fn constant<const INT: bool>(k: Value) -> Value {
    match (INT, k) {
        (true, Value::Int(x)) => Value::Int(x),
        (false, Value::Float(x)) => Value::Float(x),
        // SAFETY: `Slot::new` chose `INT` from this very constant.
        _ => unsafe { unreachable_unchecked() },
    }
}

/// Records how the handlers stopped: at `at`, with `fuel` left.
#[inline(always)]
fn stop(at: *const Slot, fuel: u64, context: &mut Context<'_>, why: Stop) {
    // Both point into the one slot array; plain address arithmetic (this is the cold
    // path) keeps it free of `unsafe`.
    context.pc = (at as usize - context.base as usize) / std::mem::size_of::<Slot>();
    context.fuel = fuel;
    context.stop = why;
}

/// The shape every handler shares: the one signature, never inlined (a fast
/// path reaches its general handler by a tail call), the op's fields bound
/// (the handler is only ever paired with its variant), `$width` units of fuel
/// charged, then `$body` and the way on that `$way` names ([`go_on!`]).
macro_rules! handler_fn {
    (
        $way:ident
        $(#[$doc:meta])*
        fn $name:ident $(<$(const $generic:ident: $gty:ty),*>)?
        ($variant:ident { $($field:ident),* }, width $width:expr)
        |$ip:ident, $regs:ident, $fuel:ident, $context:ident| $body:block
    ) => {
        $(#[$doc])*
        #[inline(never)]
        #[allow(unused_variables, clippy::unused_unit)]
        unsafe fn $name $(<$(const $generic: $gty),*>)? (
            $ip: *const Slot,
            $regs: Registers,
            $fuel: u64,
            $context: &mut Context<'_>,
        ) {
            // SAFETY: the caller passes a slot of the code (see [`run`] and [`dispatch`]).
            let slot: &Slot = unsafe { &*$ip };
            let Op::$variant { $($field),* } = slot.op else {
                // SAFETY: `Slot::new` pairs this handler with this variant only.
                unsafe { unreachable_unchecked() }
            };
            let $fuel = $fuel - $width;
            go_on!($way, $ip, $regs, $fuel, $context, $body)
        }
    };
}

/// Defines a handler whose `$body` evaluates to the next slot (or returns
/// after [`stop`]), then calls that slot's handler in tail position, unless
/// the fuel no longer covers the widest op.
macro_rules! handler {
    ($($handler:tt)*) => {
        handler_fn! { next $($handler)* }
    };
}

/// Defines a handler that branches: like [`handler!`], but `$body` evaluates to
/// whether the branch is taken, and each way has its own tail call. The
/// condition is then a conditional branch that the predictor sees before the
/// indirect jump, and each indirect jump has its own history.
macro_rules! branch_handler {
    ($($handler:tt)*) => {
        handler_fn! { branch $($handler)* }
    };
}

/// How a handler goes on after its `$body`: `next`, at the slot the body gives;
/// `branch`, at the op's first target when the body gives `true`, else at its
/// second.
macro_rules! go_on {
    (next, $ip:ident, $regs:ident, $fuel:ident, $context:ident, $body:block) => {{
        let next: *const Slot = $body;
        dispatch!(next, $regs, $fuel, $context)
    }};
    (branch, $ip:ident, $regs:ident, $fuel:ident, $context:ident, $body:block) => {{
        let taken: bool = $body;
        // SAFETY: `$ip` is this handler's own slot (see `handler_fn`).
        let jumps = unsafe { (*$ip).jumps };
        // `Slot::new` made the offsets from the op's targets, which `Code::new`
        // clamped into the code.
        if taken {
            dispatch!($ip.wrapping_byte_offset(jumps[0]), $regs, $fuel, $context)
        } else {
            dispatch!($ip.wrapping_byte_offset(jumps[1]), $regs, $fuel, $context)
        }
    }};
}

/// Goes on at `next`: stops when the fuel no longer covers the widest op,
/// and otherwise calls its handler in tail position.
macro_rules! dispatch {
    ($next:expr, $regs:ident, $fuel:ident, $context:ident) => {{
        let next: *const Slot = $next;
        if $fuel < MAX_FUSED {
            return stop(next, $fuel, $context, Stop::Exit(Exit::OutOfFuel));
        }
        // The tail call that LLVM turns into a jump (tests/tail_calls.rs).
        // SAFETY: every handler goes on at a slot of the code: the next op (the code
        // ends with `halt`), a target `Code::new` clamped, or a checked indirect target.
        return unsafe { ((*next).handler)(next, $regs, $fuel, $context) };
    }};
}

/// Stops the handlers at the current op with `why` (from inside a handler body).
macro_rules! stop_here {
    ($ip:ident, $fuel:ident, $context:ident, $why:expr) => {{
        stop($ip, $fuel, $context, $why);
        return;
    }};
}

/// Goes on in a more general handler of the same op (a fast path's fallback), by a tail
/// call with the slot, registers and context this handler was given.
macro_rules! fall_back {
    ($general:ident $(::<$($generic:tt),*>)? ($ip:ident, $regs:ident, $fuel:expr, $context:ident)) => {{
        // SAFETY: the general handler is made for the same variant, and the slot, the
        // registers and the context are the ones this handler was given.
        return unsafe { $general $(::<$($generic),*>)? ($ip, $regs, $fuel, $context) };
    }};
}

/// Handlers of `dst := a OP b`.
macro_rules! binary {
    ($($name:ident, $variant:ident, $f:expr;)*) => {$(
        handler! {
            fn $name<const T: TypeSet>($variant { a, b, dst }, width 1) |ip, regs, fuel, context| {
                set(regs, dst, $f(read::<T>(regs, a), read::<T>(regs, b)));
                ip.wrapping_add(1)
            }
        }
    )*};
}

/// Handlers of `dst := OP src`.
macro_rules! unary {
    ($($name:ident, $variant:ident, $f:expr;)*) => {$(
        handler! {
            fn $name<const T: TypeSet>($variant { src, dst }, width 1) |ip, regs, fuel, context| {
                set(regs, dst, $f(read::<T>(regs, src)));
                ip.wrapping_add(1)
            }
        }
    )*};
}

/// Handlers of `dst := a OP b` with an integer zero divisor trapping.
macro_rules! division {
    ($($name:ident, $variant:ident, $f:expr;)*) => {$(
        handler! {
            fn $name<const T: TypeSet>($variant { a, b, dst }, width 1) |ip, regs, fuel, context| {
                let (x, y) = (read::<T>(regs, a), read::<T>(regs, b));
                if integer_division_by_zero(x, y) {
                    stop_here!(ip, fuel, context, Stop::Exit(Exit::Trap(TrapKind::DivisionByZero)));
                }
                set(regs, dst, $f(x, y));
                ip.wrapping_add(1)
            }
        }
    )*};
}

/// Handlers of the fused `loadi/loadd K,t; OP a,t,dst`.
macro_rules! with_constant {
    ($($name:ident, $variant:ident, $f:expr;)*) => {$(
        handler! {
            fn $name<const INT: bool, const T: TypeSet>($variant { a, k, t, dst }, width 2)
            |ip, regs, fuel, context| {
                let k = constant::<INT>(k);
                let x = read::<T>(regs, a);
                set(regs, t, k);
                set(regs, dst, $f(x, k));
                ip.wrapping_add(2)
            }
        }
    )*};
}

binary! {
    op_add, Add, add;
    op_sub, Sub, sub;
    op_mul, Mul, mul;
    op_min, Min, super::minimum;
    op_max, Max, super::maximum;
    op_and, And, super::bit_and;
    op_or, Or, super::bit_or;
    op_xor, Xor, super::bit_xor;
    op_cmp_eq, CmpEq, |a, b| truth(compare(Cmp::Eq, a, b));
    op_cmp_ne, CmpNe, |a, b| truth(compare(Cmp::Ne, a, b));
    op_cmp_lt, CmpLt, |a, b| truth(compare(Cmp::Lt, a, b));
    op_cmp_le, CmpLe, |a, b| truth(compare(Cmp::Le, a, b));
    op_cmp_gt, CmpGt, |a, b| truth(compare(Cmp::Gt, a, b));
    op_cmp_ge, CmpGe, |a, b| truth(compare(Cmp::Ge, a, b));
}

division! {
    op_div, Div, div;
    op_mod, Mod, rem;
}

unary! {
    op_move, Move, |value| value;
    op_neg, Neg, negate;
    op_abs, Abs, absolute;
    op_sqrt, Sqrt, super::square_root;
    op_int_to_float, IntToFloat, super::to_float;
    op_float_to_int, FloatToInt, super::to_int;
    op_not, Not, super::logical_not;
}

with_constant! {
    op_add_k, AddK, add;
    op_sub_k, SubK, sub;
    op_mul_k, MulK, mul;
    op_div_k, DivK, div;
    op_mod_k, ModK, rem;
}

/// Calls the host out of line, so that the handler's only indirect call is
/// none: its tail call stays the one indirect transfer (tests/tail_calls.rs).
#[inline(never)]
fn load_sensor(host: &mut dyn Host, sensor: SensorId) -> f64 {
    host.load_sensor(sensor)
}

/// See [`load_sensor`].
#[inline(never)]
fn store_sensor(host: &mut dyn Host, sensor: SensorId, value: f64) {
    host.store_sensor(sensor, value);
}

handler! {
    fn op_load_sensor(LoadSensor { sensor, dst }, width 1) |ip, regs, fuel, context| {
        set(regs, dst, Value::Float(load_sensor(context.host, sensor)));
        ip.wrapping_add(1)
    }
}

handler! {
    fn op_store_sensor(StoreSensor { src, sensor }, width 1) |ip, regs, fuel, context| {
        store_sensor(context.host, sensor, get(regs, src).as_f64());
        ip.wrapping_add(1)
    }
}

handler! {
    fn op_load_int(LoadInt { value, dst }, width 1) |ip, regs, fuel, context| {
        set(regs, dst, Value::Int(value));
        ip.wrapping_add(1)
    }
}

handler! {
    fn op_load_float(LoadFloat { value, dst }, width 1) |ip, regs, fuel, context| {
        set(regs, dst, Value::Float(value));
        ip.wrapping_add(1)
    }
}

handler! {
    fn op_load_mem(LoadMem { addr, dst }, width 1) |ip, regs, fuel, context| {
        match memory_index(get(regs, addr), context.memory.len()) {
            Ok(index) => set(regs, dst, context.memory[index]),
            Err(kind) => stop_here!(ip, fuel, context, Stop::Exit(Exit::Trap(kind))),
        }
        ip.wrapping_add(1)
    }
}

handler! {
    fn op_load_mem_at(LoadMemAt { addr, dst }, width 1) |ip, regs, fuel, context| {
        set(regs, dst, context.memory[addr as usize]);
        ip.wrapping_add(1)
    }
}

handler! {
    fn op_store_mem(StoreMem { src, addr }, width 1) |ip, regs, fuel, context| {
        match memory_index(get(regs, addr), context.memory.len()) {
            Ok(index) => context.memory[index] = get(regs, src),
            Err(kind) => stop_here!(ip, fuel, context, Stop::Exit(Exit::Trap(kind))),
        }
        ip.wrapping_add(1)
    }
}

handler! {
    fn op_store_mem_at(StoreMemAt { src, addr }, width 1) |ip, regs, fuel, context| {
        context.memory[addr as usize] = get(regs, src);
        ip.wrapping_add(1)
    }
}

branch_handler! {
    fn op_branch<const T: TypeSet>(Branch { cond, if_true, if_false }, width 1)
    |ip, regs, fuel, context| {
        read::<T>(regs, cond).is_true()
    }
}

handler! {
    fn op_jump(Jump { target }, width 1) |ip, regs, fuel, context| {
        // SAFETY: `ip` is this handler's own slot (see `handler_fn`).
        ip.wrapping_byte_offset(unsafe { (*ip).jumps[0] })
    }
}

handler! {
    fn op_jump_indirect(JumpIndirect { register }, width 1) |ip, regs, fuel, context| {
        match indirect_target(context.program, get(regs, register), context.code_len) {
            Ok(pc) => context.base.wrapping_add(pc),
            Err(exit) => stop_here!(ip, fuel, context, Stop::Exit(exit)),
        }
    }
}

/// `yield`: charged, and stops at its own pc (the machine moves past it).
unsafe fn op_yield(ip: *const Slot, _regs: Registers, fuel: u64, context: &mut Context<'_>) {
    stop(ip, fuel - 1, context, Stop::Exit(Exit::Yield))
}

/// `halt` (and the end of the code): charged, and stops at its own pc.
unsafe fn op_halt(ip: *const Slot, _regs: Registers, fuel: u64, context: &mut Context<'_>) {
    stop(ip, fuel - 1, context, Stop::Exit(Exit::Halt))
}

handler! {
    fn op_nop(Nop {}, width 1) |ip, regs, fuel, context| {
        ip.wrapping_add(1)
    }
}

/// `write`, `writes`, `print`, `prints`: left to the `match` loop, uncharged.
unsafe fn op_output(ip: *const Slot, _regs: Registers, fuel: u64, context: &mut Context<'_>) {
    stop(ip, fuel, context, Stop::RunInLoop)
}

handler! {
    fn op_int_to_float_add<const T: TypeSet>(IntToFloatAdd { src, t, a, dst }, width 2)
    |ip, regs, fuel, context| {
        let widened = Value::Float(get(regs, src).as_f64());
        set(regs, t, widened);
        set(regs, dst, add(read::<T>(regs, a), widened));
        ip.wrapping_add(2)
    }
}

/// A loop's step `add`, back edge and test (and, for `JumpAddJumpCmpBr`, the
/// `jumpi` that led to the step): the general handlers.
macro_rules! add_jump_compare_and_branch {
    ($($name:ident, $variant:ident, $width:expr;)*) => {$(
        branch_handler! {
            fn $name<const C: usize>(
                $variant { p, q, sum, cmp, a, b, c, if_true, if_false }, width $width
            )
            |ip, regs, fuel, context| {
                set(regs, sum, add(get(regs, p), get(regs, q)));
                let result = compare(CMPS[C], get(regs, a), get(regs, b));
                set(regs, c, truth(result));
                result
            }
        }
    )*};
}

add_jump_compare_and_branch! {
    op_add_jump_cmp_br, AddJumpCmpBr, 4;
    op_jump_add_jump_cmp_br, JumpAddJumpCmpBr, 5;
}

branch_handler! {
    fn op_add_jump_cmp_k_br<const C: usize, const INT: bool>(
        AddJumpCmpKBr { p, q, sum, cmp, a, k, t, c, if_true, if_false }, width 5
    )
    |ip, regs, fuel, context| {
        set(regs, sum, add(get(regs, p), get(regs, q)));
        let k = constant::<INT>(k);
        set(regs, t, k);
        let result = compare(CMPS[C], get(regs, a), k);
        set(regs, c, truth(result));
        result
    }
}

branch_handler! {
    fn op_range_br<const INT: bool>(
        RangeBr { x, lo, t_lo, c_lo, hi, t_hi, c_hi, d, if_out, if_in }, width 6
    )
    |ip, regs, fuel, context| {
        // `INT`: both bounds are integers (as GBASIC writes them); otherwise
        // nothing is known and the comparisons test the tags.
        let (lo, hi) = if INT { (constant::<true>(lo), constant::<true>(hi)) } else { (lo, hi) };
        let index = get(regs, x);
        let below = compare(Cmp::Lt, index, lo);
        let above = compare(Cmp::Ge, index, hi);
        range_outcome(regs, [t_lo, c_lo, t_hi, c_hi, d], (lo, hi), (below, above))
    }
}

/// Integer fast paths: when every register operand holds an integer (the
/// common case in GBASIC, whose integer variables stay integers), the handler
/// computes with the tags known, so the optimiser drops the float code and its
/// registers; otherwise it goes on in the general handler by a tail call, with
/// the fuel as it was and nothing written yet. Operands read after a write of
/// the same op are integers too: the write was of an integer sum. A division
/// (`divides true`: `div`, `mod`) leaves a zero divisor to the general handler,
/// which traps; `fuse` never fuses a constant zero divisor. None of them calls
/// out (a float remainder calls `fmod`), so the handlers save no registers.
macro_rules! integer_arithmetic {
    ($(
        $name:ident, $variant:ident, $general:ident;
        $name_k:ident, $variant_k:ident, $general_k:ident;
        $f:ident, divides $divides:literal;
    )*) => {$(
        handler! {
            fn $name<const T: TypeSet>($variant { a, b, dst }, width 1) |ip, regs, fuel, context| {
                match (read::<T>(regs, a), read::<T>(regs, b)) {
                    (Value::Int(x), Value::Int(y)) if !($divides && y == 0) => {
                        set(regs, dst, Value::Int(x.$f(y)))
                    }
                    _ => fall_back!($general::<ANY>(ip, regs, fuel + 1, context)),
                }
                ip.wrapping_add(1)
            }
        }

        // The fused `loadi K,t; op a,t,dst`.
        handler! {
            fn $name_k<const T: TypeSet>($variant_k { a, k, t, dst }, width 2) |ip, regs, fuel, context| {
                let Value::Int(y) = k else {
                    // SAFETY: `Slot::new` chose this handler for an integer constant.
                    unsafe { unreachable_unchecked() }
                };
                if $divides && y == 0 {
                    // SAFETY: `fuse` leaves a division by the constant 0 plain.
                    unsafe { unreachable_unchecked() }
                }
                let Value::Int(x) = read::<T>(regs, a) else {
                    fall_back!($general_k::<true, ANY>(ip, regs, fuel + 2, context));
                };
                set(regs, t, k);
                set(regs, dst, Value::Int(x.$f(y)));
                ip.wrapping_add(2)
            }
        }
    )*};
}

// Each operation's plain and fused fast paths, with the integer operation they make.
integer_arithmetic! {
    op_add_int, Add, op_add; op_add_k_int, AddK, op_add_k; wrapping_add, divides false;
    op_sub_int, Sub, op_sub; op_sub_k_int, SubK, op_sub_k; wrapping_sub, divides false;
    op_mul_int, Mul, op_mul; op_mul_k_int, MulK, op_mul_k; wrapping_mul, divides false;
    op_div_int, Div, op_div; op_div_k_int, DivK, op_div_k; wrapping_div, divides true;
    op_mod_int, Mod, op_mod; op_mod_k_int, ModK, op_mod_k; wrapping_rem, divides true;
}

/// Integer fast paths of [`add_jump_compare_and_branch`].
macro_rules! integer_add_jump_compare_and_branch {
    ($($name:ident, $variant:ident, $general:ident, $width:expr;)*) => {$(
        branch_handler! {
            fn $name<const C: usize, const T: TypeSet>(
                $variant { p, q, sum, cmp, a, b, c, if_true, if_false }, width $width
            )
            |ip, regs, fuel, context| {
                let (Value::Int(x), Value::Int(y), Value::Int(_), Value::Int(_)) = (
                    read::<T>(regs, p),
                    read::<T>(regs, q),
                    read::<T>(regs, a),
                    read::<T>(regs, b),
                ) else {
                    fall_back!($general::<C>(ip, regs, fuel + $width, context));
                };
                set(regs, sum, Value::Int(x.wrapping_add(y)));
                // Read after the write: `a` or `b` may be `sum`, an integer as well.
                let (Value::Int(u), Value::Int(v)) = (read::<INT>(regs, a), read::<INT>(regs, b))
                else {
                    // SAFETY: `read::<INT>` gives integers.
                    unsafe { unreachable_unchecked() }
                };
                let result = compare(CMPS[C], Value::Int(u), Value::Int(v));
                set(regs, c, truth(result));
                result
            }
        }
    )*};
}

integer_add_jump_compare_and_branch! {
    op_add_jump_cmp_br_int, AddJumpCmpBr, op_add_jump_cmp_br, 4;
    op_jump_add_jump_cmp_br_int, JumpAddJumpCmpBr, op_jump_add_jump_cmp_br, 5;
}

branch_handler! {
    fn op_add_jump_cmp_k_br_int<const C: usize, const T: TypeSet>(
        AddJumpCmpKBr { p, q, sum, cmp, a, k, t, c, if_true, if_false }, width 5
    )
    |ip, regs, fuel, context| {
        let Value::Int(w) = k else {
            // SAFETY: `Slot::new` chose this handler for an integer constant.
            unsafe { unreachable_unchecked() }
        };
        let (Value::Int(x), Value::Int(y), Value::Int(_)) =
            (read::<T>(regs, p), read::<T>(regs, q), read::<T>(regs, a))
        else {
            fall_back!(op_add_jump_cmp_k_br::<C, true>(ip, regs, fuel + 5, context));
        };
        set(regs, sum, Value::Int(x.wrapping_add(y)));
        set(regs, t, k);
        // Read after the writes: `a` may be `sum` (never `t`: `fuse`), an integer as well.
        let Value::Int(u) = read::<INT>(regs, a) else {
            // SAFETY: `a` was an integer and both writes were integers.
            unsafe { unreachable_unchecked() }
        };
        let result = compare(CMPS[C], Value::Int(u), Value::Int(w));
        set(regs, c, truth(result));
        result
    }
}

// Integer fast paths of `loadm`/`storem`: an integer address inside the
// memory; anything else (a float address, a trap) goes on in the general
// handler by a tail call, so these save no registers.
handler! {
    fn op_load_mem_int<const T: TypeSet>(LoadMem { addr, dst }, width 1) |ip, regs, fuel, context| {
        match read::<T>(regs, addr) {
            Value::Int(index) if (index as u64) < context.memory.len() as u64 => {
                set(regs, dst, context.memory[index as usize]);
            }
            _ => fall_back!(op_load_mem(ip, regs, fuel + 1, context)),
        }
        ip.wrapping_add(1)
    }
}

handler! {
    fn op_store_mem_int<const T: TypeSet>(StoreMem { src, addr }, width 1) |ip, regs, fuel, context| {
        match read::<T>(regs, addr) {
            Value::Int(index) if (index as u64) < context.memory.len() as u64 => {
                context.memory[index as usize] = get(regs, src);
            }
            _ => fall_back!(op_store_mem(ip, regs, fuel + 1, context)),
        }
        ip.wrapping_add(1)
    }
}

branch_handler! {
    /// GBASIC's index check with integer bounds and an integer index.
    fn op_range_br_int<const T: TypeSet>(
        RangeBr { x, lo, t_lo, c_lo, hi, t_hi, c_hi, d, if_out, if_in }, width 6
    )
    |ip, regs, fuel, context| {
        let (Value::Int(low), Value::Int(high)) = (lo, hi) else {
            // SAFETY: `Slot::new` chose this handler for integer bounds.
            unsafe { unreachable_unchecked() }
        };
        let Value::Int(index) = read::<T>(regs, x) else {
            fall_back!(op_range_br::<true>(ip, regs, fuel + 6, context));
        };
        let (below, above) = (index < low, index >= high);
        range_outcome(regs, [t_lo, c_lo, t_hi, c_hi, d], (lo, hi), (below, above))
    }
}

/// The compare-and-branch handlers: the same body for `cmpXX; cbr` and for the
/// `jumpi` threaded into it (only the width differs).
macro_rules! compare_and_branch {
    ($($name:ident, $variant:ident, $width:expr;)*) => {$(
        branch_handler! {
            fn $name<const C: usize, const T: TypeSet>(
                $variant { cmp, a, b, c, if_true, if_false }, width $width
            )
            |ip, regs, fuel, context| {
                let result = compare(CMPS[C], read::<T>(regs, a), read::<T>(regs, b));
                set(regs, c, truth(result));
                result
            }
        }
    )*};
}

compare_and_branch! {
    op_cmp_br, CmpBr, 2;
    op_jump_cmp_br, JumpCmpBr, 3;
}

/// The same with a constant (`loadi/loadd K,t` first).
macro_rules! compare_constant_and_branch {
    ($($name:ident, $variant:ident, $width:expr;)*) => {$(
        branch_handler! {
            fn $name<const C: usize, const INT: bool, const T: TypeSet>(
                $variant { cmp, a, k, t, c, if_true, if_false }, width $width
            )
            |ip, regs, fuel, context| {
                let k = constant::<INT>(k);
                let x = read::<T>(regs, a);
                set(regs, t, k);
                let result = compare(CMPS[C], x, k);
                set(regs, c, truth(result));
                result
            }
        }
    )*};
}

compare_constant_and_branch! {
    op_cmp_k_br, CmpKBr, 3;
    op_jump_cmp_k_br, JumpCmpKBr, 4;
}

/// Integer fast paths of [`compare_and_branch`] (see [`integer_arithmetic`]).
macro_rules! integer_compare_and_branch {
    ($($name:ident, $variant:ident, $general:ident, $width:expr;)*) => {$(
        branch_handler! {
            fn $name<const C: usize, const T: TypeSet>(
                $variant { cmp, a, b, c, if_true, if_false }, width $width
            )
            |ip, regs, fuel, context| {
                let (Value::Int(x), Value::Int(y)) = (read::<T>(regs, a), read::<T>(regs, b)) else {
                    fall_back!($general::<C, ANY>(ip, regs, fuel + $width, context));
                };
                let result = compare(CMPS[C], Value::Int(x), Value::Int(y));
                set(regs, c, truth(result));
                result
            }
        }
    )*};
}

integer_compare_and_branch! {
    op_cmp_br_int, CmpBr, op_cmp_br, 2;
    op_jump_cmp_br_int, JumpCmpBr, op_jump_cmp_br, 3;
}

/// Integer fast paths of [`compare_constant_and_branch`] with an integer constant.
macro_rules! integer_compare_constant_and_branch {
    ($($name:ident, $variant:ident, $general:ident, $width:expr;)*) => {$(
        branch_handler! {
            fn $name<const C: usize, const T: TypeSet>(
                $variant { cmp, a, k, t, c, if_true, if_false }, width $width
            )
            |ip, regs, fuel, context| {
                let Value::Int(y) = k else {
                    // SAFETY: `Slot::new` chose this handler for an integer constant.
                    unsafe { unreachable_unchecked() }
                };
                // `a` is read after `t` is written in the instructions, but `fuse`
                // made sure they differ.
                let Value::Int(x) = read::<T>(regs, a) else {
                    fall_back!($general::<C, true, ANY>(ip, regs, fuel + $width, context));
                };
                set(regs, t, k);
                let result = compare(CMPS[C], Value::Int(x), Value::Int(y));
                set(regs, c, truth(result));
                result
            }
        }
    )*};
}

integer_compare_constant_and_branch! {
    op_cmp_k_br_int, CmpKBr, op_cmp_k_br, 3;
    op_jump_cmp_k_br_int, JumpCmpKBr, op_jump_cmp_k_br, 4;
}
