//! The behavior table: read from a masterdata's `behavior:` sections (a fixture in the
//! release layout: `/* */`, `END`, `#!` limits, a stray value) or the embedded release
//! table, and used by the parser's checks and the simulator's defaults.

use std::sync::Arc;

use gloc_engine::sensors::{parse_masterdata, SensorOrder};
use gloc_mission::behaviors::{BehaviorTable, TableSource};
use gloc_mission::{LoadOptions, Mission};

fn fixture_table() -> Arc<BehaviorTable> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures/sensors/release-layout.masterdata");
    let text = std::fs::read_to_string(path).expect("fixture");
    let (list, _) = parse_masterdata(&text, SensorOrder::FileOrder);
    BehaviorTable::for_sensors(&list)
}

fn with_table(table: Arc<BehaviorTable>) -> LoadOptions {
    LoadOptions {
        table: Some(table),
        ..LoadOptions::default()
    }
}

#[test]
fn the_masterdata_sections_are_the_table() {
    let table = fixture_table();
    assert_eq!(table.source(), &TableSource::Masterdata);
    let names: Vec<&str> = table.behaviors().iter().map(|b| b.name.as_str()).collect();
    // The fixture's four sections, then gloc's own two.
    assert_eq!(
        names,
        ["abend", "yo", "drift_at_depth", "surface", "hook", "gloc"]
    );
    let yo = table.behavior("Yo").expect("yo");
    assert_eq!(yo.doc, "dives and climbs");
    let depth = yo.arg("D_TARGET_DEPTH").expect("d_target_depth");
    assert_eq!(
        (depth.default, depth.allowed.min, depth.allowed.max),
        (Some(42.0), Some(1.0), Some(1000.0))
    );
    assert!(!table
        .behavior("drift_at_depth")
        .expect("drift")
        .is_simulated());
}

#[test]
fn checks_and_defaults_follow_the_active_masterdata() {
    let text = "behavior: abend\n\
                behavior: drift_at_depth\n  b_arg: drift_time(sec) 300\n\
                behavior: yo\n  b_arg: d_targt_depth(m) 20\n\
                behavior: surface\n  b_arg: force_iridium_use(nodim) 1\n";
    let mission = Mission::load_text(
        std::path::Path::new("m.mi"),
        text.to_string(),
        &with_table(fixture_table()),
        &mut |_: &std::path::Path| -> std::io::Result<String> {
            Err(std::io::ErrorKind::NotFound.into())
        },
    );
    let messages = mission.rendered();
    assert_eq!(messages.len(), 3, "{messages:#?}");
    // Line 2: `behavior: drift_at_depth`, the name at column 11.
    assert!(
        messages[0].starts_with("m.mi:2:11: note[S0111]"),
        "{}",
        messages[0]
    );
    // Line 5: the misspelt argument, with the masterdata's name as the suggestion.
    assert!(
        messages[1].starts_with("m.mi:5:3: warning[S0103]: unknown argument `d_targt_depth`")
            && messages[1].ends_with("(help: did you mean `d_target_depth`?)"),
        "{}",
        messages[1]
    );
    // Line 7: the fixture's surface section lacks force_iridium_use.
    assert!(
        messages[2].starts_with("m.mi:7:3: warning[S0103]: unknown argument `force_iridium_use`")
            && messages[2].contains("(not in the active masterdata)"),
        "{}",
        messages[2]
    );
    // The simulator's default for yo's dive target is the fixture's 42 m.
    let yo = mission
        .behaviors
        .iter()
        .find(|spec| spec.name == "yo")
        .expect("yo");
    assert_eq!(yo.value("d_target_depth"), Some(42.0));
    // drift_at_depth is kept (with its argument) but not flown.
    let drift = &mission.behaviors[1];
    assert!(drift.defined && drift.arg("drift_time") == Some(300.0));
    assert_eq!(mission.known_behaviors().count(), 3);
}

#[test]
fn the_embedded_table_knows_the_release_behaviors_and_arguments() {
    // Behaviors and arguments real missions use that gloc's old table lacked.
    let text = "behavior: abend\n\
  b_arg: undervolts_sample_time(sec) 60\n  b_arg: no_cop_tickle_percent(%) -1\n\
  b_arg: reqd_free_heap(bytes) 50000\n  b_arg: use_thruster_for_ascent(bool) 0\n\
  b_arg: samedepth_for_surfacing(sec) 600\n  b_arg: invalid_gps(nodim) 5\n\
  b_arg: remaining_charge_sample_time(sec) 60\n\
behavior: surface\n  b_arg: force_iridium_use(nodim) 0\n  b_arg: min_time_between_gps_fixes(sec) 30\n\
behavior: yo\n  b_arg: d_max_thermal_charge_time(s) 1200\n  b_arg: d_speed_min(m/s) -1\n  b_arg: c_speed_min(m/s) -1\n\
behavior: sensors_in\n  b_arg: c_leakdetect_time(sec) -1\n  b_arg: c_flntu_on(sec) -1\n  b_arg: c_logger_on(sec) -1\n  b_arg: c_dvl_on(sec) -1\n\
behavior: goto_list\n  b_arg: wpt_units_0(enum) 0\n  b_arg: wpt_units_3(enum) 0\n\
behavior: sample\n  b_arg: tod_start(hhmm) -1\n  b_arg: tod_stop(hhmm) -1\n\
behavior: nop_cmds\nbehavior: drift_at_depth\nbehavior: compass_cal\nbehavior: oob_abort\nbehavior: pinger_on\n";
    let mission = Mission::parse("m.mi", text);
    let problems: Vec<String> = mission
        .rendered()
        .into_iter()
        .filter(|message| !message.contains("note[S0111]"))
        .collect();
    assert_eq!(problems, Vec::<String>::new());
    // The five firmware behaviors gloc does not fly are each a note.
    assert_eq!(mission.rendered().len(), 5);
}
