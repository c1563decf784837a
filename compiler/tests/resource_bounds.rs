//! Resource bounds (hardening): a GBASIC program with 100,000 labels compiles
//! (each label is one GLOC label; GLOC allows 2^20), and a source over the
//! 16 MB limit is refused with one clear error.

use gloc_compiler::{load_script, Language, LoadOptions};
use gloc_engine::sensors::SensorList;

fn load(text: &str) -> gloc_compiler::LoadedScript {
    load_script(
        text,
        Language::Gbasic,
        &SensorList::embedded(),
        &LoadOptions {
            optimize: false,
            cycle_budget: None,
        },
    )
}

#[test]
fn a_program_with_100000_labels_compiles_and_keeps_them_all() {
    let labels = 100_000;
    let mut text = String::new();
    for label in 0..labels {
        // Each label is a state that yields and goes on to the next one.
        let next = (label + 1) % labels;
        text.push_str(&format!("label: s{label}\nyield\ngoto s{next}\n"));
    }
    let loaded = load(&text);
    assert!(
        !loaded.has_errors(),
        "{:?}",
        &loaded.diagnostics[..3.min(loaded.diagnostics.len())]
    );
    let program = loaded.program.expect("a program");
    let defined = program.label_pcs.iter().filter(|pc| pc.is_some()).count();
    assert!(defined >= labels, "{defined} labels defined");
}

#[test]
fn a_gbasic_source_over_16_mb_is_refused() {
    let text = "x = 1\n".repeat(3 << 20);
    assert!(text.len() > 16 << 20);
    let loaded = load(&text);
    assert!(loaded.program.is_none());
    let codes: Vec<&str> = loaded.diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(codes, ["E0013"], "{:?}", &loaded.diagnostics[..1]);
    assert!(loaded.diagnostics[0].message.contains("at most 16 MB"));
}
