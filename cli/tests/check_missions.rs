//! `gloc check` on a folder of missions, as a group's CI would run it: every problem
//! with its file, line and column, exit 1 only for errors. Fixtures in
//! `tests/fixtures/missions/check` (expected lines worked out by hand from the files).

mod support;

use std::path::PathBuf;

use support::{gloc_in, text};

fn folder() -> PathBuf {
    PathBuf::from(support::repo("tests/fixtures/missions/check"))
}

#[test]
fn a_folder_of_missions_reports_every_problem_and_fails_on_errors() {
    let output = gloc_in(
        &[
            "check",
            "missions/broken.mi",
            "missions/good.mi",
            "missions/typos.mi",
            "mafiles/surfac01.ma",
            "mafiles/yo10.ma",
        ],
        &folder(),
    );
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    let located: Vec<&str> = stdout
        .lines()
        .filter(|line| line.contains("]: "))
        .map(|line| line.split(": ").next().unwrap_or(""))
        .collect();
    // broken.mi line 5 (`b_arg:` after four spaces: column 5), typos.mi line 4
    // (`surfce` after `behavior: `: column 11) and line 7.
    assert_eq!(
        located,
        [
            "missions/broken.mi:5:5",
            "missions/typos.mi:4:11",
            "missions/typos.mi:7:5"
        ],
        "{stdout}"
    );
    assert!(stdout.contains("error[S0004]: cannot find mission argument file `yo12.ma`"));
    assert!(stdout.contains("help: did you mean `surface`?"), "{stdout}");
    assert!(
        stdout.contains("help: did you mean `d_target_depth`?"),
        "{stdout}"
    );
    assert!(stdout.ends_with("1 error, 2 warnings\n"), "{stdout}");
}

#[test]
fn warnings_alone_exit_0_and_clean_missions_print_nothing() {
    let output = gloc_in(&["check", "missions/typos.mi"], &folder());
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stdout));
    let output = gloc_in(
        &[
            "check",
            "missions/good.mi",
            "mafiles/yo10.ma",
            "mafiles/surfac01.ma",
        ],
        &folder(),
    );
    assert_eq!(output.status.code(), Some(0));
    assert_eq!(text(&output.stdout), "");
}

#[test]
fn a_masterdata_file_is_checked_and_its_behaviors_used() {
    // The release-layout fixture: one W0209 on its stray value, and with it active
    // the yo's d_targt_depth is suggested from the fixture's own section.
    let masterdata = support::repo("tests/fixtures/sensors/release-layout.masterdata");
    let output = gloc_in(&["check", &masterdata], &folder());
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    assert!(
        stdout.contains("release-layout.masterdata:12:35: warning[W0209]"),
        "{stdout}"
    );
    let output = gloc_in(
        &["check", "--masterdata", &masterdata, "missions/typos.mi"],
        &folder(),
    );
    let stdout = text(&output.stdout);
    assert!(
        stdout.contains("(not in the active masterdata)"),
        "{stdout}"
    );
    assert!(
        stdout.contains("help: did you mean `d_target_depth`?"),
        "{stdout}"
    );
}

#[test]
fn an_unreadable_mission_is_exit_3_and_garbage_is_an_error() {
    let output = gloc_in(&["check", "missions/nosuch.mi"], &folder());
    assert_eq!(output.status.code(), Some(3));
    assert!(
        text(&output.stdout).starts_with("error: cannot read mission file `missions/nosuch.mi`")
    );
    let temp = support::temp_folder("check-garbage");
    std::fs::write(temp.join("bin.mi"), b"\x00\x01\xff behavior: yo\n").expect("write");
    std::fs::write(temp.join("bin.ma"), b"\xff\xfe<start:b_arg>\x00\n").expect("write");
    let output = gloc_in(&["check", "bin.mi", "bin.ma"], &temp);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    assert!(stdout.contains("bin.mi:1:1: error[S0002]"), "{stdout}");
}

#[test]
fn mafiles_named_by_flag_or_gloc_toml_are_searched_first() {
    let temp = support::temp_folder("check-mafiles");
    std::fs::create_dir_all(temp.join("missions")).expect("mkdir");
    std::fs::create_dir_all(temp.join("shared")).expect("mkdir");
    std::fs::write(
        temp.join("missions/m.mi"),
        "behavior: surface\n  b_arg: args_from_file(enum) 10\n",
    )
    .expect("write");
    std::fs::write(
        temp.join("shared/surfac10.ma"),
        "behavior_name=surface\n<start:b_arg>\n  b_arg: gps_wait_time(sec) 300\n<end:b_arg>\n",
    )
    .expect("write");
    // Not in mafiles/ nor beside the mission: an error.
    let output = gloc_in(&["check", "missions/m.mi"], &temp);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stdout));
    // Named by the flag.
    let output = gloc_in(&["check", "--mafiles", "shared", "missions/m.mi"], &temp);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stdout));
    assert_eq!(text(&output.stdout), "");
    // Named by gloc.toml (relative to it).
    std::fs::write(temp.join("gloc.toml"), "mafiles = \"shared\"\n").expect("write");
    let output = gloc_in(&["check", "missions/m.mi"], &temp);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stdout));
}
