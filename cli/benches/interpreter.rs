//! Interpreter benchmark suite: each program in `tests/perf/programs` run by the GLOC
//! engine (compiled from GBASIC, with and without `-O`), by Lua 5.4 (`lua5.4`, Debian's
//! package) and as plain Rust, on the same work. Counts execution only: compilation and
//! Lua's process start are outside the timed region. All three are timed by CPU time:
//! Lua times itself with `os.clock` (the process's CPU time), GLOC and native Rust read
//! the thread's CPU-time clock, so a loaded machine (other processes taking turns on the
//! cores) favours neither side; wall time would count the turns of others.
//! Prints medians over `GLOC_BENCH_RUNS` runs (default 5) and the ratios GLOC/Lua and
//! GLOC/native; checks that all three compute the same results.

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

use gloc_compiler::{load_script, Language, LoadOptions};
use gloc_engine::program::Program;
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig};

mod native;

/// A native Rust version of a program: runs it and returns what it prints.
type NativeRun = fn() -> Vec<String>;

struct Quiet {
    lines: Vec<String>,
}

impl Host for Quiet {
    fn load_sensor(&mut self, _sensor: SensorId) -> f64 {
        0.0
    }
    fn store_sensor(&mut self, _sensor: SensorId, _value: f64) {}
    fn print_line(&mut self, line: &str) {
        self.lines.push(line.to_string());
    }
}

/// CPU time of the calling thread in seconds (for a one-thread process, the clock
/// Lua's `os.clock` reads).
fn thread_cpu_seconds() -> f64 {
    let mut now = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes one timespec through the valid pointer given.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut now) };
    assert_eq!(
        status, 0,
        "clock_gettime(CLOCK_THREAD_CPUTIME_ID) works on Linux"
    );
    now.tv_sec as f64 + now.tv_nsec as f64 * 1e-9
}

fn programs_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/perf/programs")
}

fn compile(name: &str, optimize: bool) -> Arc<Program> {
    let path = programs_dir().join(format!("{name}.gbas"));
    let text = std::fs::read_to_string(&path).expect("benchmark program is in the repo");
    let loaded = load_script(
        &text,
        Language::Gbasic,
        &SensorList::embedded(),
        &LoadOptions {
            optimize,
            cycle_budget: None,
        },
    );
    for diagnostic in &loaded.diagnostics {
        eprintln!(
            "{}: {:?} {}",
            path.display(),
            diagnostic.code,
            diagnostic.message
        );
    }
    loaded.program.expect("benchmark program compiles")
}

/// Runs the whole program as one cycle; returns (seconds, instructions, printed lines).
fn run_gloc(program: &Arc<Program>) -> (f64, u64, Vec<String>) {
    let mut machine = Machine::new(
        program.clone(),
        MachineConfig {
            cycle_budget: u64::MAX,
        },
    );
    let mut host = Quiet { lines: Vec::new() };
    let start = thread_cpu_seconds();
    let end = machine.run_cycle(&mut host);
    let seconds = thread_cpu_seconds() - start;
    assert!(
        matches!(end, CycleEnd::Halted),
        "benchmark program must end with `end`, got {end:?}"
    );
    (seconds, machine.instructions_this_cycle(), host.lines)
}

/// Runs the Lua version; returns (seconds measured inside Lua, printed fields).
fn run_lua(name: &str) -> Option<(f64, Vec<String>)> {
    let output = Command::new("lua5.4")
        .arg(programs_dir().join(format!("{name}.lua")))
        .output()
        .ok()?;
    if !output.status.success() {
        return None;
    }
    let stderr = String::from_utf8_lossy(&output.stderr);
    let seconds = stderr
        .lines()
        .find_map(|line| line.strip_prefix("seconds "))?
        .trim()
        .parse()
        .ok()?;
    let fields = String::from_utf8_lossy(&output.stdout)
        .split_whitespace()
        .map(str::to_string)
        .collect();
    Some((seconds, fields))
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Numbers printed by two implementations agree (floats to 1e-12 relative).
fn same_numbers(left: &[String], right: &[String]) -> bool {
    left.len() == right.len()
        && left
            .iter()
            .zip(right)
            .all(|(a, b)| match (a.parse::<f64>(), b.parse::<f64>()) {
                (Ok(x), Ok(y)) => x == y || ((x - y).abs() <= 1e-12 * x.abs().max(y.abs())),
                _ => a == b,
            })
}

fn main() {
    let runs: usize = std::env::var("GLOC_BENCH_RUNS")
        .ok()
        .and_then(|value| value.parse().ok())
        .unwrap_or(5)
        .max(1);
    let natives: [(&str, NativeRun); 3] = [
        ("arith", || {
            let (acc, x) = native::arith(black_box(3_000_000));
            vec![acc.to_string(), format!("{x:?}")]
        }),
        ("bins", || {
            let (acc, mean) = native::bins(black_box(2000));
            vec![acc.to_string(), format!("{mean:?}")]
        }),
        ("states", || {
            let (state, visits, turns) = native::states(black_box(2_000_000));
            vec![state.to_string(), visits.to_string(), turns.to_string()]
        }),
    ];
    println!("interpreter benchmark, median of {runs} runs (execution only, CPU time)");
    println!(
        "{:<8} {:>11} {:>11} {:>11} {:>11} {:>9} {:>9} {:>10} {:>8}",
        "program",
        "gloc -O ms",
        "gloc ms",
        "lua ms",
        "native ms",
        "gloc/lua",
        "gloc/nat",
        "instr",
        "ns/instr"
    );
    let mut all_agree = true;
    for (name, native_run) in natives {
        let optimized = compile(name, true);
        let plain = compile(name, false);
        let mut optimized_times = Vec::new();
        let mut plain_times = Vec::new();
        let mut lua_times = Vec::new();
        let mut native_times = Vec::new();
        let (mut instructions, mut gloc_lines, mut lua_fields, mut native_fields) =
            (0, Vec::new(), Vec::new(), Vec::new());
        for _ in 0..runs {
            let (seconds, count, lines) = run_gloc(&optimized);
            optimized_times.push(seconds);
            instructions = count;
            gloc_lines = lines;
            plain_times.push(run_gloc(&plain).0);
            if let Some((seconds, fields)) = run_lua(name) {
                lua_times.push(seconds);
                lua_fields = fields;
            }
            let start = thread_cpu_seconds();
            native_fields = native_run();
            native_times.push(thread_cpu_seconds() - start);
        }
        let gloc_fields: Vec<String> = gloc_lines
            .iter()
            .flat_map(|line| line.split_whitespace().map(str::to_string))
            .collect();
        let agree_native = same_numbers(&gloc_fields, &native_fields);
        let agree_lua = lua_times.is_empty() || same_numbers(&gloc_fields, &lua_fields);
        all_agree &= agree_native && agree_lua;
        let gloc = median(optimized_times);
        let native = median(native_times);
        let lua = (!lua_times.is_empty()).then(|| median(lua_times));
        println!(
            "{:<8} {:>11.2} {:>11.2} {:>11} {:>11.3} {:>9} {:>9.1} {:>10} {:>8.2}",
            name,
            gloc * 1e3,
            median(plain_times) * 1e3,
            lua.map_or("n/a".to_string(), |seconds| format!("{:.2}", seconds * 1e3)),
            native * 1e3,
            lua.map_or("n/a".to_string(), |seconds| format!(
                "{:.2}",
                gloc / seconds
            )),
            gloc / native,
            instructions,
            gloc * 1e9 / instructions as f64,
        );
        if !(agree_native && agree_lua) {
            println!("  results differ: gloc {gloc_fields:?} native {native_fields:?} lua {lua_fields:?}");
        }
    }
    if !all_agree {
        eprintln!("error: the implementations disagree on a result");
        std::process::exit(1);
    }
}
