//! `gloc run` in the simulator, through the real binary.

use std::path::PathBuf;

mod support;
use support::{gloc_in as gloc, temp_folder, text};

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
    // The yo's dives turn at 25 m plus up to a cycle's travel past the target,
    // the cycle the pump waits to turn (0.72 m each at 0.16 m/s and 4.5 s)
    // and comet's 1.62 m ± 10% of overshoot (the defaults): 26.5–28.9 m.
    assert!((26.5..28.9).contains(&deepest), "deepest {deepest}");
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
    assert!(text(&output.stderr).contains("`.csv`, `.dba` (Slocum ASCII) or `.dbd`"));
    // Exit code 3: an input cannot be read.
    let output = gloc(&["run", "--profile", "missing.csv"], &folder);
    assert_eq!(output.status.code(), Some(3));
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
    // 2 h of cycles of 4.51 s on average (u_cycle_time 4 s plus the default
    // 0.51 s overrun): 7200 / 4.51 = 1596.5, so 1597.
    assert!(stderr.contains("cycles        1597 "), "{stderr}");
    assert!(
        stderr.contains("still running at the end of the requested time"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&folder);
}

/// The first cycle whose logged `m_depth` is over 10 m, from a CSV log.
fn first_cycle_below_ten_metres(log: &std::path::Path) -> usize {
    let text = std::fs::read_to_string(log).expect("log written");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let column = header
        .iter()
        .position(|name| *name == "m_depth")
        .expect("m_depth logged");
    lines
        .position(|line| {
            line.split(',')
                .nth(column)
                .and_then(|cell| cell.parse::<f64>().ok())
                .is_some_and(|depth| depth > 10.0)
        })
        .expect("the glider passes 10 m")
}

#[test]
fn simulator_settings_from_flags_and_gloc_toml() {
    // At full dive volume and 26° the glider sinks at 0.160 m/s with comet's 71.547 L
    // hull and 0.279 m/s with a 71 L one (sim/tests/settings.rs): 10 m takes at least
    // 62 s and 36 s, the pump and pitch time being the same: 26 s is 5.8 cycles of
    // 4.5 s, so the heavier glider is there at least 4 cycles earlier. With all 230 cc
    // pumped out it is still 0.36 kg heavy (1024 kg/m³ × 71.23 L < 73.3 kg): it cannot
    // climb: it sinks on at about 0.045 m/s (0.2 m a cycle), from its turn at about 18 m
    // (cycle 20) to fig2's 30 m overdepth in some 60 cycles more, where abend aborts
    // it (exit 5): 100 cycles hold that with room.
    let folder = temp_folder("sim-settings");
    let run = |extra: &[&str], folder: &PathBuf, log: &str| {
        let mut args = vec!["run", "--cycles", "100", "--log", log];
        args.extend_from_slice(extra);
        let output = gloc(&args, folder);
        let heavy = extra.contains(&"hull_volume=71")
            || std::fs::read_to_string(folder.join("gloc.toml"))
                .is_ok_and(|file| file.contains("hull_volume = 71\n"))
                && !extra.contains(&"hull_volume=71.547");
        let expected = if heavy { Some(5) } else { Some(0) };
        assert_eq!(output.status.code(), expected, "{}", text(&output.stderr));
        first_cycle_below_ten_metres(&folder.join(log))
    };
    let slow = run(&[], &folder, "default.csv");
    let fast = run(&["--sim", "hull_volume=71"], &folder, "flag.csv");
    assert!(fast + 4 <= slow, "--sim: fast {fast}, slow {slow}");

    // The same from gloc.toml (found from the current folder for the embedded script),
    // and a flag still wins over the file.
    let project = temp_folder("sim-settings-toml");
    std::fs::write(project.join("gloc.toml"), "[simulator]\nhull_volume = 71\n").expect("write");
    assert_eq!(run(&[], &project, "file.csv"), fast);
    assert_eq!(
        run(&["--sim", "hull_volume=71.547"], &project, "both.csv"),
        slow
    );

    // Bad settings say what is wrong and what is allowed.
    let unknown = gloc(&["run", "--sim", "drag_c0=0.3"], &folder);
    assert_eq!(unknown.status.code(), Some(2));
    assert!(
        text(&unknown.stderr).contains("did you mean `drag_cd0`?"),
        "{}",
        text(&unknown.stderr)
    );
    let range = gloc(&["run", "--sim", "step=0"], &folder);
    assert_eq!(range.status.code(), Some(2));
    assert!(
        text(&range.stderr).contains("from 0.05 to 1.5 s"),
        "{}",
        text(&range.stderr)
    );
    let shape = gloc(&["run", "--sim", "drag_cd0"], &folder);
    assert!(
        text(&shape.stderr).contains("NAME=VALUE"),
        "{}",
        text(&shape.stderr)
    );
}

/// The last stderr line of `gloc run --summary json`, parsed.
fn json_summary(stderr: &str) -> serde_json::Value {
    let last = stderr.lines().last().unwrap_or_default();
    serde_json::from_str(last).unwrap_or_else(|error| panic!("not JSON ({error}): {last}"))
}

#[test]
fn summary_json_is_one_line_for_editors() {
    let folder = temp_folder("summary-json");
    // 40 cycles of Fig. 3: the default mission is still diving (it ends at the surface, hours
    // later) and the script never traps.
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/fig3.gbas"),
        folder.join("fig3.gbas"),
    )
    .expect("copy fig3");
    let output = gloc(
        &[
            "run",
            "fig3.gbas",
            "--cycles",
            "40",
            "--summary",
            "json",
            "--plot",
            "p.svg",
        ],
        &folder,
    );
    let stderr = text(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        !stderr.contains("mission end   "),
        "no text summary with --summary json: {stderr}"
    );
    let summary = json_summary(&stderr);
    assert_eq!(summary["cycles"], 40, "{summary}");
    assert_eq!(summary["script"], "fig3.gbas", "{summary}");
    assert_eq!(summary["completed"], false, "{summary}");
    assert_eq!(summary["trap_line"], serde_json::Value::Null, "{summary}");
    assert_eq!(summary["plot"], "p.svg", "{summary}");
    assert!(
        summary["mission_end"]
            .as_str()
            .unwrap_or_default()
            .starts_with("still running"),
        "{summary}"
    );

    // A division by zero on line 3 (counted by hand): the script traps there, the vehicle flies on.
    std::fs::write(
        folder.join("trap.gbas"),
        "dim x as integer\nx = 0\nx = 10 \\ x\nyield\n",
    )
    .expect("write trap.gbas");
    let output = gloc(
        &["run", "trap.gbas", "--cycles", "5", "--summary", "json"],
        &folder,
    );
    let stderr = text(&output.stderr);
    let summary = json_summary(&stderr);
    assert_eq!(summary["trap_line"], 3, "{summary}");
    assert!(
        summary["script_state"]
            .as_str()
            .unwrap_or_default()
            .starts_with("TRAPPED at trap.gbas:3:"),
        "{summary}"
    );

    let output = gloc(&["run", "trap.gbas", "--summary", "yaml"], &folder);
    assert_eq!(
        output.status.code(),
        Some(2),
        "an unknown format is refused"
    );
}
