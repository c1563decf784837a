//! `gloc forecast` on comet's real deployment: the surfacings printed, the
//! three output formats written, the hindcast table within its bound, and an
//! output that would overwrite an input refused (docs/forecast.md).

mod support;

use support::{gloc, real_file, temp_folder, text};

fn logs() -> Vec<String> {
    [
        "comet/from-glider/comet-2019-222-02-152.sbd",
        "comet/from-glider/comet-2019-222-02-153.sbd",
        "comet/from-glider/comet-2019-222-02-154.dbd",
    ]
    .iter()
    .map(|file| real_file(file))
    .collect()
}

fn forecast(extra: &[&str]) -> std::process::Output {
    let logs = logs();
    let mission = real_file("comet/missions/nsb3.mi");
    let cache = real_file("cac");
    let mut args: Vec<&str> = vec!["forecast"];
    args.extend(logs.iter().map(String::as_str));
    args.extend(["--sensor-cache", &cache, "--mission", &mission]);
    args.extend(extra);
    gloc(&args)
}

#[test]
fn a_forecast_prints_the_surfacings_and_writes_every_format() {
    let folder = temp_folder("forecast-formats");
    let paths: Vec<String> = ["f.geojson", "f.kml", "f.csv"]
        .iter()
        .map(|name| folder.join(name).display().to_string())
        .collect();
    let output = forecast(&[
        "--hours",
        "7",
        "--members",
        "8",
        "-o",
        &paths[0],
        "-o",
        &paths[1],
        "-o",
        &paths[2],
    ]);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    // comet's last fix, 16:42:48 UTC at 54°19.6355′ N 7°21.5827′ E (the .dbd's
    // last m_gps_lat/lon; `gloc data convert` shows the same row).
    assert!(
        stdout.contains("start    2019-08-21T16:42:48Z  5419.6355 721.5827"),
        "{stdout}"
    );
    // The 3-hour surfacing timer: two surfacings in 7 hours.
    assert_eq!(stdout.matches("m to the waypoint").count(), 2, "{stdout}");
    assert!(stdout.contains("ensemble 8 members"), "{stdout}");
    let geojson = std::fs::read_to_string(&paths[0]).expect("the GeoJSON");
    assert!(geojson.starts_with("{\"type\":\"FeatureCollection\""));
    let kml = std::fs::read_to_string(&paths[1]).expect("the KML");
    assert!(kml.contains("<kml xmlns=\"http://www.opengis.net/kml/2.2\">"));
    let csv = std::fs::read_to_string(&paths[2]).expect("the CSV");
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows[0], "time,unix_time,lat,lon,lat_nmea,lon_nmea,depth_m");
    // A point a minute for 7 hours, and the start.
    assert_eq!(rows.len(), 1 + 7 * 60 + 1, "{}", rows.len());
}

#[test]
fn the_hindcast_of_comets_segments_reports_each_against_the_bound() {
    let map = temp_folder("forecast-hindcast").join("hindcast.png");
    let map = map.display().to_string();
    let output = forecast(&["--hindcast", "-o", &map]);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    // Both segments land within max(150 m, 0.015 m/s × time underwater), their
    // surfacings replayed as comet's logs account for them
    // (forecast/tests/comet.rs holds the figures).
    assert!(
        stdout.contains("2 of 2 segments within the bound"),
        "{stdout}"
    );
    let png = std::fs::read(&map).expect("the map");
    assert!(png.starts_with(b"\x89PNG"));
    // Set up where `gloc run` sets its flights up: the mission checked against the
    // sensor list (the embedded list lacks nsb3's u_sci_dbd_sensor_list_xmit_control).
    assert!(
        text(&output.stderr).contains("warning[S0106]"),
        "{}",
        text(&output.stderr)
    );
    // A hindcast writes maps only.
    let output = forecast(&["--hindcast", "-o", "/tmp/hindcast.geojson"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).contains("a hindcast writes a map"));
}

#[test]
fn an_output_that_is_an_input_is_refused() {
    let mission = real_file("comet/missions/nsb3.mi");
    let copy = temp_folder("forecast-refuse").join("nsb3.csv");
    std::fs::copy(&mission, &copy).expect("copy");
    let copy = copy.display().to_string();
    let output = forecast(&["--currents", &copy, "-o", &copy]);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output.stderr));
    assert!(text(&output.stderr).contains("is the input"));
    let output = forecast(&["-o", "/tmp/forecast.txt"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        text(&output.stderr).contains(".geojson (or .json), .kml or .csv, or a map .png or .svg")
    );
}

/// The horizon and the ensemble's size have limits (0 < hours ≤ 720, 1 to 100,000
/// members), said with the flag and what to give.
#[test]
fn a_horizon_or_an_ensemble_out_of_bounds_is_refused() {
    for (flag, value, message) in [
        (
            "--hours",
            "0",
            "--hours 0: give a horizon above 0 and up to 720 hours",
        ),
        (
            "--hours",
            "721",
            "--hours 721: give a horizon above 0 and up to 720 hours",
        ),
        ("--members", "0", "--members 0: give 1 to 100000 members"),
        (
            "--members",
            "100001",
            "--members 100001: give 1 to 100000 members",
        ),
    ] {
        let output = forecast(&[flag, value]);
        assert_eq!(output.status.code(), Some(2), "{flag} {value}");
        assert!(
            text(&output.stderr).contains(message),
            "{}",
            text(&output.stderr)
        );
    }
}

fn run_with(logs: &[&str], extra: &[&str]) -> std::process::Output {
    let mission = real_file("comet/missions/nsb3.mi");
    let cache = real_file("cac");
    let logs: Vec<String> = logs.iter().map(|file| real_file(file)).collect();
    let mut args: Vec<&str> = vec!["forecast"];
    args.extend(logs.iter().map(String::as_str));
    args.extend(["--sensor-cache", &cache, "--mission", &mission]);
    args.extend(extra);
    gloc(&args)
}

#[test]
fn what_the_glider_sends_home_is_enough() {
    // Only the short .sbd files of 152 and 153: the last fix is 152's last,
    // 1566394933.59 = 13:42:14 UTC (153's first cycle repeats it; `gloc data
    // convert` shows both rows).
    let output = run_with(
        &[
            "comet/from-glider/comet-2019-222-02-152.sbd",
            "comet/from-glider/comet-2019-222-02-153.sbd",
        ],
        &["--hours", "4"],
    );
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    assert!(
        stdout.contains("start    2019-08-21T13:42:14Z  5418.9931 724.3016"),
        "{stdout}"
    );
    // 153's m_water_vx/vy, as gloc data convert shows them: (0.37317303, −0.100204095).
    assert!(stdout.contains("(+0.373, -0.100)"), "{stdout}");
    // The first surfacing is due 3 hours after the surfacing began; comet's real
    // one (154) came at 16:39 UTC.
    assert!(stdout.contains("   1  2019-08-21T16:"), "{stdout}");
    assert!(stdout.contains("m to the waypoint"), "{stdout}");
}

#[test]
fn a_science_log_alone_and_currents_that_end_too_soon_are_refused() {
    let output = run_with(&["comet/from-glider/comet-2019-222-02-154.ebd"], &[]);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
    assert!(text(&output.stderr).contains("a forecast needs a flight log"));
    // A current series that ends an hour after comet's last fix (16:42:48 UTC).
    let folder = temp_folder("forecast-currents");
    let series = folder.join("tide.csv");
    std::fs::write(
        &series,
        "time,u,v\n2019-08-21T16:00:00Z,-0.1,0.15\n2019-08-21T17:42:00Z,0.0,0.2\n",
    )
    .expect("write");
    let series = series.display().to_string();
    let logs = ["comet/from-glider/comet-2019-222-02-154.dbd"];
    let output = run_with(&logs, &["--currents", &series, "--hours", "3"]);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains("the currents cover 2019-08-21T16:00:00Z to 2019-08-21T17:42:00Z; the track needs 2019-08-21T17:42:"),
        "{stderr}"
    );
    let output = run_with(&logs, &["--currents", &series, "--hours", "0.9"]);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    assert!(text(&output.stdout).contains("currents from"));
}

#[test]
fn a_missing_current_file_is_unreadable_and_a_damaged_one_is_an_error() {
    let logs = ["comet/from-glider/comet-2019-222-02-154.dbd"];
    let folder = temp_folder("forecast-nc");
    let missing = folder.join("nosuch.nc").display().to_string();
    let output = run_with(&logs, &["--currents", &missing]);
    assert_eq!(output.status.code(), Some(3), "{}", text(&output.stderr));
    assert!(text(&output.stderr).contains("cannot read the currents"));
    let damaged = folder.join("model.nc");
    std::fs::write(&damaged, b"\x89HDF\r\n\x1a\nnot classic").expect("write");
    let damaged = damaged.display().to_string();
    let output = run_with(&logs, &["--currents", &damaged]);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
    assert!(text(&output.stderr).contains("nccopy -k classic"));
    let output = run_with(&logs, &["--bathymetry", &damaged]);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
}
