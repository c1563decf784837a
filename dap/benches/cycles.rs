//! Benchmarks of the debugger on a long run (`cargo bench -p gloc-dap`): `continue` to a
//! cycle breakpoint at cycle 100,000, then `stepBack` there, with reverse history on, on
//! the Fig. 3 script and on the thermocline tracker; beside each, the same cycles flown
//! the way `gloc run` flies them (`Simulation::step_cycle` on the same program, plain and
//! with `-O`). Prints figures; asserts nothing about time.
//!
//! `GLOC_BENCH_SLOW=1` also runs the debugger with its fast path off (every instruction a
//! single step), the way it ran before the fused shares.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use gloc_compiler::{load_script, Language, LoadOptions, Optimization};
use gloc_dap::debugger::{
    CycleBreakpoint, CycleBreakpointKind, Debugger, HistoryConfig, LineBreakpoint, Progress,
    RunMode, Slice, StopReason,
};
use gloc_dap::target::Target;
use gloc_dap::world::{self, LaunchConfig};
use gloc_engine::sensors::SensorList;
use gloc_sim::{Mission, SimConfig, Simulation};

const TARGET_CYCLE: u64 = 100_000;

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let fixtures = root.join("tests/fixtures");
    let examples = root.join("../examples");
    let slow_too = std::env::var_os("GLOC_BENCH_SLOW").is_some();
    // A breakpoint that never stops, on a line of the tracker's leg end (`total = 0.0`,
    // reached every few hundred cycles): the shares that may reach it are stepped up to it.
    let leg_end = LineBreakpoint {
        condition: Some("n < 0".into()),
        ..LineBreakpoint::new(2, 70)
    };
    for (name, program, mission, breakpoint) in [
        (
            "fig3",
            fixtures.join("fig3.gbas"),
            fixtures.join("endless.mi"),
            None,
        ),
        // Prints in most cycles, from print sites on two lines: those shares are stepped.
        (
            "prints",
            fixtures.join("prints.gbas"),
            fixtures.join("endless.mi"),
            None,
        ),
        (
            "thermocline",
            examples.join("thermocline.gbas"),
            examples.join("thermocline.mi"),
            Some(leg_end),
        ),
    ] {
        println!("{name}:");
        for optimization in [Optimization::Plain, Optimization::Optimized] {
            let seconds = simulate(&program, &mission, optimization);
            println!(
                "  gloc run{} for {TARGET_CYCLE} cycles: {seconds:.3} s ({:.2} µs per cycle)",
                if optimization.enabled() { " -O" } else { "" },
                seconds * 1e6 / TARGET_CYCLE as f64
            );
        }
        let speeds: &[bool] = if slow_too { &[true, false] } else { &[true] };
        for &fast in speeds {
            debug(&program, &mission, fast, None);
            if let Some(breakpoint) = &breakpoint {
                debug(&program, &mission, fast, Some(breakpoint.clone()));
            }
        }
    }
}

/// The cycles as `gloc run` flies them: no debugger, one `step_cycle` each.
fn simulate(program: &Path, mission: &Path, optimization: Optimization) -> f64 {
    let text = std::fs::read_to_string(program).expect("the program");
    let sensor_list = SensorList::embedded();
    let loaded = load_script(
        &text,
        Language::of_path(program),
        &sensor_list,
        &LoadOptions::from(optimization),
    );
    let script = loaded.program.expect("a program without errors");
    let mission = Mission::load(mission);
    let mut simulation = Simulation::new(
        &mission,
        Arc::new(sensor_list),
        Some(script),
        &SimConfig::default(),
    )
    .expect("the simulation");
    let began = Instant::now();
    for _ in 0..TARGET_CYCLE {
        assert!(simulation.step_cycle(), "the mission ended early");
    }
    began.elapsed().as_secs_f64()
}

fn debug(program: &Path, mission: &Path, fast: bool, breakpoint: Option<LineBreakpoint>) {
    let config = LaunchConfig::new(program, Some(mission.to_path_buf()));
    let (world, info) = world::launch(&config).expect("launch");
    let mut debugger = Debugger::new(world, info, Some(HistoryConfig::default()));
    debugger.fast_shares = fast;
    debugger.cycle_breakpoints.push(CycleBreakpoint::new(
        1,
        CycleBreakpointKind::At(TARGET_CYCLE),
    ));
    let mut label = String::new();
    if let Some(breakpoint) = breakpoint {
        label += &format!(" (breakpoint on line {})", breakpoint.at);
        debugger.line_breakpoints.push(breakpoint);
    }
    if !fast {
        label += " (fast path off)";
    }
    let start = debugger.clock();
    let began = Instant::now();
    loop {
        match debugger.run(RunMode::Continue, start, Slice::steps(50_000)) {
            Progress::Running => continue,
            Progress::Stopped(stop) => {
                assert_eq!(stop.reason, StopReason::CycleBreakpoint);
                break;
            }
            Progress::Ended { summary } => panic!("the mission ended early: {summary}"),
        }
    }
    let continue_time = began.elapsed();
    assert_eq!(debugger.target.cycle(), TARGET_CYCLE);
    println!(
        "  dap continue to cycle {TARGET_CYCLE}{label}: {:.3} s ({:.2} µs per cycle), {} snapshots kept",
        continue_time.as_secs_f64(),
        continue_time.as_secs_f64() * 1e6 / TARGET_CYCLE as f64,
        debugger.snapshot_count()
    );
    let mut times = Vec::new();
    for _ in 0..20 {
        let began = Instant::now();
        debugger.step_back().expect("stepBack");
        times.push(began.elapsed().as_secs_f64());
    }
    assert_eq!(debugger.target.cycle(), TARGET_CYCLE - 20);
    times.sort_by(f64::total_cmp);
    println!(
        "  dap stepBack at cycle ~{TARGET_CYCLE}{label}: median {:.3} ms, worst {:.3} ms over 20 steps",
        times[times.len() / 2] * 1e3,
        times[times.len() - 1] * 1e3
    );
    let began = Instant::now();
    let stop = debugger.reverse_continue().expect("reverseContinue");
    println!(
        "  dap reverseContinue from cycle ~{TARGET_CYCLE} with no earlier hit{label}: {:.3} s ({})",
        began.elapsed().as_secs_f64(),
        stop.description
    );
}
