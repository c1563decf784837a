//! The `gloc` binary as a user runs it: `gloc check` and `gloc run --replay`.
//! Expected outputs are written by hand from the fixtures.

use std::path::PathBuf;
use std::process::Output;

mod support;
use support::{gloc, repo};

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn temp(name: &str) -> PathBuf {
    let dir = gloc_testsupport::scratch_dir("cli");
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

#[test]
fn fig2_checks_clean_and_silently() {
    let output = gloc(&["check", &repo("examples/fig2.gloc")]);
    assert_eq!(output.status.code(), Some(0), "{}", stdout(&output));
    assert_eq!(stdout(&output), "");
}

#[test]
fn check_renders_rustc_style_and_fails() {
    let path = repo("tests/fixtures/gloc/err/register_out_of_range.gloc");
    let output = gloc(&["check", &path]);
    assert_eq!(output.status.code(), Some(1));
    let expected = format!(
        "{path}:5:9: error[E0101]: register r8 is out of range: `nregs 8` allows r0 to r7
  |
5 | loadi 1,r8
  |         ^^
1 | nregs 8
  |       - register count declared here
  = help: raise `nregs` to 9 or use a lower register
1 error, 0 warnings
"
    );
    assert_eq!(stdout(&output), expected);
}

#[test]
fn warnings_alone_exit_zero() {
    let path = repo("tests/fixtures/gloc/err/unreachable.gloc");
    let output = gloc(&["check", &path]);
    assert_eq!(output.status.code(), Some(0));
    assert!(stdout(&output).starts_with(&format!("{path}:7:1: warning[W0112]: ")));
}

#[test]
fn check_stats_reports_the_worst_case() {
    let output = gloc(&["check", "--stats", &repo("examples/fig2.gloc")]);
    assert_eq!(output.status.code(), Some(0));
    let text = stdout(&output);
    assert!(text.contains("  registers     8\n"), "{text}");
    assert!(text.contains("  labels        7\n"), "{text}");
    assert!(text.contains("  instructions  27 "), "{text}");
    assert!(
        text.contains("  worst case    16 instructions per cycle\n"),
        "{text}"
    );
}

#[test]
fn check_reads_a_cac_sensor_list() {
    // The 3-sensor list has no sensor 444: Fig. 2 fails on its loads.
    let output = gloc(&[
        "check",
        "--masterdata",
        &repo("tests/fixtures/sensors/small.cac"),
        &repo("examples/fig2.gloc"),
    ]);
    assert_eq!(output.status.code(), Some(1));
    let text = stdout(&output);
    assert!(
        text.contains(":5:7: error[E0107]: sensor 444 does not exist"),
        "{text}"
    );
    // A broken sensor list is reported with its own path and stops the check.
    let broken = repo("tests/fixtures/sensors/broken.masterdata");
    let output = gloc(&[
        "check",
        "--masterdata",
        &broken,
        &repo("examples/fig2.gloc"),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stdout(&output).starts_with(&format!("{broken}:1:16: error[E0201]: ")));
}

#[test]
fn unreadable_and_binary_files_do_not_panic() {
    // Exit code 3: an input cannot be read (README, "Exit codes").
    let output = gloc(&["check", "/no/such/file.gloc"]);
    assert_eq!(output.status.code(), Some(3));
    assert!(stdout(&output).contains("error: cannot read the script `/no/such/file.gloc`"));

    let binary = temp("garbage.gloc");
    std::fs::write(&binary, [0x7f, 0x00, 0xff, 0xfe, b'\n', 0x80, 0x81]).expect("write");
    let output = gloc(&["check", &binary.display().to_string()]);
    // Binary data (a NUL byte) is refused as the wrong kind of file, before parsing.
    assert_eq!(output.status.code(), Some(2));
    assert!(!stderr(&output).contains("panicked"));
    assert!(stdout(&output).contains("is binary data, not a script"));
    // Stray bytes in text (no NUL) are parsed, shown as U+FFFD.
    std::fs::write(&binary, [b'\n', 0x80, 0x81, b'\n']).expect("write");
    let output = gloc(&["check", &binary.display().to_string()]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stdout(&output).contains(":2:1: error[E0002]: unexpected character"));
}

/// A depth ramp 0 → 20 → 0 m in 1 m steps, one row per cycle.
fn ramp_csv() -> PathBuf {
    let mut text = String::from("m_depth\n");
    for depth in (0..=20).chain((0..20).rev()) {
        text.push_str(&format!("{depth}\n"));
    }
    let path = temp("ramp.csv");
    std::fs::write(&path, text).expect("write");
    path
}

#[test]
fn replay_of_a_depth_ramp_through_fig2() {
    let out = temp("ramp-out.csv");
    let output = gloc(&[
        "run",
        &repo("examples/fig2.gloc"),
        "--replay",
        &ramp_csv().display().to_string(),
        "--out",
        &out.display().to_string(),
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let written = std::fs::read_to_string(&out).expect("OUT written");
    let mut lines = written.lines();
    assert_eq!(lines.next(), Some("cycle,sci_ruhp_behs"));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 41);
    // Cycle 16 is the first with depth > 15 (16 m); cycle 36 the first
    // later one below 5 m (40 - 36 = 4 m). Every other row is empty.
    for (cycle, row) in rows.iter().enumerate() {
        let expected = match cycle {
            16 => "16,128".to_string(),
            36 => "36,0".to_string(),
            _ => format!("{cycle},"),
        };
        assert_eq!(*row, expected);
    }
    assert!(stderr(&output).contains("replayed 41 cycles"));
}

/// A simulator flag with --replay is refused by its own name.
#[test]
fn replay_refuses_each_simulator_length_flag_by_name() {
    let input = ramp_csv().display().to_string();
    for (flag, value) in [("--duration", "1h"), ("--cycles", "10")] {
        let output = gloc(&["run", "--replay", &input, flag, value]);
        assert_eq!(output.status.code(), Some(2), "{flag}: {}", stderr(&output));
        assert!(
            stderr(&output).contains(&format!(
                "{flag} belongs to the simulator and cannot be used with --replay"
            )),
            "{}",
            stderr(&output)
        );
    }
}

#[test]
fn replay_prints_as_it_goes_and_reports_traps() {
    let script = temp("print.gloc");
    std::fs::write(
        &script,
        "nregs 3\nnblbs 1\nninstr 8\nlabel 0\nloads 444,r0\nwrites \"depth\"\nprint r0\nloadi 10,r1\ndiv r1,r2,r2\nyield\njumpi 0\n",
    )
    .expect("write");
    let input = temp("two.csv");
    std::fs::write(&input, "\u{feff}cycle,M_DEPTH\n0,1.5\n1,\n").expect("write");
    let output = gloc(&[
        "run",
        &script.display().to_string(),
        "--replay",
        &input.display().to_string(),
    ]);
    // r2 is 0: the first cycle traps at `div` (pc 4, line 9) after printing.
    assert_eq!(stdout(&output), "depth 1.5\n");
    assert_eq!(output.status.code(), Some(1));
    let expected = format!(
        "{}:9:1: trap in cycle 0: integer division by zero (pc 4); the script stops, the replay goes on",
        script.display()
    );
    assert!(stderr(&output).contains(&expected), "{}", stderr(&output));
}

#[test]
fn replay_warns_about_unknown_columns_and_rejects_bad_cells() {
    // A column the active list lacks is one warning naming it (issue 14: real data
    // has many such sensors), and the replay goes on without it.
    let input = temp("bad-header.csv");
    std::fs::write(&input, "m_dpeth,m_depth\n1,2\n").expect("write");
    let output = gloc(&["run", "--replay", &input.display().to_string()]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let expected = format!(
        "{}: warning: 1 recorded sensor is not in the active sensor list (813b137d) and is \
         ignored: `m_dpeth` (did you mean `m_depth`?)\n",
        input.display()
    );
    assert!(stderr(&output).contains(&expected), "{}", stderr(&output));
    assert!(stderr(&output).contains("replayed 1 cycle"));

    let input = temp("bad-cell.csv");
    std::fs::write(&input, "m_depth,m_pitch\n1,0.1\n2,abc\n").expect("write");
    let output = gloc(&["run", "--replay", &input.display().to_string()]);
    // The data has an error: exit code 1 (README, "Exit codes").
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains(":3:3: `abc` is not a number"),
        "{}",
        stderr(&output)
    );
}

#[test]
fn cycle_budget_traps_the_first_cycle_that_needs_more() {
    // Fig. 2 on the ramp, counted by hand from its listing: cycle 0 runs
    // `loads loadd cmpgt cbr yield` (5); later shallow cycles start at `jumpi 0`
    // (6); cycle 16 (16 m > 15) runs `jumpi 0`, the four-instruction test,
    // `loadi stores jumpi 1`, the four-instruction test at label 1 and `yield` (13).
    let ramp = ramp_csv().display().to_string();
    let fig2 = repo("examples/fig2.gloc");
    let run = |budget: &str, out: &str| {
        let out = temp(out);
        let output = gloc(&[
            "run",
            &fig2,
            "--replay",
            &ramp,
            "--out",
            &out.display().to_string(),
            "--cycle-budget",
            budget,
        ]);
        let written = std::fs::read_to_string(&out).unwrap_or_default();
        (output, written)
    };

    let (output, _) = run("5", "budget5.csv");
    assert_eq!(output.status.code(), Some(1));
    let text = stderr(&output);
    assert!(text.contains("trap in cycle 1:"), "{text}");
    assert!(text.contains("cycle overrun"), "{text}");

    // 6 fits every shallow cycle; cycle 16's 7th instruction is the store of 128,
    // so it traps just before it.
    let (output, written) = run("6", "budget6.csv");
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("trap in cycle 16:"),
        "{}",
        stderr(&output)
    );
    assert!(!written.contains(",128"), "{written}");

    // 12 is one short of cycle 16's 13: the store happened, the `yield` traps.
    let (output, written) = run("12", "budget12.csv");
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("trap in cycle 16:"),
        "{}",
        stderr(&output)
    );
    assert!(written.contains("\n16,128\n"), "{written}");

    let (output, written) = run("13", "budget13.csv");
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(written.contains("\n16,128\n"), "{written}");
}

/// The README's replay example on the shipped examples/depths.csv: a dive to 20 m in 2 m steps
/// and back. Worked by hand from Fig. 2: the first depth past 15 m is 16 m at cycle 8 (store
/// 128), the first one under 5 m on the way up is 4 m at cycle 18 (store 0); nothing else.
#[test]
fn readme_replay_example_on_the_shipped_depths() {
    let out = temp("readme-stored.csv");
    let output = gloc(&[
        "run",
        &repo("examples/fig2.gloc"),
        "--replay",
        &repo("examples/depths.csv"),
        "--out",
        out.to_str().expect("utf-8 path"),
        "--cycle-budget",
        "5000",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let stored = std::fs::read_to_string(&out).expect("stored.csv");
    let rows: Vec<&str> = stored.lines().filter(|line| !line.ends_with(',')).collect();
    assert_eq!(rows, ["cycle,sci_ruhp_behs", "8,128", "18,0"]);
    assert_eq!(stored.lines().count(), 1 + 21, "one row per replayed cycle");
}

#[test]
fn explain_prints_a_code_from_the_registry_in_any_case() {
    // The meaning is docs/diagnostics.md's row for E0104, written there by hand.
    let output = gloc(&["explain", "e0104"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(
        stdout(&output),
        "E0104 error (GLOC): jump or branch to a label that is never defined\n"
    );
    let output = gloc(&["explain", "S0107"]);
    assert!(
        stdout(&output).starts_with("S0107 warning (missions): the script stores `sci_ruhp_behs`"),
        "{}",
        stdout(&output)
    );
}

#[test]
fn explain_refuses_an_unknown_code_and_lists_all_without_one() {
    let output = gloc(&["explain", "E4242"]);
    assert_ne!(output.status.code(), Some(0));
    assert!(
        stderr(&output).contains("`E4242` is not a gloc diagnostic code"),
        "{}",
        stderr(&output)
    );
    let output = gloc(&["explain"]);
    assert_eq!(output.status.code(), Some(0));
    let listed = stdout(&output);
    // One line per registered code: E0001 first, the GLOC parse errors before the checks.
    assert!(
        listed.starts_with("E0001 error (GLOC): unknown instruction"),
        "{listed}"
    );
    assert!(listed.lines().count() >= 90, "{listed}");
    assert!(listed.contains("\nW2302 warning (GBASIC): "), "{listed}");
}
