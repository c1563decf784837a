//! What a newcomer meets on a first run (issue 27): a closed pipe, the wrong kind of
//! file given as the script, an empty script, binary bytes in a message, and the
//! summary's wall time. Each test failed on the binary before the fix.

mod support;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

use support::{gloc, real_file, repo, temp_folder, text};

/// `gloc data info … | head -2`: the reader closes the pipe after two lines; gloc
/// ended with `failed printing to stdout: Broken pipe` and exit 101 (a panic).
#[test]
fn a_closed_pipe_ends_the_output_quietly() {
    let logs = [
        real_file("comet/from-glider/comet-2019-222-02-154.dbd"),
        real_file("comet/from-glider/comet-2019-222-02-154.ebd"),
    ];
    let mut child = Command::new(env!("CARGO_BIN_EXE_gloc"))
        .args(["data", "info", &logs[0], &logs[1], "--sensor-cache"])
        .arg(real_file("cac"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("gloc runs");
    let stdout = child.stdout.take().expect("stdout");
    let mut lines = BufReader::new(stdout).lines();
    for _ in 0..2 {
        lines.next().expect("a line").expect("text");
    }
    drop(lines); // `head` exits: the pipe closes.
    let output = child.wait_with_output().expect("gloc ends");
    let stderr = text(&output.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!stderr.contains("Broken pipe"), "{stderr}");
    assert_eq!(output.status.code(), Some(0), "{stderr}");
}

/// A glider log, a mission, a sensor list given as the script: one line saying
/// what the file is and which option takes it, exit 2 (usage), no diagnostics.
#[test]
fn the_wrong_kind_of_file_as_the_script_fails_fast_with_the_option_it_belongs_to() {
    let log = real_file("comet/from-glider/comet-2019-222-02-154.dbd");
    let mission = real_file("comet/missions/nsb3.mi");
    let list = real_file("cac/1f35be3b.cac");
    // (`gloc check` takes missions and sensor lists as files of their own: issue 24.)
    let cases: [(&[&str], &str); 4] = [
        (&["run", &log], "--replay"),
        (&["check", &log], "--replay"),
        (&["run", &mission], "--mission"),
        (&["run", &list], "--masterdata"),
    ];
    for (args, option) in cases {
        let output = gloc(args);
        let all = format!("{}{}", text(&output.stdout), text(&output.stderr));
        assert_eq!(output.status.code(), Some(2), "{args:?}: {all}");
        assert!(all.contains(option), "{args:?}: {all}");
        assert!(!all.contains("error["), "{args:?}: no diagnostics: {all}");
        assert!(all.lines().count() <= 2, "{args:?}: {all}");
    }
}

/// Binary data under a script's name (a `.dbd` renamed `.gloc`): refused as
/// binary, never parsed, its bytes never echoed.
#[test]
fn binary_data_as_a_script_is_refused_as_binary() {
    let folder = temp_folder("binary-script");
    let script = folder.join("log.gloc");
    std::fs::copy(
        real_file("comet/from-glider/comet-2019-222-02-154.dbd"),
        &script,
    )
    .expect("copy");
    let output = gloc(&["check", &script.display().to_string()]);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(2), "{stdout}");
    assert!(stdout.contains("binary"), "{stdout}");
    assert_eq!(stdout.lines().count(), 1, "{stdout}");
}

/// GLOC in a `.gbas`: the note first, then a few diagnostics and a count (27
/// errors came before the note).
#[test]
fn a_script_in_the_other_language_gets_the_note_first_and_few_errors() {
    let folder = temp_folder("other-language");
    let script = folder.join("fig2.gbas");
    std::fs::copy(repo("examples/fig2.gloc"), &script).expect("copy");
    let output = gloc(&["check", &script.display().to_string()]);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    let first = stdout.lines().next().unwrap_or("");
    assert!(
        first.contains("note: this looks like GLOC"),
        "the note comes first: {stdout}"
    );
    assert_eq!(stdout.matches("error[").count(), 3, "{stdout}");
    assert!(stdout.contains("… and 24 more problems"), "{stdout}");
}

/// An empty `.gbas` passed silently; an empty `.gloc` got a false "looks like
/// GBASIC" note.
#[test]
fn an_empty_script_is_warned_and_gets_no_false_note() {
    let folder = temp_folder("empty-script");
    let gbasic = folder.join("empty.gbas");
    let gloc_file = folder.join("empty.gloc");
    std::fs::write(&gbasic, "' nothing yet\n\n").expect("write");
    std::fs::write(&gloc_file, "").expect("write");
    let output = gloc(&["check", &gbasic.display().to_string()]);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("warning: the script is empty"), "{stdout}");
    let output = gloc(&["check", &gloc_file.display().to_string()]);
    let stdout = text(&output.stdout);
    assert!(stdout.contains("error[E0010]"), "{stdout}");
    assert!(!stdout.contains("looks like"), "{stdout}");
}

/// A control byte in an input (an escape sequence, as in binary garbage) is shown
/// as U+FFFD in a message that quotes it, never sent raw to the terminal (the
/// mission parser's "not a valid name" quoted it raw).
#[test]
fn messages_never_echo_control_bytes() {
    let folder = temp_folder("control-bytes");
    std::fs::create_dir_all(folder.join("missions")).expect("folder");
    let mission = folder.join("missions/escape.mi");
    std::fs::write(&mission, b"behavior: abend\nb_arg: ov\x1b[31mer(m) 3\n").expect("write");
    let output = gloc(&[
        "run",
        "--mission",
        &mission.display().to_string(),
        "--cycles",
        "2",
    ]);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("error[S0012]"), "{stderr}");
    assert!(!stderr.contains('\u{1b}'), "{stderr:?}");
    assert!(
        stderr.contains("`ov\u{FFFD}[31mer` is not a valid name"),
        "{stderr}"
    );
}

/// The embedded mission ends in about 134 cycles, a few milliseconds of wall time:
/// no million-fold speed-up from a clock that read 0.000 s.
#[test]
fn a_short_run_claims_no_speed_up() {
    let output = gloc(&["run"]);
    let stderr = text(&output.stderr);
    let wall = stderr
        .lines()
        .find(|line| line.starts_with("wall time"))
        .unwrap_or_else(|| panic!("a wall time line: {stderr}"));
    assert!(!wall.contains("0.000 s"), "{wall}");
    if wall.contains(" ms ") {
        assert!(wall.contains("too short to measure the speed-up"), "{wall}");
    } else {
        assert!(wall.contains("about "), "{wall}");
    }
}

/// The README's exit-code table for recordings: a glider log whose sensor list is in
/// no folder searched cannot be read (3), a replay CSV with a bad cell has errors (1),
/// a replay file that does not exist cannot be read (3). (Both were 2 before issue 28
/// gave the readers' errors their kind.)
#[test]
fn recordings_gloc_cannot_use_exit_as_the_readme_says() {
    let folder = temp_folder("recording-exit-codes");
    let log = folder.join("comet-2019-222-02-154.dbd");
    std::fs::copy(
        real_file("comet/from-glider/comet-2019-222-02-154.dbd"),
        &log,
    )
    .expect("copy");
    let fig2 = repo("examples/fig2.gloc");
    let output = Command::new(env!("CARGO_BIN_EXE_gloc"))
        .args(["run", &fig2, "--replay", &log.display().to_string()])
        .env("HOME", &folder)
        .env_remove("XDG_DATA_HOME")
        .output()
        .expect("gloc runs");
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains("sensor list 1f35be3b not found"),
        "{stderr}"
    );
    assert_eq!(output.status.code(), Some(3), "{stderr}");

    let csv = folder.join("bad.csv");
    std::fs::write(&csv, "m_depth\n1\nabc\n").expect("write");
    let output = gloc(&["run", &fig2, "--replay", &csv.display().to_string()]);
    let stderr = text(&output.stderr);
    assert!(stderr.contains("`abc` is not a number"), "{stderr}");
    assert_eq!(output.status.code(), Some(1), "{stderr}");

    let missing = folder.join("missing.csv");
    let output = gloc(&["run", &fig2, "--replay", &missing.display().to_string()]);
    assert_eq!(output.status.code(), Some(3), "{}", text(&output.stderr));
}
