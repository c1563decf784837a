//! Sensor-list identity (`# sensors: CRC`): what `gloc::check` reports when a GLOC
//! file is checked against another list, and `identity::reindex`. Expected names
//! and indices were read by hand from `data/cac/1f35be3b.cac` (comet's
//! list: 444 `m_certainly_at_surface`, 459 `m_depth`, 1387 `sci_whfctd_ref_lo`) and
//! the paper's Fig. 2 (444 `m_depth`, 1387 `sci_ruhp_behs`).

use std::sync::Arc;

use gloc_engine::gloc::{self, identity, CheckOptions};
use gloc_engine::sensors::{load_sensor_file, Sensor, SensorList, SensorOrder};
use gloc_engine::LineIndex;

const FIG2: &str = include_str!("../../examples/fig2.gloc");

fn comet() -> SensorList {
    let path = gloc_testsupport::data("cac/1f35be3b.cac");
    load_sensor_file(&path, SensorOrder::FileOrder)
        .expect("comet's list in data/cac")
        .list
}

/// `LINE:COL CODE message` of each identity diagnostic (the others are not this
/// test's business).
fn identity_report(
    text: &str,
    active: &SensorList,
    written_for: Option<SensorList>,
) -> Vec<String> {
    let options = CheckOptions {
        written_for: written_for.map(Arc::new),
        ..CheckOptions::default()
    };
    let checked = gloc::check(&gloc::parse(text), active, &options);
    let index = LineIndex::new(text);
    checked
        .diagnostics
        .iter()
        .filter(|diagnostic| identity::CODES.contains(&diagnostic.code))
        .map(|diagnostic| {
            let (line, column) = index.line_col(text, diagnostic.span.start as usize);
            format!("{line}:{column} {} {}", diagnostic.code, diagnostic.message)
        })
        .collect()
}

#[test]
fn every_index_whose_name_differs_is_an_error_with_both_names() {
    let text = format!("# sensors: 813b137d\n{FIG2}");
    assert_eq!(
        identity_report(&text, &comet(), None),
        [
            "6:7 E0113 index 444 is `m_depth` in 813b137d but `m_certainly_at_surface` in 1f35be3b",
            "12:11 E0113 index 1387 is `sci_ruhp_behs` in 813b137d but `sci_whfctd_ref_lo` in 1f35be3b",
            "18:7 E0113 index 444 is `m_depth` in 813b137d but `m_certainly_at_surface` in 1f35be3b",
            "24:11 E0113 index 1387 is `sci_ruhp_behs` in 813b137d but `sci_whfctd_ref_lo` in 1f35be3b",
        ]
    );
    // The errors stop the program: a run would store into the wrong sensor.
    let checked = gloc::check(&gloc::parse(&text), &comet(), &CheckOptions::default());
    assert!(checked.program.is_none());
    // Against the list it states (the embedded one), nothing.
    assert!(identity_report(&text, &SensorList::embedded(), None).is_empty());
}

#[test]
fn without_the_line_a_non_default_list_warns_once() {
    assert_eq!(
        identity_report(FIG2, &comet(), None),
        [
            "5:7 W0114 the sensor indices were not verified by name: this file does not say which \
          sensor list they were written for, and 1f35be3b is not the embedded list (813b137d)"
        ]
    );
    assert!(identity_report(FIG2, &SensorList::embedded(), None).is_empty());
    // A warning, not an error: the program still loads.
    assert!(
        gloc::check(&gloc::parse(FIG2), &comet(), &CheckOptions::default())
            .program
            .is_some()
    );
}

#[test]
fn a_third_list_is_compared_when_the_caller_found_it_and_warned_about_when_not() {
    // Written for comet's list, checked against the embedded one (459 is
    // `f_ocean_pressure_max` in 813b137d.cac, read by hand).
    let text = FIG2
        .replace("loads 444,", "loads 459,")
        .replace("stores r3,1387", "stores r3,2144")
        .replace("stores r7,1387", "stores r7,2144");
    let text = format!("# sensors: 1F35BE3B\n{text}");
    let report = identity_report(&text, &SensorList::embedded(), Some(comet()));
    assert_eq!(report.len(), 2, "{report:?}");
    assert_eq!(
        report[0],
        "6:7 E0113 index 459 is `m_depth` in 1f35be3b but `f_ocean_pressure_max` in 813b137d"
    );
    // 2144 is past the embedded list's end: E0107 (not this check) says so.
    assert!(
        report[1].starts_with("18:7 E0113 index 459 is `m_depth`"),
        "{report:?}"
    );
    assert_eq!(
        identity_report(&text, &SensorList::embedded(), None),
        [
            "1:12 W0115 this file's indices were written for sensor list 1f35be3b, which was not \
          found; they were not verified by name"
        ]
    );
    // The same list under its own name: nothing to say.
    assert!(identity_report(&text, &comet(), None).is_empty());
}

#[test]
fn a_malformed_line_or_one_after_the_first_statement() {
    let text = format!("# sensors: comet\n{FIG2}");
    let report = identity_report(&text, &comet(), None);
    assert_eq!(report.len(), 1);
    assert!(report[0].starts_with("1:12 W0115 `# sensors:` names a sensor list by its CRC"));
    // After the first label the line is an ordinary comment.
    let text = FIG2.replacen("label 0\n", "label 0\n# sensors: 813b137d\n", 1);
    assert_eq!(identity::stated_crc(&text), None);
    assert_eq!(identity_report(&text, &comet(), None).len(), 1);
    assert!(identity_report(&text, &comet(), None)[0].contains("W0114"));
}

#[test]
fn reindex_rewrites_by_name_and_states_the_new_list() {
    let parsed = gloc::parse(FIG2);
    let rewritten =
        identity::reindex(FIG2, &parsed, &SensorList::embedded(), &comet()).expect("all found");
    let expected = format!(
        "# sensors: 1f35be3b\n{}",
        FIG2.replace("444,", "459,").replace(",1387", ",2144")
    );
    assert_eq!(rewritten, expected);
    // And back: the paper's text with the embedded list's line.
    let back = identity::reindex(
        &rewritten,
        &gloc::parse(&rewritten),
        &comet(),
        &SensorList::embedded(),
    )
    .expect("all found");
    assert_eq!(back, format!("# sensors: 813b137d\n{FIG2}"));
    // The result checks clean against its list.
    let checked = gloc::check(&gloc::parse(&rewritten), &comet(), &CheckOptions::default());
    assert!(checked.program.is_some(), "{:?}", checked.diagnostics);
}

#[test]
fn reindex_refuses_a_name_the_target_lacks_and_names_the_place() {
    let small = SensorList::from_sensors(
        ["m_depth", "c_pitch"]
            .iter()
            .map(|name| Sensor::new(*name, "m", 0))
            .collect(),
    );
    let errors = identity::reindex(FIG2, &gloc::parse(FIG2), &SensorList::embedded(), &small)
        .expect_err("sci_ruhp_behs is missing");
    let index = LineIndex::new(FIG2);
    let places: Vec<String> = errors
        .iter()
        .map(|error| {
            let (line, column) = index.line_col(FIG2, error.span.start as usize);
            format!("{line}:{column} {} {}", error.code, error.message)
        })
        .collect();
    assert_eq!(
        places,
        [
            "11:11 E0116 index 1387 is `sci_ruhp_behs` in 813b137d, and the active sensor list has no sensor `sci_ruhp_behs`",
            "23:11 E0116 index 1387 is `sci_ruhp_behs` in 813b137d, and the active sensor list has no sensor `sci_ruhp_behs`",
        ]
    );
}
