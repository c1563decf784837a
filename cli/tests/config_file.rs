//! `gloc.toml` as the CLI reads it: found upward from the script, filling what
//! the flags leave open, and a bad file reported with its line and column.

use std::path::PathBuf;

mod support;
use support::gloc;

/// A fresh project folder with `gloc.toml` and a `scripts/` folder below it.
fn project(name: &str, config: &str) -> PathBuf {
    let dir = gloc_testsupport::scratch_dir(&format!("config-{name}"));
    std::fs::create_dir_all(dir.join("scripts")).expect("temp dir");
    std::fs::write(dir.join("gloc.toml"), config).expect("write gloc.toml");
    dir
}

/// Stores to sensor 3 of whatever list is active, and loops once per cycle.
const STORE_3: &str =
    "nregs 1\nnblbs 1\nninstr 5\nlabel 0\nloadi 1,r0\nstores r0,3\nyield\njumpi 0\n";

#[test]
fn masterdata_from_gloc_toml_replaces_the_embedded_list() {
    // In the embedded list sensor 3 is `f_enable_picozoom` (a factory sensor:
    // a warning only); in this four-sensor list it is the read-only `m_depth`.
    let dir = project("masterdata", "masterdata = \"tiny.cac\"\n");
    std::fs::write(
        dir.join("tiny.cac"),
        "s: T 0 0 4 c_pitch rad\ns: T 1 1 4 u_cycle_time sec\ns: T 2 2 4 sci_water_temp degC\ns: T 3 3 4 m_depth m\n",
    )
    .expect("write .cac");
    let script = dir.join("scripts/store.gloc");
    std::fs::write(&script, STORE_3).expect("write script");
    let script = script.display().to_string();

    let output = gloc(&["check", &script]);
    let text = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{text}");
    assert!(text.contains("m_depth"), "{text}");
    assert!(text.contains(&format!("{script}:6:")), "{text}");

    // A flag wins over the file: the embedded list makes it a warning, not an error.
    let embedded = dir.join("embedded.cac");
    std::fs::write(&embedded, "s: T 0 0 4 c_pitch rad\ns: T 1 1 4 u_cycle_time sec\ns: T 2 2 4 sci_water_temp degC\ns: T 3 3 4 c_heading rad\n")
        .expect("write .cac");
    let output = gloc(&[
        "check",
        &script,
        "--masterdata",
        &embedded.display().to_string(),
    ]);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stdout)
    );
}

#[test]
fn a_bad_gloc_toml_names_its_line_and_column() {
    let dir = project("bad", "cycle_budget = 2000\nmasterdat = \"x.cac\"\n");
    let script = dir.join("scripts/store.gloc");
    std::fs::write(&script, STORE_3).expect("write script");
    let output = gloc(&["check", &script.display().to_string()]);
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert_ne!(output.status.code(), Some(0), "{text}");
    let expected = format!("{}:2:1", dir.join("gloc.toml").display());
    assert!(text.contains(&expected), "expected {expected} in: {text}");
}

/// Stores to sensor 0 of whatever list is active.
const STORE_0: &str =
    "nregs 1\nnblbs 1\nninstr 5\nlabel 0\nloadi 1,r0\nstores r0,0\nyield\njumpi 0\n";

#[test]
fn sensor_order_numbers_a_masterdata_file_in_file_or_sorted_order() {
    // tests/fixtures/sensors/edge.masterdata lists m_present_time first; sorted
    // by upper-cased name (firmware 2014+) c_pitch comes first (C < M < U < X).
    // So sensor 0 is read-only in file order and writable when sorted.
    let masterdata = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures/sensors/edge.masterdata")
        .display()
        .to_string();
    let dir = project("order", "");
    let script = dir.join("scripts/store0.gloc");
    std::fs::write(&script, STORE_0).expect("write script");
    let script = script.display().to_string();

    let file_order = gloc(&["check", &script, "--masterdata", &masterdata]);
    let text = String::from_utf8_lossy(&file_order.stdout);
    assert_eq!(file_order.status.code(), Some(1), "{text}");
    assert!(text.contains("`m_present_time` is read-only"), "{text}");

    let sorted = gloc(&[
        "check",
        &script,
        "--masterdata",
        &masterdata,
        "--sensor-order",
        "sorted",
    ]);
    let text = String::from_utf8_lossy(&sorted.stdout);
    assert_eq!(sorted.status.code(), Some(0), "{text}");

    // The same from gloc.toml, and a flag still wins over the file. gloc.toml names
    // files inside its folder only (issue 28), so the list is copied in.
    std::fs::copy(&masterdata, dir.join("edge.masterdata")).expect("copy the list");
    std::fs::write(
        dir.join("gloc.toml"),
        "masterdata = \"edge.masterdata\"\nsensor_order = \"sorted\"\n",
    )
    .expect("write gloc.toml");
    assert_eq!(gloc(&["check", &script]).status.code(), Some(0));
    let flag_wins = gloc(&["check", &script, "--sensor-order", "file"]);
    assert_eq!(flag_wins.status.code(), Some(1));

    // A wrong value names the two right ones.
    let wrong = gloc(&["check", &script, "--sensor-order", "abc"]);
    let text = String::from_utf8_lossy(&wrong.stderr);
    assert_eq!(wrong.status.code(), Some(2), "{text}");
    assert!(text.contains("`sorted`"), "{text}");
}
