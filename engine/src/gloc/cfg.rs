//! Control-flow analysis of a resolved program: unreachable code, loops that
//! never yield (cycle safety) and the worst-case number of instructions
//! executed in one control cycle.
//!
//! The graph has one node per pc plus one "dispatch" node that stands for an
//! indirect `jump`: it has an edge to every defined label, so `J` indirect
//! jumps and `L` labels cost `J + L` edges, not `J × L`. Within a control
//! cycle `yield` and `halt` have no successors; the next cycle starts at the
//! pc after a `yield`. A strongly connected component of that graph is a loop
//! that runs without yielding.

use std::collections::HashMap;

use crate::diagnostic::{Diagnostic, Span};
use crate::gloc::{Bound, CheckOptions, WorstCase};
use crate::program::{Flow, Instr, Pc, Program};

pub struct Analysis {
    pub diagnostics: Vec<Diagnostic>,
    pub worst_case: WorstCase,
}

pub fn analyze(program: &Program, options: &CheckOptions) -> Analysis {
    let graph = Graph::new(program);
    let reachable = graph.reachable_from_start(program);
    let mut diagnostics = unreachable_code(program, &reachable);

    let bounds: HashMap<u32, u64> = options
        .loop_bounds
        .iter()
        .filter_map(|bound| {
            let pc = program.label_pc(bound.label)?;
            Some((pc.0, bound.max_iterations))
        })
        .collect();
    let members: Vec<u32> = (0..graph.node_count() as u32)
        .filter(|&node| reachable[node as usize])
        .collect();
    let instruction_weights: Vec<u64> = (0..graph.node_count())
        .map(|node| u64::from(node < graph.instruction_count))
        .collect();
    let mut cost = vec![Bound::Finite(0); graph.node_count()];
    let mut loops = Vec::new();
    solve(
        &graph,
        &members,
        None,
        &bounds,
        &instruction_weights,
        &mut cost,
        &mut loops,
    );
    // The same walk with each node weighted by the output bytes it can add.
    let output_weights: Vec<u64> = (0..graph.node_count())
        .map(|node| {
            program
                .instrs
                .get(node)
                .map_or(0, |instr| output_bytes(program, instr))
        })
        .collect();
    let mut output_cost = vec![Bound::Finite(0); graph.node_count()];
    solve(
        &graph,
        &members,
        None,
        &bounds,
        &output_weights,
        &mut output_cost,
        &mut Vec::new(),
    );

    for yield_free_loop in &loops {
        diagnostics.push(loop_diagnostic(program, &graph, yield_free_loop));
    }

    let from_start = cost[0];
    let from_yields: Vec<(Pc, Bound)> = program
        .instrs
        .iter()
        .enumerate()
        .filter(|(pc, instr)| matches!(instr, Instr::Yield) && reachable[*pc])
        .map(|(pc, _)| (Pc(pc as u32), cost[pc + 1]))
        .collect();
    let max = from_yields
        .iter()
        .map(|(_, bound)| *bound)
        .fold(from_start, Bound::max);
    let output_bytes = program
        .instrs
        .iter()
        .enumerate()
        .filter(|(pc, instr)| matches!(instr, Instr::Yield) && reachable[*pc])
        .map(|(pc, _)| output_cost[pc + 1])
        .fold(output_cost[0], Bound::max);
    Analysis {
        diagnostics,
        worst_case: WorstCase {
            from_start,
            from_yields,
            max,
            output_bytes,
        },
    }
}

/// Successor lists in compressed form.
struct Graph {
    offsets: Vec<u32>,
    targets: Vec<u32>,
    /// Instructions a node costs: 1 for each pc, 0 for the dispatch node.
    instruction_count: usize,
}

impl Graph {
    fn new(program: &Program) -> Graph {
        let count = program.instrs.len();
        let dispatch = count as u32;
        let mut offsets = Vec::with_capacity(count + 2);
        let mut targets = Vec::with_capacity(count * 2);
        for (pc, instr) in program.instrs.iter().enumerate() {
            offsets.push(targets.len() as u32);
            match instr.flow() {
                Flow::End => {}
                Flow::Jump(target) => targets.push(target.0),
                Flow::Branch(if_true, if_false) => {
                    targets.push(if_true.0);
                    if if_false != if_true {
                        targets.push(if_false.0);
                    }
                }
                Flow::Indirect => targets.push(dispatch),
                Flow::Next => targets.push(pc as u32 + 1),
            }
        }
        offsets.push(targets.len() as u32);
        let mut label_targets: Vec<u32> =
            program.label_pcs.iter().flatten().map(|pc| pc.0).collect();
        label_targets.sort_unstable();
        label_targets.dedup();
        targets.extend(label_targets);
        offsets.push(targets.len() as u32);
        Graph {
            offsets,
            targets,
            instruction_count: count,
        }
    }

    fn node_count(&self) -> usize {
        self.instruction_count + 1
    }

    fn successors(&self, node: u32) -> &[u32] {
        let start = self.offsets[node as usize] as usize;
        let end = self.offsets[node as usize + 1] as usize;
        &self.targets[start..end]
    }

    /// Reachable from pc 0 across cycles (a `yield` continues at the next pc).
    fn reachable_from_start(&self, program: &Program) -> Vec<bool> {
        let mut seen = vec![false; self.node_count()];
        let mut stack = vec![0u32];
        seen[0] = true;
        while let Some(node) = stack.pop() {
            let after_yield = program
                .instrs
                .get(node as usize)
                .filter(|instr| matches!(instr, Instr::Yield))
                .map(|_| node + 1);
            for &next in self.successors(node).iter().chain(after_yield.iter()) {
                if !seen[next as usize] {
                    seen[next as usize] = true;
                    stack.push(next);
                }
            }
        }
        seen
    }
}

/// A loop that can run without a yield, as a set of nodes.
struct YieldFreeLoop {
    nodes: Vec<u32>,
    /// Whether any edge leaves the loop (else it can never end).
    has_exit: bool,
}

/// The most characters a value prints as: an integer takes at most 20
/// (`-9223372036854775808`), a float in Rust's `{:?}` at most 24
/// (`-2.2250738585072014e-308`).
const MAX_VALUE_TEXT: u64 = 24;

/// The most bytes `instr` adds to the output: its item and the separating space.
fn output_bytes(program: &Program, instr: &Instr) -> u64 {
    match instr {
        Instr::Write { .. } | Instr::Print { .. } => 1 + MAX_VALUE_TEXT,
        Instr::WriteText { text } | Instr::PrintText { text } => {
            1 + program
                .texts
                .get(*text as usize)
                .map_or(0, |text| text.len() as u64)
        }
        _ => 0,
    }
}

/// Computes, for each node in `members`, the largest sum of `weights` (one per
/// instruction: the instruction count; output bytes) from it until the cycle ends,
/// following edges inside `members` only and never the edges into `removed_header`.
/// Loops without a bound are recorded.
fn solve(
    graph: &Graph,
    members: &[u32],
    removed_header: Option<u32>,
    bounds: &HashMap<u32, u64>,
    weights: &[u64],
    cost: &mut [Bound],
    loops: &mut Vec<YieldFreeLoop>,
) {
    let local = LocalIndex::new(members, graph.node_count());
    let edge_allowed = |to: u32| Some(to) != removed_header && local.get(to).is_some();
    let components = strongly_connected_components(graph, members, &local, &edge_allowed);
    let mut component_of = vec![0u32; members.len()];
    for (index, component) in components.iter().enumerate() {
        for &node in component {
            component_of[local.index(node)] = index as u32;
        }
    }
    // Tarjan yields components with their successors first.
    for (index, component) in components.iter().enumerate() {
        let mut exit = Bound::Finite(0);
        let mut cyclic = component.len() > 1;
        let mut has_exit = false;
        for &node in component {
            for &next in graph.successors(node) {
                if !edge_allowed(next) {
                    has_exit = true;
                    continue;
                }
                if component_of[local.index(next)] as usize == index {
                    cyclic |= next == node;
                } else {
                    has_exit = true;
                    exit = exit.max(cost[next as usize]);
                }
            }
        }
        if !cyclic {
            let node = component[0];
            cost[node as usize] = exit.plus(weights[node as usize]);
            continue;
        }
        let header = component
            .iter()
            .copied()
            .filter(|node| bounds.contains_key(node))
            .min();
        let total = match header {
            None => {
                let mut nodes = component.to_vec();
                nodes.sort_unstable();
                loops.push(YieldFreeLoop { nodes, has_exit });
                Bound::Unbounded
            }
            Some(header) => {
                let iterations = bounds.get(&header).copied().unwrap_or(0);
                let mut inner_members = component.to_vec();
                inner_members.sort_unstable();
                solve(
                    graph,
                    &inner_members,
                    Some(header),
                    bounds,
                    weights,
                    cost,
                    loops,
                );
                let longest_iteration = component
                    .iter()
                    .map(|&node| cost[node as usize])
                    .fold(Bound::Finite(0), Bound::max);
                longest_iteration
                    .times(iterations.saturating_add(1))
                    .plus_bound(exit)
            }
        };
        for &node in component {
            cost[node as usize] = total;
        }
    }
}

/// Node → position in a member list: a dense table for the whole program, a
/// hash map for the small member lists of nested loops.
enum LocalIndex {
    Dense(Vec<u32>),
    Sparse(HashMap<u32, u32>),
}

impl LocalIndex {
    const ABSENT: u32 = u32::MAX;

    fn new(members: &[u32], node_count: usize) -> LocalIndex {
        if members.len() * 8 >= node_count {
            let mut table = vec![LocalIndex::ABSENT; node_count];
            for (index, &node) in members.iter().enumerate() {
                table[node as usize] = index as u32;
            }
            LocalIndex::Dense(table)
        } else {
            LocalIndex::Sparse(
                members
                    .iter()
                    .enumerate()
                    .map(|(index, &node)| (node, index as u32))
                    .collect(),
            )
        }
    }

    fn get(&self, node: u32) -> Option<u32> {
        match self {
            LocalIndex::Dense(table) => table
                .get(node as usize)
                .copied()
                .filter(|&index| index != LocalIndex::ABSENT),
            LocalIndex::Sparse(map) => map.get(&node).copied(),
        }
    }

    /// The position of a node known to be a member.
    fn index(&self, node: u32) -> usize {
        self.get(node).map_or(0, |index| index as usize)
    }
}

/// Strongly connected components in one flat list (a 10 MB script has a
/// million of them; one `Vec` each would be a million allocations).
struct Components {
    nodes: Vec<u32>,
    /// Where each component starts in `nodes`.
    starts: Vec<u32>,
}

impl Components {
    fn iter(&self) -> impl Iterator<Item = &[u32]> {
        self.starts.iter().enumerate().map(|(index, &start)| {
            let end = self
                .starts
                .get(index + 1)
                .map_or(self.nodes.len(), |&end| end as usize);
            &self.nodes[start as usize..end]
        })
    }
}

/// Tarjan's algorithm without recursion (a 10 MB script must not overflow
/// the stack). Components come out successors first.
fn strongly_connected_components(
    graph: &Graph,
    members: &[u32],
    local: &LocalIndex,
    edge_allowed: &dyn Fn(u32) -> bool,
) -> Components {
    const UNVISITED: u32 = u32::MAX;
    let count = members.len();
    let mut index_of = vec![UNVISITED; count];
    let mut lowlink = vec![0u32; count];
    let mut on_stack = vec![false; count];
    let mut stack: Vec<u32> = Vec::new();
    let mut components = Components {
        nodes: Vec::with_capacity(count),
        starts: Vec::new(),
    };
    let mut next_index = 0u32;
    // (local node, position in its successor list)
    let mut work: Vec<(u32, usize)> = Vec::new();
    for root in 0..count as u32 {
        if index_of[root as usize] != UNVISITED {
            continue;
        }
        work.push((root, 0));
        index_of[root as usize] = next_index;
        lowlink[root as usize] = next_index;
        next_index += 1;
        stack.push(root);
        on_stack[root as usize] = true;
        while let Some(&mut (node, ref mut position)) = work.last_mut() {
            let successors = graph.successors(members[node as usize]);
            if let Some(&next) = successors.get(*position) {
                *position += 1;
                if !edge_allowed(next) {
                    continue;
                }
                let next = local.index(next) as u32;
                if index_of[next as usize] == UNVISITED {
                    index_of[next as usize] = next_index;
                    lowlink[next as usize] = next_index;
                    next_index += 1;
                    stack.push(next);
                    on_stack[next as usize] = true;
                    work.push((next, 0));
                } else if on_stack[next as usize] {
                    lowlink[node as usize] = lowlink[node as usize].min(index_of[next as usize]);
                }
                continue;
            }
            work.pop();
            if let Some(&(parent, _)) = work.last() {
                lowlink[parent as usize] = lowlink[parent as usize].min(lowlink[node as usize]);
            }
            if lowlink[node as usize] == index_of[node as usize] {
                components.starts.push(components.nodes.len() as u32);
                while let Some(member) = stack.pop() {
                    on_stack[member as usize] = false;
                    components.nodes.push(members[member as usize]);
                    if member == node {
                        break;
                    }
                }
            }
        }
    }
    components
}

fn unreachable_code(program: &Program, reachable: &[bool]) -> Vec<Diagnostic> {
    let mut diagnostics = Vec::new();
    // The implicit final `halt` is not the user's code.
    let user_instructions = program.instrs.len().saturating_sub(1);
    let mut pc = 0;
    while pc < user_instructions {
        if reachable[pc] {
            pc += 1;
            continue;
        }
        let start = pc;
        while pc < user_instructions && !reachable[pc] {
            pc += 1;
        }
        let count = pc - start;
        let first = program.spans[start];
        let mut diagnostic = Diagnostic::warning(
            crate::codes::gloc::UNREACHABLE,
            first,
            if count == 1 {
                "unreachable instruction: no path from the start of the script reaches it".to_string()
            } else {
                format!("unreachable code: no path from the start of the script reaches these {count} instructions")
            },
        )
        .with_help("remove it, or add a label and jump to it");
        if count > 1 {
            diagnostic =
                diagnostic.with_label(program.spans[pc - 1], "the unreachable code ends here");
        }
        diagnostics.push(diagnostic);
    }
    diagnostics
}

fn loop_diagnostic(
    program: &Program,
    graph: &Graph,
    yield_free_loop: &YieldFreeLoop,
) -> Diagnostic {
    let pcs: Vec<u32> = yield_free_loop
        .nodes
        .iter()
        .copied()
        .filter(|&node| (node as usize) < graph.instruction_count)
        .collect();
    let first = pcs.first().copied().unwrap_or(0);
    let last = pcs.last().copied().unwrap_or(first);
    let span = program.span(Pc(first));
    let closing: Span = program.span(Pc(last));
    let mut diagnostic = if yield_free_loop.has_exit {
        Diagnostic::warning(
            crate::codes::gloc::LOOP_MAY_OVERRUN,
            span,
            "this loop can repeat without a `yield`: it may overrun the 4-second control cycle",
        )
        .with_help("add a `yield` inside the loop, or pass its trip count as a loop bound")
    } else {
        Diagnostic::error(
            crate::codes::gloc::LOOP_WITHOUT_YIELD,
            span,
            "this loop never yields and has no way out: it would hang the vehicle's control cycle",
        )
        .with_help("add a `yield` inside the loop")
    };
    if last != first {
        diagnostic = diagnostic.with_label(closing, "the loop jumps back from here");
    }
    diagnostic
}
