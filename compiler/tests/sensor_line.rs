//! The `# sensors: CRC` line the compiler writes for a non-default list: first in
//! the text, counted in the source map's lines, ignored when the output is loaded
//! again for that list.

use gloc_compiler::{compile, load_script, CompileOptions, Language, LoadOptions};
use gloc_engine::sensors::{load_sensor_file, SensorList, SensorOrder};

const FIG3: &str = include_str!("../../examples/fig3.gbas");

fn comet() -> SensorList {
    let path = gloc_testsupport::data("cac/1f35be3b.cac");
    load_sensor_file(&path, SensorOrder::FileOrder)
        .expect("comet's list in data/cac")
        .list
}

#[test]
fn fig3_for_comet_states_its_list_and_the_map_still_points_right() {
    let compiled = compile(FIG3, &comet(), &CompileOptions::default());
    let code = compiled.code.expect("compiles");
    let gloc = code.gloc_text;
    let lines: Vec<&str> = gloc.lines().collect();
    // Worked by hand: the paper's Fig. 2 with comet's indices (m_depth 459, the hook
    // sensors appended at 2142–2144) under the line.
    assert_eq!(lines[0], "# sensors: 1f35be3b");
    assert_eq!(&lines[1..5], ["nregs 8", "nblbs 7", "ninstr 27", "label 0"]);
    assert_eq!(lines[5], "loads 459,r0");
    assert_eq!(lines[11], "stores r3,2144");
    let map = code.build.source_map;
    assert_eq!(map.header_lines, 4);
    // GLOC line 6 (`loads 459,r0`) comes from GBASIC line 2 (`if m_depth > 15.0`).
    let origin = map.origin_of_gloc_line(6).expect("mapped");
    assert_eq!(origin.line, 2);
    // GLOC line 12 (`stores r3,2144`) from GBASIC line 3.
    assert_eq!(
        map.origin_of_gloc_line(12).map(|origin| origin.line),
        Some(3)
    );
    // Loading GBASIC for comet: no identity diagnostic, a program.
    let loaded = load_script(FIG3, Language::Gbasic, &comet(), &LoadOptions::default());
    assert!(loaded.diagnostics.is_empty(), "{:?}", loaded.diagnostics);
    assert!(loaded.program.is_some());
}

#[test]
fn the_embedded_list_gets_no_line() {
    let compiled = compile(FIG3, &SensorList::embedded(), &CompileOptions::default());
    let code = compiled.code.expect("compiles");
    assert!(
        code.gloc_text.starts_with("nregs 8\n"),
        "{}",
        code.gloc_text
    );
    assert_eq!(code.build.source_map.header_lines, 3);
}
