//! Masterdata and `.cac` readers, on small files written for these tests
//! (expected values worked out by hand from the files) and, when the shared
//! data folder is present, on the real 2008 `.cac` list.

use std::path::{Path, PathBuf};

use gloc_engine::sensors::{
    load_sensor_file, parse_cac, parse_masterdata, Sensor, SensorId, SensorList, SensorOrder,
};
use gloc_engine::{Diagnostic, LineIndex};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures/sensors")
        .join(name)
}

fn read(name: &str) -> String {
    std::fs::read_to_string(fixture(name)).expect("fixture exists")
}

fn located(text: &str, diagnostics: &[Diagnostic]) -> Vec<(&'static str, usize, usize)> {
    let index = LineIndex::new(text);
    let mut found: Vec<_> = diagnostics
        .iter()
        .map(|diagnostic| {
            let (line, column) = index.line_col(text, diagnostic.span.start as usize);
            (diagnostic.code, line, column)
        })
        .collect();
    found.sort_by_key(|(_, line, column)| (*line, *column));
    found
}

fn names(list: &SensorList) -> Vec<&str> {
    list.iter()
        .map(|(_, sensor)| sensor.name.as_str())
        .collect()
}

#[test]
fn masterdata_edge_cases() {
    let text = read("edge.masterdata");
    let (list, diagnostics) = parse_masterdata(&text, SensorOrder::FileOrder);
    assert_eq!(
        names(&list),
        vec![
            "m_present_time",
            "m_depth",
            "m_pressure",
            "c_pitch",
            "u_cycle_time",
            "x_odd_units",
            "M_DEPTH"
        ]
    );
    // The duplicate (line 15) warns and points at line 6; lookups find the first.
    assert_eq!(located(&text, &diagnostics), vec![("W0203", 15, 9)]);
    let first = diagnostics[0].labels[0].span.start as usize;
    assert_eq!(LineIndex::new(&text).line_col(&text, first), (6, 12));
    assert_eq!(list.lookup("M_DEPTH"), Some(SensorId(1)));

    let sensor = |name: &str| {
        list.get(list.lookup(name).expect("listed"))
            .expect("in range")
            .clone()
    };
    let depth = sensor("m_depth");
    assert_eq!(depth.line, 6);
    assert_eq!(depth.default, Some(0.0));
    assert_eq!(
        depth.description.as_deref(),
        Some("out, calculated depth clipped at 0")
    );
    assert_eq!(sensor("m_pressure").default, None);
    let pitch = sensor("c_pitch");
    assert_eq!(
        (pitch.allowed.min, pitch.allowed.max),
        (Some(-0.5), Some(0.5))
    );
    assert_eq!(pitch.description, None);
    let cycle = sensor("u_cycle_time");
    assert_eq!(cycle.default, Some(4.0));
    assert_eq!(
        (cycle.allowed.min, cycle.allowed.max),
        (Some(2.0), Some(1000.0))
    );
    let odd = sensor("x_odd_units");
    assert_eq!(odd.units, "uW/cm^2/nm");
    assert_eq!(odd.default, Some(0.001));

    let behaviors = list.behavior_defaults();
    assert_eq!(behaviors.len(), 2);
    assert_eq!(behaviors[0].name, "climb_to");
    assert_eq!(behaviors[0].args.len(), 2);
    let target = &behaviors[0].args[1];
    assert_eq!(target.name, "target_depth");
    assert_eq!(target.default, Some(10.0));
    assert_eq!(
        (target.allowed.min, target.allowed.max),
        (Some(0.0), Some(1000.0))
    );
    assert_eq!(behaviors[1].args[0].default, Some(20.0));
}

#[test]
fn masterdata_in_firmware_2014_order() {
    let text = read("edge.masterdata");
    let (list, _) = parse_masterdata(&text, SensorOrder::SortedByName);
    // Sorted after upper-casing: C_PITCH < M_DEPTH (twice, file order kept)
    // < M_PRESENT_TIME < M_PRESSURE ('E' < 'S') < U_CYCLE_TIME < X_ODD_UNITS.
    assert_eq!(
        names(&list),
        vec![
            "c_pitch",
            "m_depth",
            "M_DEPTH",
            "m_present_time",
            "m_pressure",
            "u_cycle_time",
            "x_odd_units"
        ]
    );
    assert_eq!(list.lookup("m_depth"), Some(SensorId(1)));
}

#[test]
fn broken_masterdata_lines_are_located() {
    let text = read("broken.masterdata");
    let (list, diagnostics) = parse_masterdata(&text, SensorOrder::FileOrder);
    assert_eq!(
        located(&text, &diagnostics),
        vec![
            ("E0201", 1, 16), // the `(` with no `)`
            ("E0201", 2, 9),  // no units at all
            ("E0202", 3, 20), // `zero` is not a number
            ("W0204", 5, 1),  // not a masterdata line
        ]
    );
    assert_eq!(names(&list), vec!["c_heading"]);
    let (list, diagnostics) = parse_masterdata("", SensorOrder::FileOrder);
    assert!(list.is_empty());
    assert_eq!(diagnostics[0].code, "E0207");
}

#[test]
fn cac_files() {
    let (list, diagnostics) = parse_cac(&read("small.cac"));
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    assert_eq!(
        names(&list),
        vec!["f_max_working_depth", "m_depth", "m_present_time"]
    );
    assert_eq!(
        list.get(SensorId(2)).map(|s| s.units.as_str()),
        Some("timestamp")
    );

    let text = read("broken.cac");
    let (list, diagnostics) = parse_cac(&text);
    assert_eq!(
        located(&text, &diagnostics),
        vec![
            ("E0206", 1, 1),  // index 1 never arrives
            ("E0205", 2, 4),  // `X` is neither T nor F
            ("E0205", 3, 11), // 3 bytes
            ("W0203", 4, 13), // `a_one` again
            ("E0206", 5, 6),  // index 2 twice
            ("E0205", 6, 1),  // not an `s:` line
        ]
    );
    assert_eq!(names(&list), vec!["a_one", "a_one"]);
}

#[test]
fn loading_picks_the_reader_by_extension_or_content() {
    // Each file's sensors, then the four hook sensors it lacks (appended).
    let loaded = load_sensor_file(&fixture("small.cac"), SensorOrder::FileOrder).expect("reads");
    assert_eq!(loaded.list.len(), 3 + 4);
    let loaded =
        load_sensor_file(&fixture("edge.masterdata"), SensorOrder::FileOrder).expect("reads");
    assert_eq!(loaded.list.len(), 7 + 4);
    // A `.cac` list under another name is recognised by its `s:` lines.
    let copy = std::env::temp_dir().join(format!("gloc-sensors-{}.txt", std::process::id()));
    std::fs::write(&copy, read("small.cac")).expect("temp file");
    let loaded = load_sensor_file(&copy, SensorOrder::FileOrder).expect("reads");
    let _ = std::fs::remove_file(&copy);
    assert_eq!(loaded.list.len(), 3 + 4);
    // Not named like a CRC, so no CRC.
    assert_eq!(loaded.list.crc(), None);
    assert!(load_sensor_file(Path::new("/no/such/file.cac"), SensorOrder::FileOrder).is_err());
}

/// The real 2008 list from the shared data folder, which sits next to the
/// repository (`data/`): missing, it is a failure.
#[test]
fn the_real_2008_cac_list_matches_the_embedded_list() {
    let path = gloc_testsupport::data("813b137d.cac");
    let loaded = load_sensor_file(&path, SensorOrder::FileOrder).unwrap_or_else(|error| {
        panic!(
            "cannot read {} ({error}): a file of the repository's data/",
            path.display()
        )
    });
    assert!(loaded.diagnostics.is_empty(), "{:?}", loaded.diagnostics);
    let list = loaded.list;
    // The 1,385 sensors of the file, then the hook sensors appended: at 1385 to
    // 1388, exactly where the embedded list has them.
    assert_eq!(list.len(), 1385 + 4);
    assert_eq!(
        loaded.added_hook_sensors,
        [
            "sci_ruhp_dive_depth",
            "sci_ruhp_climb_depth",
            "sci_ruhp_behs",
            "sci_ruhp_heading"
        ]
    );
    assert_eq!(list.crc(), Some("813b137d"));
    assert_eq!(list.lookup("m_depth"), Some(SensorId(444)));
    assert_eq!(list.lookup("m_pressure"), Some(SensorId(443)));
    let embedded = SensorList::embedded();
    for (id, sensor) in list.iter() {
        let ours = embedded.get(id).expect("embedded has the 2008 list");
        assert_eq!((&ours.name, &ours.units), (&sensor.name, &sensor.units));
    }
}

/// Comet's real 2019 list (sorted by name, 2,142 sensors) lacks the hook sensors:
/// they are appended at 2142 to 2145 and every file index stays where it was
/// (checked by hand in the file: 444 `m_certainly_at_surface`, 459 `m_depth`).
#[test]
fn a_real_list_without_the_hook_sensors_gets_them_appended() {
    let path = gloc_testsupport::data("cac/1f35be3b.cac");
    let loaded = load_sensor_file(&path, SensorOrder::FileOrder).expect("comet's list in data/cac");
    assert!(loaded.diagnostics.is_empty(), "{:?}", loaded.diagnostics);
    let list = loaded.list;
    assert_eq!(list.crc(), Some("1f35be3b"));
    assert_eq!(list.len(), 2142 + 4);
    assert_eq!(list.name(SensorId(444)), Some("m_certainly_at_surface"));
    assert_eq!(list.name(SensorId(459)), Some("m_depth"));
    assert_eq!(list.name(SensorId(2141)), Some("x_why_lens_completed"));
    assert_eq!(list.lookup("sci_ruhp_dive_depth"), Some(SensorId(2142)));
    assert_eq!(list.lookup("sci_ruhp_climb_depth"), Some(SensorId(2143)));
    assert_eq!(list.lookup("sci_ruhp_behs"), Some(SensorId(2144)));
    assert_eq!(list.lookup("sci_ruhp_heading"), Some(SensorId(2145)));
}

/// A compressed list (`.ccc`, newer gliders) loads as its `.cac` would: `06a36d4e.ccc`
/// holds the list of `compressed/01600000.dcd`, whose header (written by the glider)
/// says `total_num_sensors: 2709` and `sensor_list_crc: 06a36d4e`. Before, `.ccc` was
/// read as masterdata text: every line W0204 and an empty list.
#[test]
fn a_compressed_sensor_list_loads_with_the_count_its_glider_states() {
    let shared = gloc_testsupport::data("compressed");
    let path = shared.join("06a36d4e.ccc");
    let loaded = load_sensor_file(&path, SensorOrder::FileOrder).unwrap_or_else(|error| {
        panic!(
            "cannot read {} ({error}): a file of the repository's data/",
            path.display()
        )
    });
    assert!(
        loaded.diagnostics.iter().all(|d| !d.is_error()),
        "{:?}",
        loaded.diagnostics
    );
    assert_eq!(loaded.list.len() - loaded.added_hook_sensors.len(), 2709);
    assert_eq!(loaded.list.crc(), Some("06a36d4e"));
    assert!(loaded.list.lookup("m_depth").is_some());
    let folder = gloc_testsupport::scratch_dir("ccc");
    std::fs::create_dir_all(&folder).expect("a folder");
    let bomb = folder.join("00000000.ccc");
    // One block whose header claims a literal run it does not hold: a clear error.
    std::fs::write(&bomb, [0x00, 0x03, 0xf0, 0xff, 0xff]).expect("write");
    let error = load_sensor_file(&bomb, SensorOrder::FileOrder).expect_err("corrupt LZ4");
    assert!(
        error.to_string().contains("not a compressed sensor list"),
        "{error}"
    );
    std::fs::remove_dir_all(&folder).expect("clean up");
}

#[test]
fn a_release_layout_masterdata_is_read_as_the_firmware_reads_it() {
    // `/*` … `*/` around the change log and the body, `#define`, `END`, and one
    // `0 0` default: no error, one W0209 on the stray `0`, nothing else.
    let text = read("release-layout.masterdata");
    let (list, diagnostics) = parse_masterdata(&text, SensorOrder::FileOrder);
    assert_eq!(
        names(&list),
        vec!["m_depth", "u_cycle_time", "sci_odd_channel", "c_flntu_on"]
    );
    // `sensor: sci_odd_channel(nodim)  0 0`: the second `0` is column 35 of line 12.
    assert_eq!(located(&text, &diagnostics), vec![("W0209", 12, 35)]);
    assert_eq!(
        list.lookup("sci_odd_channel")
            .and_then(|id| list.get(id))
            .map(|sensor| sensor.default),
        Some(Some(0.0))
    );
    let behaviors = list.behavior_defaults();
    let names: Vec<&str> = behaviors.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, vec!["abend", "yo", "drift_at_depth", "surface"]);
    let yo = &behaviors[1];
    assert_eq!(yo.description.as_deref(), Some("dives and climbs"));
    // `#! visible = False` is metadata, not a description.
    assert_eq!(behaviors[2].description, None);
    let depth = &yo.args[1];
    assert_eq!(
        (depth.name.as_str(), depth.units.as_str(), depth.default),
        ("d_target_depth", "m", Some(42.0))
    );
    assert_eq!(
        (depth.allowed.min, depth.allowed.max),
        (Some(1.0), Some(1000.0))
    );
    assert_eq!(depth.description.as_deref(), Some("dive to this depth"));
}

#[test]
fn behavior_argument_choices_are_read_from_metadata() {
    let text = "sensor: m_depth(m) 0\n\
behavior: yo\n\
    b_arg: start_when(enum) 2   #! choices=start_when([0, 1, 2, 4])\n\
    b_arg: end_action(enum) 2\n\
                                #! choices = end_action([0, 2]); simple=False\n\
    b_arg: c_use_pitch(enum) 3  #! choices=use_pitch\n";
    let (list, diagnostics) = parse_masterdata(text, SensorOrder::FileOrder);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let args = &list.behavior_defaults()[0].args;
    assert_eq!(args[0].allowed.choices, Some(vec![0.0, 1.0, 2.0, 4.0]));
    // On the comment line below its `b_arg:`, with other metadata after it.
    assert_eq!(args[1].allowed.choices, Some(vec![0.0, 2.0]));
    // A named list the file does not give: nothing to check against.
    assert_eq!(args[2].allowed.choices, None);
}

#[test]
fn a_sensor_line_reads_its_comments_as_a_b_arg_line_does() {
    // The same text after `sensor:` and after `b_arg:`: the same setting, but for
    // the line number.
    let entry = "c_mode(enum) 1   #! min = 0; max = 4; choices=c_mode([0, 1, 4])\n\
                                # the mode\n";
    let text = format!("sensor: {entry}behavior: yo\n    b_arg: {entry}");
    let (list, diagnostics) = parse_masterdata(&text, SensorOrder::FileOrder);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let sensor = list.get(list.lookup("c_mode").unwrap()).unwrap();
    assert_eq!(
        (sensor.allowed.min, sensor.allowed.max),
        (Some(0.0), Some(4.0))
    );
    assert_eq!(sensor.allowed.choices, Some(vec![0.0, 1.0, 4.0]));
    assert_eq!(sensor.description.as_deref(), Some("the mode"));
    assert_eq!((sensor.default, sensor.line), (Some(1.0), 1));
    let arg = &list.behavior_defaults()[0].args[0];
    assert_eq!(arg.line, 4);
    assert_eq!(
        *arg,
        Sensor {
            line: 4,
            ..sensor.clone()
        }
    );
}

#[test]
fn a_masterdata_line_without_a_colon_that_starts_with_a_wide_character_is_a_warning() {
    // Found by the fuzzer: the keyword split sliced at byte 1 of `é`.
    let (list, diagnostics) = parse_masterdata("éa b\nsensor: m_x(m) 1\n", SensorOrder::FileOrder);
    assert_eq!(list.len(), 1);
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    assert_eq!(diagnostics[0].span.start, 0);
}
