//! Mission throughput through the real binary: `gloc run` compiles GBASIC with `-O`
//! unless `--no-optimize` says otherwise, and `gloc batch` flies a sweep whose every
//! row is what `gloc run` says of the same mission, whatever the number of threads.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

use gloc_compiler::{load_script, Language, LoadOptions, Optimization};
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn gloc(args: &[&str]) -> (bool, String, String) {
    let (code, stdout, stderr) = gloc_status(args);
    (code == Some(0), stdout, stderr)
}

/// As `gloc`, with the exit status (5: a mission aborted).
fn gloc_status(args: &[&str]) -> (Option<i32>, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_gloc"))
        .current_dir(root())
        .args(args)
        .output()
        .expect("gloc runs");
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

struct Quiet;

impl Host for Quiet {
    fn load_sensor(&mut self, _: SensorId) -> f64 {
        0.0
    }
    fn store_sensor(&mut self, _: SensorId, _: f64) {}
    fn print_line(&mut self, _: &str) {}
}

/// Instructions the script's second cycle executes (after its first `yield`), compiled
/// with or without the optimizer, counted by the library's machine.
fn instructions_per_cycle(text: &str, optimization: Optimization) -> u64 {
    let loaded = load_script(
        text,
        Language::Gbasic,
        &SensorList::embedded(),
        &LoadOptions {
            optimization,
            cycle_budget: Some(1_000_000),
        },
    );
    let program = loaded.program.expect("the script compiles");
    let mut machine = Machine::new(
        Arc::clone(&program),
        MachineConfig {
            cycle_budget: 1_000_000,
        },
    );
    assert_eq!(machine.run_cycle(&mut Quiet), CycleEnd::Yielded);
    assert_eq!(machine.run_cycle(&mut Quiet), CycleEnd::Yielded);
    machine.instructions_this_cycle()
}

#[test]
fn gloc_run_optimizes_gbasic_unless_told_not_to() {
    let text = "' Sums 1..200 in every cycle.\ndim i as integer\ndim s as integer\n\
                label: top\ns = 0\nfor i = 1 to 200\n  s = s + i * 2\nnext\nyield\ngoto top\n";
    let path = std::env::temp_dir().join(format!("gloc-sum-{}.gbas", std::process::id()));
    std::fs::write(&path, text).expect("write the script");
    let optimized = instructions_per_cycle(text, Optimization::Optimized);
    let plain = instructions_per_cycle(text, Optimization::Plain);
    assert!(optimized < plain, "{optimized} vs {plain}");
    // A budget between the two: only the unoptimized code overruns it.
    let budget = ((optimized + plain) / 2).to_string();
    let path_text = path.to_string_lossy().into_owned();
    let run = |extra: &[&str]| {
        let mut args = vec![
            "run",
            &path_text,
            "--cycles",
            "5",
            "--cycle-budget",
            &budget,
        ];
        args.extend(extra);
        let (ok, _, stderr) = gloc(&args);
        assert!(ok, "{stderr}");
        stderr
    };
    let default = run(&[]);
    assert!(
        default.contains("script        ran to the end"),
        "{default}"
    );
    let with_flag = run(&["-O"]);
    assert!(
        with_flag.contains("script        ran to the end"),
        "{with_flag}"
    );
    let unoptimized = run(&["--no-optimize"]);
    assert!(
        unoptimized.contains("TRAPPED") && unoptimized.contains("cycle overrun"),
        "{unoptimized}"
    );
    let (ok, _, stderr) = gloc(&["run", &path_text, "-O", "--no-optimize"]);
    assert!(!ok && stderr.contains("cannot be used with"), "{stderr}");
    let _ = std::fs::remove_file(&path);
}

/// `energy used   1385.7 kJ, 26.160 Ah` and `depth range   0.0 – 40.5 m` of a summary.
fn summary_facts(stderr: &str) -> (String, String, String) {
    let field = |label: &str| {
        stderr
            .lines()
            .find_map(|line| line.strip_prefix(label))
            .unwrap_or_else(|| panic!("no `{label}` in\n{stderr}"))
            .trim()
            .to_string()
    };
    let energy = field("energy used");
    let (kilojoules, amp_hours) = energy.split_once(" kJ, ").expect("kJ, Ah");
    let depth = field("depth range");
    let deepest = depth
        .split(" – ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .expect("deepest");
    (
        kilojoules.to_string(),
        amp_hours.trim_end_matches(" Ah").to_string(),
        deepest.to_string(),
    )
}

#[test]
fn a_batch_row_is_what_gloc_run_says_of_that_mission_on_any_number_of_threads() {
    let csv = |jobs: &str| {
        let path =
            std::env::temp_dir().join(format!("gloc-batch-{jobs}-{}.csv", std::process::id()));
        let path_text = path.to_string_lossy().into_owned();
        let (code, stdout, stderr) = gloc_status(&[
            "batch",
            "examples/thermocline.gbas",
            "--mission",
            "examples/thermocline.mi",
            "--duration",
            "3h",
            "--seeds",
            "1-2",
            "--sim",
            "hull_volume=71.547,71",
            "--fault-set",
            "none",
            "--fault-set",
            "m_depth:nan@100..140",
            "--jobs",
            jobs,
            "--csv",
            &path_text,
        ]);
        // 71 L is 0.55 L under comet's hull: with all 230 cc pumped the glider is still
        // 0.36 kg heavy (1024 kg/m³ × 71.23 L < 73.3 kg), cannot climb and sinks past
        // abend's 43 m: those missions abort, so the sweep exits 5.
        assert_eq!(code, Some(5), "{stderr}");
        assert!(stderr.contains("4 of 8 missions aborted"), "{stderr}");
        assert!(stderr.contains("8 missions in"), "{stderr}");
        assert_eq!(stdout.lines().count(), 9, "{stdout}");
        let text = std::fs::read_to_string(&path).expect("the CSV");
        let _ = std::fs::remove_file(&path);
        text
    };
    let rows = |text: &str| -> Vec<Vec<String>> {
        text.lines()
            .map(|line| {
                let mut cells: Vec<String> = line.split(',').map(str::to_string).collect();
                // The last column is the mission's own time: it differs run to run.
                cells.pop();
                cells
            })
            .collect()
    };
    let one = rows(&csv("1"));
    let two = rows(&csv("2"));
    assert_eq!(one, two, "the table depends on the number of threads");
    // The header: the columns the README names for the table, mission to charge (the
    // last, the mission's own seconds, cut as in every row).
    assert_eq!(
        one[0].join(","),
        "mission,seed,profile,faults,settings,cycles,end,script,printed,min_depth_m,max_depth_m,energy_kj,charge_ah"
    );
    // Seed fastest, then the setting, then the fault set. Every row against `gloc run`.
    let mut expected_missions = Vec::new();
    for fault in [None, Some("m_depth:nan@100..140")] {
        for volume in ["71.547", "71"] {
            for seed in ["1", "2"] {
                expected_missions.push((fault, volume, seed));
            }
        }
    }
    for (row, (fault, volume, seed)) in one[1..].iter().zip(expected_missions) {
        assert_eq!(row[1], seed);
        assert_eq!(row[3], fault.unwrap_or("none"));
        assert_eq!(row[4], format!("hull_volume={volume}"));
        let sim = format!("hull_volume={volume}");
        let mut args = vec![
            "run",
            "examples/thermocline.gbas",
            "--mission",
            "examples/thermocline.mi",
            "--duration",
            "3h",
            "--seed",
            seed,
            "--sim",
            &sim,
        ];
        if let Some(fault) = fault {
            args.extend(["--fault", fault]);
        }
        let (code, _, stderr) = gloc_status(&args);
        let aborted = row[6].starts_with("ABORTED");
        assert_eq!(code, Some(if aborted { 5 } else { 0 }), "{row:?}\n{stderr}");
        let (kilojoules, amp_hours, deepest) = summary_facts(&stderr);
        let cycles = stderr
            .lines()
            .find_map(|line| line.strip_prefix("cycles")?.split_whitespace().next())
            .expect("a cycles line");
        assert_eq!(row[5], cycles, "the cycles `gloc run` flies in 3 h");
        // Both print kJ with one decimal and Ah with three; the run prints the depth
        // with one decimal, the table with two.
        assert_eq!(row[11], kilojoules, "{row:?}\n{stderr}");
        assert_eq!(row[12], amp_hours, "{row:?}\n{stderr}");
        let number = |text: &str| text.parse::<f64>().expect("a number");
        assert!(
            (number(&row[10]) - number(&deepest)).abs() <= 0.051,
            "{row:?}\n{stderr}"
        );
    }
}

#[test]
fn a_bad_sweep_is_refused_before_anything_flies() {
    for (args, expected) in [
        (vec!["--seeds", "9-3"], "runs backwards"),
        (vec!["--sim", "drag_c0=0.2"], "did you mean `drag_cd0`"),
        (vec!["--fault-set", "m_dpeth:nan@3"], "m_dpeth"),
        (
            vec!["--profile", "no/such/profile.csv"],
            "no/such/profile.csv",
        ),
        // 60,000 seeds × 2 settings: more than a sweep may hold.
        (
            vec!["--seeds", "1-60000", "--sim", "drag_cd0=0.1,0.2"],
            "more than 100000 missions",
        ),
    ] {
        let mut all = vec!["batch", "examples/thermocline.gbas", "--cycles", "10"];
        all.extend(args);
        let (ok, stdout, stderr) = gloc(&all);
        assert!(!ok, "{all:?}");
        assert!(stdout.is_empty(), "{stdout}");
        assert!(stderr.contains(expected), "{all:?}: {stderr}");
    }
}

/// `gloc batch` keeps `gloc run`'s rules: a mission that could never finish is refused,
/// and the table never overwrites an input (here a copy of the script), which is left
/// byte for byte as it was.
#[test]
fn a_batch_keeps_the_run_limits_and_never_writes_over_an_input() {
    let (ok, _, stderr) = gloc(&[
        "batch",
        "examples/thermocline.gbas",
        "--cycles",
        "100000001",
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("--cycles 100000001 is more than 100000000"),
        "{stderr}"
    );
    // The cycle budget has gloc run's bound (10^9), from the same parser.
    let (ok, _, stderr) = gloc(&[
        "batch",
        "examples/thermocline.gbas",
        "--cycles",
        "5",
        "--cycle-budget",
        "1000000001",
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("the cycle budget must be 1 to 1000000000"),
        "{stderr}"
    );
    let folder = gloc_testsupport::scratch_dir("batch-csv");
    std::fs::create_dir_all(&folder).expect("a folder");
    let script = folder.join("tracker.gbas");
    let original = std::fs::read(root().join("examples/thermocline.gbas")).expect("example");
    std::fs::write(&script, &original).expect("copy");
    let script_arg = script.to_str().expect("a UTF-8 path");
    let (ok, stdout, stderr) = gloc(&["batch", script_arg, "--cycles", "5", "--csv", script_arg]);
    assert!(!ok, "{stdout}");
    assert!(stderr.contains("would destroy the input"), "{stderr}");
    assert_eq!(std::fs::read(&script).expect("still there"), original);
    std::fs::remove_dir_all(&folder).expect("clean up");
}
