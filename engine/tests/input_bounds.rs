//! Input bounds (hardening, issue 19): a sensor list stops at `MAX_SENSORS` with one
//! located error, however long the file.

use gloc_engine::sensors::{parse_cac, parse_masterdata, SensorOrder, MAX_SENSORS};
use gloc_engine::LineIndex;

#[test]
fn a_masterdata_file_stops_at_65536_sensors_with_e0208() {
    let text: String = (0..200_000)
        .map(|index| format!("sensor: s{index}(nodim) 0\n"))
        .collect();
    let (list, diagnostics) = parse_masterdata(&text, SensorOrder::FileOrder);
    assert_eq!(MAX_SENSORS, 65_536);
    assert_eq!(list.len(), 65_536);
    let codes: Vec<&str> = diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(codes, ["E0208"]);
    let (line, column) = LineIndex::new(&text).line_col(&text, diagnostics[0].span.start as usize);
    assert_eq!((line, column), (65_537, 1));
}

#[test]
fn a_cac_index_at_the_limit_is_refused() {
    let text = "s: T 0 0 4 m_depth m\ns: T 65536 1 4 m_far m\n";
    let (_, diagnostics) = parse_cac(text);
    assert!(
        diagnostics
            .iter()
            .any(|d| d.code == "E0206" && d.message.contains("over the limit")),
        "{diagnostics:?}"
    );
}
