//! The CLI as one surface: exit codes by cause, the same in every subcommand; errors
//! caused by gloc.toml name it; a file in the other language gets a note; a misspelt
//! keyword gets a "did you mean". Each case here failed before the project layer.

mod support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use support::{repo, text};

fn gloc_in(folder: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gloc"))
        .args(args)
        .current_dir(folder)
        .output()
        .expect("gloc runs")
}

fn all(output: &Output) -> String {
    format!("{}{}", text(&output.stdout), text(&output.stderr))
}

fn folder(name: &str) -> PathBuf {
    let folder =
        std::env::temp_dir().join(format!("gloc-one-surface-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).expect("folder");
    folder
}

const SCRIPT: &str = "dim x as integer\nx = 1\nprint x\nyield\n";

#[test]
fn a_missing_input_is_exit_code_3_in_every_subcommand() {
    let here = folder("missing");
    for args in [
        &["check", "nosuch.gbas"][..],
        &["compile", "nosuch.gbas"],
        &["run", "nosuch.gbas", "--cycles", "1"],
        &["run", "nosuch.gbas", "--replay", "nosuch.csv"],
        &["batch", "nosuch.gbas", "--cycles", "1"],
    ] {
        let output = gloc_in(&here, args);
        assert_eq!(output.status.code(), Some(3), "{args:?}: {}", all(&output));
        assert!(
            all(&output).contains("cannot read the script `nosuch.gbas`"),
            "{args:?}: {}",
            all(&output)
        );
    }
    std::fs::write(here.join("good.gbas"), SCRIPT).expect("write");
    let output = gloc_in(&here, &["run", "good.gbas", "--replay", "nosuch.csv"]);
    assert_eq!(output.status.code(), Some(3), "{}", all(&output));
    assert!(all(&output).contains("cannot read the recording `nosuch.csv`"));
    // A bad argument is 2, a script with errors 1, in every subcommand alike.
    std::fs::write(here.join("bad.gbas"), "dim x as integer\nx = \n").expect("write");
    for args in [
        &["check", "bad.gbas"][..],
        &["compile", "bad.gbas", "-o", "out.gloc"],
        &["run", "bad.gbas", "--cycles", "1"],
    ] {
        assert_eq!(gloc_in(&here, args).status.code(), Some(1), "{args:?}");
    }
    for args in [
        &["check", "bad.gbas", "--cycle-budget", "0"][..],
        &["run", "bad.gbas", "--cycle-budget", "0"],
        &["batch", "bad.gbas", "--cycle-budget", "0"],
    ] {
        let output = gloc_in(&here, args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(
            all(&output).contains(
                "--cycle-budget: the cycle budget must be 1 to 1000000000 instructions per cycle, not 0"
            ),
            "{args:?}: {}",
            all(&output)
        );
    }
    let _ = std::fs::remove_dir_all(&here);
}

#[test]
fn a_zero_budget_in_gloc_toml_is_refused_by_the_replay_too() {
    let here = folder("replay-budget");
    std::fs::write(here.join("gloc.toml"), "cycle_budget = 0\n").expect("write");
    std::fs::write(here.join("a.gbas"), SCRIPT).expect("write");
    std::fs::write(here.join("rec.csv"), "m_depth\n1\n2\n").expect("write");
    for args in [
        &["check", "a.gbas"][..],
        &["run", "a.gbas", "--cycles", "1"],
        &["run", "a.gbas", "--replay", "rec.csv"],
        &["compile", "a.gbas", "-o", "a.gloc"],
    ] {
        let output = gloc_in(&here, args);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", all(&output));
        // `cycle_budget = ` is 15 characters: the value is at 1:16.
        assert!(
            all(&output).contains("gloc.toml:1:16: invalid gloc.toml `cycle_budget`: the cycle budget must be 1 to 1000000000 instructions per cycle, not 0"),
            "{args:?}: {}",
            all(&output)
        );
    }
    let _ = std::fs::remove_dir_all(&here);
}

#[test]
fn a_budget_in_gloc_toml_is_held_against_the_script_by_check_as_by_run() {
    // fig2.gloc runs at most 16 instructions per cycle (counted by hand in
    // tests/consistency.rs), more than a budget of 10.
    let here = folder("budget-10");
    std::fs::write(here.join("gloc.toml"), "cycle_budget = 10\n").expect("write");
    std::fs::copy(repo("examples/fig2.gloc"), here.join("fig2.gloc")).expect("copy");
    for args in [
        &["check", "fig2.gloc"][..],
        &["run", "fig2.gloc", "--cycles", "1"],
    ] {
        let output = gloc_in(&here, args);
        assert!(
            all(&output).contains(
                "fig2.gloc:1:1: warning[W2302]: a control cycle may execute 16 instructions, more than the budget of 10"
            ),
            "{args:?}: {}",
            all(&output)
        );
    }
    let _ = std::fs::remove_dir_all(&here);
}

#[test]
fn a_relative_script_in_a_subfolder_finds_the_gloc_toml_above_it() {
    // `cd project/sub && gloc check fig2.gloc` with project/gloc.toml: the search for
    // gloc.toml started at `` (the relative path's parent) and never went above `sub`.
    let here = folder("relative-subfolder");
    let sub = here.join("sub");
    std::fs::create_dir_all(&sub).expect("mkdir");
    std::fs::write(here.join("gloc.toml"), "cycle_budget = 10\n").expect("write");
    std::fs::copy(repo("examples/fig2.gloc"), sub.join("fig2.gloc")).expect("copy");
    let printed = all(&gloc_in(&sub, &["check", "fig2.gloc"]));
    assert!(
        printed.contains("fig2.gloc:1:1: warning[W2302]: a control cycle may execute 16 instructions, more than the budget of 10"),
        "{printed}"
    );
    let _ = std::fs::remove_dir_all(&here);
}

#[test]
fn check_applies_each_files_own_gloc_toml() {
    // b/ has no gloc.toml (the default budget, 10,000), a/ a budget of 10: named b first,
    // check applied b's settings to a's file too (one resolve for all files).
    let here = folder("two-projects");
    for name in ["a", "b"] {
        std::fs::create_dir_all(here.join(name)).expect("mkdir");
        std::fs::copy(
            repo("examples/fig2.gloc"),
            here.join(name).join("fig2.gloc"),
        )
        .expect("copy");
    }
    std::fs::write(here.join("a/gloc.toml"), "cycle_budget = 10\n").expect("write");
    let output = gloc_in(&here, &["check", "b/fig2.gloc", "a/fig2.gloc"]);
    let printed = all(&output);
    assert!(
        printed.contains(
            "a/fig2.gloc:1:1: warning[W2302]: a control cycle may execute 16 instructions, more than the budget of 10"
        ),
        "{printed}"
    );
    assert!(
        !printed.contains("b/fig2.gloc:1:1: warning[W2302]"),
        "{printed}"
    );
    let _ = std::fs::remove_dir_all(&here);
}

#[test]
fn files_named_in_gloc_toml_that_cannot_be_read_name_gloc_toml_and_its_line() {
    let here = folder("named");
    std::fs::write(here.join("a.gbas"), SCRIPT).expect("write");
    // `masterdata = ` is 13 characters and `mission = ` 10, on line 2 after a comment.
    std::fs::write(
        here.join("gloc.toml"),
        "# project\nmasterdata = \"nosuch.mi\"\n",
    )
    .expect("write");
    let output = gloc_in(&here, &["check", "a.gbas"]);
    assert_eq!(output.status.code(), Some(3));
    assert!(
        all(&output).contains("gloc.toml:2:14: cannot read the sensor list `nosuch.mi`: "),
        "{}",
        all(&output)
    );
    std::fs::write(
        here.join("gloc.toml"),
        "# project\nmission = \"nosuch.mi\"\n",
    )
    .expect("write");
    let output = gloc_in(&here, &["run", "a.gbas", "--cycles", "1"]);
    assert_eq!(output.status.code(), Some(3));
    let said = all(&output);
    assert!(
        said.contains("gloc.toml:2:11: cannot read the mission `nosuch.mi`: "),
        "{said}"
    );
    assert!(
        !said.contains("nosuch.mi:1:1"),
        "no empty source line: {said}"
    );
    let _ = std::fs::remove_dir_all(&here);
}

#[test]
fn a_file_in_the_other_language_gets_a_note() {
    let output = gloc_in(
        &std::env::temp_dir(),
        &[
            "compile",
            &repo("examples/fig2.gloc"),
            "-o",
            &std::env::temp_dir()
                .join(format!("gloc-one-surface-{}.gloc", std::process::id()))
                .display()
                .to_string(),
        ],
    );
    assert_eq!(output.status.code(), Some(1));
    assert!(
        all(&output).contains("note: this looks like GLOC, but it was read as GBASIC"),
        "{}",
        all(&output)
    );
    let here = folder("txt");
    std::fs::write(here.join("script.txt"), SCRIPT).expect("write");
    let output = gloc_in(&here, &["check", "script.txt"]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        all(&output).contains("script.txt: note: this looks like GBASIC, but it was read as GLOC"),
        "{}",
        all(&output)
    );
    // A GBASIC file with an ordinary mistake gets no such note.
    std::fs::write(here.join("bad.gbas"), "dim x as integer\nx = \n").expect("write");
    assert!(!all(&gloc_in(&here, &["check", "bad.gbas"])).contains("looks like"));
    let _ = std::fs::remove_dir_all(&here);
}

#[test]
fn a_misspelt_keyword_gets_did_you_mean_in_both_languages() {
    let here = folder("yeild");
    std::fs::write(here.join("a.gbas"), "dim x as integer\nx = 1\nyeild\n").expect("write");
    let said = all(&gloc_in(&here, &["check", "a.gbas"]));
    assert!(said.contains("a.gbas:3:6: error[E2001]"), "{said}");
    assert!(said.contains("did you mean `yield`?"), "{said}");
    std::fs::write(
        here.join("a.gloc"),
        "nregs 1\nnblbs 1\nninstr 3\nlabel 0\nyeild\njumpi 0\n",
    )
    .expect("write");
    let said = all(&gloc_in(&here, &["check", "a.gloc"]));
    assert!(
        said.contains("a.gloc:5:1: error[E0001]: unknown instruction `yeild`"),
        "{said}"
    );
    assert!(said.contains("did you mean `yield`?"), "{said}");
    let _ = std::fs::remove_dir_all(&here);
}
