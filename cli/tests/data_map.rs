//! `gloc data plot` draws a map below the depth plot when the logs have positions:
//! comet's 154, whose dead reckoning reached its waypoint and whose first fix
//! came 5 km from it (docs/data.md).

mod support;

use support::{gloc, real_file, temp_folder, text};

#[test]
fn a_log_with_positions_gets_a_map() {
    let folder = temp_folder("data-map");
    let out = folder.join("comet.svg");
    let output = gloc(&[
        "data",
        "plot",
        &real_file("comet/from-glider/comet-2019-222-02-154.dbd"),
        "--sensor-cache",
        &real_file("cac"),
        "-o",
        &out.display().to_string(),
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    let svg = std::fs::read_to_string(&out).expect("the plot");
    assert!(
        svg.contains("logged position (m_lat, m_lon)"),
        "no map caption"
    );
    assert!(svg.contains("east (km)") && svg.contains("north (km)"));
    // A log without positions (the science log) has no map.
    let out = folder.join("science.svg");
    let output = gloc(&[
        "data",
        "plot",
        &real_file("comet/from-glider/comet-2019-222-02-154.ebd"),
        "--sensor-cache",
        &real_file("cac"),
        "-o",
        &out.display().to_string(),
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    let svg = std::fs::read_to_string(&out).expect("the plot");
    assert!(!svg.contains("east (km)"));
}
