//! `gloc run` against comet's real mission `nsb3.mi` (no hook behavior; line 12
//! sets `u_sci_dbd_sensor_list_xmit_control`, which the embedded list lacks): both
//! mission guards are warnings with file, line, column, code and a caret.

mod support;

use support::{gloc, real_file, repo, text};

fn run(args: &[&str]) -> (Option<i32>, String) {
    let output = gloc(args);
    (output.status.code(), text(&output.stderr))
}

#[test]
fn fig2_with_nsb3_warns_about_the_hook_and_the_unknown_sensor() {
    let nsb3 = real_file("comet/missions/nsb3.mi");
    let (code, stderr) = run(&["run", "--mission", &nsb3, "--cycles", "5"]);
    assert_eq!(code, Some(0), "{stderr}");
    let expected_setting = format!(
        "{nsb3}:12:9: warning[S0106]: sensor `u_sci_dbd_sensor_list_xmit_control` is not in the \
         sensor list; the setting is ignored\n   |\n12 | sensor: \
         u_sci_dbd_sensor_list_xmit_control(enum)  2 # or 1 to send header 1st segm\n   |         \
         ^^^^^^^^^^^^^^^^^^^^^^^^^^^^^^^^^^\n"
    );
    assert!(stderr.contains(&expected_setting), "{stderr}");
    let expected_hook = format!(
        "fig2.gloc:11:1: warning[S0107]: the script stores `sci_ruhp_behs`, but the mission \
         {nsb3} has no `behavior: hook`: nothing acts on it\n   |\n11 | stores r3,1387\n   | \
         ^^^^^^^^^^^^^^\n23 | stores r7,1387\n   | -------------- stored here too\n"
    );
    assert!(stderr.contains(&expected_hook), "{stderr}");
    // The paper's own mission has the hook: no S0107.
    let (_, stderr) = run(&["run", "--cycles", "5"]);
    assert!(!stderr.contains("S0107"), "{stderr}");
}

#[test]
fn a_gbasic_script_gets_the_warning_on_its_own_line() {
    let nsb3 = real_file("comet/missions/nsb3.mi");
    let fig3 = repo("examples/fig3.gbas");
    let (_, stderr) = run(&["run", &fig3, "--mission", &nsb3, "--cycles", "5"]);
    // `SCI_RUHP_BEHS = 128` is line 3 of Fig. 3, indented two spaces.
    assert!(
        stderr.contains(&format!("{fig3}:3:3: warning[S0107]")),
        "{stderr}"
    );
}

#[test]
fn a_batch_shows_the_same_warnings_once_for_the_sweep() {
    // `gloc batch` flies through the same preparation as `gloc run`: both guards, once
    // for three seeds (before, a sweep flew nsb3 without a word about either).
    let nsb3 = real_file("comet/missions/nsb3.mi");
    let (code, stderr) = run(&[
        "batch",
        "--mission",
        &nsb3,
        "--cycles",
        "5",
        "--seeds",
        "1-3",
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    assert_eq!(stderr.matches("warning[S0106]").count(), 1, "{stderr}");
    assert_eq!(stderr.matches("warning[S0107]").count(), 1, "{stderr}");
    assert!(
        stderr.contains(&format!(
            "{nsb3}:12:9: warning[S0106]: sensor `u_sci_dbd_sensor_list_xmit_control`"
        )),
        "{stderr}"
    );
}
