//! Interpreter benchmark: a tight integer/float arithmetic loop in one long
//! cycle. Prints instructions per second and nanoseconds per loop iteration
//! (median of several runs). Run with `cargo bench -p gloc-engine --bench interp`.
//!
//! Both wall-clock time and the thread's CPU time (Linux
//! `/proc/thread-self/schedstat`) are reported: on a shared machine the
//! wall clock also counts time spent waiting for a core.
//!
//! Given GLOC files instead (`cargo bench -p gloc-engine --bench interp --
//! a.gloc b.gloc`), runs each as one cycle without a budget through both
//! dispatches, the `match` loop and threaded code, and prints the CPU time
//! (minimum and median of 7 runs): the engine alone, in a small binary.

use std::sync::Arc;
use std::time::Instant;

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::program::Program;
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{CycleEnd, Dispatch, Host, Machine, MachineConfig};

/// i := i + 1; acc := acc + i * 0.5; loop while i < n (sensor 1385).
/// Five instructions per iteration: add, mul, add, cmplt, cbr.
const LOOP: &str = "\
nregs 6
nblbs 2
ninstr 13
loadi 0,r0
loadi 1,r1
loadd 0.0,r2
loadd 0.5,r3
loads 1385,r4
label 0
add r0,r1,r0
mul r0,r3,r5
add r2,r5,r2
cmplt r0,r4,r5
cbr r5,0,1
label 1
yield
";
const INSTRUCTIONS_PER_ITERATION: u64 = 5;

struct Bench {
    iterations: f64,
}

impl Host for Bench {
    fn load_sensor(&mut self, _sensor: SensorId) -> f64 {
        self.iterations
    }
    fn store_sensor(&mut self, _sensor: SensorId, _value: f64) {}
    fn print_line(&mut self, _line: &str) {}
}

fn program() -> Arc<Program> {
    let checked = gloc::check(
        &gloc::parse(LOOP),
        &SensorList::embedded(),
        &CheckOptions::default(),
    );
    checked.program.expect("the benchmark script checks")
}

/// Runs each GLOC file through both dispatches; prints CPU times.
fn run_scripts(paths: &[String]) {
    for path in paths {
        let text = std::fs::read_to_string(path).expect("the GLOC file is readable");
        let checked = gloc::check(
            &gloc::parse(&text),
            &SensorList::embedded(),
            &CheckOptions::default(),
        );
        let program = checked.program.expect("the GLOC file checks");
        for dispatch in [Dispatch::Loop, Dispatch::Threaded] {
            let mut milliseconds = Vec::new();
            for _ in 0..7 {
                let mut machine = Machine::new(
                    Arc::clone(&program),
                    MachineConfig {
                        cycle_budget: u64::MAX,
                    },
                );
                machine.set_dispatch(dispatch);
                let mut host = Bench { iterations: 0.0 };
                let start = thread_cpu_seconds();
                machine.run_cycle(&mut host);
                if let (Some(start), Some(end)) = (start, thread_cpu_seconds()) {
                    milliseconds.push((end - start) * 1e3);
                }
            }
            milliseconds.sort_by(f64::total_cmp);
            if let (Some(min), Some(median)) = (
                milliseconds.first(),
                milliseconds.get(milliseconds.len() / 2),
            ) {
                println!("{path} {dispatch:?}: CPU min {min:.2} ms, median {median:.2} ms");
            }
        }
    }
}

fn main() {
    let scripts: Vec<String> = std::env::args()
        .skip(1)
        .filter(|arg| arg.ends_with(".gloc"))
        .collect();
    if !scripts.is_empty() {
        run_scripts(&scripts);
        return;
    }
    let iterations: u64 = std::env::args()
        .nth(1)
        .and_then(|arg| arg.parse().ok())
        .unwrap_or(20_000_000);
    let program = program();
    let mut host = Bench {
        iterations: iterations as f64,
    };
    let mut seconds = Vec::new();
    let mut cpu_seconds = Vec::new();
    let mut executed = 0;
    for _ in 0..5 {
        let mut machine = Machine::new(
            Arc::clone(&program),
            MachineConfig {
                cycle_budget: u64::MAX,
            },
        );
        let cpu_start = thread_cpu_seconds();
        let start = Instant::now();
        let end = machine.run_cycle(&mut host);
        seconds.push(start.elapsed().as_secs_f64());
        if let (Some(before), Some(after)) = (cpu_start, thread_cpu_seconds()) {
            cpu_seconds.push(after - before);
        }
        assert_eq!(end, CycleEnd::Yielded);
        executed = machine.instructions_this_cycle();
    }
    seconds.sort_by(f64::total_cmp);
    let median = seconds[seconds.len() / 2];
    assert_eq!(executed, 5 + 1 + iterations * INSTRUCTIONS_PER_ITERATION);
    println!("tight arithmetic loop: {iterations} iterations, {executed} instructions");
    report("wall clock", median, executed, iterations);
    if cpu_seconds.len() == seconds.len() {
        cpu_seconds.sort_by(f64::total_cmp);
        report(
            "CPU time  ",
            cpu_seconds[cpu_seconds.len() / 2],
            executed,
            iterations,
        );
    }
}

fn report(what: &str, seconds: f64, executed: u64, iterations: u64) {
    println!(
        "{what} (median of 5): {:.3} s, {:.1} M instructions/s, {:.2} ns per instruction, {:.2} ns per loop iteration",
        seconds,
        executed as f64 / seconds / 1e6,
        seconds * 1e9 / executed as f64,
        seconds * 1e9 / iterations as f64
    );
}

/// CPU time this thread has run, from Linux's schedstat (nanoseconds).
fn thread_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let nanoseconds: u64 = text.split_whitespace().next()?.parse().ok()?;
    Some(nanoseconds as f64 / 1e9)
}
