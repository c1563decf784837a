//! The checks no manufacturer tool makes, one fixture each: a mission and its `.ma`
//! files served from memory, and the warnings expected on hand-worked lines.

use std::collections::HashMap;
use std::path::Path;

use gloc_engine::sensors::SensorList;
use gloc_mission::Mission;

/// Loads `/m/missions/x.mi` with `files` (`"x.mi"`, `"yo10.ma"`, …) and returns every
/// diagnostic and check rendered `file:line:col: severity[code]: message`.
fn check(files: &[(&str, &str)]) -> Vec<String> {
    let served: HashMap<String, String> = files
        .iter()
        .map(|(name, text)| (name.to_string(), text.to_string()))
        .collect();
    let mission = Mission::load_with(Path::new("/m/missions/x.mi"), &mut |path: &Path| {
        let name = path
            .file_name()
            .map(|name| name.to_string_lossy().into_owned());
        served
            .get(&name.unwrap_or_default())
            .cloned()
            .ok_or_else(|| std::io::ErrorKind::NotFound.into())
    });
    let checks = mission.check(&SensorList::embedded());
    mission
        .diagnostics
        .iter()
        .chain(&checks)
        .map(|entry| {
            mission
                .render_one(entry)
                .replace("/m/mafiles/", "")
                .replace("/m/missions/", "")
        })
        .collect()
}

#[test]
fn values_outside_the_masterdata_limits() {
    // surface when_secs `#! min = 120.0`, goto_list num_waypoints `#! min = 1; max = 8`.
    let found = check(&[(
        "x.mi",
        "behavior: surface\n  b_arg: when_secs(sec) 60\nbehavior: goto_list\n  b_arg: num_waypoints(nodim) 9\n",
    )]);
    assert_eq!(found.len(), 2, "{found:#?}");
    assert!(
        found[0].starts_with("x.mi:2:3: warning[S0120]: `when_secs` is 60, outside its range")
            && found[0].contains(": at least 120"),
        "{}",
        found[0]
    );
    assert!(
        found[1].starts_with("x.mi:4:3: warning[S0120]: `num_waypoints` is 9")
            && found[1].contains(": 1 to 8"),
        "{}",
        found[1]
    );
}

#[test]
fn values_not_among_the_masterdata_choices() {
    // yo `start_when(enum) 2  #! choices=start_when([0, 1, 2, 4, 7, 8, 15, 17, 18])` and
    // surface `start_when … choices=start_when([0, 1, 2, 3, 6, 7, 8, 9, 10, 11, 12, 13, 16])`
    // in the 10.5 release masterdata: yo 12 is not among them, surface 12 is.
    let found = check(&[(
        "x.mi",
        "behavior: yo\n  b_arg: start_when(enum) 12\nbehavior: surface\n  b_arg: start_when(enum) 12\n",
    )]);
    assert_eq!(found.len(), 1, "{found:#?}");
    assert!(
        found[0].starts_with("x.mi:2:3: warning[S0127]: `start_when` is 12, not one of the values")
            && found[0].contains(": 0, 1, 2, 4, 7, 8, 15, 17, 18"),
        "{}",
        found[0]
    );
}

#[test]
fn waypoints_that_are_not_nmea() {
    let ma = "behavior_name=goto_list\n<start:b_arg>\nb_arg: num_waypoints(nodim) 5\n<end:b_arg>\n\
<start:waypoints>\n\
-7032.0640 4138.1060\n\
4138.1060 -7032.0640\n\
-70.534 41.635\n\
-7075.0 4138.0\n\
-7032.0640 4138.1060 | buoy\n\
<end:waypoints>\n";
    let found = check(&[
        (
            "x.mi",
            "behavior: goto_list\n  b_arg: args_from_file(enum) 10\n",
        ),
        ("goto_l10.ma", ma),
    ]);
    assert_eq!(found.len(), 4, "{found:#?}");
    // Line 10: a name after the numbers (a warning; the waypoint is kept).
    assert!(
        found[0].starts_with("goto_l10.ma:10:22: warning[S0126]: `| buoy`"),
        "{}",
        found[0]
    );
    // Line 7: 41°38'E 70°32'S is valid alone, but 110° from the others (70°W 41°N),
    // among which it would lie exchanged: swapped. Line 8: decimal degrees
    // (-70.534 is 70.534 minutes west of Greenwich). Line 9: 75 minutes.
    assert!(
        found[1].starts_with("goto_l10.ma:7:1: warning[S0121]") && found[1].contains("swapped"),
        "{}",
        found[1]
    );
    assert!(
        found[2].starts_with("goto_l10.ma:8:1: warning[S0121]")
            && found[2].contains("decimal degrees"),
        "{}",
        found[2]
    );
    assert!(
        found[3].starts_with("goto_l10.ma:9:1: warning[S0121]")
            && found[3].contains("75.000 minutes"),
        "{}",
        found[3]
    );
}

#[test]
fn a_waypoint_pasted_into_an_argument_stays_an_error() {
    let found = check(&[(
        "x.mi",
        "behavior: goto_list\n  b_arg: initial_wpt(enum) -07300.0 3850.2\n",
    )]);
    assert_eq!(found.len(), 1, "{found:#?}");
    // `3850.2` starts after 2 spaces, `b_arg: ` (7), `initial_wpt(enum) ` (18) and
    // `-07300.0 ` (9): 36 characters, so column 37.
    assert!(
        found[0].starts_with("x.mi:2:37: error[S0013]"),
        "{}",
        found[0]
    );
}

#[test]
fn dive_targets_against_overdepth_water_and_climb() {
    let found = check(&[
        (
            "x.mi",
            "sensor: s_water_depth_avg(m) 55\nbehavior: abend\n  b_arg: overdepth(m) 50\nbehavior: yo\n  b_arg: args_from_file(enum) 10\n",
        ),
        (
            "yo10.ma",
            "behavior_name=yo\n<start:b_arg>\n  b_arg: d_target_depth(m) 60\n  b_arg: c_target_depth(m) 70\n<end:b_arg>\n",
        ),
    ]);
    assert_eq!(found.len(), 3, "{found:#?}");
    assert!(
        found[0].starts_with("yo10.ma:3:3: warning[S0122]: yo's `d_target_depth` 60 (line 3) is deeper than abend's `overdepth` 50 (x.mi:3)"),
        "{}",
        found[0]
    );
    assert!(
        found[1].starts_with("yo10.ma:3:3: warning[S0122]")
            && found[1].contains("`s_water_depth_avg` 55 (x.mi:1)"),
        "{}",
        found[1]
    );
    assert!(
        found[2].starts_with("yo10.ma:4:3: warning[S0123]: yo's `c_target_depth` 70 (line 4) is deeper than its `d_target_depth` 60 (line 3)"),
        "{}",
        found[2]
    );
}

#[test]
fn a_surface_interval_longer_than_overtime() {
    let found = check(&[(
        "x.mi",
        "behavior: abend\n  b_arg: overtime(sec) 3600\nbehavior: surface\n  b_arg: start_when(enum) 12\n  b_arg: when_secs(sec) 7200\n",
    )]);
    assert_eq!(found.len(), 1, "{found:#?}");
    assert!(
        found[0].starts_with("x.mi:5:3: warning[S0124]: this surface behavior waits 7200 s, longer than abend's `overtime` 3600 (line 2)"),
        "{}",
        found[0]
    );
}

#[test]
fn num_waypoints_against_the_list_and_a_ma_for_another_behavior() {
    let found = check(&[
        (
            "x.mi",
            "behavior: goto_list\n  b_arg: args_from_file(enum) 10\nbehavior: yo\n  b_arg: args_from_file(enum) 10\n",
        ),
        (
            "goto_l10.ma",
            "behavior_name=goto_list\n<start:b_arg>\nb_arg: num_waypoints(nodim) 4\n<end:b_arg>\n<start:waypoints>\n-7032.0640 4138.1060\n-7031.9200 4138.1090\n-7031.9170 4138.0000\n<end:waypoints>\n",
        ),
        (
            "yo10.ma",
            "behavior_name=surface\n<start:b_arg>\n<end:b_arg>\n",
        ),
    ]);
    assert_eq!(found.len(), 2, "{found:#?}");
    assert!(
        found[0].starts_with("yo10.ma:1:1: warning[S0104]: this file is for behavior `surface`, but behavior `yo` loads it"),
        "{}",
        found[0]
    );
    assert!(
        found[1].starts_with("goto_l10.ma:3:1: warning[S0125]: `num_waypoints` is 4, but there are 3 waypoints in the list (line 6)"),
        "{}",
        found[1]
    );
}
