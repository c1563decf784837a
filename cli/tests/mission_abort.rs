//! A mission that abend aborts has its own exit status, 5, in `gloc run` and in
//! `gloc batch` (README, "Exit codes"), so a script or CI can tell "the run
//! worked and the glider aborted" from success and from a failed run.

mod support;

use support::{gloc, repo, temp_folder};

/// A yo to 20 m under an abend that aborts below 8 m: MS_ABORT_OVERDEPTH on the first dive.
const ABORTING: &str = "behavior: abend\n  b_arg: overdepth(m) 8\n  b_arg: overdepth_sample_time(s) 4\n\
                        behavior: yo\n  b_arg: start_when(enum) 0\n  b_arg: num_half_cycles_to_do(nodim) -1\n  \
                        b_arg: d_target_depth(m) 20\n  b_arg: d_target_altitude(m) -1\n  b_arg: c_target_depth(m) 3\n  \
                        b_arg: c_target_altitude(m) -1\n  b_arg: end_action(enum) 2\n";

/// The same yo with nothing to abort it.
const FLYING: &str = "behavior: abend\n  b_arg: overdepth(m) 30\n\
                      behavior: yo\n  b_arg: start_when(enum) 0\n  b_arg: num_half_cycles_to_do(nodim) -1\n  \
                      b_arg: d_target_depth(m) 20\n  b_arg: d_target_altitude(m) -1\n  b_arg: c_target_depth(m) 3\n  \
                      b_arg: c_target_altitude(m) -1\n  b_arg: end_action(enum) 2\n";

#[test]
fn an_aborted_mission_exits_5_and_a_flying_one_0() {
    let folder = temp_folder("mission-abort");
    let aborting = folder.join("aborting.mi");
    let flying = folder.join("flying.mi");
    std::fs::write(&aborting, ABORTING).expect("mission");
    std::fs::write(&flying, FLYING).expect("mission");
    let script = repo("examples/fig2.gloc");
    let run = |mission: &std::path::Path| {
        gloc(&[
            "run",
            &script,
            "--mission",
            &mission.display().to_string(),
            "--duration",
            "1h",
        ])
    };
    let output = run(&aborting);
    // The summary (on stderr) says why.
    let summary = String::from_utf8_lossy(&output.stderr);
    assert!(summary.contains("MS_ABORT_OVERDEPTH"), "{summary}");
    assert_eq!(output.status.code(), Some(5), "{summary}");
    let output = run(&flying);
    assert_eq!(output.status.code(), Some(0));

    // batch: one seed of each mission would need two sweeps; one aborting sweep exits 5.
    let output = gloc(&[
        "batch",
        &script,
        "--mission",
        &aborting.display().to_string(),
        "--duration",
        "1h",
        "--seeds",
        "1-2",
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("2 of 2 missions aborted"), "{stderr}");
    assert_eq!(output.status.code(), Some(5));
    let output = gloc(&[
        "batch",
        &script,
        "--mission",
        &flying.display().to_string(),
        "--duration",
        "1h",
        "--seeds",
        "1-2",
    ]);
    assert_eq!(output.status.code(), Some(0));
}
