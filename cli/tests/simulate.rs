//! `gloc run` in the simulator, through the real binary.

use std::path::PathBuf;
use std::process::{Command, Output};

fn gloc(args: &[&str], folder: &PathBuf) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gloc"))
        .args(args)
        .current_dir(folder)
        .output()
        .expect("gloc runs")
}

fn temp_folder(name: &str) -> PathBuf {
    let folder = std::env::temp_dir().join(format!("gloc-cli-sim-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&folder).expect("temp folder");
    folder
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn default_run_flies_fig2_and_writes_log_and_plot() {
    let folder = temp_folder("default");
    let output = gloc(&["run", "--log", "run.csv", "--plot", "run.svg"], &folder);
    let stderr = text(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("mission end   completed"), "{stderr}");
    assert!(stderr.contains("FIG2.MI with fig2.gloc"), "{stderr}");
    let log = std::fs::read_to_string(folder.join("run.csv")).expect("log written");
    let mut lines = log.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    assert_eq!(header[0], "m_present_time");
    let depth_column = header
        .iter()
        .position(|name| *name == "m_depth")
        .expect("m_depth");
    let deepest = lines
        .map(|line| {
            line.split(',')
                .nth(depth_column)
                .expect("cell")
                .parse::<f64>()
                .expect("number")
        })
        .fold(0.0, f64::max);
    // The yo's dives turn at 25 m plus about 1 m of overshoot.
    assert!((25.0..27.0).contains(&deepest), "deepest {deepest}");
    let svg = std::fs::read_to_string(folder.join("run.svg")).expect("plot written");
    assert!(svg.contains("sci_ruhp_behs=128") && svg.contains("sci_ruhp_behs=0"));
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn gbasic_fig3_flies_like_fig2() {
    let folder = temp_folder("gbas");
    let fig3 = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/fig3.gbas");
    let output = gloc(&["run", fig3, "--log", "run.dba"], &folder);
    let stderr = text(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("mission end   completed"), "{stderr}");
    let log = std::fs::read_to_string(folder.join("run.dba")).expect("log written");
    assert!(log.starts_with("dbd_label: DBD_ASC(dinkum_binary_data_ascii)file\n"));
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn malformed_mission_is_refused_with_line_and_column() {
    let folder = temp_folder("bad");
    std::fs::write(
        folder.join("bad.mi"),
        "behavior: abend\n  b_arg: overdepth(m) deep\n",
    )
    .expect("write");
    let output = gloc(&["run", "--mission", "bad.mi"], &folder);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("bad.mi:2:23: error[S0015]: `deep` is not a number"),
        "{stderr}"
    );
    assert!(stderr.contains("nothing was simulated"), "{stderr}");
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn bad_options_are_explained() {
    let folder = temp_folder("options");
    let output = gloc(&["run", "--duration", "6"], &folder);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        text(&output.stderr).contains("give the unit"),
        "{}",
        text(&output.stderr)
    );
    let output = gloc(&["run", "--log", "run.txt"], &folder);
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).contains("`.csv` or `.dba`"));
    let output = gloc(&["run", "--profile", "missing.csv"], &folder);
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).contains("missing.csv"));
    std::fs::write(folder.join("t.csv"), "depth_m,temp_degC\n0,20\n1,x\n").expect("write");
    let output = gloc(&["run", "--profile", "t.csv"], &folder);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        text(&output.stderr).contains("t.csv:3:3: error"),
        "{}",
        text(&output.stderr)
    );
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn duration_limits_an_endless_run() {
    let folder = temp_folder("duration");
    let mission = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/fig2.mi");
    let endless = std::fs::read_to_string(mission)
        .expect("fig2.mi")
        .replace(
            "num_half_cycles_to_do(nodim) 6",
            "num_half_cycles_to_do(nodim) -1",
        )
        .replace(
            "overtime(s)             7200",
            "overtime(s)               -1",
        );
    std::fs::write(folder.join("endless.mi"), endless).expect("write");
    let output = gloc(
        &[
            "run",
            "--mission",
            "endless.mi",
            "--duration",
            "2h",
            "--seed",
            "7",
        ],
        &folder,
    );
    let stderr = text(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    // 2 h of 4 s cycles.
    assert!(stderr.contains("cycles        1800 "), "{stderr}");
    assert!(
        stderr.contains("still running at the end of the requested time"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&folder);
}
