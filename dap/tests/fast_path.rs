//! The debugger's fast path (the script's share of a cycle run on the fused machine when
//! nothing can stop inside it) against the reference, every instruction a single step:
//! the same session, driven through the same commands, must stop at the same clocks with
//! the same reasons, hit counts, registers, variables, printed lines (with their source
//! lines), logpoint output and traps, forwards and backwards.

use std::path::PathBuf;

use gloc_dap::debugger::{
    CycleBreakpoint, CycleBreakpointKind, DataBreakpoint, Debugger, Edit, HistoryConfig,
    HitCondition, InstructionBreakpoint, LineBreakpoint, Pc, Progress, RunMode, Slice,
};
use gloc_dap::expr::Number;
use gloc_dap::target::Target;
use gloc_dap::world::{self, LaunchConfig, World};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(name)
}

/// One user command of a session.
#[derive(Clone, Debug)]
enum Command {
    Run(RunMode),
    StepBack,
    ReverseContinue,
    Line {
        line: u32,
        condition: Option<&'static str>,
        hit: Option<&'static str>,
        log: Option<&'static str>,
    },
    Instruction(usize),
    Cycle(CycleBreakpointKind),
    Data(&'static str),
    ClearBreakpoints,
    SetVariable(&'static str, i64),
}

use Command::*;

fn line(line: u32) -> Command {
    Line {
        line,
        condition: None,
        hit: None,
        log: None,
    }
}

/// Runs the session and describes, after every command, everything a user can see.
fn session(
    program: PathBuf,
    mission: PathBuf,
    cycle_budget: Option<u64>,
    commands: &[Command],
    fast: bool,
) -> (Vec<String>, u64) {
    let mut config = LaunchConfig {
        // A run with nothing left to stop it ends here (the missions are endless).
        max_cycles: Some(3000),
        ..LaunchConfig::new(program, Some(mission))
    };
    config.overrides.cycle_budget = cycle_budget;
    let (world, info) = world::launch(&config).expect("launch");
    let history = HistoryConfig {
        max_snapshots: 16,
        interval: 8,
    };
    let mut debugger = Debugger::new(world, info, Some(history));
    debugger.fast_shares = fast;
    let mut next_id = 1;
    let mut trace = Vec::new();
    for command in commands {
        let outcome = match command {
            Run(mode) => {
                let start = debugger.clock();
                // Small slices: a fast share must also respect the slice budget.
                let mut slices = 0;
                loop {
                    slices += 1;
                    assert!(slices < 1_000_000, "{command:?} does not stop");
                    match debugger.run(*mode, start, Slice::steps(700)) {
                        Progress::Running => continue,
                        other => break format!("{other:?}"),
                    }
                }
            }
            StepBack => format!("{:?}", debugger.step_back()),
            ReverseContinue => format!("{:?}", debugger.reverse_continue()),
            Line {
                line,
                condition,
                hit,
                log,
            } => {
                debugger.line_breakpoints.push(LineBreakpoint {
                    condition: condition.map(str::to_string),
                    hit_condition: hit.map(|text| HitCondition::parse(text).expect("hit")),
                    log_message: log.map(str::to_string),
                    ..LineBreakpoint::new(next_id, *line)
                });
                next_id += 1;
                String::new()
            }
            Instruction(pc) => {
                debugger
                    .instruction_breakpoints
                    .push(InstructionBreakpoint::new(next_id, Pc(*pc)));
                next_id += 1;
                String::new()
            }
            Cycle(kind) => {
                debugger
                    .cycle_breakpoints
                    .push(CycleBreakpoint::new(next_id, *kind));
                next_id += 1;
                String::new()
            }
            Data(name) => {
                let sensor = debugger.target.sensor_index(name).expect("a sensor");
                debugger
                    .data_breakpoints
                    .push(DataBreakpoint::new(next_id, sensor));
                next_id += 1;
                debugger.reset_baseline();
                String::new()
            }
            ClearBreakpoints => {
                debugger.line_breakpoints.clear();
                debugger.instruction_breakpoints.clear();
                debugger.cycle_breakpoints.clear();
                debugger.data_breakpoints.clear();
                String::new()
            }
            SetVariable(name, value) => format!(
                "{:?}",
                debugger.edit(Edit::Variable(name.to_string(), Number::Int(*value)))
            ),
        };
        trace.push(describe(&mut debugger, command, &outcome));
    }
    (trace, debugger.fused_run_count())
}

fn describe(debugger: &mut Debugger<World>, command: &Command, outcome: &str) -> String {
    let hits: Vec<u64> = debugger
        .line_breakpoints
        .iter()
        .map(|breakpoint| breakpoint.hits)
        .chain(
            debugger
                .cycle_breakpoints
                .iter()
                .map(|breakpoint| breakpoint.hits),
        )
        .chain(
            debugger
                .data_breakpoints
                .iter()
                .map(|breakpoint| breakpoint.hits),
        )
        .chain(
            debugger
                .instruction_breakpoints
                .iter()
                .map(|breakpoint| breakpoint.hits),
        )
        .collect();
    let outputs = debugger.take_outputs();
    let target = &debugger.target;
    let sensors: Vec<String> = target
        .touched_sensors()
        .into_iter()
        .map(|index| format!("{:?}", target.sensor(index)))
        .collect();
    format!(
        "{command:?} → {outcome}\n  clock {:?} pc {} line {:?} phase {:?}\n  registers {:?}\n  \
         variables {:?}\n  sensors {sensors:?}\n  vehicle {:?}\n  hits {hits:?}\n  \
         trap {:?}\n  outputs {:?}",
        debugger.clock(),
        debugger.shown_pc(),
        debugger.current_line(),
        target.phase(),
        target.registers(),
        target.variables(),
        target.vehicle(),
        debugger.trap,
        outputs,
    )
}

/// Runs the session both ways and compares them command by command.
fn check(program: PathBuf, mission: PathBuf, cycle_budget: Option<u64>, commands: &[Command]) {
    let (fast, fused) = session(
        program.clone(),
        mission.clone(),
        cycle_budget,
        commands,
        true,
    );
    let (slow, unfused) = session(program, mission, cycle_budget, commands, false);
    assert_eq!(unfused, 0, "the reference must not run fused runs");
    assert!(
        fused > 0,
        "the fast path never ran: the comparison proves nothing"
    );
    if std::env::var_os("GLOC_FAST_PATH_TRACE").is_some() {
        eprintln!("{} fused runs\n{}", fused, fast.join("\n"));
    }
    assert_eq!(fast.len(), slow.len());
    for (fast, slow) in fast.iter().zip(&slow) {
        assert_eq!(
            fast, slow,
            "fast path (left) and single steps (right) differ"
        );
    }
}

#[test]
fn the_thermocline_tracker_stops_alike_with_and_without_the_fast_path() {
    check(
        example("thermocline.gbas"),
        example("thermocline.mi"),
        None,
        &[
            // A logpoint on the leg's end, the print of a new thermocline, and a cycle
            // breakpoint: the first leg ends near cycle 54.
            Line {
                line: 70,
                condition: None,
                hit: None,
                log: Some("leg over at depth {depth}, n = {n}"),
            },
            line(122),
            Cycle(CycleBreakpointKind::Every(97)),
            Run(RunMode::Continue),
            Run(RunMode::Continue),
            Run(RunMode::Continue),
            Run(RunMode::Next),
            Run(RunMode::StepOut),
            Run(RunMode::StepIn { instruction: false }),
            Run(RunMode::StepOut),
            StepBack,
            ClearBreakpoints,
            Line {
                line: 113,
                condition: Some("upper > 5"),
                hit: Some(">= 2"),
                log: None,
            },
            Run(RunMode::Continue),
            Run(RunMode::Continue),
            ReverseContinue,
            Run(RunMode::Continue),
            ClearBreakpoints,
            Data("sci_ruhp_behs"),
            Run(RunMode::Continue),
            Run(RunMode::Continue),
            SetVariable("leg", 128),
            Run(RunMode::Next),
            StepBack,
            StepBack,
            Run(RunMode::Continue),
            ClearBreakpoints,
            Cycle(CycleBreakpointKind::At(2500)),
            Run(RunMode::Continue),
            ReverseContinue,
            StepBack,
            Run(RunMode::Continue),
            Run(RunMode::Continue),
        ],
    );
}

#[test]
fn printed_lines_keep_their_source_lines_from_several_print_sites() {
    check(
        fixture("prints.gbas"),
        fixture("endless.mi"),
        None,
        &[
            Cycle(CycleBreakpointKind::Every(7)),
            Run(RunMode::Continue),
            Run(RunMode::Continue),
            Run(RunMode::Next),
            Run(RunMode::Next),
            Run(RunMode::StepIn { instruction: true }),
            Run(RunMode::StepOut),
            StepBack,
            Run(RunMode::Continue),
            SetVariable("n", 100),
            Run(RunMode::Continue),
            StepBack,
            StepBack,
            Run(RunMode::Continue),
            Run(RunMode::Continue),
            ReverseContinue,
            ReverseContinue,
            Run(RunMode::Continue),
        ],
    );
}

#[test]
fn instruction_breakpoints_and_edits_mid_share_stop_alike() {
    check(
        fixture("loop.gbas"),
        fixture("endless.mi"),
        None,
        &[
            Cycle(CycleBreakpointKind::Every(50)),
            Run(RunMode::Continue),
            Instruction(3),
            Run(RunMode::Continue),
            // Change `i` part way through a share, go back before it and forward over
            // it again: the journal's edit lands mid-share, which the fast path must step
            // (the share's length, the clock at its end, depends on it).
            SetVariable("i", 2),
            ClearBreakpoints,
            StepBack,
            Run(RunMode::StepOut),
            Run(RunMode::Next),
            Run(RunMode::Next),
            StepBack,
            StepBack,
            StepBack,
            Run(RunMode::StepOut),
            ClearBreakpoints,
            Cycle(CycleBreakpointKind::Every(50)),
            Run(RunMode::Continue),
            Run(RunMode::Continue),
            ReverseContinue,
            ReverseContinue,
        ],
    );
}

#[test]
fn traps_and_overruns_stop_at_the_same_instruction() {
    // A budget of 1,000 instructions: `overrun.gloc` traps on its 1,000th.
    check(
        fixture("overrun.gloc"),
        fixture("endless.mi"),
        Some(1000),
        &[
            Run(RunMode::Continue),
            Run(RunMode::Continue),
            Cycle(CycleBreakpointKind::At(30)),
            Run(RunMode::Continue),
            StepBack,
            ReverseContinue,
        ],
    );
    check(
        fixture("trap.gbas"),
        fixture("endless.mi"),
        None,
        &[
            Run(RunMode::Continue),
            StepBack,
            Run(RunMode::StepOut),
            Run(RunMode::Continue),
            Run(RunMode::Continue),
        ],
    );
}
