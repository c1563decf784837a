//! GLOC sensors by name: `loads m_depth,r0` is `loads 444,r0` on the list that
//! has `m_depth` at 444, and a name the list lacks is E0117 with "did you mean".

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::sensors::SensorList;

const FIG2: &str = include_str!("../../examples/fig2.gloc");

#[test]
fn fig2_by_name_is_the_same_program_as_by_index() {
    // The paper names sensor 444 the depth and 1387 the hook's request variable;
    // on the embedded list those are m_depth and sci_ruhp_behs.
    let list = SensorList::embedded();
    assert_eq!(
        list.name(gloc_engine::sensors::SensorId(444)),
        Some("m_depth")
    );
    let by_name = FIG2
        .replace("loads 444,", "loads m_depth,")
        .replace(",1387", ",sci_ruhp_behs");
    assert_ne!(by_name, FIG2);
    let indices = gloc::check(&gloc::parse(FIG2), &list, &CheckOptions::default());
    let names = gloc::check(&gloc::parse(&by_name), &list, &CheckOptions::default());
    assert_eq!(names.diagnostics, vec![]);
    let (Some(indices), Some(names)) = (indices.program, names.program) else {
        panic!("both check clean");
    };
    assert_eq!(indices.instrs, names.instrs);
    // The printout keeps the names as written.
    assert_eq!(gloc::print(&gloc::parse(&by_name).file), by_name);
}

#[test]
fn an_unknown_name_is_e0117_with_did_you_mean_and_a_fix() {
    let text = "nregs 1\nnblbs 1\nninstr 4\nlabel 0\nloads m_dpth,r0\nyield\njumpi 0\n";
    let checked = gloc::check(
        &gloc::parse(text),
        &SensorList::embedded(),
        &CheckOptions::default(),
    );
    let [diagnostic] = checked.diagnostics.as_slice() else {
        panic!("one diagnostic: {:?}", checked.diagnostics);
    };
    assert_eq!(diagnostic.code, "E0117");
    // Columns 7..13 of line 5: `m_dpth`.
    let start = text.find("m_dpth").expect("in the text");
    assert_eq!(diagnostic.span.range(), start..start + 6);
    assert!(
        diagnostic.message.contains("`m_dpth`"),
        "{}",
        diagnostic.message
    );
    assert_eq!(diagnostic.help.as_deref(), Some("did you mean `m_depth`?"));
    assert!(checked.program.is_none());
}

#[test]
fn a_name_is_no_register_or_label() {
    let text = "nregs 1\nnblbs 1\nninstr 4\nlabel 0\nmov m_depth,r0\nyield\njumpi 0\n";
    let parsed = gloc::parse(text);
    let [diagnostic] = parsed.diagnostics.as_slice() else {
        panic!("one diagnostic: {:?}", parsed.diagnostics);
    };
    assert_eq!(diagnostic.code, "E0004");
    assert!(
        diagnostic.message.contains("found the name `m_depth`"),
        "{}",
        diagnostic.message
    );
}

#[test]
fn names_are_matched_without_case_as_everywhere_in_gloc() {
    // `SensorList::lookup` is the one name rule (GBASIC and the missions use it).
    let text = "nregs 1\nnblbs 1\nninstr 4\nlabel 0\nloads M_Depth,r0\nyield\njumpi 0\n";
    let checked = gloc::check(
        &gloc::parse(text),
        &SensorList::embedded(),
        &CheckOptions::default(),
    );
    assert_eq!(checked.diagnostics, vec![]);
    let program = checked.program.expect("checks clean");
    assert!(
        program.instrs.iter().any(|instr| matches!(
            instr,
            gloc_engine::program::Instr::LoadSensor { sensor, .. } if sensor.0 == 444
        )),
        "{:?}",
        program.instrs
    );
}
