//! Interpreter benchmark suite: each program in `tests/perf/programs` run by the GLOC
//! engine (compiled from GBASIC, with and without `-O`; with `-O` also through the
//! reference `match` loop, `Dispatch::Loop`, beside the build's default dispatch), by
//! Lua 5.4 (`lua5.4`, Debian's package), by LuaJIT's interpreter (`luajit -joff`,
//! Debian's `luajit`) and as plain Rust, on the same work. Counts execution only:
//! compilation and the Lua processes' start are outside the timed region. All are
//! timed by CPU time: Lua and LuaJIT time themselves with `os.clock` (the process's
//! CPU time), GLOC and native Rust read the thread's CPU-time clock, so a loaded
//! machine (other processes taking turns on the cores) favours neither side; wall
//! time would count the turns of others. Prints medians over `GLOC_BENCH_RUNS` runs
//! (default 5), nanoseconds per loop iteration and the ratios; checks that all
//! implementations compute the same results. A program's `NAME.jit.lua`, when there
//! is one, is its LuaJIT version (Lua 5.1 has no `//`).
//!
//! For instruction counts: `GLOC_BENCH_ONLY=tight` runs one program, and
//! `GLOC_BENCH_PROFILE=loop` (or `threaded`) runs only its `-O` GLOC run with that
//! dispatch, once, so that `valgrind --tool=callgrind
//! --toggle-collect='*Machine*execute*'` counts exactly that run.

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

use gloc_compiler::{load_script, Language, LoadOptions, Optimization};
use gloc_engine::program::Program;
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{CycleEnd, Dispatch, Host, Machine, MachineConfig};

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

fn compile(name: &str, optimization: Optimization) -> Arc<Program> {
    let path = programs_dir().join(format!("{name}.gbas"));
    let text = std::fs::read_to_string(&path).expect("benchmark program is in the repo");
    let loaded = load_script(
        &text,
        Language::Gbasic,
        &SensorList::embedded(),
        &LoadOptions::from(optimization),
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
fn run_gloc(program: &Arc<Program>, dispatch: Dispatch) -> (f64, u64, Vec<String>) {
    let mut machine = Machine::new(
        program.clone(),
        MachineConfig {
            cycle_budget: u64::MAX,
        },
    );
    machine.set_dispatch(dispatch);
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

/// A Lua implementation: the command and its arguments before the script, and the
/// suffix of its own version of a program, if it has one (`.jit.lua`).
struct Lua {
    command: &'static [&'static str],
    dialect: Option<&'static str>,
}

const LUA54: Lua = Lua {
    command: &["lua5.4"],
    dialect: None,
};

/// LuaJIT with the JIT compiler off: its interpreter (hand-written assembly).
const LUAJIT_INTERPRETER: Lua = Lua {
    command: &["luajit", "-joff"],
    dialect: Some("jit.lua"),
};

/// Runs the Lua version; returns (seconds measured inside Lua, printed fields), or
/// `None` when the interpreter is not installed.
fn run_lua(lua: &Lua, name: &str) -> Option<(f64, Vec<String>)> {
    let mut script = programs_dir().join(format!("{name}.lua"));
    if let Some(dialect) = lua.dialect {
        let own = programs_dir().join(format!("{name}.{dialect}"));
        if own.exists() {
            script = own;
        }
    }
    let output = Command::new(lua.command[0])
        .args(&lua.command[1..])
        .arg(script)
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

/// One benchmark program: its name, the loop iterations it runs (all its loops'
/// bodies together, for nanoseconds per iteration) and its native version.
struct Bench {
    name: &'static str,
    iterations: u64,
    native: NativeRun,
}

/// Medians of one implementation's runs, or `None` when it is not installed.
fn median_of(times: Vec<f64>) -> Option<f64> {
    (!times.is_empty()).then(|| median(times))
}

fn ms(seconds: Option<f64>) -> String {
    seconds.map_or("n/a".to_string(), |seconds| format!("{:.2}", seconds * 1e3))
}

fn ratio(left: f64, right: Option<f64>) -> String {
    right.map_or("n/a".to_string(), |right| format!("{:.2}", left / right))
}

fn per_iteration(seconds: Option<f64>, iterations: u64) -> String {
    seconds.map_or("n/a".to_string(), |seconds| {
        format!("{:.1}", seconds * 1e9 / iterations as f64)
    })
}

fn main() {
    let runs: usize = std::env::var("GLOC_BENCH_RUNS")
        .ok()
        .and_then(|value| value.parse().ok())
        .unwrap_or(5)
        .max(1);
    let benches = [
        Bench {
            name: "arith",
            iterations: 3_000_000,
            native: || {
                let (acc, x) = native::arith(black_box(3_000_000));
                vec![acc.to_string(), format!("{x:?}")]
            },
        },
        Bench {
            name: "bins",
            // 2,000 repetitions of loops of 50 + 400 + 50 + 49 + 49 iterations.
            iterations: 2000 * 598,
            native: || {
                let (acc, mean) = native::bins(black_box(2000));
                vec![acc.to_string(), format!("{mean:?}")]
            },
        },
        Bench {
            name: "states",
            iterations: 2_000_000,
            native: || {
                let (state, visits, turns) = native::states(black_box(2_000_000));
                vec![state.to_string(), visits.to_string(), turns.to_string()]
            },
        },
        Bench {
            name: "tight",
            iterations: 5_000_000,
            native: || vec![native::tight(black_box(5_000_000)).to_string()],
        },
    ];
    let default = Dispatch::default();
    let only = std::env::var("GLOC_BENCH_ONLY").ok();
    let benches = benches
        .into_iter()
        .filter(|bench| only.as_deref().is_none_or(|only| only == bench.name));
    if let Ok(profile) = std::env::var("GLOC_BENCH_PROFILE") {
        let dispatch = match profile.as_str() {
            "loop" => Dispatch::Loop,
            "threaded" => Dispatch::Threaded,
            _ => {
                eprintln!("error: GLOC_BENCH_PROFILE is `loop` or `threaded`, not `{profile}`");
                std::process::exit(2);
            }
        };
        for bench in benches {
            let (seconds, instructions, _) =
                run_gloc(&compile(bench.name, Optimization::Optimized), dispatch);
            println!(
                "{} -O, {dispatch:?}: {instructions} GLOC instructions in {:.2} ms",
                bench.name,
                seconds * 1e3
            );
        }
        return;
    }
    println!(
        "interpreter benchmark, median of {runs} runs (execution only, CPU time); \
         gloc dispatch: {default:?}, `loop`: the reference match loop"
    );
    println!(
        "{:<8} {:>10} {:>10} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>8}",
        "program",
        "gloc -O ms",
        "loop -O ms",
        "gloc ms",
        "lua ms",
        "luajit ms",
        "native ms",
        "gloc/lua",
        "gloc/jit",
        "instr",
        "ns/instr"
    );
    let mut all_agree = true;
    let mut per_iteration_rows = Vec::new();
    for bench in benches {
        let name = bench.name;
        let optimized = compile(name, Optimization::Optimized);
        let plain = compile(name, Optimization::Plain);
        let (mut optimized_times, mut loop_times, mut plain_times) =
            (Vec::new(), Vec::new(), Vec::new());
        let (mut lua_times, mut luajit_times, mut native_times) =
            (Vec::new(), Vec::new(), Vec::new());
        let (mut instructions, mut gloc_lines, mut native_fields) = (0, Vec::new(), Vec::new());
        let (mut lua_fields, mut luajit_fields, mut loop_lines) =
            (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..runs {
            let (seconds, count, lines) = run_gloc(&optimized, default);
            optimized_times.push(seconds);
            instructions = count;
            gloc_lines = lines;
            let (seconds, _, lines) = run_gloc(&optimized, Dispatch::Loop);
            loop_times.push(seconds);
            loop_lines = lines;
            plain_times.push(run_gloc(&plain, default).0);
            if let Some((seconds, fields)) = run_lua(&LUA54, name) {
                lua_times.push(seconds);
                lua_fields = fields;
            }
            if let Some((seconds, fields)) = run_lua(&LUAJIT_INTERPRETER, name) {
                luajit_times.push(seconds);
                luajit_fields = fields;
            }
            let start = thread_cpu_seconds();
            native_fields = (bench.native)();
            native_times.push(thread_cpu_seconds() - start);
        }
        let gloc_fields: Vec<String> = gloc_lines
            .iter()
            .flat_map(|line| line.split_whitespace().map(str::to_string))
            .collect();
        let agree_native = same_numbers(&gloc_fields, &native_fields);
        let agree_loop = gloc_lines == loop_lines;
        let agree_lua = lua_times.is_empty() || same_numbers(&gloc_fields, &lua_fields);
        let agree_luajit = luajit_times.is_empty() || same_numbers(&gloc_fields, &luajit_fields);
        let agree = agree_native && agree_loop && agree_lua && agree_luajit;
        all_agree &= agree;
        let gloc = median(optimized_times);
        let lua = median_of(lua_times);
        let luajit = median_of(luajit_times);
        let native = median(native_times);
        let reference = median(loop_times);
        println!(
            "{:<8} {:>10.2} {:>10.2} {:>9.2} {:>9} {:>9} {:>9.3} {:>9} {:>9} {:>10} {:>8.2}",
            name,
            gloc * 1e3,
            reference * 1e3,
            median(plain_times) * 1e3,
            ms(lua),
            ms(luajit),
            native * 1e3,
            ratio(gloc, lua),
            ratio(gloc, luajit),
            instructions,
            gloc * 1e9 / instructions as f64,
        );
        if !agree {
            println!(
                "  results differ: gloc {gloc_fields:?} loop {loop_lines:?} native \
                 {native_fields:?} lua {lua_fields:?} luajit {luajit_fields:?}"
            );
        }
        per_iteration_rows.push(format!(
            "{:<8} {:>10} {:>10} {:>10} {:>9} {:>9} {:>9} {:>11.2}",
            name,
            bench.iterations,
            per_iteration(Some(gloc), bench.iterations),
            per_iteration(Some(reference), bench.iterations),
            per_iteration(lua, bench.iterations),
            per_iteration(luajit, bench.iterations),
            per_iteration(Some(native), bench.iterations),
            reference / gloc,
        ));
    }
    println!();
    println!("ns per loop iteration (the same medians)");
    println!(
        "{:<8} {:>10} {:>10} {:>10} {:>9} {:>9} {:>9} {:>11}",
        "program", "iterations", "gloc -O", "loop -O", "lua", "luajit", "native", "loop/gloc"
    );
    for row in per_iteration_rows {
        println!("{row}");
    }
    if !all_agree {
        eprintln!("error: the implementations disagree on a result");
        std::process::exit(1);
    }
}
