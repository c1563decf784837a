//! The README's thermocline command, `gloc run examples/thermocline.gbas --mission
//! examples/thermocline.mi --duration 2h`, through the real binary from the
//! repository root, on the built-in profile and on the amadeus profile in
//! the repository's `data/`.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The bounds stored by the tracker in each logged cycle: `(dive, climb)`.
struct Flown {
    stderr: String,
    bounds: Vec<(f64, f64)>,
}

fn fly(name: &str, extra: &[&str]) -> Flown {
    let log = std::env::temp_dir().join(format!(
        "gloc-thermocline-{name}-{}.csv",
        std::process::id()
    ));
    let output = Command::new(env!("CARGO_BIN_EXE_gloc"))
        .current_dir(root())
        .args([
            "run",
            "examples/thermocline.gbas",
            "--mission",
            "examples/thermocline.mi",
            "--duration",
            "2h",
            "--log",
        ])
        .arg(&log)
        .args(extra)
        .output()
        .expect("gloc runs");
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(output.status.success(), "{stderr}");
    // 2 h of cycles of 4.51 s on average (u_cycle_time 4 s plus the default
    // 0.51 s overrun): 7200 / 4.51 = 1596.5, so 1597.
    assert!(stderr.contains("cycles        1597 ("), "{stderr}");
    assert!(
        stderr.contains("mission end   still running at the end of the requested time"),
        "{stderr}"
    );
    assert!(
        stderr.contains("script        ran to the end of the run"),
        "{stderr}"
    );
    let text = std::fs::read_to_string(&log).expect("log written");
    std::fs::remove_file(&log).ok();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let column = |name: &str| {
        header
            .iter()
            .position(|column| *column == name)
            .unwrap_or_else(|| panic!("no {name} column in {header:?}"))
    };
    let (dive, climb) = (
        column("sci_ruhp_dive_depth"),
        column("sci_ruhp_climb_depth"),
    );
    let bounds: Vec<(f64, f64)> = lines
        .map(|line| {
            let cells: Vec<&str> = line.split(',').collect();
            let number = |index: usize| -> f64 {
                cells[index]
                    .parse()
                    .unwrap_or_else(|_| panic!("not a number in {line}"))
            };
            (number(dive), number(climb))
        })
        .collect();
    assert_eq!(bounds.len(), 1597, "one log row per cycle");
    Flown { stderr, bounds }
}

/// Before the first leg ends the tracker has stored only the full-depth dive:
/// the mission's water depth is 44 m (`s_water_depth_avg`), more than MARGIN + 10,
/// so fulldepth = min(44 - 4, 45 - 1) = 40 m, and no climb depth yet (0).
fn assert_starts_with_the_full_depth_dive(flown: &Flown) {
    assert_eq!(flown.bounds[0], (40.0, 0.0), "{}", flown.stderr);
}

#[test]
fn the_tracker_finds_the_built_in_thermocline() {
    let flown = fly("built-in", &[]);
    assert_starts_with_the_full_depth_dive(&flown);
    // The built-in profile is T(z) = 9.5 + 13.5 · ½ · (1 − tanh((z − 16) / 4)), so
    // |dT/dz| = 1.6875 · sech²((z − 16) / 4). The first dive samples 0–40 m, where T
    // falls by about 13.5 °C, so the mean of the 1 m derivatives is about
    // 13.5 / 40 ≈ 0.34. sech²(u) > 0.34 / 1.6875 = 0.2 for |u| < acosh(√5) ≈ 1.44,
    // that is 10.2 m < z < 21.8 m; a derivative between bins i and i + 1 counts at
    // depth i + 1, so the bounds are 11 m (climb) and 21 m (dive). One metre either
    // way allows for the bins' sampling.
    let (dive, climb) = *flown.bounds.last().expect("rows");
    assert!((10.0..=12.0).contains(&climb), "climb depth {climb}");
    assert!((20.0..=22.0).contains(&dive), "dive depth {dive}");
    assert!(
        flown.stderr.contains("thermocline from"),
        "{}",
        flown.stderr
    );
}

#[test]
fn the_tracker_finds_the_amadeus_thermocline() {
    let profile = "data/amadeus_2014-07-24_temp_profile.csv";
    assert!(gloc_testsupport::data("amadeus_2014-07-24_temp_profile.csv").is_file());
    let flown = fly("amadeus", &["--profile", profile]);
    assert_starts_with_the_full_depth_dive(&flown);
    // From the CSV's 1 m means: the steps between neighbouring bins sum to about
    // 20.19 − 14.72 ≈ 5.5 °C over 40 m, a mean of about 0.14 °C/m. Steps above it:
    // 2.5→3.5 m (0.157, counted at 3 m), 5.5→9.5 m (0.41, 0.60, 0.32, 0.141) and
    // 9.5→13.5 m (0.16, 0.54, 1.84, 0.67, the last counted at 13 m); deeper steps are
    // under 0.05. So the bounds are 3 m (climb) and 13 m (dive), give or take one
    // metre for the 3 m step, which is close to the mean. The mean is over the bins
    // the glider has sampled: with bins to 36 m it is 0.157 °C/m, the 3 m step itself,
    // and with bins to 30 m only 0.188, which leaves the 3 m step out and puts the
    // climb bound at the next step above the mean, 6 m (the same 1 m means, by hand
    // and in a short script). Either is the algorithm's answer on this profile.
    let (dive, climb) = *flown.bounds.last().expect("rows");
    assert!(
        (2.0..=4.0).contains(&climb) || climb == 6.0,
        "climb depth {climb}"
    );
    assert!((12.0..=14.0).contains(&dive), "dive depth {dive}");
}
