//! The optimizer (`-O`): constant folding, copy propagation and coalescing, dead-code
//! and unreachable-code removal, jump threading, register reuse from liveness, and
//! label renumbering. Every pass keeps the observable behavior: the same sensor
//! writes in the same cycles, the same output, the same traps. Each instruction
//! keeps the GBASIC span it came from.

use std::collections::{HashMap, HashSet};

use gloc_engine::Span;

use crate::codegen::ForBound;
use crate::ir::{Addr, Code, Instr, Lbl, Op1, Op2, Reg};

/// What the caller must update after optimizing.
#[derive(Clone, Debug, Default)]
pub struct Optimized {
    /// The loop bounds with their labels renumbered (a removed loop loses its bound).
    pub for_bounds: Vec<ForBound>,
    /// Old label → new label, for the labels that remain.
    pub labels: HashMap<Lbl, Lbl>,
}

/// The largest liveness table the optimizer builds: instructions × registers, in
/// bits. Liveness is a bit set per instruction, so its memory and time grow with the
/// product (32,000 `x=1` lines took 542 MB and 12 s); the largest real script is
/// far below (a 4,000-line generated program is about 2^29: 1.3 s, 151 MB), and this
/// keeps each table at 128 MB.
pub const MAX_LIVENESS_BITS: usize = 1 << 30;

/// Optimizes `code` in place; `None`, with `code` untouched, when it is over
/// [`MAX_LIVENESS_BITS`].
pub fn optimize(code: &mut Code, for_bounds: &[ForBound]) -> Option<Optimized> {
    if code
        .instrs
        .len()
        .saturating_mul(code.register_count as usize)
        > MAX_LIVENESS_BITS
    {
        return None;
    }
    let mut body: Vec<(Instr, Span)> = code.instrs.drain(..).zip(code.spans.drain(..)).collect();
    // Passes enable each other (folding a branch makes code unreachable, removing
    // code makes copies adjacent); a few rounds reach a fixed point in practice.
    for _ in 0..8 {
        let before = body.clone();
        fold_and_propagate(&mut body);
        coalesce_copies(&mut body);
        thread_jumps(&mut body);
        remove_unreachable(&mut body);
        remove_dead(&mut body);
        remove_untargeted_labels(&mut body);
        if body == before {
            break;
        }
    }
    let register_count = allocate_registers(&mut body);
    let (label_count, renumbering) = renumber_labels(&mut body);
    let bounds = for_bounds
        .iter()
        .filter_map(|bound| {
            renumbering.get(&bound.header).map(|header| ForBound {
                header: *header,
                trip_count: bound.trip_count,
            })
        })
        .collect();
    let (instrs, spans) = body.into_iter().unzip();
    code.instrs = instrs;
    code.spans = spans;
    code.register_count = register_count;
    code.label_count = label_count;
    Some(Optimized {
        for_bounds: bounds,
        labels: renumbering,
    })
}

/// A value known at compile time, with the machine's type.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Const {
    Int(i64),
    Float(f64),
}

impl Const {
    fn as_f64(self) -> f64 {
        match self {
            Const::Int(value) => value as f64,
            Const::Float(value) => value,
        }
    }

    fn as_i64(self) -> i64 {
        match self {
            Const::Int(value) => value,
            Const::Float(value) => value as i64,
        }
    }

    fn is_true(self) -> bool {
        match self {
            Const::Int(value) => value != 0,
            Const::Float(value) => value != 0.0 && !value.is_nan(),
        }
    }

    fn load(self, dst: Reg) -> Instr {
        match self {
            Const::Int(value) => Instr::LoadI { value, dst },
            Const::Float(value) => Instr::LoadD { value, dst },
        }
    }
}

/// Evaluates a binary operation the way the machine does; `None` when the result
/// would trap, overflow, or is not a finite float (left for run time).
fn fold_binary(op: Op2, a: Const, b: Const) -> Option<Const> {
    let both_int = matches!((a, b), (Const::Int(_), Const::Int(_)));
    let compare = |ordering: Option<std::cmp::Ordering>, accept: fn(std::cmp::Ordering) -> bool| {
        Some(Const::Int(i64::from(ordering.is_some_and(accept))))
    };
    let ordering = if both_int {
        Some(a.as_i64().cmp(&b.as_i64()))
    } else {
        a.as_f64().partial_cmp(&b.as_f64())
    };
    let result = match op {
        Op2::CmpEq => return compare(ordering, |o| o.is_eq()),
        Op2::CmpNe => {
            return Some(Const::Int(i64::from(ordering.is_none_or(|o| o.is_ne()))));
        }
        Op2::CmpLt => return compare(ordering, |o| o.is_lt()),
        Op2::CmpLe => return compare(ordering, |o| o.is_le()),
        Op2::CmpGt => return compare(ordering, |o| o.is_gt()),
        Op2::CmpGe => return compare(ordering, |o| o.is_ge()),
        Op2::And => return Some(Const::Int(a.as_i64() & b.as_i64())),
        Op2::Or => return Some(Const::Int(a.as_i64() | b.as_i64())),
        _ if both_int => {
            let (x, y) = (a.as_i64(), b.as_i64());
            Const::Int(match op {
                Op2::Add => x.checked_add(y)?,
                Op2::Sub => x.checked_sub(y)?,
                Op2::Mul => x.checked_mul(y)?,
                Op2::Div => x.checked_div(y)?,
                Op2::Mod => x.checked_rem(y)?,
                Op2::Min => x.min(y),
                Op2::Max => x.max(y),
                _ => return None,
            })
        }
        _ => {
            let (x, y) = (a.as_f64(), b.as_f64());
            Const::Float(match op {
                Op2::Add => x + y,
                Op2::Sub => x - y,
                Op2::Mul => x * y,
                Op2::Div => x / y,
                Op2::Mod => x % y,
                // Min and max of floats are left to the machine (NaN and -0.0 rules).
                _ => return None,
            })
        }
    };
    match result {
        Const::Float(value) if !value.is_finite() => None,
        _ => Some(result),
    }
}

fn fold_unary(op: Op1, a: Const) -> Option<Const> {
    let result = match (op, a) {
        (Op1::Neg, Const::Int(value)) => Const::Int(value.checked_neg()?),
        (Op1::Neg, Const::Float(value)) => Const::Float(-value),
        (Op1::Abs, Const::Int(value)) => Const::Int(value.checked_abs()?),
        (Op1::Abs, Const::Float(value)) => Const::Float(value.abs()),
        (Op1::Sqrt, _) => Const::Float(a.as_f64().sqrt()),
        (Op1::I2d, _) => Const::Float(a.as_f64()),
        (Op1::D2i, _) => Const::Int(a.as_i64()),
        (Op1::Not, _) => Const::Int(i64::from(!a.is_true())),
    };
    match result {
        Const::Float(value) if !value.is_finite() => None,
        _ => Some(result),
    }
}

/// What the forward pass knows about registers at one point.
#[derive(Clone, Debug, Default)]
struct Knowledge {
    constants: HashMap<Reg, Const>,
    /// dst → src of a `mov` still valid.
    copies: HashMap<Reg, Reg>,
    /// A pure operation already computed → the register that holds its result.
    expressions: HashMap<ExprKey, Reg>,
    /// Registers that hold exactly 0 or 1 (comparisons, `not`, and/or of those).
    booleans: HashSet<Reg>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum ExprKey {
    Binary(Op2, Reg, Reg),
    Unary(Op1, Reg),
}

impl Knowledge {
    /// Forgets everything that mentions `reg` (it is about to be overwritten).
    fn kill(&mut self, reg: Reg) {
        self.constants.remove(&reg);
        self.copies.remove(&reg);
        self.copies.retain(|_, source| *source != reg);
        self.expressions.retain(|key, holder| {
            *holder != reg
                && match key {
                    ExprKey::Binary(_, a, b) => *a != reg && *b != reg,
                    ExprKey::Unary(_, a) => *a != reg,
                }
        });
        self.booleans.remove(&reg);
    }

    fn holder_of_constant(&self, value: Const) -> Option<Reg> {
        self.constants
            .iter()
            .filter(|(_, known)| same_constant(**known, value))
            .map(|(reg, _)| *reg)
            .min()
    }
}

/// Same type and same bits (so `0.0` and `-0.0` stay apart).
fn same_constant(a: Const, b: Const) -> bool {
    match (a, b) {
        (Const::Int(x), Const::Int(y)) => x == y,
        (Const::Float(x), Const::Float(y)) => x.to_bits() == y.to_bits(),
        _ => false,
    }
}

/// `loadi -1,rT` + `loadm rT,…` is the compiler's array-index trap: the load always
/// traps, so control never continues after it.
fn is_trap(body: &[(Instr, Span)], index: usize) -> bool {
    let Some((
        Instr::LoadM {
            addr: Addr::Reg(reg),
            ..
        },
        _,
    )) = body.get(index)
    else {
        return false;
    };
    index > 0 && matches!(body[index - 1].0, Instr::LoadI { value: -1, dst } if dst == *reg)
}

/// How many control-flow edges enter each label.
fn predecessor_counts(body: &[(Instr, Span)]) -> HashMap<Lbl, usize> {
    let mut counts: HashMap<Lbl, usize> = HashMap::new();
    for (index, (instr, _)) in body.iter().enumerate() {
        match instr {
            Instr::Cbr {
                on_true, on_false, ..
            } => {
                *counts.entry(*on_true).or_default() += 1;
                if on_false != on_true {
                    *counts.entry(*on_false).or_default() += 1;
                }
            }
            Instr::Jumpi(label) => *counts.entry(*label).or_default() += 1,
            _ => {}
        }
        if let Some((Instr::Label(next), _)) = body.get(index + 1) {
            if !instr.ends_flow() && !is_trap(body, index) {
                *counts.entry(*next).or_default() += 1;
            }
        }
    }
    counts
}

/// Forward pass over extended blocks (a label entered by one edge only continues
/// what was known on that edge): known constants and copies replace register
/// reads, operations on constants become loads, a pure operation computed twice
/// becomes a copy, a constant already in a register is copied from it, and
/// branches on known conditions become jumps. On each arm of a branch on a 0/1
/// condition the condition's value is known.
/// `instr` with what is known of its operands folded in: a constant result, a decided
/// branch, a constant address; `None` when nothing is known.
fn fold(known: &Knowledge, instr: &Instr) -> Option<Instr> {
    match instr {
        Instr::Binary { op, a, b, dst } => match (known.constants.get(a), known.constants.get(b)) {
            (Some(x), Some(y)) => fold_binary(*op, *x, *y).map(|value| value.load(*dst)),
            _ => None,
        },
        Instr::Unary { op, src, dst } => known
            .constants
            .get(src)
            .and_then(|value| fold_unary(*op, *value))
            .map(|value| value.load(*dst)),
        Instr::Mov { src, dst } => known.constants.get(src).map(|value| value.load(*dst)),
        Instr::Cbr {
            cond,
            on_true,
            on_false,
        } => known
            .constants
            .get(cond)
            .map(|value| Instr::Jumpi(if value.is_true() { *on_true } else { *on_false })),
        Instr::LoadM {
            addr: Addr::Reg(reg),
            dst,
        } => match known.constants.get(reg) {
            Some(Const::Int(at)) if *at >= 0 && *at <= i64::from(u32::MAX) => Some(Instr::LoadM {
                addr: Addr::At(*at as u32),
                dst: *dst,
            }),
            _ => None,
        },
        Instr::StoreM {
            src,
            addr: Addr::Reg(reg),
        } => match known.constants.get(reg) {
            Some(Const::Int(at)) if *at >= 0 && *at <= i64::from(u32::MAX) => Some(Instr::StoreM {
                src: *src,
                addr: Addr::At(*at as u32),
            }),
            _ => None,
        },
        _ => None,
    }
}

fn fold_and_propagate(body: &mut [(Instr, Span)]) {
    let predecessors = predecessor_counts(body);
    let mut pending: HashMap<Lbl, Knowledge> = HashMap::new();
    let mut known = Knowledge::default();
    for index in 0..body.len() {
        if let Instr::Label(label) = body[index].0 {
            let falls_in = index > 0 && !body[index - 1].0.ends_flow() && !is_trap(body, index - 1);
            let single = predecessors.get(&label).copied().unwrap_or(0) == 1;
            known = match (single, falls_in, pending.remove(&label)) {
                (true, false, Some(edge)) => edge,
                (true, true, _) => known,
                _ => Knowledge::default(),
            };
            continue;
        }
        let instr = &mut body[index].0;
        instr.map_uses(|reg| known.copies.get(&reg).copied().unwrap_or(reg));
        let folded = fold(&known, instr);
        if let Some(folded) = folded {
            *instr = folded;
        }
        // Reuse a value already in a register. `loadi -1` stays: it is the trap idiom.
        let key = match &*instr {
            Instr::Binary { op, a, b, .. } => Some(ExprKey::Binary(*op, *a, *b)),
            Instr::Unary { op, src, .. } => Some(ExprKey::Unary(*op, *src)),
            _ => None,
        };
        let reuse = match &*instr {
            Instr::LoadI { value, .. } if *value != -1 => {
                known.holder_of_constant(Const::Int(*value))
            }
            Instr::LoadD { value, .. } => known.holder_of_constant(Const::Float(*value)),
            _ => key.and_then(|key| known.expressions.get(&key).copied()),
        };
        if let (Some(source), Some(dst)) = (reuse, instr.def()) {
            if source != dst {
                let constant = known.constants.get(&source).copied();
                let boolean = known.booleans.contains(&source);
                *instr = Instr::Mov { src: source, dst };
                known.kill(dst);
                known.copies.insert(dst, source);
                if let Some(constant) = constant {
                    known.constants.insert(dst, constant);
                }
                if boolean {
                    known.booleans.insert(dst);
                }
                continue;
            }
        }
        match &*instr {
            Instr::Cbr {
                cond,
                on_true,
                on_false,
            } => {
                let mut when_true = known.clone();
                let mut when_false = known.clone();
                if known.booleans.contains(cond) {
                    when_true.constants.insert(*cond, Const::Int(1));
                    when_false.constants.insert(*cond, Const::Int(0));
                }
                if on_true != on_false {
                    pending.insert(*on_true, when_true);
                    pending.insert(*on_false, when_false);
                }
            }
            Instr::Jumpi(label) => {
                pending.insert(*label, known.clone());
            }
            _ => {}
        }
        let Some(def) = instr.def() else { continue };
        let is_boolean = match &*instr {
            Instr::Binary { op, a, b, .. } => match op {
                Op2::CmpEq | Op2::CmpNe | Op2::CmpLt | Op2::CmpLe | Op2::CmpGt | Op2::CmpGe => true,
                Op2::And | Op2::Or => known.booleans.contains(a) && known.booleans.contains(b),
                _ => false,
            },
            Instr::Unary { op: Op1::Not, .. } => true,
            Instr::LoadI { value, .. } => *value == 0 || *value == 1,
            Instr::Mov { src, .. } => known.booleans.contains(src),
            _ => false,
        };
        known.kill(def);
        match &*instr {
            Instr::LoadI { value, .. } => {
                known.constants.insert(def, Const::Int(*value));
            }
            Instr::LoadD { value, .. } => {
                known.constants.insert(def, Const::Float(*value));
            }
            Instr::Mov { src, dst } if src != dst => {
                known.copies.insert(*dst, *src);
            }
            _ => {}
        }
        if let Some(key) = key {
            let operands_kept = match key {
                ExprKey::Binary(_, a, b) => a != def && b != def,
                ExprKey::Unary(_, a) => a != def,
            };
            if operands_kept {
                known.expressions.insert(key, def);
            }
        }
        if is_boolean {
            known.booleans.insert(def);
        }
    }
}

/// `op …,rT` directly followed by `mov rT,rX`, where rT is read nowhere else and
/// written nowhere else, becomes `op …,rX`.
fn coalesce_copies(body: &mut Vec<(Instr, Span)>) {
    let mut reads: HashMap<Reg, usize> = HashMap::new();
    let mut writes: HashMap<Reg, usize> = HashMap::new();
    for (instr, _) in body.iter() {
        for reg in instr.uses() {
            *reads.entry(reg).or_default() += 1;
        }
        if let Some(def) = instr.def() {
            *writes.entry(def).or_default() += 1;
        }
    }
    let mut index = 0;
    while index + 1 < body.len() {
        let (first, second) = (&body[index].0, &body[index + 1].0);
        if let (Some(temp), Instr::Mov { src, dst }) = (first.def(), second) {
            if *src == temp && reads.get(&temp) == Some(&1) && writes.get(&temp) == Some(&1) {
                let dst = *dst;
                body[index].0.map_def(|_| dst);
                body.remove(index + 1);
                continue;
            }
        }
        index += 1;
    }
}

fn label_positions(body: &[(Instr, Span)]) -> HashMap<Lbl, usize> {
    body.iter()
        .enumerate()
        .filter_map(|(index, (instr, _))| match instr {
            Instr::Label(label) => Some((*label, index)),
            _ => None,
        })
        .collect()
}

/// Where control goes after `index` when it reaches `label`: the first instruction
/// after the label (and any labels right after it).
fn first_real_after(body: &[(Instr, Span)], mut index: usize) -> usize {
    while index < body.len() && matches!(body[index].0, Instr::Label(_)) {
        index += 1;
    }
    index
}

/// A jump to a label whose first instruction is `jumpi M` goes to M directly; a
/// branch with both arms equal becomes a jump; a jump to the very next line goes.
fn thread_jumps(body: &mut Vec<(Instr, Span)>) {
    let positions = label_positions(body);
    let resolve = |label: Lbl| -> Lbl {
        let mut current = label;
        let mut seen = HashSet::new();
        while seen.insert(current) {
            let Some(position) = positions.get(&current) else {
                break;
            };
            match body.get(first_real_after(body, *position)) {
                Some((Instr::Jumpi(next), _)) => current = *next,
                _ => break,
            }
        }
        // Of several labels in a row, always use the first, so the others go.
        let Some(mut position) = positions.get(&current).copied() else {
            return current;
        };
        while position > 0 {
            match &body[position - 1].0 {
                Instr::Label(label) => {
                    current = *label;
                    position -= 1;
                }
                _ => break,
            }
        }
        current
    };
    let resolved: Vec<Option<Instr>> = body
        .iter()
        .map(|(instr, _)| match instr {
            Instr::Jumpi(label) => Some(Instr::Jumpi(resolve(*label))),
            Instr::Cbr {
                cond,
                on_true,
                on_false,
            } => {
                let (on_true, on_false) = (resolve(*on_true), resolve(*on_false));
                Some(if on_true == on_false {
                    Instr::Jumpi(on_true)
                } else {
                    Instr::Cbr {
                        cond: *cond,
                        on_true,
                        on_false,
                    }
                })
            }
            _ => None,
        })
        .collect();
    for ((instr, _), new) in body.iter_mut().zip(resolved) {
        if let Some(new) = new {
            *instr = new;
        }
    }
    // A jump to a label that directly follows it (through other labels) is a no-op.
    let mut index = 0;
    while index < body.len() {
        if let Instr::Jumpi(target) = body[index].0 {
            let mut next = index + 1;
            let mut falls_into = false;
            while let Some((Instr::Label(label), _)) = body.get(next) {
                if *label == target {
                    falls_into = true;
                    break;
                }
                next += 1;
            }
            if falls_into {
                body.remove(index);
                continue;
            }
        }
        index += 1;
    }
}

/// Drops labels nothing jumps to, so the blocks around them merge for folding.
fn remove_untargeted_labels(body: &mut Vec<(Instr, Span)>) {
    let targeted: HashSet<Lbl> = body.iter().flat_map(|(instr, _)| instr.targets()).collect();
    body.retain(|(instr, _)| match instr {
        Instr::Label(label) => targeted.contains(label),
        _ => true,
    });
}

/// Successor instruction indices of each instruction (`body.len()` = off the end).
fn successors(body: &[(Instr, Span)], positions: &HashMap<Lbl, usize>) -> Vec<Vec<usize>> {
    body.iter()
        .enumerate()
        .map(|(index, (instr, _))| match instr {
            Instr::Jumpi(label) => positions.get(label).copied().into_iter().collect(),
            Instr::Cbr {
                on_true, on_false, ..
            } => [on_true, on_false]
                .iter()
                .filter_map(|label| positions.get(label).copied())
                .collect(),
            Instr::Halt => Vec::new(),
            _ if is_trap(body, index) => Vec::new(),
            _ => vec![index + 1],
        })
        .collect()
}

/// Removes instructions no path from the start reaches.
fn remove_unreachable(body: &mut Vec<(Instr, Span)>) {
    let positions = label_positions(body);
    let next = successors(body, &positions);
    let mut reached = vec![false; body.len()];
    let mut stack = vec![0usize];
    while let Some(index) = stack.pop() {
        if index >= body.len() || reached[index] {
            continue;
        }
        reached[index] = true;
        stack.extend(next[index].iter().copied());
    }
    let mut index = 0;
    body.retain(|_| {
        let keep = reached[index];
        index += 1;
        keep
    });
}

/// Registers live before each instruction, as bit sets.
struct Liveness {
    live_in: Vec<Vec<u64>>,
    live_out: Vec<Vec<u64>>,
}

fn words(registers: usize) -> usize {
    registers.div_ceil(64).max(1)
}

fn set(bits: &mut [u64], reg: Reg) {
    bits[reg.0 as usize / 64] |= 1 << (reg.0 % 64);
}

fn clear(bits: &mut [u64], reg: Reg) {
    bits[reg.0 as usize / 64] &= !(1 << (reg.0 % 64));
}

fn has(bits: &[u64], reg: Reg) -> bool {
    bits[reg.0 as usize / 64] & (1 << (reg.0 % 64)) != 0
}

/// The registers in a bit set, in increasing order.
fn members(bits: &[u64]) -> impl Iterator<Item = u32> + '_ {
    bits.iter().enumerate().flat_map(|(word_index, word)| {
        let mut rest = *word;
        std::iter::from_fn(move || {
            if rest == 0 {
                return None;
            }
            let bit = rest.trailing_zeros();
            rest &= rest - 1;
            Some(word_index as u32 * 64 + bit)
        })
    })
}

fn register_bound(body: &[(Instr, Span)]) -> usize {
    body.iter()
        .flat_map(|(instr, _)| instr.uses().into_iter().chain(instr.def()))
        .map(|reg| reg.0 as usize + 1)
        .max()
        .unwrap_or(0)
}

fn liveness(body: &[(Instr, Span)], registers: usize) -> Liveness {
    let positions = label_positions(body);
    let next = successors(body, &positions);
    let width = words(registers);
    let mut live_in = vec![vec![0u64; width]; body.len()];
    let mut live_out = vec![vec![0u64; width]; body.len()];
    let mut changed = true;
    while changed {
        changed = false;
        for index in (0..body.len()).rev() {
            let mut out = vec![0u64; width];
            for successor in &next[index] {
                if let Some(bits) = live_in.get(*successor) {
                    for (word, other) in out.iter_mut().zip(bits) {
                        *word |= other;
                    }
                }
            }
            let mut input = out.clone();
            let instr = &body[index].0;
            if let Some(def) = instr.def() {
                clear(&mut input, def);
            }
            for reg in instr.uses() {
                set(&mut input, reg);
            }
            if input != live_in[index] || out != live_out[index] {
                live_in[index] = input;
                live_out[index] = out;
                changed = true;
            }
        }
    }
    Liveness { live_in, live_out }
}

/// Removes pure instructions whose result is never read, and `mov r,r`.
fn remove_dead(body: &mut Vec<(Instr, Span)>) {
    loop {
        let registers = register_bound(body);
        let live = liveness(body, registers);
        let before = body.len();
        let mut index = 0;
        body.retain(|(instr, _)| {
            let out = &live.live_out[index];
            index += 1;
            if let Instr::Mov { src, dst } = instr {
                if src == dst {
                    return false;
                }
            }
            match instr.def() {
                Some(def) if instr.is_pure() => has(out, def),
                _ => true,
            }
        });
        if body.len() == before {
            break;
        }
    }
}

/// Gives registers whose values are never live at the same time the same number
/// (greedy coloring of the interference graph, copies coalesced when possible).
/// Returns the number of registers used.
fn allocate_registers(body: &mut [(Instr, Span)]) -> u32 {
    let registers = register_bound(body);
    if registers == 0 {
        return 0;
    }
    let live = liveness(body, registers);
    let mut interferes: Vec<HashSet<u32>> = vec![HashSet::new(); registers];
    let mut add_edge = |a: u32, b: u32| {
        if a != b {
            interferes[a as usize].insert(b);
            interferes[b as usize].insert(a);
        }
    };
    // Registers live at the start hold the machine's initial 0 together.
    if let Some(entry) = live.live_in.first() {
        let live_at_entry: Vec<u32> = (0..registers as u32)
            .filter(|reg| has(entry, Reg(*reg)))
            .collect();
        for (position, a) in live_at_entry.iter().enumerate() {
            for b in &live_at_entry[position + 1..] {
                add_edge(*a, *b);
            }
        }
    }
    for (index, (instr, _)) in body.iter().enumerate() {
        let Some(def) = instr.def() else { continue };
        let copy_source = match instr {
            Instr::Mov { src, .. } => Some(*src),
            _ => None,
        };
        for reg in members(&live.live_out[index]) {
            if Some(Reg(reg)) != copy_source {
                add_edge(def.0, reg);
            }
        }
    }
    let moves: Vec<(u32, u32)> = body
        .iter()
        .filter_map(|(instr, _)| match instr {
            Instr::Mov { src, dst } => Some((src.0, dst.0)),
            _ => None,
        })
        .collect();
    // Color in order of first appearance so the output reads top to bottom.
    let mut order = Vec::with_capacity(registers);
    let mut seen = vec![false; registers];
    for (instr, _) in body.iter() {
        for reg in instr.uses().into_iter().chain(instr.def()) {
            if !seen[reg.0 as usize] {
                seen[reg.0 as usize] = true;
                order.push(reg.0);
            }
        }
    }
    let mut color: Vec<Option<u32>> = vec![None; registers];
    for reg in order {
        let taken: HashSet<u32> = interferes[reg as usize]
            .iter()
            .filter_map(|other| color[*other as usize])
            .collect();
        let preferred = moves
            .iter()
            .filter_map(|(a, b)| {
                if *a == reg {
                    color[*b as usize]
                } else if *b == reg {
                    color[*a as usize]
                } else {
                    None
                }
            })
            .find(|candidate| !taken.contains(candidate));
        let chosen = preferred.unwrap_or_else(|| {
            (0..)
                .find(|candidate| !taken.contains(candidate))
                .unwrap_or(0)
        });
        color[reg as usize] = Some(chosen);
    }
    let map = |reg: Reg| Reg(color[reg.0 as usize].unwrap_or(reg.0));
    for (instr, _) in body.iter_mut() {
        instr.map_uses(map);
        instr.map_def(map);
    }
    color
        .iter()
        .flatten()
        .map(|value| value + 1)
        .max()
        .unwrap_or(0)
}

/// Drops labels nothing jumps to and numbers the rest 0, 1, 2… in order.
fn renumber_labels(body: &mut Vec<(Instr, Span)>) -> (u32, HashMap<Lbl, Lbl>) {
    let targeted: HashSet<Lbl> = body.iter().flat_map(|(instr, _)| instr.targets()).collect();
    body.retain(|(instr, _)| match instr {
        Instr::Label(label) => targeted.contains(label),
        _ => true,
    });
    // Also drop `mov r,r` left by register allocation.
    body.retain(|(instr, _)| !matches!(instr, Instr::Mov { src, dst } if src == dst));
    let mut renumbering = HashMap::new();
    for (instr, _) in body.iter() {
        if let Instr::Label(label) = instr {
            let next = Lbl(renumbering.len() as u32);
            renumbering.insert(*label, next);
        }
    }
    for (instr, _) in body.iter_mut() {
        match instr {
            Instr::Label(label) | Instr::Jumpi(label) => {
                *label = renumbering.get(label).copied().unwrap_or(*label)
            }
            Instr::Cbr {
                on_true, on_false, ..
            } => {
                *on_true = renumbering.get(on_true).copied().unwrap_or(*on_true);
                *on_false = renumbering.get(on_false).copied().unwrap_or(*on_false);
            }
            _ => {}
        }
    }
    (renumbering.len() as u32, renumbering)
}
