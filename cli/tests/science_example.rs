//! The README's science example, run as the README says: in `examples/science`, whose
//! gloc.toml names the mission and the science computer's assumed figures. It broke
//! unseen once (its gloc.toml named `../thermocline.mi`, which a project file may no
//! longer name), so it is run here.

mod support;

use std::path::Path;

use support::{gloc_in, repo, text};

/// The `by consumer` line of a run's summary.
fn consumers(stderr: &str) -> String {
    stderr
        .lines()
        .find(|line| line.starts_with("by consumer"))
        .unwrap_or_else(|| panic!("a summary: {stderr}"))
        .to_string()
}

#[test]
fn the_science_example_runs_in_its_folder_and_waking_saves_energy() {
    let folder = repo("examples/science");
    let folder = Path::new(&folder);
    let always = gloc_in(&["run", "always-on.gbas", "--duration", "24h"], folder);
    let always_err = text(&always.stderr);
    assert_eq!(always.status.code(), Some(0), "{always_err}");
    // Always on: 1.5 W (gloc.toml's science_on_power) for the run's 86,395 s
    // (23 h 59 min 55 s of whole cycles) is 129.6 kJ, worked by hand; one wake.
    assert!(
        always_err.contains("simulated     23h 59m 55s"),
        "{always_err}"
    );
    assert!(
        consumers(&always_err).contains("science 129.6 kJ (1 wakes)"),
        "{always_err}"
    );
    let woken = gloc_in(&["run", "wake-on-event.gbas", "--duration", "24h"], folder);
    let woken_err = text(&woken.stderr);
    assert_eq!(woken.status.code(), Some(0), "{woken_err}");
    // Woken on events: many wakes, less science energy than always on.
    let line = consumers(&woken_err);
    let science: f64 = line
        .split("science ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|kj| kj.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!(science < 129.6, "{line}");
    assert!(!line.contains("(1 wakes)"), "{line}");
}
