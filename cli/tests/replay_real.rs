//! `gloc run --replay` on real glider logs: comet's `comet-2019-222-02-154.dbd` with
//! its science log `.ebd` (data/comet/from-glider), their sensor lists in
//! data/cac. Expected figures come from elsewhere:
//! - 2,244 cycles: dbdreader 0.6.3 gives 2,244 `m_present_time` values for the
//!   `.dbd` with `skip_initial_line=False` (2,243 by default, which drops the first);
//! - 889 ignored sensors: the names of `1f35be3b.cac` and `537a6a61.cac` (2,142 in
//!   all) that `engine/data/sensors-2008.txt` lacks, counted with a Python one-liner;
//! - the thermocline: the same algorithm by hand over the whole file (dbdreader's
//!   `sci_water_temp` in 1 m bins of `sci_water_pressure` × 10) puts |dT/dz| above
//!   its mean between the bins of 0 and 10 m (18.44 °C at the top, 18.00 °C at 10 m,
//!   17.97 °C at 13 m); with the tracker's MINGRAD only the 3 m derivative passes.

mod support;

use support::{gloc, real_file, repo};

fn comet(extension: &str) -> String {
    real_file(&format!(
        "comet/from-glider/comet-2019-222-02-154.{extension}"
    ))
}

#[test]
fn the_thermocline_tracker_replays_a_real_deployment_and_finds_the_thermocline() {
    let cache = real_file("cac");
    let output = gloc(&[
        "run",
        &repo("examples/thermocline.gbas"),
        "--replay",
        &comet("dbd"),
        &comet("ebd"),
        "--sensor-cache",
        &cache,
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(stderr.contains("replayed 2244 cycles"), "{stderr}");
    // One line for the sensors the embedded list lacks, not an error each.
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|line| line.contains("warning"))
        .collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    assert!(
        warnings[0].contains("889 recorded sensors are not in the active sensor list (813b137d)"),
        "{stderr}"
    );
    assert!(warnings[0].ends_with("and 869 more"), "{stderr}");
    let bounds: Vec<(f64, f64)> = stdout
        .lines()
        .filter_map(|line| {
            let rest = line.strip_prefix("thermocline from ")?.strip_suffix(" m")?;
            let (upper, lower) = rest.split_once(" to ")?;
            Some((upper.parse().ok()?, lower.parse().ok()?))
        })
        .collect();
    assert!(bounds.len() >= 5, "{stdout}");
    // Worked out with dbdreader 0.6.3 (tests/e2e/.venv) from the same two files: each
    // depth sample with the latest temperature at or before it, in 1 m bins, dT/dz
    // between neighbouring bins over their mean depths. Over the whole recording the
    // mean |dT/dz| is 0.013 degC/m and the only derivative above it that also passes
    // the tracker's MINGRAD (0.1) is 0.148 degC/m at 3 m: upper = lower = 3, widened
    // to 3..5 m. So the last leg reports 3 to 5 m, and every leg's upper bound lies
    // in the well-mixed upper water (2 to 4 m; 2 is the tracker's SHALLOWEST, used when
    // no derivative passes, with the full range below).
    assert_eq!(bounds.last(), Some(&(3.0, 5.0)), "{bounds:?}");
    assert!(
        bounds.iter().all(|(upper, _)| (2.0..=4.0).contains(upper)),
        "{bounds:?}"
    );
}

#[test]
fn a_missing_sensor_list_names_the_crc_and_the_folders() {
    let output = gloc(&["run", "--replay", &comet("dbd")]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    // An input that cannot be read: exit code 3 (README, "Exit codes").
    assert_eq!(output.status.code(), Some(3), "{stderr}");
    assert!(stderr.contains("1f35be3b"), "{stderr}");
    assert!(stderr.contains("from-glider"), "{stderr}");
}

#[test]
fn a_real_list_without_the_hook_sensors_still_runs_the_thermocline_tracker() {
    // Comet's own list as the active list: the hook sensors are appended (issue 14
    // saw E2101 here), and the data's sensors all map by name.
    let cache = real_file("cac");
    let output = gloc(&[
        "run",
        &repo("examples/thermocline.gbas"),
        "--masterdata",
        &real_file("cac/1f35be3b.cac"),
        "--replay",
        &comet("dbd"),
        &comet("ebd"),
        "--sensor-cache",
        &cache,
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
    assert!(String::from_utf8_lossy(&output.stdout).contains("thermocline from"));
}
