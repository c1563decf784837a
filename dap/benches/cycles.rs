//! Benchmarks of the debugger on a long run (`cargo bench -p gloc-dap`): `continue` to a
//! cycle breakpoint at cycle 100,000, then `stepBack` there, with reverse history on.
//! Prints figures; asserts nothing about time.

use std::path::PathBuf;
use std::time::Instant;

use gloc_dap::debugger::{
    CycleBreakpoint, CycleBreakpointKind, Debugger, HistoryConfig, Progress, RunMode,
};
use gloc_dap::target::Target;
use gloc_dap::world::{self, LaunchConfig};

const TARGET_CYCLE: u64 = 100_000;

fn main() {
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
    let config = LaunchConfig {
        program: fixtures.join("fig3.gbas"),
        mission: Some(fixtures.join("endless.mi")),
        ..LaunchConfig::default()
    };
    let (world, info) = world::launch(&config).expect("launch");
    let mut debugger = Debugger::new(world, info, Some(HistoryConfig::default()));
    debugger.cycle_breakpoints.push(CycleBreakpoint {
        id: 1,
        kind: CycleBreakpointKind::At(TARGET_CYCLE),
        condition: None,
        hit_condition: None,
        hits: 0,
    });
    let start = debugger.clock();
    let began = Instant::now();
    loop {
        match debugger.run(RunMode::Continue, start, 50_000) {
            Progress::Running => continue,
            Progress::Stopped(stop) => {
                assert_eq!(stop.reason, "function breakpoint");
                break;
            }
            Progress::Ended { summary } => panic!("the mission ended early: {summary}"),
        }
    }
    let continue_time = began.elapsed();
    assert_eq!(debugger.target.cycle(), TARGET_CYCLE);
    println!(
        "continue to cycle {TARGET_CYCLE}: {:.3} s ({:.2} µs per cycle), {} snapshots kept",
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
        "stepBack at cycle ~{TARGET_CYCLE}: median {:.3} ms, worst {:.3} ms over 20 steps",
        times[times.len() / 2] * 1e3,
        times[times.len() - 1] * 1e3
    );
    let began = Instant::now();
    let stop = debugger.reverse_continue().expect("reverseContinue");
    println!(
        "reverseContinue from cycle ~{TARGET_CYCLE} with no earlier hit (back to the start): {:.3} s ({})",
        began.elapsed().as_secs_f64(),
        stop.description
    );
}
