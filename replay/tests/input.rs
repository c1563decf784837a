//! `gloc_replay` on its own: CSV input, the unknown-sensor warning, a whole recording
//! of comet's real `.dbd` (data/; the depths were read with dbdreader 0.6.3,
//! `skip_initial_line=False`: 15.43901252746582 m in cycle 38 of 2,244).

use std::path::PathBuf;

use gloc_engine::sensors::SensorList;
use gloc_replay::{ColumnMap, Input, Recording};

fn temp(name: &str, text: &str) -> PathBuf {
    let path = std::env::temp_dir().join(format!("gloc-replay-{}-{name}", std::process::id()));
    std::fs::write(&path, text).expect("write");
    path
}

fn shared(path: &str) -> PathBuf {
    gloc_testsupport::data(path)
}

#[test]
fn a_csv_gives_its_non_empty_cells_per_row() {
    let path = temp(
        "rows.csv",
        "\u{feff}cycle,M_DEPTH,c_pitch\n0,1.5,\n\n1,,0.2\n",
    );
    let mut input = Input::open(&[path], None).expect("opens");
    assert_eq!(input.names(), ["M_DEPTH", "c_pitch"]);
    let mut updates = Vec::new();
    assert!(input.next_cycle(&mut updates).expect("row 1"));
    assert_eq!(updates, [(0, 1.5)]);
    assert!(input.next_cycle(&mut updates).expect("row 2"));
    assert_eq!(updates, [(1, 0.2)]);
    assert!(!input.next_cycle(&mut updates).expect("end"));
}

#[test]
fn csv_errors_name_the_line_and_column() {
    let path = temp("bad.csv", "m_depth,m_pitch\n1,0.1\n2,abc\n");
    let shown = path.display().to_string();
    let mut input = Input::open(&[path], None).expect("opens");
    let mut updates = Vec::new();
    assert!(input.next_cycle(&mut updates).expect("row 1"));
    let error = input.next_cycle(&mut updates).expect_err("row 2");
    assert_eq!(
        error.message,
        format!(
            "{shown}:3:3: `abc` is not a number (sensor values are decimal numbers such as `12.5`)"
        )
    );
    let path = temp("short.csv", "m_depth,m_pitch\n1\n");
    let mut input = Input::open(&[path], None).expect("opens");
    assert!(input
        .next_cycle(&mut updates)
        .expect_err("short row")
        .message
        .ends_with(":2:1: this row has 1 cells but the header has 2 names"));
    let csv = temp("mix.csv", "m_depth\n1\n");
    let error = Input::open(
        &[csv, shared("comet/from-glider/comet-2019-222-02-154.dbd")],
        None,
    )
    .err()
    .expect("refused");
    assert!(
        error.message.contains("a CSV replay is one file"),
        "{}",
        error.message
    );
}

#[test]
fn the_warning_names_twenty_then_counts_and_suggests_only_for_a_few() {
    let list = SensorList::embedded();
    let names: Vec<String> = (0..25)
        .map(|index| format!("x_unknown_{index:02}"))
        .collect();
    let map = ColumnMap::new(&names, &list);
    let warning = map.warning(&list).expect("a warning");
    assert!(warning.starts_with(
        "warning: 25 recorded sensors are not in the active sensor list (813b137d) and are ignored: `x_unknown_00`, "
    ));
    assert!(warning.ends_with("`x_unknown_19`, and 5 more"), "{warning}");
    assert!(!warning.contains("did you mean"));
    let map = ColumnMap::new(&["m_dpeth".to_string(), "m_depth".to_string()], &list);
    assert_eq!(map.ids[1], list.lookup("m_depth"));
    assert_eq!(
        map.warning(&list).as_deref(),
        Some("warning: 1 recorded sensor is not in the active sensor list (813b137d) and is ignored: `m_dpeth` (did you mean `m_depth`?)")
    );
    assert_eq!(
        ColumnMap::new(&["m_depth".to_string()], &list).warning(&list),
        None
    );
}

#[test]
fn a_recording_of_a_real_log_keeps_each_cycle_in_the_active_lists_indices() {
    let input = Input::open(
        &[shared("comet/from-glider/comet-2019-222-02-154.dbd")],
        Some(&shared("cac")),
    )
    .expect("opens with the cache");
    let list = SensorList::embedded();
    let recording = Recording::read(input, &list).expect("reads");
    assert_eq!(recording.len(), 2244);
    let depth = list.lookup("m_depth").expect("m_depth");
    let depth_in = |cycle: usize| {
        recording
            .cycle(cycle)
            .expect("a cycle")
            .iter()
            .find(|(id, _)| *id == depth)
            .map(|(_, value)| *value)
    };
    assert_eq!(depth_in(38), Some(15.43901252746582));
    assert_eq!(depth_in(37), Some(14.824023246765137));
    assert!(recording.cycle(2244).is_none());
    assert!(recording.warnings[0].contains("not in the active sensor list"));
}
