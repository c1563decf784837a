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
fn the_hindcast_of_comets_segments_is_within_the_bound() {
    let output = forecast(&["--hindcast"]);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    assert!(
        stdout.contains("2 of 2 segments within the bound"),
        "{stdout}"
    );
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
