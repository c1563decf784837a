//! `gloc run` with a script that traps or overruns mid-mission (hardening):
//! the run goes on to the mission's end, the log keeps every cycle, and the
//! summary says what happened and where.

use std::path::PathBuf;
use std::process::Command;

const FIG2: &str = include_str!("../../examples/fig2.gloc");

/// Fig. 2 with a counter (r8) of the passes through its loop heads (labels
/// 0, 1, 2: at least one per cycle) that runs `failure` at pass 150 (the
/// mission runs about 340 cycles). `failure` gets two free label numbers.
fn failing_script(failure: impl Fn(u32) -> Vec<String>) -> String {
    let mut body = Vec::new();
    let mut next_label = 7; // Fig. 2 uses labels 0-6.
    for line in FIG2.lines().skip(3) {
        body.push(line.to_string());
        if line == "label 0" || line == "label 1" || line == "label 2" {
            let (fail, go_on, spare) = (next_label, next_label + 1, next_label + 2);
            next_label += 4;
            body.extend([
                "loadi 1,r9".to_string(),
                "add r8,r9,r8".to_string(),
                "loadi 150,r9".to_string(),
                "cmpeq r8,r9,r10".to_string(),
                format!("cbr r10,{fail},{go_on}"),
                format!("label {fail}"),
            ]);
            body.extend(failure(spare));
            body.push(format!("label {go_on}"));
        }
    }
    format!(
        "nregs 11\nnblbs {next_label}\nninstr {}\n{}\n",
        body.len(),
        body.join("\n")
    )
}

fn scratch(name: &str) -> PathBuf {
    let folder = gloc_testsupport::scratch_dir("fault-summary");
    std::fs::create_dir_all(&folder).expect("a scratch folder");
    folder.join(name)
}

/// Runs `gloc run SCRIPT --log LOG`; returns (stderr, log rows, exit success).
fn gloc_run(name: &str, script: &str) -> (String, usize, bool) {
    let script_path = scratch(&format!("{name}.gloc"));
    let log_path = scratch(&format!("{name}.csv"));
    std::fs::write(&script_path, script).expect("write the script");
    let output = Command::new(env!("CARGO_BIN_EXE_gloc"))
        .arg("run")
        .arg(&script_path)
        .arg("--log")
        .arg(&log_path)
        .output()
        .expect("run gloc");
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{stderr}");
    let log = std::fs::read_to_string(&log_path).expect("the log was written");
    let rows = log.lines().count().saturating_sub(1);
    let _ = std::fs::remove_file(&script_path);
    let _ = std::fs::remove_file(&log_path);
    (stderr, rows, output.status.success())
}

/// The number after `cycles` in the summary.
fn summary_cycles(stderr: &str) -> usize {
    stderr
        .lines()
        .find_map(|line| line.strip_prefix("cycles"))
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|count| count.parse().ok())
        .unwrap_or_else(|| panic!("no cycle count in the summary:\n{stderr}"))
}

#[test]
fn a_trap_mid_mission_is_in_the_summary_and_the_log_goes_to_the_end() {
    let (stderr, rows, _) = gloc_run(
        "trap",
        &failing_script(|_| vec!["loadi 0,r9".to_string(), "div r9,r9,r9".to_string()]),
    );
    assert!(stderr.contains("TRAPPED at"), "{stderr}");
    assert!(stderr.contains("division by zero"), "{stderr}");
    assert!(stderr.contains("(the vehicle flew on)"), "{stderr}");
    assert!(
        stderr.contains("completed"),
        "the mission completed:\n{stderr}"
    );
    let cycles = summary_cycles(&stderr);
    assert!(cycles > 150, "the run went on after the trap: {cycles}");
    assert_eq!(rows, cycles, "one log row per cycle:\n{stderr}");
}

#[test]
fn an_overrun_mid_mission_is_in_the_summary_and_the_log_goes_to_the_end() {
    let (stderr, rows, _) = gloc_run(
        "overrun",
        &failing_script(|label| {
            vec![
                "loadi 1000000,r9".to_string(),
                "loadi 1,r10".to_string(),
                format!("label {label}"),
                "sub r9,r10,r9".to_string(),
                "cmpgt r9,r8,r7".to_string(),
                format!("cbr r7,{label},{}", label + 1),
                format!("label {}", label + 1),
            ]
        }),
    );
    assert!(stderr.contains("TRAPPED at"), "{stderr}");
    assert!(stderr.contains("overrun"), "{stderr}");
    assert!(
        stderr.contains("completed"),
        "the mission completed:\n{stderr}"
    );
    let cycles = summary_cycles(&stderr);
    assert!(cycles > 150, "the run went on after the overrun: {cycles}");
    assert_eq!(rows, cycles, "one log row per cycle:\n{stderr}");
}

/// Runs `gloc run` (the embedded mission and script) with these extra
/// arguments and a CSV log; returns (exit code, stderr, the log's text or "").
fn gloc_run_args(name: &str, extra: &[&str]) -> (Option<i32>, String, String) {
    let log_path = scratch(&format!("{name}.csv"));
    let _ = std::fs::remove_file(&log_path);
    let output = Command::new(env!("CARGO_BIN_EXE_gloc"))
        .arg("run")
        .arg("--log")
        .arg(&log_path)
        .args(extra)
        .output()
        .expect("run gloc");
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{stderr}");
    let log = std::fs::read_to_string(&log_path).unwrap_or_default();
    let _ = std::fs::remove_file(&log_path);
    (output.status.code(), stderr, log)
}

#[test]
fn a_nan_depth_fault_is_named_in_the_summary_and_the_mission_completes() {
    let (code, stderr, log) = gloc_run_args(
        "nan",
        &[
            "--fault",
            "m_depth:nan@20",
            "--fault",
            "m_depth:spike=5@100000..100001",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    // NaN compares false, so the Fig. 2 script never asks the hook for
    // anything; the yo flies by the vehicle's true depth, completes its six
    // half cycles, and surface (end_action 0) completes the mission.
    assert!(stderr.contains("mission end   completed"), "{stderr}");
    // The fault lasts from cycle 20 to the end: every cycle flown from 20
    // on, the last being cycle C − 1 of the C cycles the summary counts.
    let cycles = summary_cycles(&stderr);
    // Cycle 20 starts about 20 × 4.51 s (u_cycle_time 4 s plus the default
    // 0.51 s overrun) = 90 s in.
    let expected = format!(
        "fault         m_depth:nan@20: m_depth reads NaN in cycles 20–{} (1m 30s – ",
        cycles - 1
    );
    assert!(stderr.contains(&expected), "{expected}\n{stderr}");
    // The run (a few hundred cycles) ends long before cycle 100,000.
    assert!(
        stderr.contains(
            "fault         m_depth:spike=5@100000..100001: not injected (the run ended before cycle 100000)"
        ),
        "{stderr}"
    );
    // The log keeps every cycle, and shows what the script saw.
    let mut lines = log.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let at = header
        .iter()
        .position(|name| *name == "m_depth")
        .expect("m_depth is logged");
    let depths: Vec<String> = lines
        .map(|line| line.split(',').nth(at).expect("a cell").to_string())
        .collect();
    assert_eq!(depths.len(), cycles, "one log row per cycle");
    assert!(depths[..20].iter().all(|cell| cell != "NaN"), "{depths:?}");
    assert!(depths[20..].iter().all(|cell| cell == "NaN"), "{depths:?}");
}

#[test]
fn a_bad_fault_argument_is_a_command_line_error_with_the_right_form() {
    for (argument, problem) in [
        (
            "m_dpth:nan@20",
            "the sensor list has no sensor `m_dpth` (did you mean `m_depth`?)",
        ),
        ("m_depth:nan", "no `@` before the cycle the fault starts at"),
        ("m_depth:wobble@3", "unknown kind `wobble`"),
        ("m_depth:stuck@3", "`stuck` needs a value: `stuck=VALUE`"),
        (
            "m_depth:nan@30..10",
            "the end cycle (10, excluded) must come after the start (30)",
        ),
    ] {
        let (code, stderr, log) = gloc_run_args("bad", &["--fault", argument]);
        // Exit code 2: a bad command line, as for a bad --duration.
        assert_eq!(code, Some(2), "{argument}: {stderr}");
        let expected = format!(
            "error: --fault `{argument}` is not a fault: {problem}; write SENSOR:KIND@START[..END]"
        );
        assert!(stderr.contains(&expected), "{expected}\n{stderr}");
        assert!(stderr.contains("e.g. `m_depth:nan@20`"), "{stderr}");
        // Nothing was flown.
        assert!(!stderr.contains("mission end"), "{stderr}");
        assert!(log.is_empty(), "{argument}: a log was written");
    }
}
